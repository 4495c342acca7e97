"""An independent check that the ring's periodic-orbit engine misses no stable steady state: run
the co-simulation to a steady state from many starts, outside the engine's continuation, and look
for every settled orbit on the engine's branches.

Starts, at every speed of a grid across the band: rest with blade 0 kicked by KICK (an exact rest
keeps the tuned ring on its travelling wave, stable or not), and `random` random states per speed:
the engine's random start (ring_orbits.seeds.random_state: blade i displaced by a_i cos(phi_i) with
velocity -a_i omega sin(phi_i), the contacts' forces and the master's history zero), a_i uniform in
AMPLITUDES x SCALE (the tuned study ring's response is about 5e-5 m), phi_i uniform in [0, 2 pi), drawn
from numpy's default_rng([seed, round(100 rpm)]) (a speed's starts do not depend on the grid; the
engine draws its own from another seed). Each
run is the period map iterated at fixed speed, x <- P(x) (the co-simulation run period by period),
until its scaled period residual max |P(x) - x| / scale is below `settle` (or `max_periods`: not
settled, reported, not polished), then polished by the engine's Newton (ring_orbits.shooting.shoot)
to a periodic orbit with its Floquet multipliers. A run reached its state by time integration, so
the orbit should be stable; one that is not is reported.

Every settled stable orbit is compared with the engine's branches over the band (ring_branches with
its default settings, harness/validation/branch_match.py: per-blade amplitudes, up to the ring's
symmetries, on a stable segment). One that is not within the tolerance gets a second opinion: the
engine's Newton at that speed from the state interpolated on each branch segment that covers the
speed (branches.crossings); if an orbit found so equals it within NEWTON_RTOL and lies within
NEWTON_NEAR of the segment, it counts as on that branch (the line between points was too coarse).
What is left is a stable steady state the engine did not find.
"""

from __future__ import annotations

import json
import math
import time
from concurrent.futures import ProcessPoolExecutor
from dataclasses import asdict, dataclass
from pathlib import Path
from typing import Any, Callable, Sequence

import numpy as np

from harness.analysis.periodic.shooting import newton
from harness.files.atomic import atomic_write_text
from harness.studies.mistuning import Study, factors, mistuned, tuned_ring
from harness.system.engine_identity import ring_engine_digest
from harness.system.ring import Ring
from harness.system.ring_orbits.branches import RingBranches, ring_branches
from harness.system.ring_orbits.period_map import RingMapFailed, RingPeriodMap, RingShootingSettings
from harness.system.ring_orbits.seeds import random_state
from harness.system.ring_orbits.shooting import shoot
from harness.system.ring_orbits.symmetry import index_maps
from harness.validation.branch_match import Branch, match, sym_distance

BAND = (5000.0, 7500.0)  # [rpm]
SPACING = 10.0  # [rpm] between the grid's speeds
RANDOM = 3  # random starts per speed
SEED = 1
SCALE = 5e-5  # [m] the order of the tuned study ring's response
AMPLITUDES = (0.2, 1.5)  # random start amplitudes, multiples of SCALE
KICK = 1e-9  # [m] blade 0's start displacement in the run from rest
SETTLE = 1e-6  # settled: scaled period residual below this
MAX_PERIODS = 1500
STEPS = 160  # communication steps per period: the study's h = T / 160 (a finer h shows what the step makes)
WINDOW = 100  # periods over which an unsettled run's range of amplitudes is reported
NEWTON_RTOL = 1e-5  # the second opinion's orbit is this one (both Newton-converged: about 1e-8 apart)
NEWTON_NEAR = 5e-2  # ... and stayed near the segment it started from


def study_ring(n: int = 6, pattern: tuple[float, int] | None = None) -> Ring:
    """The mistuning study's tuned ring with friction (harness/studies/mistuning.py), or with its blade
    stiffness pattern (sigma, index): EI of blade i times factors(n, sigma, the study's seed, index)."""
    study = Study(n=n)
    ring = tuned_ring(study, "friction")
    if pattern is None:
        return ring
    sigma, index = pattern
    return mistuned(ring, study.parameter, factors(n, sigma, study.seed, index))


