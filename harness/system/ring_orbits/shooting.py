"""Periodic orbits of the ring: Newton shooting on its period map, Floquet multipliers.

Newton on R(x) = P(x) - x is the single blade's (harness.analysis.periodic.shooting.newton: damped,
quasi-Newton with a forward-difference DP updated by Broyden, scaled by the map's `scales`). The
monodromy matrix at a converged orbit is DP by forward differences over the state (backward where a
phi sits in its upper half; the ring's DP from forward and central differences agree to 1e-4, the
period_map's `central_differences`; its columns' periods on the map's threads, `images`), or with
`RingShootingSettings.dp` "low-rank" from directional differences in the row space of a DP taken
before, checked (derivative.py: about 2 m N + 8 periods instead of dim + 1), its eigenvalues the
Floquet multipliers; it is kept in the map's
memo of DPs (`jacobians`, continuation.JacobianMemo), so a continuation from the orbit starts without
another one. The period residual reported
is max |P(x) - x| / scale (scales: the largest displacement for every displacement, times omega for
every rate, 1 for every phi).
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import Callable

import numpy as np

from harness.analysis.periodic.continuation import JacobianMemo
from harness.analysis.periodic.shooting import UNIT_CIRCLE_TOL, classify, multipliers, newton
from harness.system.ring_orbits.derivative import forward_differences
from harness.system.ring_orbits.period_map import RingMapFailed, RingPeriodMap


@dataclass
class RingOrbit:
    """One periodic orbit of the ring at one speed."""

    speed: float  # [rpm]
    x: np.ndarray  # the state at load phase 0 (period_map)
    amplitudes: np.ndarray  # per blade max |q| over the period [m]
    multipliers: np.ndarray  # Floquet multipliers, largest modulus first
    residual: float  # scaled period residual max |P(x) - x| / scale
    iterations: int = 0

    @property
    def amplitude(self) -> float:
        return float(np.max(self.amplitudes))

    @property
    def max_multiplier(self) -> float:
        return float(np.max(np.abs(self.multipliers)))

    @property
    def stable(self) -> bool:
        return self.max_multiplier < 1.0 - UNIT_CIRCLE_TOL

    @property
    def label(self) -> str:
        return classify(self.multipliers)

    def as_dict(self) -> dict:
        return {
            "speed_rpm": self.speed,
            "amplitudes_m": self.amplitudes.tolist(),
            "stable": self.stable,
            "label": self.label,
            "max_multiplier": self.max_multiplier,
            "period_residual": self.residual,
            "multipliers": [{"re": float(m.real), "im": float(m.imag)} for m in self.multipliers],
        }


def jacobians(pm: RingPeriodMap) -> JacobianMemo:
    """The map's memo of DPs, shared by every branch problem on it (attached on first use)."""
    memo = getattr(pm, "jacobians", None)
    if memo is None:
        memo = pm.jacobians = JacobianMemo()
    return memo


def monodromy(pm: RingPeriodMap, x: np.ndarray, speed: float, Px: np.ndarray | None = None) -> np.ndarray:
    """DP at x, by forward differences (one-sided away from a bound) or low-rank as the map's
    settings say (derivative.py), in physical units; from the map's memo where it was taken before."""
    memo = jacobians(pm)
    known = memo.get(x, speed)
    if known is not None:
        return known[0]
    if Px is None:
        Px = pm(x, speed)[0]
    got = pm.state_jacobian(x, speed, Px)
    J = got[0] if got is not None else forward_differences(pm, x, speed, Px)[0]
    memo.put(x, speed, J)
    return J


def shoot(
    pm: RingPeriodMap,
    x0: np.ndarray,
    speed: float,
    tol: float | None = None,
    skip: Callable[[float, np.ndarray], bool] | None = None,
) -> RingOrbit | None:
    """The periodic orbit Newton reaches from x0 at speed, with its multipliers; None if Newton
    does not converge, the map fails, or skip(speed, per-blade amplitudes) says the orbit is known
    (then before its DP is taken: a DP costs dim + 1 periods)."""
    sol = newton(pm, x0, speed, tol=tol)
    if sol is None:
        return None
    amp, res = pm.measures(sol.x, speed)
    if skip is not None and skip(float(speed), amp):
        return None
    try:
        J = monodromy(pm, sol.x, speed, sol.Px)
    except RingMapFailed:
        return None
    return RingOrbit(float(speed), sol.x.copy(), amp.copy(), multipliers(J), res, sol.iterations)
