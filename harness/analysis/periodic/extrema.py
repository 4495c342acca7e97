"""Peaks and folds of a branch of periodic orbits, located by refinement, not read off its points.

Continuation samples a branch every few rpm; the largest sampled max|q| is not the peak and the
last point before the speed turns back is not the fold. Around every sampled extremum (a point
whose max|q| is above both neighbours', or where the speed turns back) the branch is parameterised
by sigma = a . z, a the unit secant through the two neighbours in the continuation's scaled
coordinates z = (x / sc, n / SPEED_SCALE); each sigma is one corrector solve of
H(z) = 0, a . z = sigma (harness.analysis.periodic.continuation.correct). Along sigma:
- a peak is the maximum of max|q| (d max|q| / ds = 0),
- a fold is the extremum of the speed (dn / ds = 0, the turning point of the branch),
found by Brent's bounded search (scipy.optimize.minimize_scalar) to SIGMA_TOL (1e-4 rpm of speed
for a unit secant along the speed). The multipliers are those of the located orbit.
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import Callable

import numpy as np
from scipy.optimize import minimize_scalar

from harness.analysis.periodic.continuation import Branch, BranchProblem, ContinuationSettings, correct
from harness.analysis.periodic.period_map import PeriodMap
from harness.analysis.periodic.shooting import classify, multipliers
from harness.fmu.blade import FMUError
from harness.model.params import ParameterError

SIGMA_TOL = 1e-7  # Brent's tolerance in sigma (scaled arc: 1e-4 rpm along the speed)


@dataclass
class Extremum:
    """A located peak or fold of a branch."""

    kind: str  # "peak" | "fold"
    speed: float  # [rpm]
    amplitude: float  # max |q| [m]
    x: np.ndarray  # the orbit's unknowns (period_map)
    multipliers: np.ndarray  # Floquet multipliers of the located orbit
    sides: tuple[str, str]  # stability labels of the sampled neighbours, in arc order

    @property
    def stable(self) -> bool:
        """A peak: its orbit is stable. A fold: it bounds a stable part of the branch (its orbit is
        the limit of stable orbits; its largest multiplier is 1)."""
        if self.kind == "fold":
            return "stable" in self.sides
        return classify(self.multipliers) == "stable"

    @property
    def stability(self) -> str:
        if self.kind == "peak":
            return _said(classify(self.multipliers))
        a, b = (_said(s) for s in self.sides)
        return (
            f"turning point between two {a} orbits"
            if a == b
            else f"turning point between a {a} and an {b} orbit"
            if b.startswith("unstable")
            else f"turning point between an {a} and a {b} orbit"
        )

    def as_dict(self) -> dict:
        return {
            "kind": self.kind,
            "speed_rpm": self.speed,
            "amplitude_m": self.amplitude,
            "stable": self.stable,
            "stability": self.stability,
            "mu_abs_max": float(np.max(np.abs(self.multipliers))),
        }


def _said(label: str) -> str:
    """'stable', or 'unstable (<why>)' for a label of shooting.classify."""
    return label if label == "stable" else f"unstable ({label})"


def candidates(branch: Branch) -> list[tuple[int, str]]:
    """(index, kind) of the sampled interior points that bracket a peak or a fold."""
    A, n = branch.amplitudes, branch.speeds
    out = []
    for i in range(1, len(A) - 1):
        if A[i] > A[i - 1] and A[i] >= A[i + 1]:
            out.append((i, "peak"))
        if (n[i] - n[i - 1]) * (n[i + 1] - n[i]) < 0:
            out.append((i, "fold"))
    return out


class _Section:
    """The branch near point i, parameterised by sigma along the secant through i - 1 and i + 1."""

    def __init__(self, pm: PeriodMap, branch: Branch, i: int, settings: ContinuationSettings):
        self.settings = settings
        pts = branch.points[i - 1 : i + 2]
        self.prob = BranchProblem(pm, pm.scales(pts[1].x, pts[1].speed))
        self.z = [self.prob.to_z(p.x, p.speed) for p in pts]
        self.amplitudes = [p.amplitude for p in pts]
        a = self.z[2] - self.z[0]
        self.a = a / np.linalg.norm(a)
        self.sigma = [float(self.a @ z) for z in self.z]
        Hz, Px, _ = self.prob.H(self.z[1])
        self.Jz = self.prob.jac(self.z[1], Hz, Px)[0]
        self.solved: dict[float, tuple[np.ndarray, float]] = {}  # sigma -> (z, amplitude)

    def guess(self, sigma: float) -> np.ndarray:
        """The nearest solved point (else the sampled one), moved onto the plane a . z = sigma."""
        known = [(s, z) for s, (z, _) in self.solved.items()] + list(zip(self.sigma, self.z))
        z = min(known, key=lambda sz: abs(sz[0] - sigma))[1]
        return z + (sigma - float(self.a @ z)) * self.a

    def solve(self, sigma: float) -> tuple[np.ndarray, float] | None:
        """(z, max|q|) of the branch point on a . z = sigma, or None if the corrector fails."""
        if sigma in self.solved:
            return self.solved[sigma]
        zp = self.guess(sigma)
        for quasi in (True, False):
            try:
                done = correct(self.prob, zp, self.a, self.Jz, self.settings, quasi)
            except (FMUError, ParameterError):
                done = None
            if done is not None:
                self.solved[sigma] = (done[0], done[3])
                return self.solved[sigma]
        return None

    def located(
        self,
        kind: str,
        objective: Callable[[np.ndarray, float], float],
        sides: tuple[str, str],
        xatol: float = SIGMA_TOL,
    ) -> Extremum | None:
        """The minimum of objective(z, amplitude) over sigma between the neighbours."""
        # where the corrector finds no branch point the objective is undefined: a finite value above
        # the three sampled points' keeps Brent away from it (an infinite one turns its parabola
        # step into inf - inf = nan)
        sampled = [objective(z, amp) for z, amp in zip(self.z, self.amplitudes)]
        worse = max(sampled) + (max(sampled) - min(sampled)) + abs(max(sampled)) + 1.0

        def f(sigma: float) -> float:
            sol = self.solve(sigma)
            return worse if sol is None else objective(*sol)

        lo, hi = sorted((self.sigma[0], self.sigma[2]))
        res = minimize_scalar(f, bounds=(lo, hi), method="bounded", options={"xatol": xatol})
        sol = self.solve(float(res.x))
        if sol is None:
            return None
        z, amp = sol
        Hz, Px, _ = self.prob.H(z)
        try:
            DP = self.prob.jac(z, Hz, Px)[1]
        except (FMUError, ParameterError):
            return None
        x, n = self.prob.from_z(z)
        return Extremum(kind, n, amp, x, multipliers(DP), sides)


def locate(
    pm: PeriodMap,
    branch: Branch,
    settings: ContinuationSettings = ContinuationSettings(),
    keep: Callable[[int, str], bool] | None = None,
    xatol: float = SIGMA_TOL,
) -> list[Extremum]:
    """The located peaks and folds of `branch` (in arc order); an extremum whose refinement fails
    is left out (its sampled point stays on the branch). keep(index, kind): locate only the
    candidates it accepts (default: all); xatol: Brent's tolerance in sigma."""
    out = []
    for i, kind in candidates(branch):
        if keep is not None and not keep(i, kind):
            continue
        p = branch.points
        sides = (p[i - 1].label, p[i + 1].label)
        sec = _Section(pm, branch, i, settings)
        if kind == "peak":
            e = sec.located(kind, lambda z, amp: -amp, sides, xatol)
        else:
            turn = 1.0 if p[i].speed > p[i - 1].speed else -1.0  # +1: the speed has a maximum here
            e = sec.located(kind, lambda z, amp: -turn * float(z[-1]), sides, xatol)
        if e is not None:
            out.append(e)
    return out