@dataclass
class Settled:
    """One run to a steady state and its polished orbit."""

    speed: float  # [rpm]
    start: str  # "rest" or "random k"
    periods: int  # periods run to settle
    residual: float  # scaled period residual when the run stopped
    settled: bool
    amplitudes: np.ndarray  # per blade [m]: the polished orbit's, else the run's last period
    spread: tuple[float, float]  # the largest blade's max |q| over the run's last WINDOW periods: (min, max) [m]
    polished: bool = False  # Newton converged
    period_residual: float = math.nan  # the orbit's
    max_multiplier: float = math.nan
    stable: bool = False
    on_branch: bool | None = None  # None: not compared (not a settled stable orbit)
    distance: float = math.nan  # to the nearest stable segment, relative
    tolerance: float = math.nan
    branch: int = -1
    newton_on_branch: bool = False  # on a branch by the second opinion only


def rest_state(pm: RingPeriodMap) -> np.ndarray:
    x = np.zeros(pm.dim)
    x[0] = KICK
    return x


def run_to_steady(
    pm: RingPeriodMap, x: np.ndarray, speed: float, settle: float, max_periods: int
) -> tuple[np.ndarray, float, int, tuple[float, float]]:
    """x <- P(x) at `speed` until the scaled period residual is below `settle`: (x, residual,
    periods, the range of the largest blade's max |q| [m] over the last WINDOW periods run)."""
    res = math.inf
    largest: list[float] = []
    for k in range(1, max_periods + 1):
        Px, amp = pm(x, speed)
        largest = (largest + [amp])[-WINDOW:]
        res = float(np.max(np.abs(Px - x) / pm.scales(x, speed)))
        if res < settle:
            break  # x: its residual is the one measured
        x = Px
    return x, res, k, (min(largest), max(largest))


def starts(pm: RingPeriodMap, speed: float, random: int, seed: int) -> list[tuple[str, np.ndarray]]:
    rng = np.random.default_rng([seed, round(100 * speed)])
    return [("rest", rest_state(pm))] + [
        (f"random {k}", random_state(pm, speed, rng, SCALE, AMPLITUDES)) for k in range(random)
    ]


def collect(
    ring: Ring,
    speeds: Sequence[float],
    random: int = RANDOM,
    seed: int = SEED,
    settle: float = SETTLE,
    max_periods: int = MAX_PERIODS,
    jobs: int = 1,
    progress: Callable[[Settled], None] | None = None,
    steps: int = STEPS,
) -> tuple[list[Settled], dict[str, Any]]:
    """Every start's run and polished orbit, in speed order, and the cost (periods run settling and
    polishing, CPU s summed over the processes); on `jobs` processes, every jobs-th speed each (a
    speed's starts do not depend on which process runs it; `progress` only with one)."""
    if jobs <= 1:
        return _collect(ring, speeds, random, seed, settle, max_periods, progress, steps)
    parts = [
        (ring, [float(v) for v in speeds[j::jobs]], random, seed, settle, max_periods, None, steps) for j in range(jobs)
    ]
    with ProcessPoolExecutor(max_workers=jobs) as ex:
        done = list(ex.map(_collect_part, parts))
    runs = sorted((s for r, _ in done for s in r), key=lambda s: s.speed)  # stable: a speed's starts in order
    return runs, {k: sum(c[k] for _, c in done) for k in done[0][1]}


def _collect_part(job: tuple[Any, ...]) -> tuple[list[Settled], dict[str, Any]]:
    return _collect(*job)


def _collect(
    ring: Ring,
    speeds: Sequence[float],
    random: int,
    seed: int,
    settle: float,
    max_periods: int,
    progress: Callable[[Settled], None] | None,
    steps: int,
) -> tuple[list[Settled], dict[str, Any]]:
    out: list[Settled] = []
    cost: dict[str, Any] = {"settle_periods": 0, "polish_periods": 0}
    c0 = time.process_time()
    with RingPeriodMap(ring, map_settings(steps)) as pm:
        for speed in speeds:
            for label, x0 in starts(pm, float(speed), random, seed):
                e0 = pm.evaluations
                try:
                    x, res, k, spread = run_to_steady(pm, x0, float(speed), settle, max_periods)
                except RingMapFailed:
                    continue
                s = Settled(float(speed), label, k, res, res < settle, pm.measures(x, speed)[0].copy(), spread)
                e1 = pm.evaluations
                if s.settled:
                    orb = shoot(pm, x, float(speed))
                    if orb is not None:
                        s.polished, s.amplitudes = True, orb.amplitudes.copy()
                        s.period_residual, s.max_multiplier, s.stable = orb.residual, orb.max_multiplier, orb.stable
                cost["settle_periods"] += e1 - e0
                cost["polish_periods"] += pm.evaluations - e1
                out.append(s)
                if progress is not None:
                    progress(s)
    cost["cpu_s"] = time.process_time() - c0
    return out, cost


