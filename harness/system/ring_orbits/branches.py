"""All the branches of the ring's periodic orbits over a speed band, from every seed, and the largest
stable steady state among them.

Seeds (harness/system/ring_orbits/seeds.py): the travelling wave (tuned ring), a run from rest at
each grid speed, a sweep of the period map up and back down the grid, random starts at speeds at most
RANDOM_SPACING apart, and every state where a C-loop
sweep up and back down (harness/system/ring_sweep.py, the sweeps' own path and settle rule) leaves a
speed, at most SWEEP_SPACING apart (and of any further C-loop sweep given, its peak's refinement
included: a study passes its own sweep, whose located peak is then a seed): the states the sweeps
report are then on the traced branches. The given sweeps' states come first, then the others, the
largest first. A seed whose state already lies on a traced branch (up to the ring's symmetries,
symmetry.py, by the per-blade amplitudes) is dropped; otherwise Newton finds its orbit, which is
dropped if it lies on a traced branch, else continued both ways across the band (continuation.py)
until it leaves the band or runs onto a branch traced before. Once `max_branches` are traced, every
remaining seed still gets its Newton and multipliers: an orbit on no traced branch is kept
(`untraced`, not continued) and counts in the largest stable steady state, so no seed goes untried.
At every branch point next to a stable point (where a stable branch can emanate; all of them
unless `max_switches` bounds their number) the other branch is entered along the critical eigenvector
(continuation.switch) and traced too. The largest stable steady state: the largest blade amplitude
over the stable points, the located peaks that are stable, and the stability boundaries (a fold
bounding a stable part, a branch point, period doubling or Neimark-Sacker point next to a stable
point), and the stable untraced orbits.
"""

from __future__ import annotations

import math
import time
from dataclasses import dataclass, field
from typing import Sequence

import numpy as np

from harness.analysis.periodic.shooting import newton
from harness.system.ring import Ring
from harness.system.ring_orbits.continuation import RingBranch, switch, trace
from harness.system.ring_orbits.period_map import RingPeriodMap, RingShootingSettings
from harness.system.ring_orbits.seeds import (
    Seed,
    SweepPath,
    from_rest,
    random_starts,
    settled_states,
    sweep,
    travelling_wave,
)
from harness.system.ring_orbits.shooting import RingOrbit, shoot
from harness.system.ring_orbits.symmetry import distance, index_maps, tuned

SAME_RTOL = 1e-3  # two orbits are the same (up to symmetry): per-blade amplitudes within this of the largest


@dataclass
class RingBranches:
    """What ring_branches found."""

    branches: list[RingBranch]
    band: tuple[float, float]
    peak_stable_amplitude: float  # [m] (nan if no stable orbit)
    peak_stable_speed: float  # [rpm]
    peak_stable_blade: int
    seeds: int  # seeds tried
    evaluations: int  # period-map evaluations (periods of the ring simulated)
    wall_time: float  # [s]
    points: int = 0  # continuation points over all branches
    stats: dict = field(default_factory=dict)
    # orbits Newton found from seeds (or at branch points) once max_branches were traced, on none of
    # them: not continued, but counted in the largest stable steady state
    untraced: list[tuple[str, RingOrbit]] = field(default_factory=list)
    seeds_shot: int = 0  # seeds Newton was run from (the others lay on a traced branch or untraced orbit)

    def as_dict(self) -> dict:
        nan = math.isnan(self.peak_stable_amplitude)
        return {
            "band_rpm": list(self.band),
            "branches": [b.as_dict() for b in self.branches],
            "peak_stable_amplitude_m": None if nan else self.peak_stable_amplitude,
            "peak_stable_speed_rpm": None if nan else self.peak_stable_speed,
            "peak_stable_blade": None if nan else self.peak_stable_blade,
            "peak_stable_at_band_edge": (not nan) and self.peak_stable_speed in self.band,
            "seeds": self.seeds,
            "seeds_shot": self.seeds_shot,
            # the largest stable state is an untraced orbit: a sampled point, its branch not continued
            "peak_stable_untraced": any(
                o.stable and o.amplitude == self.peak_stable_amplitude for _, o in self.untraced
            ),
            "untraced_orbits": [{"origin": o, **orb.as_dict()} for o, orb in self.untraced],
            "evaluations": self.evaluations,
            "continuation_points": self.points,
            "periods_per_point": self.evaluations / max(self.points, 1),
            "wall_time_s": self.wall_time,
            **self.stats,
        }


