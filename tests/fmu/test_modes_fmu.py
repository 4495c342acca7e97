"""The blade as m bending modes in the FMUs (docs/model.md s.2a), against independent computations
(tests/support/modes_galerkin.py: roots by brentq, shapes in long double, matrices by scipy quad):

- modeFrequency[1..6] at m = 6: at rest the exact natural frequencies of the cantilever with the
  tip mass, lambda_i^2 sqrt(EI / (rho A)) / (2 pi) (the exact modes make the Galerkin problem
  diagonal), rtol 1e-9; at 8000 rpm the eigenvalues of the independent matrices, rtol 1e-9;
- open contact (d = 1 m) at m = 3, started on the linear periodic orbit q(t) = Im(Q e^{i w t}),
  Q = (K - w^2 M + i w C)^-1 g F_w0 (a complex 3 x 3 solve): tip, modal coordinates and root moment
  stay on it over two periods within 1e-7 of the amplitude (RK4 at maxStep 1e-6 s);
- the modal Jacobian sensitivity[r,c] at m = 3 with the contact closing (Jenkins element and
  describing function) against central differences of the modal start values (1e-6 of the row's
  scale);
- the faces agree at m = 3: FMI 3.0 = FMI 2.0 co-simulation bit for bit, BladeExternalContact with
  F = 0 = ShroudedBlade with the contact open bit for bit, model exchange (fmpy CVode, rtol 1e-10)
  within 8e-7 of co-simulation (8.2e-8 measured); FMU state get/set and serialize continue bit-identically.
"""

from __future__ import annotations

import numpy as np
import pytest
import scipy.linalg as sl
from fmpy import read_model_description, simulate_fmu
from fmpy.fmi2 import FMU2Slave
from fmpy import extract

from harness.fmu import build as _build
from tests.support.modes_galerkin import Modes

TWO_PI = 2.0 * np.pi


def _cs(fmu, stop, dt, start_values, output, **kw):
    return simulate_fmu(str(fmu), stop_time=stop, output_interval=dt, start_values=start_values, output=output, **kw)


def test_mode_frequencies_at_rest_are_the_exact_ones(fmu_path):
    r = _cs(
        fmu_path,
        1e-4,
        1e-4,
        {"modes": 6, "formulation": 2, "maxStep": 1e-6},
        [f"modeFrequency[{i}]" for i in range(1, 7)],
        input=_speed(0.0),
    )
    g = Modes(6)
    exact = np.sqrt(g.EI / g.rhoA) * (g.aL / g.l) ** 2 / TWO_PI
    got = np.array([r[f"modeFrequency[{i}]"][0] for i in range(1, 7)])
    assert got == pytest.approx(exact, rel=1e-9)
    assert exact[0] == pytest.approx(231.9, abs=0.05)  # docs/model.md s.2


def _speed(n):
    return np.array([(0.0, 0.0, n), (1.0, 0.0, n)], dtype=[("time", float), ("aeroLoad", float), ("rotorSpeed", float)])


def test_mode_frequencies_rotating_match_independent_galerkin(fmu_path):
    n = 8000.0
    r = _cs(
        fmu_path,
        1e-4,
        1e-4,
        {"modes": 6, "formulation": 2, "maxStep": 1e-6},
        [f"modeFrequency[{i}]" for i in range(1, 7)] + ["naturalFrequency"],
        input=_speed(n),
    )
    M, C, K, K2, g = Modes(6).matrices()
    Om = TWO_PI * n / 60.0
    ref = np.sqrt(sl.eigh(K + Om**2 * K2, M, eigvals_only=True)) / TWO_PI
    got = np.array([r[f"modeFrequency[{i}]"][0] for i in range(1, 7)])
    assert got == pytest.approx(ref, rel=1e-9)
    assert r["naturalFrequency"][0] == r["modeFrequency[1]"][0]
    # the centrifugal terms couple the modes: K2 is not diagonal in the non-rotating modes
    assert abs(K2[0, 1]) > 1e-3 * np.sqrt(K2[0, 0] * K2[1, 1])