# --- the engine's branches, cached ---------------------------------------------------------------------


def _key(ring: Ring, band: tuple[float, float], steps: int) -> str:
    key: dict[str, Any] = {"ring": asdict(ring), "band": list(band), "engine": ring_engine_digest()}
    if steps != STEPS:  # (the key of a cache written at the study's step is unchanged)
        key["steps_per_period"] = steps
    return json.dumps(key, sort_keys=True)


def map_settings(steps: int = STEPS, workers: int | None = 1) -> RingShootingSettings:
    """The period map's settings of the check: the engine's defaults at `steps` steps per period, on
    `workers` threads (None: the engine's default)."""
    return RingShootingSettings(steps_per_period=steps, workers=workers)


def engine_branches(
    ring: Ring, band: tuple[float, float], cache: Path | None = None, steps: int = STEPS
) -> tuple[list[Branch], list[np.ndarray], dict[str, Any]]:
    """The engine's branches over the band (ring_branches, default settings at `steps` steps per
    period) as Branch, their states (P, dim) per branch, and the engine's cost; read from `cache`
    (.npz) if it holds this ring, band, step and engine (ring_engine_digest), else computed and
    written there."""
    key = _key(ring, band, steps)
    if cache is not None and cache.exists():
        with np.load(cache) as z:
            if str(z["key"]) == key:
                nb = int(z["count"])
                brs = [Branch(z[f"s{b}"], z[f"a{b}"], z[f"st{b}"]) for b in range(nb)]
                return brs, [z[f"x{b}"] for b in range(nb)], json.loads(str(z["cost"]))
    c0 = time.process_time()
    r = ring_branches(ring, band, settings=map_settings(steps, None))
    brs, xs, cost = from_result(r, time.process_time() - c0)
    if cache is not None:
        save(cache, key, brs, xs, cost)
    return brs, xs, cost


def from_result(r: RingBranches, cpu_s: float) -> tuple[list[Branch], list[np.ndarray], dict[str, Any]]:
    """ring_branches' result as Branch (an untraced orbit: a branch of one point), states, cost."""
    rows = [b.orbits for b in r.branches] + [[o] for _, o in r.untraced]
    brs = [
        Branch(
            np.array([o.speed for o in os_]), np.array([o.amplitudes for o in os_]), np.array([o.stable for o in os_])
        )
        for os_ in rows
    ]
    xs = [np.array([o.x for o in os_]) for os_ in rows]
    cost = {
        "periods": r.evaluations,
        "cpu_s": cpu_s,
        "wall_s": r.wall_time,
        "branches": len(r.branches),
        "untraced": len(r.untraced),
        "points": r.points,
    }
    return brs, xs, cost


def save(cache: Path, key: str, brs: list[Branch], xs: list[np.ndarray], cost: dict[str, Any]) -> None:
    """The branches, their states and the cost in `cache` (.npz) under `key`."""
    arrays: dict[str, np.ndarray] = {
        "key": np.array(key),
        "count": np.array(len(brs)),
        "cost": np.array(json.dumps(cost)),
    }
    for b, (br, x) in enumerate(zip(brs, xs)):
        arrays.update({f"s{b}": br.speeds, f"a{b}": br.amplitudes, f"st{b}": br.stable, f"x{b}": x})
    cache.parent.mkdir(parents=True, exist_ok=True)
    np.savez_compressed(cache, **arrays)  # type: ignore[arg-type]


# --- the comparison ------------------------------------------------------------------------------------


def second_opinion(
    pm: RingPeriodMap, branches: list[Branch], xs: list[np.ndarray], s: Settled, maps: list[np.ndarray]
) -> int:
    """The branch whose segment at s.speed leads the engine's Newton to s's orbit (module docstring), or -1."""
    for b, (br, X) in enumerate(zip(branches, xs)):
        S = br.speeds
        for k in range(len(S) - 1):
            if (S[k] - s.speed) * (S[k + 1] - s.speed) > 0 or S[k] == S[k + 1]:
                continue
            if not (br.stable[k] or br.stable[k + 1]):
                continue
            f = (s.speed - S[k]) / (S[k + 1] - S[k])
            a = br.amplitudes[k] + f * (br.amplitudes[k + 1] - br.amplitudes[k])
            if sym_distance(a, s.amplitudes, maps) > NEWTON_NEAR:
                continue
            try:
                sol = newton(pm, X[k] + f * (X[k + 1] - X[k]), s.speed)  # type: ignore[arg-type]  # duck-typed map
            except RingMapFailed:
                continue
            if sol is not None and sym_distance(pm.measures(sol.x, s.speed)[0], s.amplitudes, maps) <= NEWTON_RTOL:
                return b
    return -1


