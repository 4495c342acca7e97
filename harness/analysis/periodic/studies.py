"""The paper's studies as branches of periodic orbits: one curve = one model at one study value.

A curve is every branch of one model (fixedPoint: the paper's B = A(B), i.e. the tracked-amplitude
model's periodic solutions with their stability; jenkins: the time-domain Jenkins element; coulomb:
the Coulomb describing function's fixed point) over the speed range, traced by
harness.analysis.periodic.branches in one worker with one FMU instance. `trace_curve` is the picklable task
harness.studies.paper maps over a Runner; `curve_summary` turns a curve into a CurveSummary, the numbers
the study rows (and through them the claims table and the study CSVs) use.
"""
from __future__ import annotations

import atexit
import math
import time
from dataclasses import dataclass, field, replace
from pathlib import Path
from typing import Any, Mapping

from harness.analysis.periodic.branches import BranchSettings, TraceStats, trace_branches
from harness.analysis.periodic.continuation import Branch
from harness.fmu.blade import BladeFMU


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


_FMUS: dict = {}  # the FMU of each path in this (worker) process, reused by all its curves


def _process_fmu(path: Path | str):
    """The process's BladeFMU for `path`, opened on first use (~11 ms: extract, load,
    instantiate) and closed at exit; every period-map evaluation resets it and sets every
    parameter, so curves cannot see each other."""
    key = str(path)
    if key not in _FMUS:
        _FMUS[key] = BladeFMU(path)
        atexit.register(_FMUS[key].close)
    return _FMUS[key]


def trace_curve(task: CurveTask) -> Curve:
    t0 = time.perf_counter()
    fmu = _process_fmu(task.fmu_path)
    branches, stats = trace_branches(fmu, dict(task.params), task.model, task.speed_range, task.settings)
    return Curve(task, branches, replace(stats, wall=time.perf_counter() - t0))


def peak(branches: list[Branch], stable_only: bool = True,
         speed_range: tuple[float, float] = (0.0, math.inf)) -> tuple[float, float]:
    """(largest max |q| [m], its speed [rpm]) over the (stable) points inside speed_range (a
    branch's last point may lie just outside); nan if there is none."""
    lo, hi = speed_range
    best = (math.nan, math.nan)
    for b in branches:
        for p in b.points:
            if (p.stable or not stable_only) and lo <= p.speed <= hi and not p.amplitude <= best[0]:
                best = (p.amplitude, p.speed)
    return best


def jump_speed(branches: list[Branch], a_pk: float) -> float:
    """Speed [rpm] where the stable part holding the peak orbit (max |q| = a_pk, from `peak`) ends at
    a fold: where a slow run-up on it jumps down (nan if that stable part does not end in a fold)."""
    for b in branches:
        pts = b.points
        for i, p in enumerate(pts):
            if not (p.stable and p.amplitude == a_pk):
                continue
            for step in (1, -1):  # walk along the stable part in both directions to its ends
                j = i
                while 0 <= j + step < len(pts) and pts[j + step].stable:
                    j += step
                if 0 <= j + step < len(pts) and "fold" in pts[j + step].label:
                    return 0.5 * (pts[j].speed + pts[j + step].speed)
    return math.nan


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

    peak: float  # [m] largest max|q| of a stable orbit (nan: none)
    speed: float  # [rpm] its speed
    peak_any: float  # [m] largest max|q| of any orbit, stable or not
    speed_any: float  # [rpm] its speed
    jump: float  # [rpm] where the stable part holding the peak ends in a fold (nan: it does not)
    branches: int  # branches traced
    points: int  # orbits on them
    unstable_contact: list[tuple[float, float, str]]  # (low [rpm], high [rpm], kind) of unstable contact stretches
    stats: TraceStats  # what tracing the curve cost


def curve_summary(curve: Curve) -> CurveSummary:
    d, rng = float(curve.task.params["d"]), curve.task.speed_range
    a, n = peak(curve.branches, speed_range=rng)
    a_any, n_any = peak(curve.branches, stable_only=False, speed_range=rng)
    return CurveSummary(a, n, a_any, n_any, jump_speed(curve.branches, a), len(curve.branches),
                        sum(len(b.points) for b in curve.branches), unstable_ranges(curve.branches, d), curve.stats)
