"""The paper's fixed point A(B) = B at one rotor speed, with the FMU (amplitudeMode 1).

A(B) is the steady max |q| of a run from rest with the amplitude fixed at B. Every root in
(d, B_max] is bracketed on a geometric scan and refined by brentq; a sign change where A(B) jumps
across the diagonal is reported as a "jump", not a root; the open root B = A(open) <= d comes from
one contact-free run (run with the tracked amplitude, whose exact period maxima tell whether it
ever reaches d). With gating, a contact-free run that never reaches d is the same run for every
B > d, so the scan is skipped there. A(B) is the max |q| of one extra, finely sampled period at
the end of the run (`plateau.period_peak`). Each A(B) is cached on disk (an interrupted run loses
only the evaluation in progress). `run_fixed_point` returns a FixedPointResult (its FixedPointRoot
records); `fixed_refinement` bisects the speed intervals next to a curve's largest root where it
changes a lot (the narrow low-kn peak).
"""

from __future__ import annotations

import math
import time as _time
from dataclasses import dataclass, replace
from pathlib import Path
from typing import Any, Mapping, Sequence

import numpy as np
from scipy.optimize import brentq

from harness.analysis.config import ALGO_VERSION, SweepSettings, SweepSpec
from harness.analysis.cache import PointCache, point_key
from harness.analysis.plateau import PLATEAU_OUTPUTS, Start, omega_of, period_peak, settle
from harness.model.galerkin import galerkin
from harness.fmu.pool import worker_fmu


@dataclass(frozen=True)
class FixedPointTask:
    params: dict
    speed: float
    settings: SweepSettings
    fmu_path: str
    fmu_hash: str
    cache_dir: str | None


@dataclass(frozen=True)
class FixedPointRoot:
    """One root of A(B) = B (or a jump of A(B) across the diagonal, which is none)."""

    B: float  # [m]
    kind: str  # open (B <= d) | contact | jump
    reached: bool  # every evaluation that located it reached its steady state
    slope: float  # (A(B_hi) - A(B_lo)) / (B_hi - B_lo) over its scan bracket (0: open root or
    #               time-domain element; nan: the scan hit the root exactly)


@dataclass(frozen=True)
class FixedPointResult:
    """Every root of A(B) = B at one speed."""

    speed: float  # [rpm]
    roots: list[FixedPointRoot]
    n_evals: int  # A(B) evaluations (cached ones included)
    all_reached: bool  # every evaluation reached its steady state
    B_max: float  # [m] top of the scan


def amplitude_for(
    fmu: Any,
    cache: PointCache,
    fmu_hash: str,
    params: dict,
    speed: float,
    B: float,
    s: SweepSettings,
    cap_factor: float = 1.0,
    tracked: bool = False,
) -> dict:
    """A(B): steady max |q| of the FMU with the amplitude fixed at B (amplitudeMode 1), from rest.
    Also `peak_all`: max |q| over the whole run, transient included (a lower bound: the samples at
    the period starts and the final period's maximum). tracked=True runs amplitudeMode 2 from B
    instead: A and peak_all are then the FMU's exact period maxima (its `amplitude` output: the
    last one, the largest one)."""
    key = point_key(
        kind="A(B)",
        v=ALGO_VERSION,
        fmu=fmu_hash,
        params=params,
        speed=speed,
        B=B,
        settings=s.fixed_key(),
        cap_factor=cap_factor,
        tracked=tracked,
    )
    rec = cache.get(key)
    if rec is not None:
        return rec
    p = dict(params, amplitudeMode=2 if tracked else 1, B=float(B))
    t0 = _time.perf_counter()
    cap = s.fixed_max_time * cap_factor
    data, ss, t_end, phase = settle(fmu, p, speed, Start(), s, cap, list(PLATEAU_OUTPUTS))
    if tracked:
        A, peak = float(data["amplitude"][-1]), float(np.max(data["amplitude"]))
    else:
        # the period maximum from one more, finely sampled period (the settling run is sampled
        # once per period); peak_all then only bounds the transient's peak from below
        A = period_peak(fmu, p, speed, t_end, phase, s)
        peak = max(A, float(np.max(np.abs(data["tipDisplacement"]))))
    rec = {
        "B": float(B),
        "A": A,
        "A_h1": float(ss.harmonic_amplitude),
        "reached": bool(ss.reached),
        "rel_change": float(ss.rel_change),
        "sim_time": t_end,
        "peak_all": peak,
        "wall": _time.perf_counter() - t0,
        "message": ss.message,
    }
    cache.put(key, rec)
    return rec


_GALERKIN: dict[str, Any] = {}


def linear_bound(params: Mapping[str, Any], speed: float) -> float:
    """G Fw0 / (C0 omega) [m]: the contact-free resonant amplitude bound at this speed (the
    Galerkin constants of harness.model.galerkin, computed once per parameter set and process)."""
    key = repr(sorted(params.items()))
    if key not in _GALERKIN:
        _GALERKIN[key] = galerkin(params, params["formulation"])
    g = _GALERKIN[key]
    return g.loadGain * params["Fw0"] / (g.C0 * omega_of(params, speed))