def compare(ring: Ring, runs: list[Settled], branches: list[Branch], xs: list[np.ndarray], steps: int = STEPS) -> int:
    """Fills every settled stable orbit's on_branch, distance, tolerance, branch; the periods the
    second opinions ran."""
    maps = index_maps(ring)
    with RingPeriodMap(ring, map_settings(steps)) as pm:
        for s in runs:
            if not (s.polished and s.stable):
                continue
            m = match(branches, s.speed, s.amplitudes, maps)
            s.on_branch, s.distance, s.tolerance, s.branch = m.on, m.distance, m.tolerance, m.branch
            if not m.on:
                b = second_opinion(pm, branches, xs, s, maps)
                if b >= 0:
                    s.on_branch, s.newton_on_branch, s.branch = True, True, b
        return pm.evaluations


def distinct(runs: list[Settled], maps: list[np.ndarray], rtol: float = 1e-3) -> list[Settled]:
    """One settled stable orbit per state: per speed, the orbits apart by more than rtol up to symmetry."""
    kept: list[Settled] = []
    for s in runs:
        if (
            s.polished
            and s.stable
            and not any(k.speed == s.speed and sym_distance(k.amplitudes, s.amplitudes, maps) <= rtol for k in kept)
        ):
            kept.append(s)
    return kept


# --- outputs -------------------------------------------------------------------------------------------


def write_csv(path: Path, runs: list[Settled]) -> None:
    """One row per run."""
    n = len(runs[0].amplitudes) if runs else 0
    head = ["speed_rpm", "start", "periods", "settle_residual", "settled", "polished", "period_residual"]
    head += ["stable", "max_multiplier", *[f"amplitude{i}_m" for i in range(n)], "on_branch", "distance"]
    head += ["tolerance", "branch", "newton_on_branch", "last_periods_min_m", "last_periods_max_m"]
    yes = {True: "yes", False: "no", None: ""}
    rows = [",".join(head)]
    for s in runs:
        row = [f"{s.speed:.6g}", s.start, str(s.periods), f"{s.residual:.3e}", yes[s.settled], yes[s.polished]]
        row += [f"{s.period_residual:.3e}", yes[s.stable], f"{s.max_multiplier:.6f}"]
        row += [f"{a:.8e}" for a in s.amplitudes] + [yes[s.on_branch], f"{s.distance:.3e}", f"{s.tolerance:.3e}"]
        row += [str(s.branch), yes[s.newton_on_branch], f"{s.spread[0]:.6e}", f"{s.spread[1]:.6e}"]
        rows.append(",".join(row))
    atomic_write_text(path, "\n".join(rows) + "\n")


def summary(runs: list[Settled], maps: list[np.ndarray]) -> dict[str, Any]:
    """Counts, and every settled stable orbit that is on no branch."""
    stable = [s for s in runs if s.polished and s.stable]
    missed = [s for s in distinct(stable, maps) if s.on_branch is False]
    return {
        "runs": len(runs),
        "not_settled": [
            {"speed_rpm": s.speed, "start": s.start, "residual": s.residual, "largest_range_m": list(s.spread)}
            for s in runs
            if not s.settled
        ],
        "not_polished": sum(1 for s in runs if s.settled and not s.polished),
        "unstable_after_settling": [
            {"speed_rpm": s.speed, "start": s.start, "max_multiplier": s.max_multiplier}
            for s in runs
            if s.polished and not s.stable
        ],
        "settled_stable_orbits": len(stable),
        "distinct_states": len(distinct(stable, maps)),
        "on_branches": sum(1 for s in stable if s.on_branch),
        "on_branches_by_newton": sum(1 for s in stable if s.newton_on_branch),
        "missed": [
            {
                "speed_rpm": s.speed,
                "start": s.start,
                "amplitudes_m": s.amplitudes.tolist(),
                "max_multiplier": s.max_multiplier,
                "distance": s.distance,
                "tolerance": s.tolerance,
            }
            for s in missed
        ],
    }
