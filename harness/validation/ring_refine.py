"""Do the engine's stability verdicts hold at a finer step? Its orbits at the study's h = T/160 shot
again at finer steps h = T/K: each orbit by the engine's Newton (ring_orbits.shooting.shoot) at
every K in turn, started from the orbit at the step before, with its Floquet multipliers.

The co-simulation's coupling error moves the multipliers, not only the orbit: near a kink of the
period map (a contact event changing its communication step) an orbit that the monolithic reference
settles on has largest multiplier 1.21 at T/160 and 0.93 at T/640
(tests/validation/test_ring_step_stability.py). An orbit whose verdict
differs between the first and the finest step is listed; one Newton does not follow (it did not
converge, or it converged on an orbit more than FOLLOW_RTOL away in amplitude, a neighbour across a
kink) is counted apart.
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any, Sequence

import numpy as np

from harness.files.atomic import atomic_write_text
from harness.system.ring import Ring
from harness.system.ring_orbits.period_map import RingMapFailed, RingPeriodMap
from harness.system.ring_orbits.shooting import shoot
from harness.validation.branch_match import Branch
from harness.validation.ring_completeness import map_settings

FOLLOW_RTOL = 0.02  # an orbit at the next step further than this (largest amplitude, relative) is another


@dataclass
class Refined:
    """One of the engine's orbits at each step: largest blade amplitude [m], largest multiplier, stable."""

    branch: int
    point: int
    speed: float  # [rpm]
    amplitude: list[float] = field(default_factory=list)
    multiplier: list[float] = field(default_factory=list)
    stable: list[bool] = field(default_factory=list)
    states: list[np.ndarray] = field(default_factory=list)  # the orbit's state at each step followed

    def followed(self, steps: int) -> bool:
        return len(self.stable) == steps

    def changed(self) -> bool:
        return self.stable[0] != self.stable[-1]


def sample(branches: Sequence[Branch], every: int, above: float) -> list[tuple[int, int]]:
    """(branch, point) of every `every`-th orbit, in branch order, with a blade above `above` [m]."""
    pts = [(b, k) for b, br in enumerate(branches) for k in range(len(br.speeds)) if br.amplitudes[k].max() > above]
    return pts[::every]


def refine(
    ring: Ring,
    branches: Sequence[Branch],
    xs: Sequence[np.ndarray],
    steps: Sequence[int],
    every: int = 1,
    above: float = 0.0,
    workers: int | None = None,
) -> list[Refined]:
    """The sampled orbits (`sample`) at every step of `steps` (the first: the branches' own)."""
    rows: list[Refined] = []
    maps = [RingPeriodMap(ring, map_settings(K, workers)) for K in steps]
    try:
        for b, k in sample(branches, every, above):
            row = Refined(b, k, float(branches[b].speeds[k]))
            x = xs[b][k]
            for pm in maps:
                try:
                    orb = shoot(pm, x, row.speed)
                except RingMapFailed:
                    orb = None
                if orb is None:
                    break
                amp = float(orb.amplitudes.max())
                if row.amplitude and abs(amp - row.amplitude[-1]) > FOLLOW_RTOL * row.amplitude[-1]:
                    break
                row.amplitude.append(amp)
                row.multiplier.append(orb.max_multiplier)
                row.stable.append(bool(orb.stable))
                row.states.append(orb.x)
                x = orb.x
            rows.append(row)
    finally:
        for pm in maps:
            pm.close()
    return rows


def summary(rows: Sequence[Refined], steps: Sequence[int]) -> dict[str, Any]:
    """Counts: orbits, followed to the finest step, verdicts changed (stable -> unstable and back),
    the largest amplitude among the changed, and the largest stable amplitude at the first and at the
    finest step among the followed."""
    n = len(steps)
    done = [r for r in rows if r.followed(n)]
    changed = [r for r in done if r.changed()]

    def largest(rs: Sequence[Refined], i: int) -> float:
        return max((r.amplitude[i] for r in rs if r.stable[i]), default=math.nan)

    return {
        "steps_per_period": list(steps),
        "orbits": len(rows),
        "followed": len(done),
        "not_followed": len(rows) - len(done),
        "changed": len(changed),
        "stable_to_unstable": sum(r.stable[0] for r in changed),
        "unstable_to_stable": sum(not r.stable[0] for r in changed),
        "changed_largest_m": max((max(r.amplitude) for r in changed), default=math.nan),
        "changed_speeds_rpm": sorted(round(r.speed, 1) for r in changed),
        "largest_stable_first_m": largest(done, 0),
        "largest_stable_finest_m": largest(done, -1),
    }


def write_csv(path: Path, rows: Sequence[Refined], steps: Sequence[int]) -> None:
    """One row per orbit: branch, point, speed, and per step amplitude, multiplier, stable (empty
    from the step Newton did not follow on)."""
    head = ["branch", "point", "speed_rpm"] + [
        f"{c}_{K}" for K in steps for c in ("amplitude_m", "multiplier", "stable")
    ]
    out = [",".join(head)]
    for r in rows:
        cells = [str(r.branch), str(r.point), f"{r.speed:.2f}"]
        for i in range(len(steps)):
            done = i < len(r.stable)
            cells += (
                [f"{r.amplitude[i]:.6e}", f"{r.multiplier[i]:.4f}", "yes" if r.stable[i] else "no"]
                if done
                else [""] * 3
            )
        out.append(",".join(cells))
    atomic_write_text(path, "\n".join(out) + "\n")
