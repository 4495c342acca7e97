"""The ring's period map on several threads (RingPeriodMap.images, `workers`): the columns of a
finite-difference DP run on two threads, each on its own FMU instances, give the serial DP bit for
bit (tolerance 0: an image is a function of x alone, whichever instances run it), with the same
evaluation count and the same cache; a failing point raises as the serial path does; runs settled
side by side on the threads (seeds.settle_all) end where `settle` alone ends each, a failing one
left out; a bad `workers` is refused. The 4-blade tuned ring at 6000 rpm (EO 3, c = 298 N s/m2, Fw0 = 300 N/m,
extrapolation order 2), at a state reached from rest.

The reference is the serial path (workers = 1: one period after another on one set of instances),
not the code under test; the threaded run must have run periods on both threads.
"""

from __future__ import annotations

import threading

import numpy as np
import pytest

from harness.analysis.periodic.continuation import BranchProblem
from harness.analysis.periodic.shooting import jacobian
from harness.system.ring import Ring
from harness.system.ring_orbits.crossings import estimator
from harness.system.ring_orbits.period_map import RingMapFailed, RingPeriodMap, RingShootingSettings
from harness.system.ring_orbits.seeds import from_rest, kicked, settle, settle_all
from harness.system.ring_orbits.shooting import monodromy

SMALL = Ring(n=4, engine_order=3, fw0=300.0, blade={"c": 298.0}, order=2)
RPM = 6000.0


@pytest.fixture(scope="module")
def start() -> np.ndarray:
    with RingPeriodMap(SMALL, RingShootingSettings(workers=1)) as pm:
        return from_rest(pm, [RPM], max_periods=40, min_periods=40)[0].x


def _derivatives(pm: RingPeriodMap, x: np.ndarray) -> list[np.ndarray]:
    """Every finite-difference derivative the engine takes through `images`: the ring's monodromy
    (forward, columns skipped where a phi does not act), the single blade's jacobian (forward and
    central), the continuation's dH/dz (with the speed column) and the crossings' estimator."""
    Px = pm(x, RPM)[0]
    DP = monodromy(pm, x, RPM, Px)
    prob = BranchProblem(pm, pm.scales(x, RPM))
    prob.memo = None  # take dH/dz afresh, not from the monodromy's memo
    z = prob.to_z(x, RPM)
    Hz, P, _ = prob.H(z)
    # the complex pair nearest the circle (|mu| 0.86 here; the real multipliers sit near 0, whose
    # cluster the estimator cannot resolve)
    est = estimator(pm, DP, "Neimark-Sacker")(x * (1 + 1e-7), pm(x * (1 + 1e-7), RPM)[0], RPM)
    return [
        DP,
        jacobian(pm, x, RPM, Px),
        jacobian(pm, x, RPM, Px, central=True),
        prob.jac(z, Hz, P)[0],
        np.array([est]),
    ]


def test_threaded_derivatives_equal_the_serial_ones_bit_for_bit(start, monkeypatch):
    with RingPeriodMap(SMALL, RingShootingSettings(workers=1)) as pm:
        serial = _derivatives(pm, start)
        serial_count, serial_seen = pm.evaluations, list(pm.seen)
    threads: set[str] = set()
    period = RingPeriodMap._period

    def spy(self: RingPeriodMap, x: np.ndarray, rpm: float):  # type: ignore[no-untyped-def]
        threads.add(threading.current_thread().name)
        return period(self, x, rpm)

    monkeypatch.setattr(RingPeriodMap, "_period", spy)
    with RingPeriodMap(SMALL, RingShootingSettings(workers=2)) as pm:
        threaded = _derivatives(pm, start)
        count, seen = pm.evaluations, list(pm.seen)
    assert len(threads) == 2  # both threads ran periods
    for a, b in zip(serial, threaded):
        assert a.shape == b.shape and np.array_equal(a, b)
    assert count == serial_count
    assert seen == serial_seen  # the same images kept, in the same order
    assert np.any(serial[0] != 0.0) and np.isfinite(serial[-1][0])


def test_a_failing_point_raises_as_in_serial(start):
    """A state far outside (every displacement 1e4 times larger: the ring diverges) among good
    ones: RingMapFailed, the good points before it kept, as one call after another does."""
    x = start
    points = [(x * (1 + 1e-6 * k), RPM) for k in range(3)] + [(x * 1e4, RPM)] + [(x * 1.001, RPM)]
    kept = []
    for workers in (1, 2):
        with RingPeriodMap(SMALL, RingShootingSettings(workers=workers)) as pm:
            with pytest.raises(RingMapFailed):
                pm.images(points)
            kept.append(list(pm.seen))
            assert pm.evaluations >= 4
    assert kept[0] == kept[1] and len(kept[0]) == 3


def test_runs_settled_side_by_side_are_each_run_alone(start):
    """Four runs (from rest at two speeds, from the settled state, one that diverges) settled side by
    side on two threads, and each by `settle` on one: the same states and changes bit for bit, the
    same number of periods each (one stops on its change, the others at max_periods or min_periods),
    the diverging one None."""
    with RingPeriodMap(SMALL, RingShootingSettings(workers=2)) as pm:
        k = kicked(pm)
        runs = [(k, 5800.0), (k, 6200.0), (start, RPM), (start * 1e4, RPM)]
        both = settle_all(pm, runs, settle_tol=1e-3, max_periods=8, min_periods=3)
        threaded = pm.evaluations
    alone = []
    with RingPeriodMap(SMALL, RingShootingSettings(workers=1)) as pm:
        for x0, rpm in runs:
            try:
                alone.append(settle(pm, x0, rpm, 1e-3, 8, 3))
            except RingMapFailed:
                alone.append(None)
        # a batch that fails drops the image a thread ran past the failure: at most one period more
        assert pm.evaluations <= threaded <= pm.evaluations + 1
    assert alone[3] is None and both[3] is None
    for a, b in zip(alone[:3], both[:3]):
        assert b is not None and np.array_equal(a[0], b[0]) and a[1] == b[1]
    assert min(a[1] for a in alone[:3]) < 1e-3 < max(a[1] for a in alone[:3])  # both kinds of ending


@pytest.mark.parametrize("bad", [0, -1, 65, 1.5, True, "2"])
def test_bad_workers_refused(bad):
    with pytest.raises(ValueError) as e:
        RingPeriodMap(SMALL, RingShootingSettings(workers=bad))
    msg = str(e.value)
    assert "RingShootingSettings.workers" in msg and repr(bad) in msg and "[1, 64]" in msg
