"""The ring engine's branches hold every stable steady state the co-simulation settles on from rest
and from random starts (harness/validation/ring_completeness.py), on a small band of the tuned
6-blade study ring where the runs settle (near 5800 rpm they do not: no periodic steady state).
About 13 s (the engine over the band included), so among the default tests; dropping the branch
the first matched orbit lies on makes it fail."""

from __future__ import annotations

from harness.system.ring_orbits.branches import SEED_KINDS, ring_branches
from harness.validation.ring_completeness import collect, compare, engine_branches, from_result, study_ring

BAND = (6400.0, 6600.0)  # [rpm]
SPEEDS = (6400.0, 6500.0, 6600.0)


def test_every_settled_stable_orbit_lies_on_the_engines_branches():
    ring = study_ring(6)
    branches, xs, _ = engine_branches(ring, BAND)
    runs, _ = collect(ring, SPEEDS, random=2, seed=1)
    compare(ring, runs, branches, xs)
    stable = [s for s in runs if s.polished and s.stable]
    assert len(stable) >= 6, [(s.speed, s.start, s.residual) for s in runs]  # the check compared something
    missed = [(s.speed, s.start, s.amplitudes.tolist(), s.distance, s.tolerance) for s in stable if not s.on_branch]
    assert not missed


def test_random_starts_reach_the_family_rest_and_sweeps_miss():
    """Over 6800-7100 rpm the tuned ring has a stable family of asymmetric states (6720-7285 rpm) that
    neither rest nor a sweep reaches: the check's random starts (its own generator) settle on it at
    6950 and 7050 rpm. The engine finds it with its random starts, and without them it does not (so
    the second half fails if random starts stop reaching it). About 14 s."""
    ring = study_ring(6)
    band = (6800.0, 7100.0)
    runs, _ = collect(ring, (6850.0, 6950.0, 7050.0), random=3, seed=1)
    stable = [s for s in runs if s.polished and s.stable]
    assert len(stable) >= 10, [(s.speed, s.start, s.residual) for s in runs]

    def missed(kinds: tuple[str, ...]) -> list:
        brs, xs, _ = from_result(ring_branches(ring, band, seed_kinds=kinds), 0.0)
        compare(ring, runs, brs, xs)
        return [(s.speed, s.start, float(s.amplitudes.max()), s.distance) for s in stable if not s.on_branch]

    without = missed(tuple(k for k in SEED_KINDS if k != "random"))
    assert without and all(d > 0.1 for *_, d in without), without  # the family: > 10 % from any traced branch
    assert not missed(SEED_KINDS)


def test_a_pattern_ring_is_the_studys():
    """--pattern 0.05 0: blade i's EI is the tuned EI times 1 + 0.05 z_i, z from the study's generator
    (seed 1, pattern 0), computed here."""
    import numpy as np

    from harness.studies.mistuning import blade_value

    tuned = study_ring(6)
    ring = study_ring(6, (0.05, 0))
    z = np.random.default_rng([1, 0]).standard_normal(6)
    got = np.array([b["EI"] for b in ring.blade_each])
    assert np.allclose(got, blade_value(tuned, "EI") * (1 + 0.05 * z), rtol=1e-15, atol=0)


def test_the_step_reaches_the_engine_and_keys_its_cache(tmp_path, monkeypatch):
    """--steps-per-period K: the engine runs at h = T / K, and its cached branches are read back only
    at the K they were computed at (a cache of another step is computed again, not reused)."""
    from types import SimpleNamespace

    import harness.validation.ring_completeness as rc

    asked: list[int] = []

    def fake_engine(ring, band, settings):
        asked.append(settings.steps_per_period)
        return SimpleNamespace(branches=[], untraced=[], evaluations=0, wall_time=0.0, points=0)

    monkeypatch.setattr(rc, "ring_branches", fake_engine)
    ring, cache = study_ring(6), tmp_path / "b.npz"
    for k in (160, 160, 320, 320, 160):
        rc.engine_branches(ring, BAND, cache, k)
    assert asked == [160, 320, 160]
