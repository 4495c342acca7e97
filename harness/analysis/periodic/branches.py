"""All branches of periodic orbits of one model over a speed range, and every orbit at one speed.

Every orbit found at the seed speeds (harness.analysis.periodic.search.solutions_at: the lowest speed of the
range, then every `seed_step` rpm) that does not lie on a branch traced so far starts a new
continuation (both directions, through folds; its peaks and folds located by
harness.analysis.periodic.extrema), so the main branch is traced from below to above
resonance and isolated branches are picked up wherever a seed finds one of their orbits.

`orbits_at` (one speed) takes the orbits of the search at that speed and, in addition, every
crossing of that speed by the branches traced over a window around it: near a fold the roots of
B = A(B) sit in a window of B narrower than any scan grid (at 9000 rpm in the base case, 5.1..5.35
um wide; closing at the fold, 9431 rpm), but the branch through them is traced from speeds where
the search finds it.
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field
from typing import Any, Mapping

import numpy as np

from harness.fmu.blade import SPEED_RANGE, BladeFMU
from harness.analysis.periodic.continuation import Branch, ContinuationSettings, continue_branch
from harness.analysis.periodic.extrema import locate
from harness.analysis.periodic.period_map import PeriodMap, ShootingSettings
from harness.analysis.periodic.search import SearchSettings, hb_guesses, same_orbit, solutions_at
from harness.analysis.periodic.shooting import Orbit, newton, orbit
from harness.model.params import ParameterError


@dataclass(frozen=True)
class BranchSettings:
    seed_step: float = 500.0  # [rpm] between seed speeds
    shooting: ShootingSettings = field(default_factory=ShootingSettings)
    continuation: ContinuationSettings = field(default_factory=ContinuationSettings)
    search: SearchSettings = field(default_factory=SearchSettings)


@dataclass(frozen=True)
class TraceStats:
    """What tracing the branches of one model cost."""

    evaluations: int  # period-map evaluations (periods simulated)
    seeds: int  # orbits found at the seed speeds
    simulated_s: float  # [s] blade time simulated
    fmi_s: float  # [s] wall time in the FMI calls of the evaluations
    wall: float = math.nan  # [s] wall time of the whole curve in its worker (set by trace_curve)


def seed_speeds(lo: float, hi: float, step: float) -> list[float]:
    n = max(1, int(math.ceil((hi - lo) / step)))
    return list(np.linspace(lo, hi, n + 1))


def trace_branches(
    fmu: BladeFMU,
    params: Mapping[str, Any] | None,
    model: str,
    speed_range: tuple[float, float],
    s: BranchSettings = BranchSettings(),
    pm: PeriodMap | None = None,
) -> tuple[list[Branch], TraceStats]:
    """(branches, statistics) of `model` over speed_range [rpm] (with the period map pm, if given:
    its evaluations count there)."""
    lo, hi = (float(v) for v in speed_range)
    if not (math.isfinite(lo) and math.isfinite(hi) and 0.0 < lo < hi <= SPEED_RANGE[1]):
        raise ParameterError(f"speed range {speed_range!r} rpm: need 0 < low < high <= {SPEED_RANGE[1]:g}")
    if not (math.isfinite(s.seed_step) and s.seed_step > 0):
        raise ParameterError(f"seed_step = {s.seed_step!r} rpm must be > 0")
    pm = pm or PeriodMap(fmu, params, model, s.shooting)
    branches: list[Branch] = []
    seeds = 0
    speeds = seed_speeds(lo, hi, s.seed_step)
    for n, hb in zip(speeds, hb_guesses(pm, speeds)):
        for sol in solutions_at(pm, n, s.search, hb):
            seeds += 1
            if any(b.contains(n, sol.amplitude) for b in branches):
                continue
            branch = continue_branch(pm, sol.x, n, (lo, hi), s.continuation)
            branch.extrema = locate(pm, branch, s.continuation)
            branches.append(branch)
    return branches, TraceStats(pm.evaluations, seeds, pm.simulated, pm.fmi_seconds)


WINDOW = 1.25  # orbits_at traces the branches over [speed / WINDOW, speed * WINDOW]


def orbits_at(pm: PeriodMap, speed_rpm: float, s: BranchSettings = BranchSettings()) -> list[Orbit]:
    """Every periodic orbit found at `speed_rpm` (the search there, and every crossing of `speed_rpm` by
    a branch traced around it, refined by Newton at `speed_rpm`), with multipliers, by amplitude."""
    speed_rpm = float(speed_rpm)
    found = solutions_at(pm, speed_rpm, s.search)
    rng = (speed_rpm / WINDOW, min(speed_rpm * WINDOW, SPEED_RANGE[1]))
    branches, _ = trace_branches(pm.fmu, pm.p, pm.model, rng, s, pm)
    for b in branches:
        for a, c in zip(b.points[:-1], b.points[1:]):
            if (a.speed - speed_rpm) * (c.speed - speed_rpm) > 0 or a.speed == c.speed:
                continue
            f = (speed_rpm - a.speed) / (c.speed - a.speed)
            sol = newton(pm, a.x + f * (c.x - a.x), speed_rpm)
            if sol is not None and not any(same_orbit(pm, sol.x, o.x, speed_rpm, s.search.same_rtol) for o in found):
                found.append(sol)
    return [orbit(pm, sol, speed_rpm) for sol in sorted(found, key=lambda o: o.amplitude)]
