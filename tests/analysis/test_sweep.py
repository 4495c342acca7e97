"""Sweeps: configuration checks, load phase continuity, FMU sweeps against independent answers,
and the dask path against the local one."""

from __future__ import annotations

import math
import subprocess
import sys

import numpy as np
import pytest

from harness.analysis import curves as sw
from harness.model.excitation import AeroLoad, Stepped
from harness.analysis.executor import Runner
from harness.model.params import ParameterError, validate
from harness.analysis.harmonic_balance import harmonic_balance
from harness.reference import galerkin

# The contact-free blade is lightly damped (tau = 2M/C0 ~ 0.2 s): plateaus need a few seconds to be
# declared steady at rtol 1e-3 (cheap: ~0.1 s of wall time per simulated second).
SLOW_SETTLE = sw.SweepSettings(refine_levels=0, max_time=6.0, rtol=1e-3)


# ---------------------------------------------------------------------------------------------
# A bad configuration fails before any work, naming the value
# ---------------------------------------------------------------------------------------------
@pytest.mark.parametrize(
    "spec, needle",
    [
        (sw.SweepSpec({"d": -1e-5}, [3000, 4000]), "d = -1e-05"),
        (sw.SweepSpec({"kn": "stiff"}, [3000, 4000]), "kn = 'stiff'"),
        (sw.SweepSpec({"bogus": 1}, [3000, 4000]), "'bogus'"),
        (sw.SweepSpec({}, [3000, 40000]), "40000"),
        (sw.SweepSpec({}, [3000, float("nan")]), "nan"),
        (sw.SweepSpec({}, [3000]), "at least 2"),
        (sw.SweepSpec({}, [3000, 4000], methods=("time", "magic")), "'magic'"),
        (sw.SweepSpec({}, [3000, 4000], directions=("sideways",)), "'sideways'"),
        (sw.SweepSpec({}, [3000, 4000], settings=sw.SweepSettings(rtol=0.0)), "rtol = 0.0"),
        (sw.SweepSpec({}, [3000, 4000], settings=sw.SweepSettings(max_time=-1)), "max_time = -1"),
        (
            sw.SweepSpec({}, [3000, 4000], settings=sw.SweepSettings(steps_per_period=8, derivative_order=0)),
            "steps_per_period = 8",
        ),
    ],
)
def test_bad_configuration_fails_before_any_work(monkeypatch, spec, needle):
    # Two good curves first, the bad one last: nothing may be computed or even located.
    def boom(*a, **k):
        raise AssertionError("work started before the configuration was validated")

    monkeypatch.setattr(sw, "fmu_identity", boom)
    monkeypatch.setattr(sw, "worker_fmu", boom)
    monkeypatch.setattr(sw, "hb_curve", boom)
    good = sw.SweepSpec({}, [3000, 4000])
    with pytest.raises(ParameterError) as exc:
        sw.run_sweeps([good, good, spec])
    assert needle in str(exc.value)


def test_cli_bad_configuration_one_line_error(tmp_path):
    cases = [
        (["--start-values", "gamma", "2"], "gamma = "),
        (["--speeds", "3000:1000:100"], "3000:1000:100"),
        (["--rtol", "-1"], "--rtol -1"),
        (["--workers", "0"], "--workers 0"),
    ]
    for extra, needle in cases:
        proc = subprocess.run(
            [
                sys.executable,
                "-m",
                "harness",
                "sweep",
                "--cache-dir",
                str(tmp_path / "c"),
                "--output-file",
                str(tmp_path / "o.csv"),
                *extra,
            ],
            capture_output=True,
            text=True,
            timeout=120,
        )
        assert proc.returncode == 2, proc.stderr
        lines = [ln for ln in proc.stderr.splitlines() if ln.strip()]
        assert lines and lines[-1].startswith("error: ") and needle in lines[-1], proc.stderr
        assert not (tmp_path / "o.csv").exists() and not (tmp_path / "c").exists()