def on_branch(br: RingBranch, speed: float, amps: np.ndarray, maps: list[np.ndarray], rtol: float) -> bool:
    """True if (speed, per-blade amplitudes) lies on br up to a symmetry: between two neighbouring
    points in speed, within rtol of the interpolated amplitudes (plus half their difference)."""
    S, A = br.speeds, br.amplitudes
    for k in range(len(S) - 1):
        lo, hi = min(S[k], S[k + 1]), max(S[k], S[k + 1])
        if not lo - 1e-9 <= speed <= hi + 1e-9:
            continue
        f = 0.0 if hi == lo else (speed - S[k]) / (S[k + 1] - S[k])
        a = A[k] + f * (A[k + 1] - A[k])
        slack = 0.5 * float(np.max(np.abs(A[k + 1] - A[k]))) / max(float(np.max(a)), 1e-300)
        if distance(a, amps, maps) <= rtol + slack:
            return True
    return any(abs(s - speed) <= 1e-6 * speed and distance(a, amps, maps) <= rtol for s, a in zip(S, A))


def known(branches: list[RingBranch], speed: float, amps: np.ndarray, maps: list[np.ndarray], rtol: float) -> bool:
    return any(on_branch(b, speed, amps, maps, rtol) for b in branches)


def merged(branches: list[RingBranch], maps: list[np.ndarray]) -> list[RingBranch]:
    """The branches without those whose every point lies on another kept branch (up to the ring's
    symmetries): a branch entered twice, from two seeds or from a branch point. Longest first."""
    kept: list[RingBranch] = []
    for br in sorted(branches, key=lambda b: -len(b.orbits)):
        if not all(known(kept, o.speed, o.amplitudes, maps, SAME_RTOL) for o in br.orbits):
            kept.append(br)
    return kept


def in_band(branches: list[RingBranch], band: tuple[float, float]) -> list[RingBranch]:
    """The branches with a point inside the band (a corrector from a branch point may land outside)."""
    return [b for b in branches if any(band[0] <= o.speed <= band[1] for o in b.orbits)]


def peak_stable(
    branches: list[RingBranch], band: tuple[float, float], untraced: Sequence[RingOrbit] = ()
) -> tuple[float, float, int]:
    """(amplitude [m], speed [rpm], blade) of the largest stable steady state in the band (see the
    module docstring), the stable `untraced` orbits counted too; nan, nan, -1 if none."""
    cands: list[tuple[float, float, np.ndarray]] = [(o.amplitude, o.speed, o.amplitudes) for o in untraced if o.stable]
    for br in branches:
        cands += [(o.amplitude, o.speed, o.amplitudes) for o in br.orbits if o.stable]
        cands += [(o.amplitude, o.speed, o.amplitudes) for o in br.peaks if o.stable]
        cands += [(o.amplitude, o.speed, o.amplitudes) for o, ok in zip(br.folds, br.fold_sides) if ok]
        st = br.stable
        for b in br.bifurcations:
            if b.kind != "fold" and 0 < b.index < len(st) and (st[b.index - 1] or st[b.index]):
                cands.append((b.amplitude, b.speed, b.amplitudes))
    cands = [c for c in cands if band[0] <= c[1] <= band[1]]
    if not cands:
        return math.nan, math.nan, -1
    a, s, amps = max(cands, key=lambda c: c[0])
    return float(a), float(s), int(np.argmax(amps))


SEED_SPACING = 300.0  # [rpm] between seed speeds by default: 6 seeds over 4000-9000 rpm missed the study
# ring's largest stable state (a run from rest near 5800 rpm reaches its branch; from 5000 or 6000 none does)


# a safety bound, not a budget: the 2 % ring of the mistuning study has 75 branches over its band; cut at
# 24, its largest stable state (5.0210e-5 m at 5795.5 rpm, on the branch of a seed the cut left untried) was missed
MAX_BRANCHES = 200


SWEEP_SPACING = 100.0  # [rpm] between the C-loop sweep's speeds by default (the spacing a sweep is run at)
# [rpm] between the random starts' speeds: at 300 rpm (3 per speed) the tuned study ring's stable family at
# 6760-7240 rpm was reached in one draw and not in another (docs/findings/ring-completeness.md)
RANDOM_SPACING = 100.0
SEED_KINDS = ("travelling wave", "rest", "map sweep", "C-loop sweep", "random")


def default_seed_points(band: tuple[float, float], spacing: float = SEED_SPACING) -> int:
    """Seed speeds across the band at most `spacing` apart, at least 4."""
    return max(4, math.ceil((band[1] - band[0]) / spacing) + 1)


