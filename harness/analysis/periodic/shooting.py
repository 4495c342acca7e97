"""Newton shooting on the FMU's period map, Floquet multipliers and their labels.

A periodic orbit is a fixed point x = P(x) of the period map (harness.analysis.periodic.period_map). Newton
on R(x) = P(x) - x, damped by halving while the scaled residual grows, with DP from the FMU's
sensitivities (every period brings its exact DP, docs/model-notes.md s.8), or else a
forward-difference DP (one period per unknown) updated by Broyden. The monodromy matrix is DP at
the orbit (sensitivities, or central differences once converged, one-sided where the unknown
sits on a bound: the Jenkins element's slip limit |phi| = 1); its eigenvalues are the Floquet
multipliers. An orbit is stable if every
multiplier lies inside the unit circle; an unstable one is labelled by how it lost stability:
"fold" (a real multiplier > 1), "period-doubling" (a real one < -1), "Neimark-Sacker" (a complex
pair outside).
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field
from typing import Any, cast

import numpy as np

from harness.fmu.blade import FMUError
from harness.model.params import ParameterError
from harness.analysis.periodic.period_map import PeriodMap

MAX_UPHILL = 3  # Newton steps that raise the residual even at the smallest damping, then give up
UNIT_CIRCLE_TOL = 1e-6  # |mu| within this of 1 counts as on the circle (finite-difference accuracy)


@dataclass
class Orbit:
    """One periodic orbit at one speed."""

    model: str
    speed: float  # [rpm]
    x: np.ndarray  # unknowns at load phase 0 (see period_map: q0 [m], q0' [m/s], B [m] or phi [-])
    amplitude: float  # max |q| over the period [m]
    B: float  # amplitude in use by the describing function [m] (nan for the Jenkins element)
    multipliers: np.ndarray  # Floquet multipliers (complex), largest modulus first
    residual: float  # max scaled |P(x) - x|
    iterations: int
    start_values: dict[str, Any] = field(default_factory=dict)  # FMU start values that start a run on the orbit

    @property
    def stable(self) -> bool:
        return bool(np.max(np.abs(self.multipliers)) < 1.0 - UNIT_CIRCLE_TOL)

    @property
    def label(self) -> str:
        return classify(self.multipliers)

    def as_dict(self) -> dict[str, Any]:
        return {
            "model": self.model,
            "speed_rpm": self.speed,
            "amplitude_m": self.amplitude,
            "B_m": None if math.isnan(self.B) else self.B,
            "stable": self.stable,
            "label": self.label,
            "stability": describe(self.multipliers),
            "multipliers": [{"re": float(m.real), "im": float(m.imag), "abs": float(abs(m))} for m in self.multipliers],
            "start_values": self.start_values,
            "residual": self.residual,
            "iterations": self.iterations,
        }


def classify(mu: np.ndarray) -> str:
    """'stable', or the kind of the multipliers outside the unit circle: 'fold' (real > 1),
    'period-doubling' (real < -1), 'Neimark-Sacker' (complex pair); joined with '+' if several."""
    out = []
    for m in mu:
        if abs(m) < 1.0 + UNIT_CIRCLE_TOL:
            continue
        if abs(m.imag) > UNIT_CIRCLE_TOL * abs(m):
            kind = "Neimark-Sacker"
        else:
            kind = "fold" if m.real > 0 else "period-doubling"
        if kind not in out:
            out.append(kind)
    return "+".join(out) if out else ("stable" if np.max(np.abs(mu)) < 1.0 - UNIT_CIRCLE_TOL else "marginal")


def describe(mu: np.ndarray) -> str:
    """What the multipliers say, in words: 'stable', 'marginal (...)' or 'unstable: <kind> (<which
    multiplier>)' for every kind of classify (fold: a real multiplier > 1; period doubling: a real
    one < -1; Neimark-Sacker: a complex pair outside the unit circle)."""
    label = classify(mu)
    if label == "stable":
        return label
    if label == "marginal":
        return f"marginal (largest |mu| = {np.max(np.abs(mu)):.6f}, on the unit circle)"
    why = []
    for kind in label.split("+"):
        if kind == "fold":
            m = max(float(m.real) for m in mu if abs(m.imag) <= UNIT_CIRCLE_TOL * abs(m) and m.real > 0)
            why.append(f"fold (a real multiplier {m:.4g} > 1)")
        elif kind == "period-doubling":
            m = min(float(m.real) for m in mu if abs(m.imag) <= UNIT_CIRCLE_TOL * abs(m) and m.real < 0)
            why.append(f"period doubling (a real multiplier {m:.4g} < -1)")
        else:
            m = max(abs(m) for m in mu if abs(m.imag) > UNIT_CIRCLE_TOL * abs(m))
            why.append(f"Neimark-Sacker (a complex pair of modulus {m:.4g} > 1)")
    return "unstable: " + "; ".join(why)


def bounded(pm: PeriodMap, x: np.ndarray) -> np.ndarray:
    """x moved into the unknowns' domain: B > 0, |phi| <= 1 (and phi = 0 while open). A period map
    with its own domain (a method `bounded`, e.g. the ring's) moves x itself."""
    if hasattr(pm, "bounded"):
        return cast(np.ndarray, pm.bounded(x))
    x = x.copy()
    if pm.model == "jenkins":
        x[-1] = 0.0 if abs(pm.tip(x)[0]) <= pm.d else min(max(float(x[-1]), -1.0), 1.0)
    elif pm.dim % 2:  # fixedPoint, coulomb: the last unknown is B
        x[-1] = max(x[-1], 1e-3 * max(pm.d, 1e-9))
    return x


def fd_direction(pm: PeriodMap, x: np.ndarray, j: int) -> float:
    """+1, or -1 where a forward step would leave the domain (phi at +1, B near 0); the period
    map's own rule if it has one (`fd_direction`)."""
    if hasattr(pm, "fd_direction"):
        return float(pm.fd_direction(x, j))
    if pm.model == "jenkins" and j == pm.dim - 1 and x[j] > 0.0:
        return -1.0
    return 1.0


def at_bound(pm: PeriodMap, x: np.ndarray, j: int) -> bool:
    """True if unknown j sits on its bound (the Jenkins element's slip limit |phi| = 1), where only
    a one-sided difference stays in the domain; the period map's own rule if it has one."""
    if hasattr(pm, "at_bound"):
        return bool(pm.at_bound(x, j))
    return pm.model == "jenkins" and j == pm.dim - 1 and abs(x[j]) >= 1.0


def images(pm: PeriodMap, points: list[tuple[np.ndarray, float]]) -> list[np.ndarray]:
    """P(x) at every (x, speed), in order: the map's own batch where it has one (`images`: the ring's
    runs them on several threads, the same numbers), else one call each."""
    if hasattr(pm, "images"):
        return cast(list[np.ndarray], pm.images(points))
    return [pm(x, n)[0] for x, n in points]


def jacobian(pm: PeriodMap, x: np.ndarray, speed_rpm: float, Px: np.ndarray, central: bool = False) -> np.ndarray:
    """DP at x (forward differences from the known P(x), or central ones) in physical units; the
    map's own forward DP where it takes one (`state_jacobian`: the ring's "low-rank" DP)."""
    own = getattr(pm, "state_jacobian", None) if not central else None
    got = own(x, speed_rpm, Px) if own is not None else None
    if got is not None:
        return cast(np.ndarray, got[0])
    sc = pm.scales(x, speed_rpm)
    J = np.empty((pm.dim, pm.dim))
    steps: list[tuple[float, bool]] = []  # per column: (h, central)
    points: list[tuple[np.ndarray, float]] = []
    for j in range(pm.dim):
        h = pm.s.fd_rel * sc[j] * fd_direction(pm, x, j)
        xp = x.copy()
        xp[j] += h
        points.append((xp, speed_rpm))
        both = central and not at_bound(pm, x, j)
        if both:
            xm = x.copy()
            xm[j] -= h
            points.append((xm, speed_rpm))
        steps.append((h, both))
    P = iter(images(pm, points))
    for j, (h, both) in enumerate(steps):
        Pp = next(P)
        J[:, j] = (Pp - next(P)) / (2.0 * h) if both else (Pp - Px) / h
    return J


def multipliers(J: np.ndarray) -> np.ndarray:
    mu = np.linalg.eigvals(J)
    return mu[np.argsort(-np.abs(mu))]


def broyden(J: np.ndarray, dx: np.ndarray, dP: np.ndarray, sc: np.ndarray) -> np.ndarray:
    """Broyden's ("good") rank-one update of a Jacobian J ~ DP after the step dx moved P by dP:
    the least change (in the unknowns' scales sc) with J dx = dP."""
    w = dx / sc**2
    den = float(dx @ w)
    return J + np.outer(dP - J @ dx, w) / den if den > 0.0 else J


@dataclass
class Solution:
    """A converged root of P(x) = x (no multipliers): what newton() returns."""

    x: np.ndarray
    Px: np.ndarray
    amplitude: float
    residual: float
    iterations: int
    J: np.ndarray | None  # DP near x, Broyden-updated (an estimate), or exact at x; None if none was needed
    exact: bool = False  # J is DP at x from the FMU's sensitivities (the monodromy matrix)


def newton(
    pm: PeriodMap,
    x0: np.ndarray,
    speed_rpm: float,
    J0: np.ndarray | None = None,
    tol: float | None = None,
    quasi: bool = True,
) -> Solution | None:
    """Damped Newton on R(x) = P(x) - x from x0, or None. With the FMU's sensitivities (the
    default settings) every evaluation brings DP at its point: Newton proper, J0 and quasi unused.
    Without them, quasi (default) makes it a quasi-Newton method: DP from J0 (DP of a nearby
    problem, e.g. the previous point of a scan) or forward differences (one period per unknown),
    updated by Broyden after every step, a fresh DP only when a step fails to halve the residual;
    without quasi every step takes a fresh DP."""
    tol = pm.s.tol if tol is None else tol
    sens = pm.s.sensitivities  # every evaluation brings its exact DP: Newton proper
    x = bounded(pm, np.asarray(x0, dtype=float))
    try:
        Px, A = pm(x, speed_rpm)
    except (FMUError, ParameterError):
        return None
    Jx = pm.DP
    J, fresh = (None, False) if J0 is None else (np.array(J0, dtype=float), False)
    uphill = 0  # steps with a fresh DP that did not lower the residual (give up after MAX_UPHILL)
    for it in range(1, pm.s.max_iter + 1):
        sc = pm.scales(x, speed_rpm)
        res = float(np.max(np.abs((Px - x) / sc)))
        if res <= tol:
            return Solution(x, Px, float(A), res, it - 1, Jx if sens else J, exact=sens)
        try:
            if sens:
                J, fresh = Jx, True
            elif J is None:
                J, fresh = jacobian(pm, x, speed_rpm, Px), True
            assert J is not None  # with sensitivities every evaluation sets DP
            dx = np.linalg.solve(J - np.eye(pm.dim), -(Px - x))
        except (FMUError, ParameterError, np.linalg.LinAlgError):
            return None
        lam = 1.0
        for _ in range(8):  # damping: halve while the residual grows or the FMU refuses the start
            xn = bounded(pm, x + lam * dx)
            try:
                Pn, An = pm(xn, speed_rpm)
                Jn = pm.DP
                rn = float(np.max(np.abs((Pn - xn) / pm.scales(xn, speed_rpm))))
            except (FMUError, ParameterError):
                rn = math.inf
            if rn < res or lam < 0.02 or not fresh:
                break
            lam *= 0.5
        if not fresh and not rn < 0.5 * res:
            J = None  # the updated DP no longer points the way: a fresh one, from x again
            if not rn < res:
                continue
        if not math.isfinite(rn):
            return None
        if rn >= res:
            uphill += 1
            if uphill > MAX_UPHILL:
                return None  # Newton crawls away from a root it cannot reach from here
        if J is not None and not sens:
            J, fresh = (broyden(J, xn - x, Pn - Px, sc), False) if quasi else (None, False)
        x, Px, A, Jx = xn, Pn, An, Jn
    return None


def shoot(pm: PeriodMap, x0: np.ndarray, speed_rpm: float) -> Orbit | None:
    """newton() from x0; the orbit with its multipliers, or None if Newton does not converge (or
    the FMU refuses every damped step)."""
    sol = newton(pm, x0, speed_rpm)
    return None if sol is None else orbit(pm, sol, speed_rpm)


def orbit(pm: PeriodMap, sol: Solution, speed_rpm: float, central: bool = True) -> Orbit:
    """The Orbit of a converged root: its monodromy matrix taken afresh (central differences, or
    forward ones), its multipliers and the FMU start values that start a run on it."""
    x = sol.x
    J = sol.J if sol.exact else jacobian(pm, x, speed_rpm, sol.Px, central=central)
    assert J is not None  # an exact solution carries its DP
    B = math.nan if pm.model == "jenkins" else (pm.B if pm.model == "fixedB" else float(x[-1]))
    return Orbit(
        pm.model,
        float(speed_rpm),
        x.copy(),
        sol.amplitude,
        B,
        multipliers(J),
        sol.residual,
        sol.iterations,
        pm.start_values(x),
    )