@pytest.mark.parametrize("m", [3, 5])
def test_open_contact_gives_the_linear_multi_mode_response(fmu_path, m):
    n, Fw0, c, EO = 4000.0, 100.0, 200.0, 3
    gal = Modes(m, c=c)
    M, C, K, K2, g = gal.matrices()
    Om = TWO_PI * n / 60.0
    w = EO * Om
    Q = np.linalg.solve(K + Om**2 * K2 - w**2 * M + 1j * w * C, g * Fw0)  # f_w = F_w0 sin(w t)
    starts = {"modes": m, "formulation": 2, "Fw0": Fw0, "c": c, "d": 1.0, "amplitudeMode": 1, "maxStep": 1e-6}
    starts.update({f"modalDisplacement[{i + 1}]": Q[i].imag for i in range(m)})
    starts.update({f"modalVelocity[{i + 1}]": (1j * w * Q[i]).imag for i in range(m)})
    T = TWO_PI / w
    names = ["tipDisplacement", "rootMoment"] + [f"modalDisplacement[{i + 1}]" for i in range(m)]
    r = _cs(fmu_path, 2 * T, T / 50, starts, names, input=_speed(n))
    t = r["time"]
    tip = np.exp(1j * w * t) * Q.sum()
    scale = abs(Q.sum())
    assert np.abs(r["tipDisplacement"] - tip.imag).max() < 1e-7 * scale
    for i in range(m):
        qi = (np.exp(1j * w * t) * Q[i]).imag
        assert np.abs(r[f"modalDisplacement[{i + 1}]"] - qi).max() < 1e-7 * scale
    Mroot = gal.EI * (np.exp(1j * w * t)[:, None] * Q[None, :] * gal.curvature0()[None, :]).sum(axis=1).imag
    assert np.abs(r["rootMoment"] - Mroot).max() < 1e-7 * np.abs(Mroot).max()
    # the higher modes matter for the root moment: more than for the tip
    assert abs(gal.curvature0()[1:] @ Q[1:]) / abs(gal.curvature0() @ Q) > 1e-3


def _run_jacobian(fmu_path, starts, stop, h):
    md = read_model_description(str(fmu_path))
    vr = {v.name: v.valueReference for v in md.modelVariables}
    d = extract(str(fmu_path))
    f = FMU2Slave(guid=md.guid, unzipDirectory=d, modelIdentifier="ShroudedBlade", instanceName="jac")
    f.instantiate()
    try:

        def run(values):
            f.reset()
            for k, x in values.items():
                if isinstance(x, bool):
                    f.setBoolean([vr[k]], [x])
                elif isinstance(x, int):
                    f.setInteger([vr[k]], [x])
                else:
                    f.setReal([vr[k]], [float(x)])
            f.setupExperiment(startTime=0.0)
            f.enterInitializationMode()
            f.exitInitializationMode()
            t = 0.0
            while t < stop - 1e-12:
                f.doStep(t, h)
                t += h
            state = f.getReal(
                [vr[f"modalDisplacement[{i}]"] for i in range(1, 7)]
                + [vr[f"modalVelocity[{i}]"] for i in range(1, 7)]
                + [vr["jenkinsForce"]]
            )
            jac = f.getReal([vr[f"sensitivity[{r},{c}]"] for r in range(1, 16) for c in range(1, 15)])
            return np.array(state), np.array(jac).reshape(15, 14)

        return run
    finally:
        pass