# ---------------------------------------------------------------------------------------------
# Load phase: plateau by plateau equals AeroLoad under a Stepped speed (independent code)
# ---------------------------------------------------------------------------------------------
def test_phased_sine_chain_matches_aeroload_under_stepped_speed():
    levels, durs = [4000.0, 5000.0, 6500.0], [0.013, 0.021, 0.017]
    ref = AeroLoad(100.0, 3, Stepped(levels, durs))
    t0, phase = 0.0, 0.0
    for n, dur in zip(levels, durs):
        om = 3 * 2 * math.pi * n / 60
        sig = sw.PhasedSine(100.0, om, phase, t0)
        t = np.linspace(t0, t0 + dur, 50, endpoint=False)
        # values and the 8 derivatives: the reference series is exact (Taylor arithmetic), ours is
        # closed form; both carry the phase error of ~1e-15 rad per unit, scaled by omega^j.
        d_ours = sig.derivatives(t, 8)
        d_ref = ref.derivatives(t, 8)
        for j in range(9):
            assert np.allclose(d_ours[j], d_ref[j], rtol=0, atol=1e-10 * 100 * om**j), j
        phase = (phase + om * dur) % (2 * math.pi)
        t0 += dur


# ---------------------------------------------------------------------------------------------
# FMU sweeps against independent answers
# ---------------------------------------------------------------------------------------------
def _linear_amplitude(p: dict, n: float) -> float:
    g = galerkin(p, p["formulation"])
    Om = 2 * math.pi * n / 60
    om = p["engineOrder"] * Om
    return g.loadGain * p["Fw0"] / abs(complex(g.K0static + g.K0omega2 * Om * Om - g.M * om * om, g.C0 * om))


def test_contact_free_plateaus_match_closed_form(fmu_path, tmp_path):
    # Large gap: the contact never closes, the blade is linear and the steady amplitude is the
    # closed form F / |K0 - M w^2 + i C0 w| (reference Galerkin constants, an independent code).
    # Tolerance 2e-3: steady-state rtol 1e-3 (an upper estimate of the distance) plus the FMU's RK4 error (maxStep 1e-5, ~1e-6) and
    # the order-8 input Taylor error (~1e-7); the FMU's `amplitude` is the exact period maximum.
    p = validate({"d": 1e-2})
    speeds = [3000.0, 4000.0, 4800.0]
    res = sw.sweep(
        sw.SweepSpec(p, speeds, methods=("time",), directions=("up",), settings=SLOW_SETTLE),
        fmu_path=fmu_path,
        cache_dir=tmp_path,
    )
    assert len(res.time) == 3
    for row in res.time:
        assert row["reached"]
        assert row["amplitude"] == pytest.approx(_linear_amplitude(p, row["speed"]), rel=2e-3)


def test_ungated_sweeps_follow_stable_hb_branches_and_fixed_points_find_every_hb_root(fmu_path, tmp_path):
    # gating off: with B given, the describing-function model is linear, so (docs/model.md s.3) the
    # tracked steady state is a one-harmonic solution and A(B) = B holds exactly at the harmonic-
    # balance amplitudes. The harmonic balance (frequency domain, another method) gives every root.
    p = validate({"gating": False, "kn": 1e6})
    speeds = tuple(np.arange(5200.0, 6601.0, 200.0))
    hb_all = harmonic_balance(p, np.array(speeds))
    multi = [s for s, sols in zip(speeds, hb_all) if len(sols) >= 3]
    assert multi, "test premise: some speed has three harmonic-balance solutions"
    s = sw.SweepSettings(refine_levels=0, max_time=6.0, rtol=1e-3, n_scan=24, fixed_max_time=6.0)
    res = sw.sweep(
        sw.SweepSpec(p, speeds, methods=("time", "fixed"), fixed_speeds=[multi[0]], settings=s),
        fmu_path=fmu_path,
        cache_dir=tmp_path,
    )
    branch_seen = set()
    for row in res.time:
        if not row["reached"]:
            continue
        sols = hb_all[speeds.index(row["speed"])]
        stable = [x.B for x in sols if x.stable]
        err = min(abs(row["amplitude"] - b) / b for b in stable)
        # 5e-3: steady-state rtol 1e-3 (upper estimate) plus RK4 and Taylor errors
        assert err < 5e-3, (row, stable)
        if len(sols) >= 3:
            branch_seen.add((row["direction"], int(np.argmin([abs(row["amplitude"] - b) for b in stable]))))
    # hysteresis: in the multi-solution region the up and down sweeps end on different branches
    assert {d for d, _ in branch_seen} == {"up", "down"}
    assert len({b for _, b in branch_seen}) == 2, branch_seen
    roots = sorted(res.fixed["B"][res.fixed["speed"] == multi[0]])
    hb_roots = sorted(x.B for x in hb_all[speeds.index(multi[0])])
    assert len(roots) == len(hb_roots), (roots, hb_roots)
    for a, b in zip(roots, hb_roots):
        assert a == pytest.approx(b, rel=5e-3)


