"""The FMU with m = 3 modes at a point that is not the default, against the reference's own m-mode
model (harness.reference.modes / simulate), the finite-element beam and, for the periodic solver,
the reference's time integration started on the FMU's orbits.

The point: consistent formulation, modes = 3, EI = 380 N m^2, m0 = 0.04 kg, d = 0.025 mm, c = 40 N s/m^2,
k_n = 3e6 N/m, mu = 0.3, F_w0 = 150 N/m, 7000 rpm. maxStep = 1e-6 s: with the contact closed the
third mode's RK4 error at the default 1e-5 s is 1.4e-3 of the tip amplitude (4.9e-6 at 2.5e-6 s,
1.1e-7 at 1e-6 s, measured for the fixed-B describing function), so the step, not the model,
would dominate the comparison. Measured at 1e-6 s over 0.03 s (max difference / max of the
reference): tip 3e-9 (Jenkins) and 4e-8 (tracked DF), root moment 3e-8 / 1.3e-7, modal
coordinate 3 (amplitude 2e-7 m) 5.7e-7 / 9.2e-7; natural frequencies vs the reference 1e-15,
vs the FE beam 7.9e-6, 6.6e-6, 2.2e-6 (modes 1..3, from above).
"""

from __future__ import annotations

import math

import numpy as np
import pytest

from harness import reference
from harness.analysis.periodic.period_map import PeriodMap, ShootingSettings
from harness.analysis.periodic.search import solutions_at
from harness.analysis.periodic.shooting import jacobian, orbit
from harness.model.excitation import AeroLoad, Constant
from harness.model.params import validate
from harness.reference.beam_fe import beam_fe
from harness.reference.modes import modal_galerkin

POINT = dict(maxStep=1e-6, formulation=2, modes=3, EI=380.0, m0=0.04, d=2.5e-5, c=40.0, kn=3e6, mu=0.3, Fw0=150.0)
SPEED = 7000.0
STATE = [
    "tipDisplacement",
    "tipVelocity",
    "rootMoment",
    "dissipatedEnergy",
    *(f"modalDisplacement[{i}]" for i in (1, 2, 3)),
    *(f"modalVelocity[{i}]" for i in (1, 2, 3)),
]
TOL = 1e-6  # relative to the reference's largest value of each quantity (measured <= 3.4e-7)
TOL_MODE3 = 5e-6  # the third modal coordinate, 1/300 of the tip (measured <= 1.3e-6)


@pytest.mark.parametrize(
    "extra", [dict(frictionModel=3), dict(frictionModel=1, amplitudeMode=2, B=6e-5)], ids=["jenkins", "trackedDF"]
)
def test_fmu_runs_like_the_reference(fmu, extra):
    p = validate(dict(POINT, **extra))
    speed = Constant(SPEED)
    r = fmu.run(p, 0.03, 1e-4, speed_rpm=speed, outputs=STATE)
    ref = reference.simulate(
        p, 0.03, AeroLoad(p["Fw0"], p["engineOrder"], speed), speed, t_eval=r["time"], rtol=1e-10, breakpoints=r["time"]
    )
    assert np.max(np.abs(ref["tipDisplacement"])) > 2 * p["d"]  # the contact works
    for k in STATE:
        err = np.max(np.abs(r[k] - ref[k])) / np.max(np.abs(ref[k]))
        assert err < (TOL_MODE3 if k.endswith("[3]") else TOL), (k, err)


def test_mode_frequencies_match_reference_and_fe(fmu):
    p = validate(POINT)
    outs = [f"modeFrequency[{i}]" for i in range(1, 7)]
    r = fmu.run(p, 1e-4, 1e-4, speed_rpm=SPEED, outputs=outs)
    f = np.array([r[k][-1] for k in outs])
    assert np.all(f[3:] == 0.0)  # above m
    np.testing.assert_allclose(f[:3], modal_galerkin(p).frequencies_hz(SPEED), rtol=1e-12)
    fe = beam_fe(p, 120).frequencies_hz(SPEED, 3)
    err = (f[:3] - fe) / fe
    assert np.all(err > 0.0) and np.all(err < 1e-5), err  # Rayleigh-Ritz: from above


@pytest.mark.parametrize("model", ["jenkins", "fixedPoint"])
def test_periodic_orbit_m3_is_periodic_in_the_reference(fmu, model):
    """Shooting with m = 3 (state 2m + 1 = 7, DP from the FMU's modal Jacobian): every orbit found at 7000 rpm,
    started in the reference at load phase 0 (the describing function with its B fixed at the
    orbit's), comes back to its modal state after one period within 1e-6 of the state's scale, with
    max |q| over the period = the orbit's amplitude within 1e-6 of it. The orbits start open
    (|q0| < d), where the Jenkins element is unloaded, as the reference starts it."""
    pm = PeriodMap(fmu, POINT, model)
    assert pm.dim == 7 and pm.s.sensitivities
    sols = solutions_at(pm, SPEED)
    assert sols, "no orbit found"
    om = int(pm.p["engineOrder"]) * 2 * math.pi * SPEED / 60
    T = 2 * math.pi / om
    for sol in sols:
        o = orbit(pm, sol, SPEED)
        q0 = float(np.sum(o.x[:3]))
        assert abs(q0) < pm.d
        p = dict(pm.p, amplitudeMode=1, B=o.B) if model == "fixedPoint" else dict(pm.p)
        te = np.linspace(0.0, T, 257)
        ref = reference.simulate(
            p, T, lambda t: pm.p["Fw0"] * math.sin(om * t), lambda t: SPEED, te, rtol=1e-10, initial=(o.x[:3], o.x[3:6])
        )
        end = np.array(
            [ref[f"modalDisplacement[{i}]"][-1] for i in (1, 2, 3)]
            + [ref[f"modalVelocity[{i}]"][-1] for i in (1, 2, 3)]
        )
        sc = pm.scales(o.x, SPEED)[:6]
        assert np.max(np.abs(end - o.x[:6]) / sc) < 1e-6, (end, o.x)
        # max |q| over the period: sampled at 256 points, so the sampled max may fall short of the
        # located one by at most (omega T/256)^2 / 8 of it (a peak sampled off by half a step)
        amax = float(np.max(np.abs(ref["tipDisplacement"])))
        assert o.amplitude * (1 - (2 * math.pi / 256) ** 2 / 8) - 1e-6 * o.amplitude <= amax <= o.amplitude * (1 + 1e-6)


@pytest.mark.parametrize(
    "model, x",
    [
        ("fixedB", [1e-5, 2e-6, -1e-7, 0.05, 0.002, 0.0]),
        ("fixedPoint", [2e-5, 2e-6, -1e-7, 0.07, 0.002, 0.0, 4e-5]),
        ("jenkins", [3e-5, 2e-6, -1e-7, 0.07, 0.002, 0.0, 0.3]),  # in contact at the start: F0 = 0.3 L
    ],
)
def test_period_map_jacobian_m3_is_the_finite_difference_one(fmu, model, x):
    """DP of the m = 3 period map from the FMU's sensitivity[r,c] against central differences of the
    map itself (sensitivities off), scaled by the unknowns' scales: measured <= 3e-8 (entries ~10)."""
    x = np.array(x)
    pm = PeriodMap(fmu, POINT, model)
    pm(x, SPEED)
    fd = PeriodMap(fmu, POINT, model, ShootingSettings(sensitivities=False))
    J = jacobian(fd, x, SPEED, fd(x, SPEED)[0], central=True)
    sc = pm.scales(x, SPEED)
    assert np.max(np.abs((pm.DP - J) * sc[None, :] / sc[:, None])) < 3e-7
