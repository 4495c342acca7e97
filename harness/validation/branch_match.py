"""Whether a steady state lies on a set of branches of periodic orbits: its per-blade amplitude
vector against each branch, interpolated linearly in speed between neighbouring points, up to the
ring's symmetries (harness/system/ring_orbits/symmetry.py: a state and its rotated or reflected
images have permuted amplitude vectors).

Tolerance on a segment [k, k + 1] of a branch at speed s: RTOL of the largest amplitude plus twice
the linear interpolation's own error there, estimated as the largest difference (over the blades)
between the line through points k, k + 1 and the parabola through them and a neighbour (k - 1 or
k + 2) whose speeds run the same way (a parabola's correction to the line is the leading term of
the line's error; twice it for the unknown higher terms). Where no neighbour runs the same way (a
fold next to the segment, a branch of two points) the whole change over the segment is taken. RTOL:
two Newton-converged orbits (period residual 1e-10) that are the same orbit have amplitudes equal to
about 1e-8; 1e-3 is the engine's own "same orbit" rule (branches.SAME_RTOL), far below the
differences between the ring's distinct states (tens of percent) except next to a branch point,
where the branches meet anyway.

A segment counts as stable if either of its points is stable (a stability boundary lies between
them, and the engine resolves it no finer than its points).
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

RTOL = 1e-3


@dataclass(frozen=True)
class Branch:
    """A branch as the comparison needs it: points in arc order."""

    speeds: np.ndarray  # (P,) [rpm]
    amplitudes: np.ndarray  # (P, N) per-blade max |q| [m]
    stable: np.ndarray  # (P,) bool


@dataclass(frozen=True)
class Match:
    """The nearest stable segment to a state (distances relative to the largest amplitude)."""

    on: bool  # within the tolerance of a stable segment
    distance: float  # to the nearest stable segment covering the speed (inf if none covers it)
    tolerance: float  # of that segment
    branch: int  # its branch (-1 if none)
    distance_any: float  # to the nearest segment, stable or not (inf if none covers the speed)


def sym_distance(a: np.ndarray, b: np.ndarray, maps: list[np.ndarray]) -> float:
    """min over the symmetries g of max_i |a[g_i] - b_i| / max(max a, max b)."""
    scale = max(float(np.max(a)), float(np.max(b)), 1e-300)
    return min(float(np.max(np.abs(a[g] - b))) for g in maps) / scale


def interpolation_error(S: np.ndarray, A: np.ndarray, k: int, speed: float) -> float:
    """Estimated error [m] of the line through points k, k + 1 at `speed` (module docstring)."""
    line = A[k] + (speed - S[k]) / (S[k + 1] - S[k]) * (A[k + 1] - A[k])
    up = S[k + 1] > S[k]
    errs = []
    for j in (k - 1, k + 2):
        if not 0 <= j < len(S):
            continue
        idx = sorted((j, k, k + 1))
        s = S[idx]
        if not (np.all(np.diff(s) > 0) if up else np.all(np.diff(s) < 0)):
            continue
        quad = np.zeros_like(line)
        for m, i in enumerate(idx):
            others = [s[n] for n in range(3) if n != m]
            quad += A[i] * (speed - others[0]) * (speed - others[1]) / ((s[m] - others[0]) * (s[m] - others[1]))
        errs.append(float(np.max(np.abs(quad - line))))
    return max(errs) if errs else float(np.max(np.abs(A[k + 1] - A[k])))


def segments(br: Branch, speed: float) -> list[tuple[int, np.ndarray, float]]:
    """(k, interpolated amplitudes, interpolation error [m]) of every segment [k, k + 1] of br that
    covers `speed`, and of every single point exactly at it (a branch of one point)."""
    S, A = br.speeds, br.amplitudes
    out = []
    for k in range(len(S) - 1):
        lo, hi = min(S[k], S[k + 1]), max(S[k], S[k + 1])
        if not lo <= speed <= hi:
            continue
        if hi == lo:
            out.append((k, 0.5 * (A[k] + A[k + 1]), float(np.max(np.abs(A[k + 1] - A[k])))))
            continue
        f = (speed - S[k]) / (S[k + 1] - S[k])
        out.append((k, A[k] + f * (A[k + 1] - A[k]), interpolation_error(S, A, k, speed)))
    if len(S) == 1 and math.isclose(S[0], speed, rel_tol=1e-9):
        out.append((-1, A[0], 0.0))
    return out


def match(
    branches: list[Branch], speed: float, amplitudes: np.ndarray, maps: list[np.ndarray], rtol: float = RTOL
) -> Match:
    """The state (speed [rpm], per-blade amplitudes [m]) against the branches (module docstring)."""
    amps = np.asarray(amplitudes, dtype=float)
    best = (math.inf, math.inf, -1)  # (excess over the tolerance, distance, branch) of the stable segments
    tol_best, any_best = math.nan, math.inf
    for b, br in enumerate(branches):
        for k, a, err in segments(br, speed):
            d = sym_distance(a, amps, maps)
            any_best = min(any_best, d)
            stable = bool(br.stable[0]) if k < 0 else bool(br.stable[k] or br.stable[k + 1])
            if not stable:
                continue
            tol = rtol + 2.0 * err / max(float(np.max(a)), float(np.max(amps)), 1e-300)
            if d - tol < best[0]:
                best, tol_best = (d - tol, d, b), tol
    return Match(best[0] <= 0.0, best[1], tol_best, best[2], any_best)
