"""The ring's periodic orbits (harness/system/ring_orbits): the mistuning study's tuned ring (6
blades, EO 3, c = 298 N s/m2, Fw0 = 300 N/m, extrapolation order 2; its travelling wave is unstable
at 5800 rpm, the state reached from rest stable) and a 4-blade ring of the same blades.

Checks and tolerances:
- the period map is a function of its state: the same x gives a bit-identical image whatever ran
  before (another speed, another state); nothing else carries over;
- it is the continuous co-simulation's period-to-period map: a run of the C loop without restarts,
  read at each period's start (state and history), is mapped onto its next period's start (1e-12);
  the map with the history restarted at point 0 is not (1.5e-5);
- every orbit Newton returns has a period residual max |P(x) - x| / scale <= 1e-8 (the shooting's
  own tolerance is 1e-10);
- the multipliers against the time domain (the co-simulation iterated period by period from the
  orbit moved by 1e-6 of its scale along a random direction, up to 60 periods or until the deviation
  passes 1e-3 of the scale, still linear): the per-period growth of the deviation over the second
  half of the run (the dominant multiplier has taken over) equals the largest |multiplier| within
  5 % (measured: 2e-5..4e-5 on the unstable orbits, 9e-4 and 8e-3 on the stable ones, whose
  deviation decays more slowly through complex pairs); a stable orbit's deviation shrinks, an
  unstable one's grows;
- the same check with a deliberately broken DP (one column doubled) or a broken stability test
  (stable read as the largest |multiplier| above 1) fails;
- a sweep's settled states (harness/system/ring_sweep.py, up and down) lie on the reported branches'
  stable orbits (tolerance: the settle rule's bound, see the test).
"""

from __future__ import annotations

import numpy as np
import pytest

from harness.system.ring import Ring
from harness.system.ring_orbits.branches import crossings, ring_branches
from harness.system.ring_orbits.symmetry import distance, index_maps
from harness.system.ring_sweep import sweep
from harness.system.ring_orbits.period_map import RingPeriodMap
from harness.system.ring_orbits.seeds import from_rest, kicked, settle, travelling_wave
from harness.analysis.periodic.shooting import multipliers
from harness.system.ring_orbits.shooting import monodromy, shoot

RATE_RTOL = 0.05  # measured: 2e-5..4e-5 (unstable orbits), 9e-4 and 7.9e-3 (stable: slower, complex pairs)
STUDY = Ring(n=6, engine_order=3, fw0=300.0, blade={"c": 298.0}, order=2)
SMALL = Ring(n=4, engine_order=3, fw0=300.0, blade={"c": 298.0}, order=2)


@pytest.fixture(scope="module")
def pm():
    with RingPeriodMap(STUDY) as m:
        yield m


def test_map_is_a_function_of_the_state():
    with RingPeriodMap(SMALL) as pm:
        _function_of_state(pm)


def _function_of_state(pm: RingPeriodMap) -> None:
    x = from_rest(pm, [6000.0], max_periods=40, min_periods=40)[0].x
    pm.seen.clear()
    P1, A1 = pm(x, 6000.0)
    pm(np.zeros(pm.dim), 6500.0)  # something else in between: another speed, another state
    pm(P1 * 1.1, 5000.0)
    pm.seen.clear()  # no cached image: the period is run again
    e = pm.evaluations
    P2, A2 = pm(x, 6000.0)
    assert pm.evaluations == e + 1
    assert np.array_equal(P1, P2) and A1 == A2


CONTINUOUS_TOL = 1e-12  # measured 5.7e-14, 6.5e-14, 3.1e-13 one to three periods in (4 blades, 6000 rpm)