@pytest.mark.parametrize(
    "friction, starts",
    [
        (
            3,
            {
                "modalDisplacement[1]": 4.5e-5,
                "modalDisplacement[2]": 3e-7,
                "modalDisplacement[3]": -5e-8,
                "modalVelocity[1]": 0.02,
                "modalVelocity[2]": -1e-3,
                "modalVelocity[3]": 2e-4,
            },
        ),
        (1, {"modalDisplacement[1]": 6e-5, "modalDisplacement[2]": 1e-7}),
    ],
)
def test_modal_jacobian_matches_central_differences(fmu_path, friction, starts):
    """Over one period (4 ms) with the contact closing and opening (Jenkins element; describing
    function with its gate at fixed B). maxStep 1e-6 s and no amplitude tracking: the extremum
    events of the tracking cut the RK4 steps where the state says, so central differences would
    also see the truncation error move with the cuts."""
    m = 3
    base = {
        "modes": m,
        "formulation": 2,
        "frictionModel": friction,
        "Fw0": 150.0,
        "sensitivities": True,
        "amplitudeMode": 1,
        "B": 6e-5,
        "maxStep": 1e-6,
        **starts,
    }
    run = _run_jacobian(fmu_path, base, 0.004, 4e-4)
    y0, J = run(base)
    assert abs(J).max() > 0 and np.all(J[m:6] == 0) and np.all(J[:, m:6] == 0)  # nothing above m
    cols = list(range(m)) + [6 + i for i in range(m)]
    keys = [f"modalDisplacement[{i}]" for i in range(1, m + 1)] + [f"modalVelocity[{i}]" for i in range(1, m + 1)]
    for key, col in zip(keys, cols):
        x0 = base.get(key, 0.0)
        hstep = 1e-5 * max(abs(x0), 1e-7 if "Displacement" in key else 1e-3)
        yp, _ = run({**base, key: x0 + hstep})
        ym, _ = run({**base, key: x0 - hstep})
        fd = (yp - ym) / (2 * hstep)
        for r in cols + ([12] if friction == 3 else []):  # modal states (and jenkinsForce)
            scale = np.abs(J[r, cols]).max()
            assert J[r, col] == pytest.approx(fd[r], abs=1e-6 * scale), (key, r)


def test_fmi3_equals_fmi2_at_three_modes(fmu_path, fmu3_path):
    sv = {"modes": 3, "formulation": 2, "frictionModel": 3, "Fw0": 120.0, "modalDisplacement[2]": 1e-6}
    names = [
        "tipDisplacement",
        "tipVelocity",
        "jenkinsForce",
        "rootMoment",
        "modalDisplacement[2]",
        "modalVelocity[3]",
        "modeFrequency[3]",
    ]
    a = _cs(fmu_path, 0.02, 1e-4, sv, names)
    b = _cs(fmu3_path, 0.02, 1e-4, sv, names)
    assert np.abs(a["tipDisplacement"]).max() > 3e-5  # the contact closes
    for k in names:
        assert np.array_equal(a[k].view(np.int64), b[k].view(np.int64)), k


def test_external_contact_free_equals_open_shrouded_blade(fmu_path):
    ext = _build.build(("blade_external_fmu",)).parent / "BladeExternalContact.fmu"
    sv = {"modes": 4, "formulation": 2, "Fw0": 100.0, "modalDisplacement[1]": 1e-5, "modalVelocity[3]": 1e-3}
    names = [
        "tipDisplacement",
        "tipVelocity",
        "dissipatedEnergy",
        "rootMoment",
        "modalDisplacement[4]",
        "modeFrequency[4]",
    ]
    a = _cs(fmu_path, 0.02, 1e-4, {**sv, "d": 1.0, "amplitudeMode": 1}, names)
    b = _cs(ext, 0.02, 1e-4, sv, names)
    for k in names:
        assert np.array_equal(a[k].view(np.int64), b[k].view(np.int64)), k


def test_model_exchange_agrees_with_co_simulation(fmu_path):
    sv = {
        "modes": 3,
        "formulation": 2,
        "frictionModel": 3,
        "Fw0": 100.0,
        "modalDisplacement[1]": 2e-5,
        "modalDisplacement[2]": 2e-7,
    }
    names = ["tipDisplacement", "modalDisplacement[2]", "modalDisplacement[3]"]
    cs = _cs(fmu_path, 0.008, 1e-4, {**sv, "maxStep": 1e-6}, names)
    me = simulate_fmu(
        str(fmu_path),
        fmi_type="ModelExchange",
        solver="CVode",
        relative_tolerance=1e-10,
        stop_time=0.008,
        output_interval=1e-4,
        start_values=sv,
        output=names,
    )
    amp = np.abs(cs["tipDisplacement"]).max()
    assert amp > 3e-5
    for k in names:
        # measured 8.2e-8 (tip), 8.2e-9 and 3.4e-8 (modes 2, 3) of the amplitude: CVode at rtol 1e-10
        # against RK4 at 1e-6 s; tolerance 8e-7, 10x the largest
        assert np.abs(np.interp(cs["time"], me["time"], me[k]) - cs[k]).max() < 8e-7 * amp, k


