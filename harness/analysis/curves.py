"""Harmonic-balance response curves of one parameter set (docs/model.md section 5): every solution
with its stability at each speed (`hb_curve`), the largest stable one located between the samples
(`hb_stable_peak`), and the load's circular frequency at a speed (`omega_of`). The FMU's own curves
are branches of periodic orbits (harness.analysis.periodic)."""

from __future__ import annotations

import math
from typing import Any, Iterable, Mapping

import numpy as np
from scipy.optimize import minimize_scalar

from harness.analysis.harmonic_balance import harmonic_balance


def omega_of(params: Mapping[str, Any], speed: float) -> float:
    """Excitation circular frequency omega = engineOrder * 2 pi n / 60 [rad/s]."""
    return params["engineOrder"] * 2.0 * math.pi * speed / 60.0


def hb_curve(params: Mapping[str, Any], speeds: Iterable[float]) -> np.ndarray:
    """Every harmonic-balance solution at each speed: rows (speed, B, stable, phase)."""
    sp = np.asarray(list(speeds), dtype=float)
    rows = []
    for s, sols in zip(sp, harmonic_balance(params, sp) if len(sp) else []):
        for sol in sols:
            rows.append((float(s), float(sol.B), bool(sol.stable), float(sol.phase)))
    return np.array(rows, dtype=[("speed", "f8"), ("B", "f8"), ("stable", "?"), ("phase", "f8")])


def hb_stable_peak(params: Mapping[str, Any], curve: np.ndarray) -> tuple[float, float]:
    """(B [m], speed [rpm]) of the largest stable harmonic-balance solution, located: the largest
    stable B as a function of speed, maximised by Brent's bounded search between the sampled
    neighbours of the largest stable sample of `curve` (hb_curve's rows); nan if none is stable.
    Where the stable part ends in a fold, the maximum is that fold's edge."""
    st = curve[curve["stable"]] if len(curve) else curve
    if not len(st):
        return math.nan, math.nan
    k = int(np.argmax(st["B"]))
    speeds = np.unique(curve["speed"])
    i = int(np.searchsorted(speeds, st["speed"][k]))
    lo, hi = speeds[max(i - 1, 0)], speeds[min(i + 1, len(speeds) - 1)]

    def neg_stable_B(n: float) -> float:
        return -max((s.B for s in harmonic_balance(params, n) if s.stable), default=0.0)

    r = minimize_scalar(neg_stable_B, bounds=(lo, hi), method="bounded", options={"xatol": 1e-4})
    B, n = -float(r.fun), float(r.x)
    return (B, n) if B >= st["B"][k] else (float(st["B"][k]), float(st["speed"][k]))
