"""The completeness check's comparison (harness/validation/branch_match.py) on synthetic branches
whose amplitudes are known in closed form: a state on a stable branch (between its points, on a
rotated or reflected copy) is accepted, one off it or on an unstable part is flagged."""

from __future__ import annotations

import numpy as np

from harness.system.ring import Ring
from harness.system.ring_orbits.symmetry import index_maps
from harness.validation.branch_match import RTOL, Branch, interpolation_error, match

MAPS = index_maps(Ring(n=6, engine_order=3))  # 6 rotations and 6 reflections (2 EO = 0 mod N)


def exact(s: np.ndarray | float) -> np.ndarray:
    """Per-blade amplitudes [m] of the synthetic branch at speed s [rpm]: smooth, distinct blades."""
    x = (np.atleast_1d(s)[:, None] - 6000.0) / 500.0
    return 3e-5 * (1.0 + 0.3 * np.arange(6) / 6 + 0.4 * x**2 - 0.1 * x**3)


def branch(stable: bool = True) -> Branch:
    S = np.linspace(5500.0, 6500.0, 21)  # 50 rpm apart, as the engine's continuation points roughly are
    return Branch(S, exact(S), np.full(len(S), stable))


def test_a_state_between_points_is_on_the_branch_and_the_tolerance_bounds_the_line_error():
    br = branch()
    for s in (5512.3, 5777.7, 6020.0, 6333.3, 6499.0):
        a = exact(s)[0]
        m = match([br], s, a, MAPS)
        assert m.on and m.branch == 0, (s, m)
        # the true error of the line between the points is within the estimate's factor 2 (the tolerance's)
        k = int(np.searchsorted(br.speeds, s)) - 1
        line = br.amplitudes[k] + (s - br.speeds[k]) / 50.0 * (br.amplitudes[k + 1] - br.amplitudes[k])
        assert np.max(np.abs(line - a)) <= 2 * interpolation_error(br.speeds, br.amplitudes, k, s) + 1e-18


def test_a_rotated_or_reflected_copy_is_on_the_branch():
    s = 5871.0
    a = exact(s)[0]
    for g in (np.roll(np.arange(6), 2), (3 - np.arange(6)) % 6):
        assert match([branch()], s, a[g], MAPS).on


def test_a_state_off_the_branch_is_flagged():
    s = 5871.0
    a = exact(s)[0]
    for bad in (
        a * (1 + 5 * RTOL),
        a + np.array([0, 0, 0, 1e-6, 0, 0]),
        a[[1, 0, 2, 3, 4, 5]],
    ):  # 0.5 % off, a blade 1e-6 m off, two blades swapped (no symmetry)
        m = match([branch()], s, bad, MAPS)
        assert not m.on and m.distance > m.tolerance, m


def test_on_an_unstable_part_or_outside_the_branch_is_not_on_it():
    s = 5871.0
    a = exact(s)[0]
    m = match([branch(stable=False)], s, a, MAPS)
    assert not m.on and m.distance == np.inf and m.distance_any < RTOL
    assert not match([branch()], 7000.0, exact(7000.0)[0], MAPS).on


def test_a_second_branch_is_searched_and_a_fold_does_not_hide_a_point():
    # a branch turning at 6000 rpm (a fold): the upper half runs back down in speed
    S = np.concatenate([np.linspace(5500.0, 6000.0, 11), np.linspace(5950.0, 5500.0, 10)])
    A = np.vstack([exact(S[:11]), 1.5 * exact(S[11:])])
    fold = Branch(S, A, np.ones(len(S), dtype=bool))
    s = 5725.0
    assert match([branch(stable=False), fold], s, 1.5 * exact(s)[0], MAPS).branch == 1
    assert match([branch(stable=False), fold], s, exact(s)[0], MAPS).on
    assert not match([fold], s, 1.2 * exact(s)[0], MAPS).on
