"""Every periodic orbit of a model that a search at one speed finds (the seeds of the branches).

Seeds, each refined by Newton shooting (harness.analysis.periodic.shooting), duplicates merged:
- the contact-free linear orbit and the one-harmonic orbits of the blade linearised at amplitudes
  B on a geometric grid (harness.analysis.harmonic_balance.linear_orbit): one guess per amplitude level;
- the harmonic-balance solutions (gating off, harness.analysis.harmonic_balance), every branch;
- for the fixed point B = A(B) (fixedPoint, coulomb): the fixed-B orbit followed along a geometric
  scan of B over (d, B_max] (each Newton warm-started from the previous B), g(B) = A(B) - B on it;
  every sign change of g, and every interior local minimum of |g| (where two roots can hide in
  one cell), is refined by Newton on the augmented problem (q0, q0', B). A(B) here is the max |q|
  of the fixed-B periodic orbit, not of a transient from rest, so roots on orbits that a
  transient does not reach are found as well.
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from typing import Any, Mapping

import numpy as np

from harness.analysis.curves import omega_of
from harness.analysis.periodic.period_map import PeriodMap, omega
from harness.analysis.periodic.shooting import Solution, newton
from harness.analysis.harmonic_balance import harmonic_balance, linear_orbit, linear_orbits
from harness.model.galerkin import galerkin

SCAN_TOL = 1e-7  # Newton tolerance of the fixed-B orbits of the B scan (they only place the roots of
#                  g(B), which Newton on the augmented problem then refines to the shooting tolerance)


@dataclass(frozen=True)
class SearchSettings:
    n_levels: int = 8  # amplitude levels of the linearised guesses
    n_scan: int = 32  # B values of the fixed-point scan over (d, B_max]
    same_rtol: float = 1e-5  # two orbits are one if their states differ by less (scaled)


def _df_params(pm: PeriodMap) -> dict:
    """Parameters for the describing-function guesses (the Jenkins element uses the macroslip DF)."""
    p = dict(pm.p)
    if int(p["frictionModel"]) == 3:
        p["frictionModel"] = 1
    return p


_GALERKIN: dict[str, Any] = {}


def linear_bound(params: Mapping[str, Any], speed_rpm: float) -> float:
    """G Fw0 / (C0 omega) [m]: the contact-free resonant amplitude bound at this speed (the
    Galerkin constants of harness.model.galerkin, computed once per parameter set and process)."""
    key = repr(sorted(params.items()))
    if key not in _GALERKIN:
        _GALERKIN[key] = galerkin(params, params["formulation"])
    g = _GALERKIN[key]
    return g.loadGain * params["Fw0"] / (g.C0 * omega_of(params, speed_rpm))


def _b_max(pm: PeriodMap, speed: float) -> float:
    return 1.5 * linear_bound(pm.p, speed)


def hb_guesses(pm: PeriodMap, speeds: list[float]) -> list[list]:
    """The harmonic-balance solutions that seed the search at each of `speeds` (one vectorised
    call; none for fixedB)."""
    if pm.model == "fixedB":
        return [[] for _ in speeds]
    return harmonic_balance(_df_params(pm), np.asarray(speeds, dtype=float))


def _guesses(pm: PeriodMap, speed: float, s: SearchSettings, hb: list | None = None) -> list[np.ndarray]:
    """Starting states: contact-free orbit, linearised orbits at amplitude levels, HB solutions
    (hb: those at this speed if known, else computed here)."""
    p, d = _df_params(pm), pm.d
    w = omega(pm.p, speed)
    levels = [None] + list(np.geomspace(d * (1 + 1e-6), max(_b_max(pm, speed), 2 * d), s.n_levels)) if d > 0 else [None]
    states = []
    for B in levels:
        q0, v0 = linear_orbit(p, speed, B if pm.model != "fixedB" else (pm.B if B is not None else None))
        states.append((q0, v0, B if B is not None else math.hypot(q0, v0 / w)))
        if pm.model != "jenkins" and B is not None:
            # fixed B: one linearised guess (at pm.B) besides the contact-free one; fixed point:
            # the B scan of fixed_point_candidates covers every amplitude level systematically
            break
    if pm.model != "fixedB":
        for sol in harmonic_balance(p, speed) if hb is None else hb:
            states.append((sol.B * math.sin(sol.phase), sol.B * w * math.cos(sol.phase), sol.B))
    out = []
    for q0, v0, B in states:
        third = {"fixedB": None, "jenkins": 0.0}.get(pm.model, B)
        out.append(pm.lift(q0, v0, third))
    return out


def same_orbit(pm: PeriodMap, xa: np.ndarray, xb: np.ndarray, speed_rpm: float, rtol: float) -> bool:
    sc = np.maximum(pm.scales(xa, speed_rpm), pm.scales(xb, speed_rpm))
    if pm.model == "jenkins":  # phi is free while open or in stick at the section: compare q, q'
        sc, xa, xb = sc[:-1], xa[:-1], xb[:-1]
    return bool(np.max(np.abs(xa - xb) / sc) <= rtol)


def _add(pm: PeriodMap, found: list[Solution], sol: Solution | None, speed: float, s: SearchSettings) -> None:
    if sol is not None and not any(same_orbit(pm, sol.x, f.x, speed, s.same_rtol) for f in found):
        found.append(sol)


def solutions_at(
    pm: PeriodMap, speed_rpm: float, s: SearchSettings = SearchSettings(), hb: list | None = None
) -> list[Solution]:
    """Every root of the period map found at `speed_rpm` (no multipliers), sorted by amplitude (hb:
    the harmonic-balance solutions at `speed_rpm`, if already known: hb_guesses)."""
    found: list[Solution] = []
    for x0 in _guesses(pm, speed_rpm, s, hb):
        _add(pm, found, newton(pm, x0, speed_rpm), speed_rpm, s)
    if pm.model in ("fixedPoint", "coulomb") and pm.d > 0:
        for x0 in fixed_point_candidates(pm, speed_rpm, s):
            _add(pm, found, newton(pm, x0, speed_rpm), speed_rpm, s)
    return sorted(found, key=lambda o: o.amplitude)


def fixed_b_map(pm: PeriodMap) -> PeriodMap:
    """A fixedB period map with the same FMU and parameters (its B is set per scan point)."""
    return pm.with_model("fixedB")


def fixed_point_candidates(pm: PeriodMap, speed_rpm: float, s: SearchSettings) -> list[np.ndarray]:
    """Augmented starting states (q0, q0', B) next to every root of g(B) = A(B) - B on the
    fixed-B orbits of a geometric B scan (sign changes and interior local minima of |g|)."""
    fb = fixed_b_map(pm)
    p = _df_params(pm)
    grid = np.geomspace(pm.d * (1 + 1e-6), max(_b_max(pm, speed_rpm), 2 * pm.d), s.n_scan)
    xs, g, Bs = [], [], []
    prev = None  # the previous B's orbit: its state and DP start the next B's quasi-Newton
    lin_q, lin_v = linear_orbits(p, speed_rpm, grid)  # the linearised orbit at each B
    for k, B in enumerate(grid):
        fb.B = float(B)
        sol = newton(fb, prev[0], speed_rpm, prev[1], SCAN_TOL) if prev is not None else None
        if sol is None or not sol.amplitude > pm.d:  # else from the linearised orbit at B
            sol = newton(fb, pm.lift(lin_q[k], lin_v[k]), speed_rpm, tol=SCAN_TOL)
        if sol is None:
            prev = None
            continue
        prev = (sol.x, sol.J)
        xs.append(sol.x)
        g.append(sol.amplitude - B)
        Bs.append(B)
    out = []
    for i in range(len(g) - 1):
        if g[i] == 0.0 or g[i] * g[i + 1] < 0:
            f = g[i] / (g[i] - g[i + 1]) if g[i] != g[i + 1] else 0.0
            B = Bs[i] + f * (Bs[i + 1] - Bs[i])
            x = xs[i] + f * (xs[i + 1] - xs[i])
            out.append(np.append(x, B))
    for i in range(1, len(g) - 1):  # a dip of |g| without a sign change: two roots may hide here
        if abs(g[i]) < abs(g[i - 1]) and abs(g[i]) < abs(g[i + 1]) and g[i - 1] * g[i + 1] > 0:
            for j in (i - 1, i, i + 1):
                out.append(np.append(xs[j], Bs[j] + g[j]))
    return out
