"""The paper's studies as branches of periodic orbits: one curve = one model at one study value.

A curve is every branch of one model (fixedPoint: the paper's B = A(B), i.e. the tracked-amplitude
model's periodic solutions with their stability; jenkins: the time-domain Jenkins element; coulomb:
the Coulomb describing function's fixed point) over the speed range, traced by
harness.analysis.periodic.branches in one worker with one FMU instance. `trace_curve` is the picklable task
harness.studies.paper maps over a Runner; `curve_summary` turns a curve into a CurveSummary, the numbers
the study rows (and through them the claims table and the study CSVs) use.
"""

from __future__ import annotations

import math
import time
from dataclasses import dataclass, field, replace
from typing import Any, Mapping

from harness.analysis.periodic.branches import BranchSettings, TraceStats, trace_branches
from harness.analysis.periodic.continuation import Branch
from harness.fmu.pool import worker_fmu


@dataclass(frozen=True)
class CurveTask:
    key: str  # study key (gap | mass | angle | kn)
    value: float  # the study parameter's value
    model: str  # fixedPoint | jenkins | coulomb
    params: Mapping[str, Any]  # full parameter set (validated by the PeriodMap)
    speed_range: tuple[float, float]  # [rpm]
    fmu_path: str | None = None
    settings: BranchSettings = field(default_factory=BranchSettings)


@dataclass
class Curve:
    task: CurveTask
    branches: list[Branch]
    stats: TraceStats


def trace_curve(task: CurveTask) -> Curve:
    t0 = time.perf_counter()
    fmu = worker_fmu(task.fmu_path)
    branches, stats = trace_branches(fmu, dict(task.params), task.model, task.speed_range, task.settings)
    return Curve(task, branches, replace(stats, wall=time.perf_counter() - t0))


def peak_orbit(
    branches: list[Branch], stable_only: bool = True, speed_range: tuple[float, float] = (0.0, math.inf)
) -> Any:
    """The (stable) orbit of largest max |q| inside speed_range: a located peak or fold (a fold that
    bounds a stable part is the limit of its stable orbits) or a sampled point (the largest may sit
    at a branch end), with its unknowns x; None if there is none."""
    lo, hi = speed_range
    best = None
    for b in branches:
        for p in [*b.points, *b.extrema]:
            if (p.stable or not stable_only) and lo <= p.speed <= hi and (best is None or p.amplitude > best.amplitude):
                best = p
    return best


def peak(
    branches: list[Branch], stable_only: bool = True, speed_range: tuple[float, float] = (0.0, math.inf)
) -> tuple[float, float]:
    """(largest max |q| [m], its speed [rpm]) of `peak_orbit`; nan if there is none."""
    p = peak_orbit(branches, stable_only, speed_range)
    return (math.nan, math.nan) if p is None else (p.amplitude, p.speed)


def jump_speed(branches: list[Branch], a_pk: float, n_pk: float) -> float:
    """Speed [rpm] where the stable part holding the peak orbit (max |q| = a_pk at n_pk, from
    `peak`) ends at a located fold: where a slow sweep on it jumps (nan if it does not end in one)."""
    for b in branches:
        pts = b.points
        for e in b.extrema:
            if e.amplitude == a_pk and e.speed == n_pk and e.kind == "fold":
                return e.speed  # the peak is the fold itself
        on = [i for i, p in enumerate(pts) if p.stable and abs(p.speed - n_pk) <= _span(pts, i)]
        for i in on:
            for step in (1, -1):  # walk along the stable part in both directions to its ends
                j = i
                while 0 <= j + step < len(pts) and pts[j + step].stable:
                    j += step
                k = j + step
                if not 0 <= k < len(pts):
                    continue
                lo, hi = sorted((pts[j].speed, pts[k].speed))
                folds = [e.speed for e in b.located("fold") if lo - _span(pts, j) <= e.speed <= hi + _span(pts, k)]
                if folds:
                    return min(folds, key=lambda n: abs(n - 0.5 * (lo + hi)))
    return math.nan


def _span(pts: list, i: int) -> float:
    """Half the speed distance from point i to its farther neighbour [rpm]."""
    d = [abs(pts[i].speed - pts[j].speed) for j in (i - 1, i + 1) if 0 <= j < len(pts)]
    return max(d, default=0.0)


def unstable_ranges(branches: list[Branch], d: float) -> list[tuple[float, float, str]]:
    """(low, high [rpm], kind) of every unstable stretch of orbits with contact (max |q| > d)."""
    out = []
    for b in branches:
        run: list = []
        for p in b.points + [None]:
            if p is not None and not p.stable and p.amplitude > d:
                run.append(p)
                continue
            if run:
                kinds = sorted({q.label for q in run})
                out.append((min(q.speed for q in run), max(q.speed for q in run), "/".join(kinds)))
                run = []
    return out


@dataclass(frozen=True)
class CurveSummary:
    """The numbers of one curve (one model at one study value) inside its speed range."""

    peak: float  # [m] largest max|q| of a stable orbit, located (nan: none)
    speed: float  # [rpm] its speed
    peak_any: float  # [m] largest max|q| of any orbit, stable or not
    speed_any: float  # [rpm] its speed
    jump: float  # [rpm] the located fold where the stable part holding the peak ends (nan: it does not)
    branches: int  # branches traced
    points: int  # orbits on them
    unstable_contact: list[tuple[float, float, str]]  # (low [rpm], high [rpm], kind) of unstable contact stretches
    stats: TraceStats  # what tracing the curve cost


def curve_summary(curve: Curve) -> CurveSummary:
    d, rng = float(curve.task.params["d"]), curve.task.speed_range
    a, n = peak(curve.branches, speed_range=rng)
    a_any, n_any = peak(curve.branches, stable_only=False, speed_range=rng)
    return CurveSummary(
        a,
        n,
        a_any,
        n_any,
        jump_speed(curve.branches, a, n),
        len(curve.branches),
        sum(len(b.points) for b in curve.branches),
        unstable_ranges(curve.branches, d),
        curve.stats,
    )
