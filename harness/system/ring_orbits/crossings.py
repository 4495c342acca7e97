"""Branch points, period doublings and Neimark-Sacker points of a ring branch: detected beyond the
multipliers' noise, located in the arc by Brent's method on the test function.

Test functions of an orbit's multipliers mu (per kind, of the multiplier that crosses the circle):
- branch point: the real positive multiplier closest to +1, minus 1 (not the largest: on an
  unstable travelling wave another real multiplier may sit far above 1 while a second one crosses);
- period doubling: |the real negative multiplier closest to -1| - 1;
- Neimark-Sacker: |the complex multiplier closest to the circle| - 1.
Detection with hysteresis: a multiplier within NOISE of the circle is undecided (the
finite-difference DP puts a multiplier that sits at 1 anywhere within about 1e-3 of it, so a branch
along which one hovers there would list a crossing between most neighbours). For each kind a point
is decided when none of its multipliers of that kind is within NOISE of the circle; a crossing is a
change of the number outside between two decided points, the undecided ones between them skipped.
It is located on the segment between neighbours where the test function changes sign (the first,
else the one next to the decided point before): Newton on the plane normal to the chord at the arc
fraction f (quasi-Newton from the last DP taken, the segment start's from the map's memo; where that
fails, from a fresh DP at f, and only then Newton with a fresh DP per iteration), and f
chosen by Brent's method (secant and inverse quadratic steps, bisection where they do not shrink the
bracket fast enough) until the bracket of both signs is ARC_TOL of scaled arc long (about 0.1 rpm
where the branch runs along the speed). First on an estimated test function (estimator: the
multipliers from k directional derivatives in the invariant subspace of the critical multiplier of
the nearer end's DP, k periods where a DP is one per unknown), then the bracket so found checked with
a fresh DP at each end; where the signs hold it is the result, else Brent's method goes on with a
fresh DP per fraction (at most MAX_STEPS) from the shortest bracket of both signs known. The located
orbit is the bracket's end with the smaller |test function|. Where the corrector fails inside the
bracket (a kink of the map: the multiplier jumps through 1 there rather than crossing it) the search
stops and the bracket's better end is returned with its length, flagged `located` False; where it
fails at once or the test function has the same sign at both ends (another multiplier came closer),
the point is the linear zero between the ends, also `located` False. A located crossing whose test function is still
beyond JUMP at the bracket's better end is a jump of the multiplier through the circle (a kink of the
map), not a smooth crossing: `jump` True (no branch need emanate there).
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import Callable

import numpy as np
from scipy.optimize import brentq

from harness.analysis.periodic.continuation import BranchPoint, BranchProblem, ContinuationSettings, correct
from harness.analysis.periodic.shooting import UNIT_CIRCLE_TOL, multipliers
from harness.fmu.blade import FMUError
from harness.system.ring_orbits.period_map import RingPeriodMap
from harness.system.ring_orbits.shooting import jacobians, monodromy

NOISE = 1e-3  # a multiplier within this of the unit circle is undecided (the finite-difference DP's spread)
ARC_TOL = 1e-4  # the location ends when the bracket is this long in scaled arc (0.1 rpm along the speed)
MAX_STEPS = 14  # corrector solves (each with its DP) per crossing
JUMP = 1e-2  # a bracket of ARC_TOL whose better end is still this far from 0: the multiplier jumps
# through the circle there (a kink of the map: a contact opening or closing at the period's start)
KINDS = ("branch point", "period doubling", "Neimark-Sacker")
CLUSTER = 0.1  # the estimator's subspace: the multipliers within this of the critical one
MAX_ESTIMATES = 30  # corrector solves with an estimated test function per crossing


def _select(mu: np.ndarray, kind: str) -> np.ndarray:
    real = np.abs(mu.imag) <= UNIT_CIRCLE_TOL * np.maximum(np.abs(mu), 1e-300)
    sel = {"branch point": real & (mu.real > 0), "period doubling": real & (mu.real < 0)}.get(kind, ~real)
    return mu[sel]


def critical_value(mu: np.ndarray, kind: str) -> float:
    """|mu| - 1 of the multiplier of `kind` closest to the circle (nan if there is none)."""
    vals = np.abs(_select(mu, kind)) - 1.0
    return float(vals[np.argmin(np.abs(vals))]) if len(vals) else float("nan")


def decided(mu: np.ndarray, kind: str, noise: float = NOISE) -> int | None:
    """The number of multipliers of `kind` outside the circle, or None if one is within `noise` of it."""
    r = np.abs(_select(mu, kind))
    if np.any(np.abs(r - 1.0) <= noise):
        return None
    return int(np.sum(r > 1.0))


def detect(mus: list[np.ndarray], kind: str, noise: float = NOISE) -> list[tuple[int, int]]:
    """(i, j): the decided points around each crossing of `kind` along a branch's multipliers."""
    out = []
    last: tuple[int, int] | None = None  # (index, count) of the last decided point
    for k, mu in enumerate(mus):
        c = decided(mu, kind, noise)
        if c is None:
            continue
        if last is not None and c != last[1]:
            out.append((last[0], k))
        last = (k, c)
    return out