def test_converging_plateau_extends_past_its_cap_irregular_one_stops(fmu_path):
    # From rest, contact-free (large gap): the transient decays regularly with tau = 2M/C0 = 0.22 s
    # and needs more than a 0.4 s cap to reach rtol 1e-3 (its fitted decay says so): with extend 1
    # it stops unconverged at the cap, with extend 5 it goes on, settles before 2 s (tau ln(1e4))
    # and its amplitude is the closed form (tolerance as above). The base case at 5000 rpm with
    # the tracked amplitude is irregular (no recurrence fits): it stops at the cap either way.
    path, fhash = sw.fmu_identity(fmu_path)
    free = validate({"d": 1e-2})
    T = 60.0 / (3 * 4000.0)

    def one(p, speed, extend):
        s = sw.SweepSettings(refine_levels=0, max_time=0.4, extend=extend, rtol=1e-3)
        return sw.run_chain(sw.ChainTask(p, (speed,), "up", s, path, fhash, None))[0]

    capped, extended = one(free, 4000.0, 1.0), one(free, 4000.0, 5.0)
    assert not capped.reached and capped.sim_time == pytest.approx(0.4, abs=T)
    assert extended.reached and 0.4 < extended.sim_time < 2.0 and extended.t_settle < 2.0
    assert extended.amplitude == pytest.approx(_linear_amplitude(free, 4000.0), rel=2e-3)
    irregular = one(validate({}), 5000.0, 5.0)
    assert not irregular.reached and irregular.sim_time <= 0.4 + 60.0 / (3 * 5000.0)


def test_refinement_narrows_the_peak(fmu_path, tmp_path):
    # A coarse 500 rpm grid; the refined sweep must put a point within min_dn..2 min_dn of the
    # contact-free resonance (at large gap the peak is the EO-3 crossing of the Campbell diagram,
    # located here independently from the reference Galerkin constants).
    p = validate({"d": 1e-2})
    g = galerkin(p, 1)
    # omega_n(Omega) = 3 Omega:  K0s + K0w Om^2 = M 9 Om^2
    Om = math.sqrt(g.K0static / (9 * g.M - g.K0omega2))
    n_res = Om * 60 / (2 * math.pi)
    s = sw.SweepSettings(refine_levels=5, min_dn=15.0, max_time=0.6, rtol=1e-3)
    res = sw.sweep(
        sw.SweepSpec(p, (4000.0, 4500.0, 5000.0, 5500.0, 6000.0), methods=("time",), directions=("up",), settings=s),
        fmu_path=fmu_path,
        cache_dir=tmp_path,
    )
    sp, _ = res.peak("time")
    assert abs(sp - n_res) < 2 * 15.0 + 500 / 2**5, (sp, n_res)
    assert len(res.time) > 5


def test_dask_local_cluster_gives_the_local_numbers(fmu_path, tmp_path):
    distributed = pytest.importorskip("distributed")
    p = validate({"kn": 1e6})
    spec = sw.SweepSpec(
        p,
        (4500.0, 5500.0, 6500.0),
        methods=("time", "fixed"),
        fixed_speeds=(5000.0, 6000.0),
        settings=sw.SweepSettings(refine_levels=1, max_time=0.3, fixed_max_time=0.2, n_scan=6),
    )
    local = sw.sweep(spec, Runner(workers=1, progress=False), fmu_path=fmu_path, cache_dir=None)
    with distributed.LocalCluster(n_workers=2, threads_per_worker=1, processes=True, dashboard_address=None) as cl:
        with distributed.Client(cl) as client:
            with Runner(scheduler=client, progress=False) as r:
                remote = sw.sweep(spec, r, fmu_path=fmu_path, cache_dir=None)
    # same FMU binary, same inputs, deterministic arithmetic: identical to the last bit
    assert_same(local.time, remote.time)
    assert_same(local.fixed, remote.fixed)


def assert_same(a: np.ndarray, b: np.ndarray) -> None:
    """Structured arrays equal field by field, bit for bit (nan == nan)."""
    assert a.dtype == b.dtype and len(a) == len(b) and len(a) > 0
    for name in a.dtype.names:
        if a.dtype[name].kind == "f":
            assert np.array_equal(a[name], b[name], equal_nan=True), name
        else:
            assert np.array_equal(a[name], b[name]), name