def test_map_is_the_continuous_runs_period_map():
    """The C loop run on the exact grid for four periods without a restart, from a state reached by
    iterating the map (4 blades, 6000 rpm, contacts acting): its state and history at each period's
    start, mapped by the period map, equal its state one period later to CONTINUOUS_TOL of the scale.
    Not to zero: the blades integrate the load phase psi with the state, so the run's psi after j
    periods carries the rounding of j K steps at psi ~ 2 pi j (it grows like j^2; the map starts
    every period from psi = 0). The earlier map (history restarted at point 0) misses by 1.5e-5."""
    rpm = 6000.0
    with RingPeriodMap(SMALL) as pm:
        x0 = settle(pm, kicked(pm), rpm, 0.0, 40)[0]
        K, cr = pm.s.steps_per_period, pm._cr
        h = 60.0 / (SMALL.engine_order * rpm) / K
        pm._start(x0, rpm)
        cr.rpm = rpm
        cr.restart_exact(h)
        cr.set_history(*pm.history(x0))
        run = [x0]
        for _ in range(4):
            cr.advance(K, rpm)
            saved = cr.save()
            cr.advance(0, rpm, finish=True)  # point jK pushed, not stepped: the state there
            run.append(pm.read(cr))
            cr.restore(saved)
        k = 2 * pm.m * pm.n + pm.n  # the blades' and contacts' part (without the history)
        for a, b in zip(run, run[1:]):
            sc = pm.scales(b, rpm)
            assert np.max(np.abs(pm(a, rpm)[0] - b) / sc) <= CONTINUOUS_TOL
            pm._start(a, rpm)  # the restart map: the same period from the same state, no history
            cr.restart_exact(h)
            cr.advance(K, rpm, finish=True)
            assert np.max(np.abs(pm.read(cr)[:k] - b[:k]) / sc[:k]) > 1e3 * CONTINUOUS_TOL