def run_fixed_point(task: FixedPointTask) -> FixedPointResult:
    """All roots of A(B) = B at one speed: the open root (B <= d) and every sign change of A(B) - B
    on a geometric scan of (d, B_max], refined by brentq. Non-converged evaluations are reported."""
    fmu = worker_fmu(task.fmu_path)
    cache = PointCache(None if task.cache_dir is None else Path(task.cache_dir))
    s, p, sp = task.settings, task.params, task.speed
    d = float(p["d"])
    evals: list[dict] = []

    def A(B: float, cap_factor: float = 1.0, tracked: bool = False) -> dict:
        r = amplitude_for(fmu, cache, task.fmu_hash, p, sp, B, s, cap_factor, tracked)
        evals.append(r)
        return r

    roots: list[FixedPointRoot] = []
    B_max = s.B_max if s.B_max is not None else 1.5 * linear_bound(p, sp)
    # B <= d: regime open, the contact-free response; lightly damped (tau = 2M/C0 ~ 0.2 s), so it
    # gets at least 2 s (transient down to ~1e-4 of its start). It runs with the tracked amplitude
    # from B = d/2: while the period maxima stay <= d that is the very same open run as with B
    # fixed <= d, and the FMU reports each period maximum exactly (its `amplitude` output), so
    # whether the transient ever reaches d is known exactly. If it does, the tracked run leaves the
    # open regime (B > d from the next period end on), and the open run is redone with B fixed
    # (not needed for the time-domain element, which ignores B).
    open_run = touched = None
    if d > 0:
        cap = max(1.0, 2.0 / s.fixed_max_time)
        open_run = A(0.5 * d, cap, tracked=True)
        touched = open_run["peak_all"] >= d
        if touched and int(p["frictionModel"]) != 3:
            open_run = A(0.5 * d, cap)
    if open_run is not None and open_run["A"] <= d:
        roots.append(FixedPointRoot(open_run["A"], "open", open_run["reached"], 0.0))
    # With gating (and for the time-domain element) nothing depends on B while |q| <= d: if the
    # contact-free run from rest never reaches d, every run with B > d is the same run,
    # A(B) = A(open) < B: no contact root.
    skip = open_run is not None and (p["gating"] or int(p["frictionModel"]) == 3) and not touched
    if int(p["frictionModel"]) == 3 and not skip:
        r = A(max(2.0 * d, 1e-9))  # the element needs no B: A(B) is one constant
        if r["A"] > d:
            roots.append(FixedPointRoot(r["A"], "contact", r["reached"], 0.0))
        skip = True
    B_lo = d * (1 + 1e-6) if d > 0 else B_max * 1e-4
    if not skip and B_max > B_lo:
        grid = np.geomspace(B_lo, B_max, s.n_scan)
        g = [A(float(B)) for B in grid]
        for i in range(len(grid) - 1):
            ga, gb = g[i]["A"] - grid[i], g[i + 1]["A"] - grid[i + 1]
            if ga == 0.0:
                roots.append(FixedPointRoot(float(grid[i]), "contact", g[i]["reached"], math.nan))
            if ga * gb >= 0:
                continue
            seen: list[dict] = []

            def f(B: float) -> float:
                r = A(B)
                seen.append(r)
                return r["A"] - B

            try:
                B = brentq(f, float(grid[i]), float(grid[i + 1]), xtol=1e-3 * max(d, 1e-9), rtol=1e-3, maxiter=30)
                rB = A(B)
                # A(B) continuous through the root, or a jump of A(B) across the diagonal?
                kind = "contact" if abs(rB["A"] - B) <= 0.02 * B else "jump"
                ok = all(r["reached"] for r in seen) and g[i]["reached"] and g[i + 1]["reached"]
            except (RuntimeError, ValueError):
                B, ok, kind = 0.5 * (grid[i] + grid[i + 1]), False, "jump"
            slope = (g[i + 1]["A"] - g[i]["A"]) / (grid[i + 1] - grid[i])
            roots.append(FixedPointRoot(float(B), kind, bool(ok), float(slope)))
    return FixedPointResult(float(sp), roots, len(evals), all(r["reached"] for r in evals), float(B_max))


def fixed_refinement(
    specs: Sequence[SweepSpec], fixed: list[tuple[int, FixedPointTask]], fixed_out: list[FixedPointResult], level: int
) -> list[tuple[int, FixedPointTask]]:
    """Bisect the speed intervals next to each curve's largest fixed point where the largest root
    changes by more than refine_tol of it (the narrow low-kn peak falls between coarse speeds)."""
    extra = []
    for i, sp in enumerate(specs):
        s = sp.settings
        if level >= s.refine_levels:
            continue
        pts = sorted(
            (o.speed, max([r.B for r in o.roots if r.kind != "jump"], default=0.0))
            for (j, _), o in zip(fixed, fixed_out)
            if j == i
        )
        if len(pts) < 2:
            continue
        speeds, amps = [x for x, _ in pts], [a for _, a in pts]
        k = int(np.argmax(amps))
        task0 = next(t for (j, t) in fixed if j == i)
        for a, b in ((k - 1, k), (k, k + 1)):
            if a < 0 or b >= len(pts) or speeds[b] - speeds[a] < 2 * s.min_dn:
                continue
            if abs(amps[b] - amps[a]) > s.refine_tol * amps[k]:
                extra.append((i, replace(task0, speed=0.5 * (speeds[a] + speeds[b]))))
    return extra