@dataclass
class Located:
    """A located crossing: the orbit there and its multipliers."""

    x: np.ndarray
    speed: float  # [rpm]
    multipliers: np.ndarray
    DP: np.ndarray | None  # the monodromy matrix there (physical units), None if interpolated
    value: float  # the test function there
    bracket: float  # the final bracket's length in scaled arc
    located: bool  # False: the linear zero between the segment's ends

    @property
    def jump(self) -> bool:
        return self.located and abs(self.value) > JUMP


def segment(mus: list[np.ndarray], i: int, j: int, kind: str) -> int:
    """The k in [i, j) whose segment (k, k + 1) holds the sign change of the test function (first
    one), else i."""
    for k in range(i, j):
        a, b = critical_value(mus[k], kind), critical_value(mus[k + 1], kind)
        if np.isfinite(a) and np.isfinite(b) and a * b <= 0.0:
            return k
    return i


class _Stop(Exception):
    """The corrector or the multipliers failed inside the bracket: the search ends there."""


def locate(pm: RingPeriodMap, a: BranchPoint, b: BranchPoint, kind: str, settings: ContinuationSettings) -> Located:
    """The zero of the test function of `kind` on the branch between its neighbouring points a, b
    (see the module docstring)."""
    ga, gb = critical_value(a.multipliers, kind), critical_value(b.multipliers, kind)
    f_lin = 0.5 if not (np.isfinite(ga) and np.isfinite(gb)) or ga == gb else min(1.0, max(0.0, ga / (ga - gb)))
    interpolated = Located(
        a.x + f_lin * (b.x - a.x),
        a.speed + f_lin * (b.speed - a.speed),
        a.multipliers if f_lin < 0.5 else b.multipliers,
        None,
        float("nan"),
        float("nan"),
        False,
    )
    if not (np.isfinite(ga) and np.isfinite(gb)) or ga * gb > 0.0:
        return interpolated
    jacobians(pm)
    prob = BranchProblem(pm, pm.scales(a.x, a.speed))
    za, zb = prob.to_z(a.x, a.speed), prob.to_z(b.x, b.speed)
    chord = zb - za
    length = float(np.linalg.norm(chord))
    t = chord / length
    try:
        Hz, Px, _ = prob.H(za)
        Jz = [prob.jac(za, Hz, Px)[0]]  # the last DP taken: the next corrector's start (a's from the memo)
    except FMUError:
        return interpolated
    # f -> (g, x, speed, multipliers, DP) at the fraction f of the chord
    seen: dict[float, tuple] = {
        0.0: (ga, a.x, a.speed, a.multipliers, None),
        1.0: (gb, b.x, b.speed, b.multipliers, None),
    }
    solved: dict[float, tuple] = {}  # f -> the corrector's (z, H, P) there

    def solve(f: float) -> tuple:
        if f not in solved:
            try:
                zf = za + f * chord
                # Broyden from the last DP taken, else from a fresh one at zf (one DP), else a
                # fresh one per iteration (its first from the memo)
                done = (
                    correct(prob, zf, t, Jz[0], settings, quasi=True)
                    or correct(prob, zf, t, Jz[0], settings, quasi=True, fresh_start=True)
                    or correct(prob, zf, t, Jz[0], settings, quasi=False)
                )
            except FMUError:
                raise _Stop from None
            if done is None:
                raise _Stop  # a kink of the map inside the bracket: the multiplier jumps there
            solved[f] = done[:3]
        return solved[f]

    def g(f: float) -> float:
        if f in seen:
            return seen[f][0]
        if len(seen) - 2 >= MAX_STEPS:
            raise _Stop
        zk, Hk, Pk = solve(f)
        try:
            Jk, DP = prob.jac(zk, Hk, Pk)
        except FMUError:
            raise _Stop from None
        mu = multipliers(DP)
        val = critical_value(mu, kind)
        if not np.isfinite(val):
            raise _Stop
        Jz[0] = Jk
        x, speed = prob.from_z(zk)
        seen[f] = (val, x, speed, mu, DP)
        return val

    xtol = ARC_TOL / length
    try:  # the bracket by the estimated test function, then its ends with full DPs
        lo, hi = _estimated_bracket(pm, prob, a, b, kind, solve, xtol)
        g(lo), g(hi)
    except (_Stop, FMUError, np.linalg.LinAlgError):
        pass
    lo, hi = (e[0] for e in _bracket(seen, ga))
    if (hi - lo) * length > ARC_TOL:
        try:  # Brent's method on the test function: ends with a bracket of both signs shorter than ARC_TOL
            brentq(g, lo, hi, xtol=xtol, maxiter=MAX_STEPS + 2)
        except (_Stop, RuntimeError):
            pass
    lo, hi = _bracket(seen, ga)
    best = min((e for e in (lo, hi) if e[1][4] is not None), key=lambda e: abs(e[1][0]), default=None)
    if best is None:
        return interpolated
    val, x, speed, mu, DP = best[1]
    bracket = (hi[0] - lo[0]) * length
    return Located(x, speed, mu, DP, val, bracket, bracket <= ARC_TOL)


