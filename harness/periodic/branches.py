"""All branches of periodic orbits of one model over a speed range.

Every orbit found at the seed speeds (harness.periodic.search.solutions_at: the lowest speed of the
range, then every `seed_step` rpm) that does not lie on a branch traced so far starts a new
continuation (both directions, through folds), so the main branch is traced from below to above
resonance and isolated branches are picked up wherever a seed finds one of their orbits.
"""
from __future__ import annotations

import math
from dataclasses import dataclass, field
from typing import Any, Mapping

import numpy as np

from harness.fmu import BladeFMU
from harness.periodic.continuation import Branch, ContinuationSettings, continue_branch
from harness.periodic.period_map import PeriodMap, ShootingSettings
from harness.periodic.search import SearchSettings, solutions_at
from harness.params import ParameterError


@dataclass(frozen=True)
class BranchSettings:
    seed_step: float = 500.0  # [rpm] between seed speeds
    shooting: ShootingSettings = field(default_factory=ShootingSettings)
    continuation: ContinuationSettings = field(default_factory=ContinuationSettings)
    search: SearchSettings = field(default_factory=SearchSettings)


def seed_speeds(lo: float, hi: float, step: float) -> list[float]:
    n = max(1, int(math.ceil((hi - lo) / step)))
    return list(np.linspace(lo, hi, n + 1))


def trace_branches(fmu: BladeFMU, params: Mapping[str, Any] | None, model: str, speed_range: tuple[float, float],
                   s: BranchSettings = BranchSettings()) -> tuple[list[Branch], dict]:
    """(branches, statistics) of `model` over speed_range [rpm]."""
    lo, hi = (float(v) for v in speed_range)
    if not (math.isfinite(lo) and math.isfinite(hi) and 0.0 < lo < hi <= 30000.0):
        raise ParameterError(f"speed range {speed_range!r} rpm: need 0 < low < high <= 30000")
    if not (math.isfinite(s.seed_step) and s.seed_step > 0):
        raise ParameterError(f"seed_step = {s.seed_step!r} rpm must be > 0")
    pm = PeriodMap(fmu, params, model, s.shooting)
    branches: list[Branch] = []
    seeds = 0
    for n in seed_speeds(lo, hi, s.seed_step):
        for sol in solutions_at(pm, n, s.search):
            seeds += 1
            if any(b.contains(n, sol.amplitude) for b in branches):
                continue
            branches.append(continue_branch(pm, sol.x, n, (lo, hi), s.continuation))
    return branches, {"evaluations": pm.evaluations, "seeds": seeds, "simulated_s": pm.simulated,
                      "fmi_s": pm.fmi_seconds}
