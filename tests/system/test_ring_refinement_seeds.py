"""The ring's periodic-orbit engine seeded by a sweep's peak refinement: harness/system/ring_sweep.py
calls on_settled at the refinement's speeds too, harness/system/ring_orbits/seeds.py settled_states
turns those states into seeds, and ring_branches takes such a sweep (`sweeps`), as the mistuning
study passes its own.

The case: a 4-blade ring with EI scaled by (1.05, 0.95, 1.00, 0.97), swept up and down at 6000,
8000, 10000, 11000 and 12000 rpm, the peak located to 30 rpm. Swept up it stays on a high branch up
to a fold near 11450 rpm, where the refinement locates its peak (4.96e-5 m at 11444 rpm); at
11556 rpm the refinement lands on a third state (3.6e-5 m) that no speed of the sweep's grid
reaches (at 11000 rpm up: 4.4e-5 m, down: 6.9e-6 m). Every settled state of the refinement inside
the band 11000-11600 rpm must equal an orbit on a stable branch the engine reports, and the
engine's largest stable state must not be below the sweep's located peak. Without the refinement's
states among the seeds the 3.6e-5 m branch is not found and the test fails.

Tolerance: a refinement state equals an orbit when the per-blade amplitudes (relative to the
largest) are within SAME_BRANCH = 2e-4: measured 6e-6..4.2e-5 from the nearest stable orbit (on the
load-aligned grid the sweep runs on), 0.12 or more from any other branch crossing the speed; the
settle rule's own bound, 1e-4 mu / (1 - mu) + 1e-4 = 1.3e-3 at mu = 0.92, is looser. The engine's
largest stable state is at least the sweep's located peak less 1e-4 (the sweep's measure against
the period map's).
"""

from __future__ import annotations

import numpy as np
import pytest

from harness.studies.mistuning import mistuned
from harness.system.ring import Ring
from harness.system.ring_orbits.branches import crossings, ring_branches
from harness.system.ring_orbits.period_map import RingPeriodMap
from harness.system.ring_orbits.seeds import SweepPath
from harness.system.ring_orbits.symmetry import distance, index_maps
from harness.system.ring_sweep import sweep

RING = mistuned(Ring(n=4, engine_order=3, fw0=300.0, blade={"c": 298.0}, order=2), "EI", (1.05, 0.95, 1.0, 0.97))
SPEEDS = (6000.0, 8000.0, 10000.0, 11000.0, 12000.0)
BAND = (11000.0, 11600.0)
SPEED_TOL = 30.0
SETTLE_RTOL = 1e-4  # the sweep's settle rule
MEASURE_RTOL = 1e-4  # the sweep's amplitude measure against the period map's orbit
SAME_BRANCH = 2e-4  # measured 6e-6..4.2e-5 to the nearest stable orbit, >= 0.12 to any other branch


def test_refinement_states_are_seeds_and_on_the_branches():
    path = SweepPath(SPEEDS, rtol=SETTLE_RTOL, refine=True, speed_tol=SPEED_TOL)
    r = ring_branches(RING, BAND, points=2, sweep_speeds=(), sweeps=(path,), seed_kinds=("C-loop sweep",))
    sw = sweep(RING, SPEEDS, "both", rtol=SETTLE_RTOL, speed_tol=SPEED_TOL)
    grid = set(SPEEDS)
    refined = [e for e in sw.refinement if e["settled"] and BAND[0] <= e["speed_rpm"] <= BAND[1]]
    # the case is what the docstring says: a located peak off the grid, and a state off both branches the grid reaches
    assert sw.peak_speed_rpm not in grid and BAND[0] < sw.peak_speed_rpm < BAND[1], sw.peak_speed_rpm
    assert any(
        max(e["amplitudes_m"]) < 0.9 * sw.amplitudes_m["up"][3].max()
        and max(e["amplitudes_m"]) > 2 * sw.amplitudes_m["down"][3].max()
        for e in refined
    )
    maps = index_maps(RING)
    with RingPeriodMap(RING) as pm:
        for e in refined:
            s, a = float(e["speed_rpm"]), np.asarray(e["amplitudes_m"])
            found = [(distance(o, a, maps), mu) for o, mu in crossings(pm, r.branches, s) if mu < 1]
            assert found, (s, max(a), "no stable orbit crosses this speed")
            dist, mu = min(found)
            assert dist <= SAME_BRANCH, (s, max(a), dist, mu)
    assert r.peak_stable_amplitude >= sw.peak_amplitude_m * (1 - MEASURE_RTOL), (
        r.peak_stable_amplitude,
        sw.peak_amplitude_m,
    )


def test_seeds_past_the_branch_cap_still_count():
    """With one branch allowed (max_branches = 1) every refinement state is still on that branch or
    equal to a stable untraced orbit at its speed (Newton from the seed, not continued), at least one
    of them only there, and the largest stable state is still at least the sweep's located peak.
    Stopping at the cap (the seeds past it never shot) loses the states off the first branch and fails."""
    path = SweepPath(SPEEDS, rtol=SETTLE_RTOL, refine=True, speed_tol=SPEED_TOL)
    r = ring_branches(
        RING, BAND, points=2, sweep_speeds=(), sweeps=(path,), seed_kinds=("C-loop sweep",), max_branches=1
    )
    assert len(r.branches) == 1
    sw = sweep(RING, SPEEDS, "both", rtol=SETTLE_RTOL, speed_tol=SPEED_TOL)
    refined = [e for e in sw.refinement if e["settled"] and BAND[0] <= e["speed_rpm"] <= BAND[1]]
    maps = index_maps(RING)
    only_untraced = 0
    with RingPeriodMap(RING) as pm:
        for e in refined:
            s, a = float(e["speed_rpm"]), np.asarray(e["amplitudes_m"])
            on_branch = [distance(o, a, maps) for o, mu in crossings(pm, r.branches, s) if mu < 1]
            untraced = [
                distance(o.amplitudes, a, maps) for _, o in r.untraced if o.stable and abs(o.speed - s) <= 1e-6 * s
            ]
            assert min(on_branch + untraced, default=np.inf) <= SAME_BRANCH, (s, max(a), on_branch, untraced)
            only_untraced += min(on_branch, default=np.inf) > SAME_BRANCH
    assert only_untraced > 0, "the case must put a state off the one traced branch"
    assert r.peak_stable_amplitude >= sw.peak_amplitude_m * (1 - MEASURE_RTOL)


def test_a_bad_branch_bound_is_refused_before_any_work():
    with pytest.raises(ValueError, match=r"max_branches = 0: need a whole number >= 1"):
        ring_branches(RING, BAND, max_branches=0)


def test_a_bad_switch_bound_is_refused_before_any_work():
    with pytest.raises(ValueError, match=r"max_switches = -1: need None \(every branch point\) or a whole number >= 0"):
        ring_branches(RING, BAND, max_switches=-1)