def estimator(pm: RingPeriodMap, DP: np.ndarray, kind: str) -> Callable[[np.ndarray, np.ndarray, float], float]:
    """The test function of `kind` at an orbit x (image Px, speed) near the one whose DP is given,
    from k directional derivatives (k periods) instead of a DP: DP's invariant subspace of the
    critical multiplier and of those within CLUSTER of it (and their conjugates), a real basis Q of
    it and its left eigenvectors L; the multipliers there are those of (L Q)^-1 L DP(x) Q, exact to
    first order in the change of DP (the eigenvalues' perturbation), the rest of second order."""
    w, V = np.linalg.eig(DP)
    sel = np.isin(w, _select(w, kind))
    c = int(np.argmin(np.where(sel, np.abs(np.abs(w) - 1.0), np.inf)))
    near = (np.abs(w - w[c]) <= CLUSTER) | (np.abs(w - np.conj(w[c])) <= CLUSTER)
    k = int(np.sum(near))
    U = np.linalg.svd(np.hstack([V[:, near].real, V[:, near].imag]), full_matrices=False)[0]
    Q = U[:, :k]
    L = np.linalg.inv(V)[near, :]
    LQ = L @ Q

    def value(x: np.ndarray, Px: np.ndarray, speed: float) -> float:
        sc = pm.scales(x, speed)
        DQ = np.empty((pm.dim, k))
        steps = []
        for j in range(k):
            q = Q[:, j]
            h = pm.s.fd_rel / float(np.max(np.abs(q / sc)))
            out = [i for i in range(pm.dim) if pm.at_bound(x, i) and q[i] * x[i] > 0.0]
            steps.append(-h if out else h)  # keep a phi on its slip limit inside the cone
        for j, (h, Pq) in enumerate(zip(steps, pm.images([(x + h * Q[:, j], speed) for j, h in enumerate(steps)]))):
            DQ[:, j] = (Pq - Px) / h
        return critical_value(np.linalg.eigvals(np.linalg.solve(LQ, L @ DQ)), kind)

    return value


def _estimated_bracket(
    pm: RingPeriodMap, prob: BranchProblem, a, b, kind: str, solve, xtol: float
) -> tuple[float, float]:
    """(lo, hi): the chord fractions around the zero of the estimated test function (estimator,
    from the DP of the nearer end: the memo's), by Brent's method to xtol; each fraction one
    corrector solve and k periods."""
    ends = [estimator(pm, monodromy(pm, p.x, p.speed), kind) for p in (a, b)]
    est: dict[float, float] = {0.0: critical_value(a.multipliers, kind), 1.0: critical_value(b.multipliers, kind)}

    def g(f: float) -> float:
        if f not in est:
            zk, _, Pk = solve(f)
            x, speed = prob.from_z(zk)
            est[f] = ends[f > 0.5](x, Pk, speed)
            if not np.isfinite(est[f]):
                raise _Stop
        return est[f]

    try:
        brentq(g, 0.0, 1.0, xtol=xtol, maxiter=MAX_ESTIMATES)
    except RuntimeError:
        pass
    fs = sorted(est)
    pairs = [(p, q) for p, q in zip(fs[:-1], fs[1:]) if (est[p] * est[0.0] > 0.0) != (est[q] * est[0.0] > 0.0)]
    return min(pairs, key=lambda pq: pq[1] - pq[0])


def _bracket(seen: dict[float, tuple], ga: float) -> tuple[tuple[float, tuple], tuple[float, tuple]]:
    """The shortest pair of neighbouring fractions whose test functions have opposite signs (the
    first one's that of a), as (f, entry) each: the bracket the search ended with."""
    fs = sorted(seen)
    pairs = [(p, q) for p, q in zip(fs[:-1], fs[1:]) if (seen[p][0] * ga > 0.0) != (seen[q][0] * ga > 0.0)]
    p, q = min(pairs, key=lambda pq: pq[1] - pq[0])
    return (p, seen[p]), (q, seen[q])