def test_state_restore_and_serialization_at_three_modes(fmu_path):
    md = read_model_description(str(fmu_path))
    vr = {v.name: v.valueReference for v in md.modelVariables}
    f = FMU2Slave(guid=md.guid, unzipDirectory=extract(str(fmu_path)), modelIdentifier="ShroudedBlade")
    f.instantiate()
    f.setInteger([vr["modes"], vr["formulation"], vr["frictionModel"]], [3, 2, 3])
    f.setReal([vr["Fw0"], vr["modalDisplacement[2]"]], [100.0, 1e-6])
    f.setupExperiment(startTime=0.0)
    f.enterInitializationMode()
    f.exitInitializationMode()
    out = [vr[k] for k in ("tipDisplacement", "modalDisplacement[2]", "modalVelocity[3]", "rootMoment")]
    for k in range(50):
        f.doStep(k * 1e-4, 1e-4)
    s = f.getFMUstate()
    blob = f.serializeFMUstate(s)
    ref = []
    for k in range(50, 100):
        f.doStep(k * 1e-4, 1e-4)
        ref.append(f.getReal(out))
    for restore in (lambda: f.setFMUstate(s), lambda: f.setFMUstate(f.deSerializeFMUstate(blob))):
        restore()
        got = []
        for k in range(50, 100):
            f.doStep(k * 1e-4, 1e-4)
            got.append(f.getReal(out))
        assert np.array_equal(np.array(got).view(np.int64), np.array(ref).view(np.int64))
    f.terminate()
    f.freeInstance()


@pytest.mark.parametrize("m", [1, 3])
def test_harness_reads_the_monodromy(fmu_path, m):
    """harness.fmu.modal: at m = 1 the 3 x 3 monodromy is the one-mode sensitivities bit for bit."""
    from harness.fmu import modal

    starts = {"modalDisplacement[1]": 5e-5, "modalVelocity[1]": 0.01}
    if m > 1:
        starts["modalDisplacement[2]"] = 2e-7
    base = {"modes": m, "formulation": 2, "frictionModel": 3, "Fw0": 100.0, "sensitivities": True, **starts}
    md = read_model_description(str(fmu_path))
    by_name = {v.name: v for v in md.modelVariables}
    assert [
        by_name[modal.name(r, c)].valueReference for r in range(1, 16) for c in range(1, 15)
    ] == modal.value_references()
    assert all(by_name[modal.name(r, c)].causality == "local" for r in (1, 15) for c in (1, 14))
    r = simulate_fmu(
        str(fmu_path),
        stop_time=0.004,
        output_interval=4e-4,
        start_values=base,
        output=[modal.name(r, c) for r in range(1, 16) for c in range(1, 15)]
        + [f"d{a}_d{b}" for a in ("TipDisplacement", "TipVelocity", "JenkinsForce") for b in ("Q0", "V0", "F0")],
    )
    J = np.array([r[modal.name(i, j)][-1] for i in range(1, 16) for j in range(1, 15)])
    P = modal.monodromy(J, m)
    assert P.shape == (2 * m + 1, 2 * m + 1) and np.all(np.isfinite(P)) and abs(P).max() > 0
    # the documented layout (docs/model.md s.2a): rows and columns {1..m, 7..6+m, 13} of sensitivity[r,c]
    idx = list(range(1, m + 1)) + [6 + i for i in range(1, m + 1)] + [13]
    want = np.array([[r[f"sensitivity[{i},{j}]"][-1] for j in idx] for i in idx])
    assert np.array_equal(P, want)
    assert np.count_nonzero(P) > (2 * m + 1) ** 2 // 2  # the modes couple: a dense block, not a diagonal
    if m == 1:
        old = np.array(
            [
                r[f"d{a}_d{b}"][-1]
                for a in ("TipDisplacement", "TipVelocity", "JenkinsForce")
                for b in ("Q0", "V0", "F0")
            ]
        ).reshape(3, 3)
        assert np.array_equal(P.view(np.int64), old.view(np.int64))