def ring_branches(
    ring: Ring,
    band: tuple[float, float],
    points: int | None = None,
    settings: RingShootingSettings = RingShootingSettings(),
    switch_branches: bool = True,
    max_branches: int = MAX_BRANCHES,
    settle: float = 1e-3,
    max_periods: int = 300,
    max_switches: int | None = None,
    sweep_speeds: Sequence[float] | None = None,
    seed_kinds: Sequence[str] = SEED_KINDS,
    sweeps: Sequence[SweepPath] = (),
) -> RingBranches:
    """Every branch found from the seeds at `points` speeds across `band` [rpm] (default: at most
    SEED_SPACING apart), a C-loop sweep at `sweep_speeds` (default: across the band at most
    SWEEP_SPACING apart; none if empty) and the C-loop sweeps `sweeps` (e.g. a study's own, with its peak's
    refinement: their states inside the band); only the seeds of `seed_kinds` (see the module docstring). Raises ValueError on a
    bad band, count or kind."""
    lo, hi = (float(v) for v in band)
    if points is None:
        points = default_seed_points((lo, hi))
    if not (math.isfinite(lo) and math.isfinite(hi) and 0.0 < lo < hi):
        raise ValueError(f"band {band!r} rpm: need 0 < FROM < TO")
    if not (isinstance(points, int) and 2 <= points <= 1000):
        raise ValueError(f"points = {points!r}: need a whole number in [2, 1000]")
    if not (isinstance(max_branches, int) and max_branches >= 1):
        raise ValueError(f"max_branches = {max_branches!r}: need a whole number >= 1")
    if not (max_switches is None or (isinstance(max_switches, int) and max_switches >= 0)):
        raise ValueError(f"max_switches = {max_switches!r}: need None (every branch point) or a whole number >= 0")
    bad = [k for k in seed_kinds if k not in SEED_KINDS]
    if bad or not seed_kinds:
        raise ValueError(f"seed_kinds {list(seed_kinds)!r}: need some of {', '.join(SEED_KINDS)}")
    if sweep_speeds is None:
        sweep_speeds = np.linspace(lo, hi, default_seed_points((lo, hi), SWEEP_SPACING))
    own_sweep = "C-loop sweep" in seed_kinds and len(sweep_speeds) > 0  # none: only the given `sweeps`
    t0 = time.perf_counter()
    grid = np.linspace(lo, hi, points)
    random_grid = np.linspace(lo, hi, default_seed_points((lo, hi), RANDOM_SPACING))
    branches: list[RingBranch] = []
    maps = index_maps(ring)
    symmetric = tuned(ring)
    with RingPeriodMap(ring, settings) as pm:
        given = [
            sd
            for path in sweeps
            if "C-loop sweep" in seed_kinds
            for sd in settled_states(pm, ring, path)
            if lo <= sd.speed <= hi
        ]
        own = (
            (travelling_wave(pm, grid, settle, max_periods) if symmetric and "travelling wave" in seed_kinds else [])
            + (from_rest(pm, grid, settle, max_periods) if "rest" in seed_kinds else [])
            + (sweep(pm, grid, settle, max_periods) if "map sweep" in seed_kinds else [])
            + (settled_states(pm, ring, SweepPath(tuple(sweep_speeds))) if own_sweep else [])
        )

        def largest(sd: Seed) -> float:
            return float(pm.measures(sd.x, sd.speed)[0].max())

        if "random" in seed_kinds:  # on the scale of the largest response the other seeds reached
            scale = max(map(largest, given + own), default=0.0)
            own += random_starts(pm, random_grid, scale, settle, max_periods) if scale > 0.0 else []
        # the given sweeps' states first (max_branches must not cut off a study's located peak), then
        # the largest first: should max_branches be reached, the branches traced are those of the largest seeds
        seeds = given + sorted(own, key=lambda sd: -largest(sd))
        e_seeds = pm.evaluations
        todo: list = []  # orbits to continue (from seeds, then from branch points)
        untraced: list[tuple[str, RingOrbit]] = []  # orbits found once max_branches were traced
        switches, switch_cost, shot = 0, 0, 0
        sweep_orbits: list[dict] = []  # per C-loop sweep state: its Newton orbit
        stage: dict[str, int] = {}  # periods per stage of tracing (every branch traced, kept or merged away)

        def seen(speed: float, amps: np.ndarray, rtol: float) -> bool:
            """On a traced branch, or an untraced orbit at this speed (up to the ring's symmetries)."""
            return known(branches, speed, amps, maps, rtol) or any(
                abs(o.speed - speed) <= 1e-6 * speed and distance(o.amplitudes, amps, maps) <= rtol for _, o in untraced
            )

        for sd in seeds:
            swept = sd.origin.startswith("C-loop sweep")
            amps = pm.measures(sd.x, sd.speed)[0]
            # a sweep's state always gets its Newton: the orbit it reports must be on a branch; a
            # refinement's (many, near each other) only off the traced branches (settled: within SAME_RTOL)
            rtol = SAME_RTOL if sd.origin.startswith("C-loop") else min(max(SAME_RTOL, 10 * sd.change), 2e-2)
            if not swept and seen(sd.speed, amps, rtol):
                continue
            shot += 1
            # a sweep's orbit is reported with its multipliers; any other is skipped if known, before its DP
            orb = shoot(pm, sd.x, sd.speed, skip=None if swept else lambda n, a: seen(n, a, SAME_RTOL))
            if swept:
                sweep_orbits.append(
                    {
                        "origin": sd.origin,
                        "speed_rpm": sd.speed,
                        "seed_amplitudes_m": amps.tolist(),
                        "seed_residual": sd.change,
                        "orbit": None
                        if orb is None
                        else {k: orb.as_dict()[k] for k in ("amplitudes_m", "max_multiplier", "period_residual")},
                    }
                )
            if orb is None or seen(orb.speed, orb.amplitudes, SAME_RTOL):
                continue
            todo.append((orb, f"{sd.origin} at {sd.speed:.1f} rpm"))
            while todo:
                o, origin = todo.pop(0)
                if seen(o.speed, o.amplitudes, SAME_RTOL):
                    continue
                if len(branches) >= max_branches:  # every seed still gets its Newton: the orbit counts
                    untraced.append((origin, o))
                    continue
                done = list(branches)
                br = trace(pm, o, (lo, hi), joined=lambda n, a: known(done, n, a, maps, SAME_RTOL))
                br.origin = origin
                for k, v in br.cost.items():
                    stage[k] = stage.get(k, 0) + v
                branches.append(br)
                if switch_branches:
                    st = br.stable
                    for b in br.bifurcations:
                        # the branch points that bound a stable part: where stable branches emanate
                        if b.kind != "branch point" or switches == max_switches or not (st[b.index - 1] or st[b.index]):
                            continue
                        switches += 1
                        e_sw = pm.evaluations
                        guesses = switch(pm, br, b)
                        switch_cost += pm.evaluations - e_sw
                        for guess in guesses:
                            if known(branches, guess.speed, guess.amplitudes, maps, SAME_RTOL):
                                continue
                            new = shoot(pm, guess.x, guess.speed, skip=lambda n, a: seen(n, a, SAME_RTOL))
                            if new is not None:
                                todo.append((new, f"branch point at {b.speed:.1f} rpm"))
        branches = merged(in_band(branches, (lo, hi)), maps)
        untraced = [(o, orb) for o, orb in untraced if lo <= orb.speed <= hi]
        amp, speed, blade = peak_stable(branches, (lo, hi), [orb for _, orb in untraced])
        npts = sum(len(b.orbits) for b in branches)
        return RingBranches(
            branches,
            (lo, hi),
            amp,
            speed,
            blade,
            len(seeds),
            pm.evaluations,
            time.perf_counter() - t0,
            npts,
            {
                "seed_evaluations": e_seeds,
                "sweep_orbits": sweep_orbits,
                "steps_per_period": settings.steps_per_period,
                # the low-rank DPs: how many passed their check, took the acting unknowns, fell back
                # (none with the full differences: the study's records as they were)
                **({"dp": {"mode": settings.dp, **pm.low_rank.summary()}} if pm.low_rank is not None else {}),
                "evaluations_by_stage": {
                    "seeds": e_seeds,
                    **stage,
                    "switching": switch_cost,
                    # Newton (with the multipliers) from every seed and switched-to guess
                    "shooting": pm.evaluations - e_seeds - sum(stage.values()) - switch_cost,
                },
            },
            untraced,
            shot,
        )


def crossings(pm: RingPeriodMap, branches: list[RingBranch], speed: float) -> list[tuple[np.ndarray, float]]:
    """(per-blade amplitudes [m], largest |multiplier| of the two points around it) of every orbit
    where a branch crosses `speed`: Newton at that speed from the state interpolated between the two
    points around it."""
    out = []
    for br in branches:
        S = br.speeds
        for k in range(len(S) - 1):
            if (S[k] - speed) * (S[k + 1] - speed) > 0 or S[k] == S[k + 1]:
                continue
            a, b = br.orbits[k], br.orbits[k + 1]
            f = (speed - S[k]) / (S[k + 1] - S[k])
            sol = newton(pm, a.x + f * (b.x - a.x), speed)
            if sol is not None:
                out.append((pm.measures(sol.x, speed)[0].copy(), max(a.max_multiplier, b.max_multiplier)))
    return out