def growth(pm: RingPeriodMap, x: np.ndarray, speed: float, seed: int = 0) -> tuple[float, float, float]:
    """(per-period growth of the scaled deviation over the second half of the run, first and last
    deviation): from x moved by 1e-6 of its scale along a random direction, the map iterated until
    the deviation passes 1e-3 (still linear) or 60 periods."""
    sc = pm.scales(x, speed)
    d = np.random.default_rng(seed).standard_normal(pm.dim)
    y = pm.bounded(x + 1e-6 * sc * d / np.max(np.abs(d)))
    dev = []
    for _ in range(60):
        y = pm(y, speed)[0]
        dev.append(float(np.linalg.norm((y - x) / sc)))
        if dev[-1] > 1e-3:
            break
    end = len(dev) - 1
    start = max(3, end // 2)
    return (dev[end] / dev[start]) ** (1 / (end - start)), dev[0], dev[end]


@pytest.fixture(scope="module")
def orbits(pm):
    """Stable and unstable orbits of the study's ring: the travelling wave and the states reached
    from rest (kicked) at three speeds."""
    out = []
    for sd in travelling_wave(pm, [5800.0, 6600.0]) + from_rest(pm, [5800.0, 6200.0, 6600.0]):
        o = shoot(pm, sd.x, sd.speed)
        if o is not None:
            out.append(o)
    return out


def test_period_residuals(orbits):
    assert len(orbits) >= 5
    for o in orbits:
        assert o.residual <= 1e-8, (o.speed, o.residual)


def agrees(rate: float, first: float, last: float, mu_max: float, stable: bool) -> bool:
    """The time domain's growth agrees with the largest multiplier (10 %) and with the stability."""
    return abs(rate - mu_max) <= RATE_RTOL * mu_max and (last < first) == stable


@pytest.fixture(scope="module")
def measured(pm, orbits):
    return [growth(pm, o.x, o.speed) for o in orbits]


def test_multipliers_against_the_time_domain(orbits, measured):
    assert {o.stable for o in orbits} == {True, False}, "need stable and unstable orbits"
    for o, (rate, first, last) in zip(orbits, measured):
        assert agrees(rate, first, last, o.max_multiplier, o.stable), (o.speed, rate, o.max_multiplier, o.stable)


def test_broken_jacobian_fails(pm, orbits, measured):
    """DP with one column doubled: its largest multiplier disagrees with the time domain."""
    bad = 0
    for o, (rate, first, last) in zip(orbits, measured):
        J = monodromy(pm, o.x, o.speed)
        J[:, 0] *= 2.0
        mu = float(np.max(np.abs(multipliers(J))))
        bad += not agrees(rate, first, last, mu, mu < 1.0)
    assert bad > 0


def test_broken_stability_test_fails(orbits, measured):
    """Stability read as the largest |multiplier| above 1 (inverted): the check fails."""
    assert not all(
        agrees(r, f, la, o.max_multiplier, o.max_multiplier > 1.0) for o, (r, f, la) in zip(orbits, measured)
    )


SWEEP_SPEEDS = [5600.0, 6000.0, 6400.0]
SETTLE_RTOL = 1e-4  # the sweep's settle rule: per-period change below this over 5 periods


def test_sweeps_settled_states_lie_on_the_branches():
    """ring_branches over 5500-6500 rpm on the 4-blade ring seeded by nothing but a C-loop sweep up
    and down at three speeds (harness/system/ring_sweep.py, the state carried), and that sweep run
    again on its own: every state where it settled, up and down, equals (per blade, relative to the
    largest, up to the ring's symmetries) an orbit where a reported branch crosses its speed. Without
    the sweep's seeds there is no branch, and the test fails. Tolerance: a state whose per-period
    change is below the settle rule's 1e-4 is within 1e-4 mu / (1 - mu) of the stable orbit it
    approaches (mu its largest multiplier, the geometric series of the remaining changes): 5.7e-4..
    6.6e-4; the sweep steps on the map's own grid aligned to the load and measures the amplitude as
    the map does, so nothing else enters; measured 1.6e-6..6.1e-6 (1.3e-5..2.3e-4 on the earlier
    grid of whole ns, which drifted against the load)."""
    r = ring_branches(SMALL, (5500.0, 6500.0), points=2, sweep_speeds=SWEEP_SPEEDS, seed_kinds=("C-loop sweep",))
    sw = sweep(SMALL, SWEEP_SPEEDS, "both", refine=False, rtol=SETTLE_RTOL)
    maps = index_maps(SMALL)
    assert set(sw.amplitudes_m) == {"up", "down"}
    with RingPeriodMap(SMALL) as pm:
        for d, amps in sw.amplitudes_m.items():
            for s, a, ok in zip(sw.speeds_rpm, amps, sw.settled[d]):
                assert ok.all(), (d, s)
                found = [(distance(o, a, maps), mu) for o, mu in crossings(pm, r.branches, float(s)) if mu < 1]
                assert found, (d, s, "no stable orbit crosses this speed")
                dist, mu = min(found)
                assert dist <= SETTLE_RTOL * mu / (1 - mu), (d, s, dist, mu)


@pytest.mark.parametrize(
    "kw,words",
    [
        ({"speed_range_rpm": (6000.0, 5000.0)}, ["speed_range_rpm", "FROM must be below TO"]),
        ({"speed_range_rpm": (5000.0, 6000.0), "seed_points": 1}, ["seed_points = 1", "[2, 200]"]),
        ({"speed_range_rpm": (5000.0, 6000.0), "steps_per_period": 4}, ["steps_per_period = 4", "[8, 100000]"]),
        ({"speed_range_rpm": "fast"}, ["speed_range_rpm = 'fast'", "two speeds"]),
        ({"speed_range_rpm": (5000.0, 6000.0), "sweep_seeds_rpm": [6000.0, 5000.0]}, ["sweep_seeds_rpm", "increasing"]),
        (
            {"speed_range_rpm": (5000.0, 6000.0), "sweep_seeds_rpm": [5000.0, -1.0]},
            ["sweep_seeds_rpm = -1.0", "(0, 30000]"],
        ),
        ({"speed_range_rpm": (5000.0, 6000.0), "sweep_seeds_rpm": "x"}, ["sweep_seeds_rpm = 'x'", "speeds"]),
    ],
)
def test_api_refuses_bad_input(kw, words):
    import harness

    with pytest.raises(harness.ParameterError) as e:
        harness.ring_branches(SMALL, **kw)
    for w in words:
        assert w in str(e.value), (w, str(e.value))


def test_cli_refuses_branches_without_band():
    import subprocess
    import sys

    p = subprocess.run(
        [sys.executable, "-m", "harness", "ring", "--blades", "4", "--branches"],
        capture_output=True,
        text=True,
        timeout=120,
    )
    assert p.returncode == 2 and "--branches" in p.stderr and "--speeds" in p.stderr, p.stderr


def test_api_passes_a_sweep_of_seeds_to_the_engine(monkeypatch):
    """sweep_seeds_rpm reaches the engine as a C-loop sweep up and down with its peak located."""
    import harness.api as api

    got = {}
    monkeypatch.setattr(api, "trace_ring_branches", lambda ring, band, **kw: got.update(kw))
    api.ring_branches(SMALL, (5500.0, 6500.0), sweep_seeds_rpm=[5000, 6000, 7000])
    (path,) = got["sweeps"]
    assert path.speeds == (5000.0, 6000.0, 7000.0) and path.refine
