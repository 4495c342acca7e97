"""Independent Python reference, part 2: the shroud contact (paper eq. 1-13, MODEL.md s.3).

Normal force (eq. 3), the macroslip friction loop (eq. 4) with its angles (eq. 5) and the Coulomb
limit of the loop (docs/model-notes.md s.5), and their describing functions f_k, f_c, p_k, K_eq,
C_eq computed two ways: the closed forms (eq. 7, eq. 8 with the MODEL.md fix, eq. 10; full stick;
Coulomb) vectorised over the amplitude B, and a numerical (Gauss-Legendre) quadrature of the
piecewise loop split at its breakpoints. All per unit v (the contact coordinate), f_c carries 1/omega.
Also: the loop state at a phase (model-notes s.4) and the closed-form cycle dissipation of the
time-domain Jenkins element driven by a prescribed harmonic motion (model-notes s.2), which is not
the paper's loop: see `jenkins_cycle_dissipation`.
"""
from __future__ import annotations

import math
from dataclasses import dataclass
from typing import Any, Mapping

import numpy as np

from harness.params import validate

OPEN, STICK_SLIP, FULL_STICK = 0, 1, 2  # regime (MODEL.md s.3)
STATE_OPEN, STATE_STICK, STATE_SLIP = 0, 1, 2  # contactState (model-notes s.4)
MACROSLIP_DF, COULOMB_DF, MACROSLIP_TD = 1, 2, 3  # frictionModel


@dataclass(frozen=True)
class ContactConsts:
    """Contact constants: k_n [N/m], k_d [N/m], mu [-], gamma [rad], d [m]."""

    kn: float
    kd: float
    mu: float
    gamma: float
    d: float

    @property
    def a(self) -> float:
        """k_d sin(gamma): tangential spring force per unit v [N/m]."""
        return self.kd * math.sin(self.gamma)

    @property
    def b(self) -> float:
        """mu k_n cos(gamma): friction limit per unit of |v| - d [N/m]."""
        return self.mu * self.kn * math.cos(self.gamma)

    @property
    def full_stick(self) -> bool:
        """k_d tan(gamma) < mu k_n (MODEL.md s.3): the loop never slips."""
        return self.kd * math.tan(self.gamma) < self.mu * self.kn


def contact_consts(params: Mapping[str, Any]) -> ContactConsts:
    p = validate(params)
    kn = float(p["kn"])
    return ContactConsts(kn=kn, kd=float(p["kdRatio"]) * kn, mu=float(p["mu"]), gamma=float(p["gamma"]),
                         d=float(p["d"]))


@dataclass
class DF:
    """Describing function at amplitude(s) B. Arrays broadcast like B (scalars for scalar B)."""

    fk: Any  # friction stiffness per unit v [N/m] (eq. 7)
    fc: Any  # friction damping per unit v [N s/m] (eq. 8 fixed), = fcOmega / omega
    pk: Any  # normal stiffness per unit v [N/m] (eq. 10)
    Keq: Any  # equivalent stiffness [N/m] (eq. 12, projection applied)
    Ceq: Any  # equivalent damping [N s/m] (eq. 13, projection applied)
    regime: Any  # 0 open, 1 stick-slip, 2 full stick
    theta1: Any  # loop angles eq. 5 [rad] (0 where not defined)
    theta2: Any
    theta3: Any
    fcOmega: Any  # f_c * omega [N/m]
    CeqOmega: Any  # C_eq * omega [N/m]


def normal_force(params: Mapping[str, Any] | ContactConsts, v: Any) -> Any:
    """F_n(v) [N], eq. 3 (vectorised)."""
    cc = params if isinstance(params, ContactConsts) else contact_consts(params)
    v = np.asarray(v, dtype=float)
    cg = math.cos(cc.gamma)
    out = np.where(v > cc.d, cc.kn * (v - cc.d) * cg, np.where(v < -cc.d, cc.kn * (v + cc.d) * cg, 0.0))
    return out[()] if out.ndim == 0 else out


def _clip_acos(x: np.ndarray) -> np.ndarray:
    return np.arccos(np.clip(x, -1.0, 1.0))


def loop_angles(params: Mapping[str, Any] | ContactConsts, B: Any, model: int = MACROSLIP_DF) -> tuple[Any, Any, Any]:
    """theta1, theta2, theta3 of eq. 5 for amplitude B > d (Coulomb: theta1 = 0, theta3 = pi - theta2).
    In full stick the eq.-5 arguments leave [-1, 1]; the clipped values are returned (theta1 = theta2,
    theta3 = pi in the limit k_d tan g = mu k_n). Where B <= d all three are 0."""
    cc = params if isinstance(params, ContactConsts) else contact_consts(params)
    Bv = np.asarray(B, dtype=float)
    Bs = np.where(Bv > cc.d, Bv, np.nan)
    th2 = _clip_acos(cc.d / Bs)
    if model == COULOMB_DF:
        th1 = np.zeros_like(th2)
        th3 = math.pi - th2
    else:
        kdt = cc.kd * math.tan(cc.gamma)
        mkn = cc.mu * cc.kn
        th1 = _clip_acos((kdt * Bs + 2.0 * mkn * cc.d - mkn * Bs) / (kdt * Bs + mkn * Bs))
        th3 = _clip_acos(-(cc.d * kdt + mkn * (Bs - cc.d)) / (Bs * kdt))
    th1, th2, th3 = (np.where(Bv > cc.d, t, 0.0) for t in (th1, th2, th3))
    if Bv.ndim == 0:
        return float(th1), float(th2), float(th3)
    return th1, th2, th3


def regime(params: Mapping[str, Any] | ContactConsts, B: Any, model: int = MACROSLIP_DF) -> Any:
    """0 open (B <= d), 1 stick-slip, 2 full stick (macroslip with k_d tan g < mu k_n)."""
    cc = params if isinstance(params, ContactConsts) else contact_consts(params)
    Bv = np.asarray(B, dtype=float)
    fs = FULL_STICK if (model != COULOMB_DF and cc.full_stick) else STICK_SLIP
    out = np.where(Bv > cc.d, fs, OPEN)
    return int(out) if out.ndim == 0 else out


def loop_friction(params: Mapping[str, Any] | ContactConsts, B: float, theta: Any, model: int = MACROSLIP_DF) -> Any:
    """F_f(theta) [N] of eq. 4 (model 1) or its Coulomb limit (model 2) for amplitude B > d,
    vectorised in theta (taken modulo 2 pi). In full stick (model 1, k_d tan g < mu k_n) the
    loop is elastic: F_f = k_d sin(g) (v -+ d) while |v| > d, else 0."""
    cc = params if isinstance(params, ContactConsts) else contact_consts(params)
    th = np.mod(np.asarray(theta, dtype=float), 2.0 * math.pi)
    B = float(B)
    if not B > cc.d:
        out = np.zeros_like(th)
        return out[()] if out.ndim == 0 else out
    sg, cg = math.sin(cc.gamma), math.cos(cc.gamma)
    v = B * np.cos(th)
    du = v * sg
    if model == MACROSLIP_DF and cc.full_stick:
        out = np.where(v > cc.d, cc.kd * (du - cc.d * sg), np.where(v < -cc.d, cc.kd * (du + cc.d * sg), 0.0))
        return out[()] if out.ndim == 0 else out
    t1, t2, t3 = loop_angles(cc, B, model)
    Ns = cc.mu * cc.kn * cg * (B - cc.d)
    # Interval edges of eq. 4, [edge_i, edge_{i+1}); interval 10 is closed at 2 pi.
    pieces = [
        cc.kd * (du - B * sg) + cc.mu * cc.kn * cg * (v - cc.d),  # 1
        -Ns + 0.0 * v,  # 2
        0.0 * v,  # 3
        cc.kd * (du + cc.d * sg),  # 4
        -Ns + 0.0 * v,  # 5
        cc.kd * (du + B * sg) + cc.mu * cc.kn * cg * (v + cc.d),  # 6
        Ns + 0.0 * v,  # 7
        0.0 * v,  # 8
        cc.kd * (du - cc.d * sg),  # 9
        Ns + 0.0 * v,  # 10
    ]
    idx = loop_interval(cc, B, th, model, angles=(t1, t2, t3))
    out = np.choose(idx - 1, pieces)
    return out[()] if out.ndim == 0 else out


def loop_interval(cc: ContactConsts, B: float, theta: Any, model: int = MACROSLIP_DF,
                  angles: tuple[float, float, float] | None = None) -> np.ndarray:
    """Number 1..10 of the eq.-4 interval that holds theta in [0, 2 pi) (empty intervals are skipped)."""
    t1, t2, t3 = angles if angles is not None else loop_angles(cc, B, model)
    pi = math.pi
    edges = np.array([0.0, t1, t2, pi - t2, t3, pi, pi + t1, pi + t2, 2 * pi - t2, pi + t3])
    th = np.asarray(theta, dtype=float)
    # the last edge e_i <= theta gives interval i (edges are nondecreasing)
    return np.searchsorted(edges, th, side="right").astype(int).clip(1, 10)


def loop_state(params: Mapping[str, Any] | ContactConsts, B: float, theta: Any, model: int = MACROSLIP_DF) -> Any:
    """contactState of the loop at phase theta (model-notes s.4): 1 stick on intervals 1, 4, 6, 9,
    2 slip on 2, 5, 7, 10, 0 open on 3, 8; always 1 in full stick; 0 when B <= d."""
    cc = params if isinstance(params, ContactConsts) else contact_consts(params)
    th = np.mod(np.asarray(theta, dtype=float), 2.0 * math.pi)
    if not B > cc.d:
        out = np.zeros(th.shape, dtype=int)
    elif model == MACROSLIP_DF and cc.full_stick:
        out = np.ones(th.shape, dtype=int)
    else:
        idx = loop_interval(cc, B, th, model)
        table = np.array([0, 1, 2, 0, 1, 2, 1, 2, 0, 1, 2])
        out = table[idx]
    return int(out) if out.ndim == 0 else out


def _df_closed(cc: ContactConsts, B: np.ndarray, model: int) -> tuple[np.ndarray, np.ndarray, np.ndarray, tuple]:
    """(f_k, f_c * omega, p_k) in closed form, vectorised over B (zero where B <= d)."""
    sg, cg = math.sin(cc.gamma), math.cos(cc.gamma)
    kd, kn, mu, d = cc.kd, cc.kn, cc.mu, cc.d
    on = B > d
    Bs = np.where(on, B, 2.0 * d + 1.0)  # dummy amplitude where open (results masked below)
    t1, t2, t3 = loop_angles(cc, Bs, model)
    t1, t2, t3 = np.atleast_1d(t1), np.atleast_1d(t2), np.atleast_1d(t3)
    Ns = mu * kn * cg * (Bs - d)
    pk = kn * cg * (2 * Bs * t2 + Bs * np.sin(2 * t2) - 4 * d * np.sin(t2)) / (math.pi * Bs)  # eq. 10
    if model == COULOMB_DF:  # model-notes s.5
        fk = np.zeros_like(Bs)
        fcw = 4.0 * Ns * (1.0 - d / Bs) / (math.pi * Bs)
    elif cc.full_stick:  # MODEL.md s.3: elastic, no dissipation
        fk = kd * math.tan(cc.gamma) / kn * pk
        fcw = np.zeros_like(Bs)
    else:
        fk = 2.0 / (math.pi * Bs) * (  # eq. 7
            0.25 * Bs * kd * sg * (2 * t1 + np.sin(2 * t1) - 4 * np.sin(t1))
            + 0.25 * mu * kn * cg * (2 * Bs * t1 + Bs * np.sin(2 * t1) - 4 * d * np.sin(t1))
            - Ns * (np.sin(t2) - np.sin(t1) - np.sin(t3))
            + 0.25 * kd * sg * (2 * Bs * (t2 + t3 - math.pi) + Bs * (np.sin(2 * t3) + np.sin(2 * t2))
                                + 4 * d * (np.sin(t3) - np.sin(t2))))
        fcw = -2.0 / (math.pi * Bs) * (  # eq. 8 with the MODEL.md fix (4 cos theta1), times omega
            0.25 * Bs * kd * sg * (4 * np.cos(t1) - np.cos(2 * t1) - 3)
            + 0.25 * mu * kn * cg * (Bs + 4 * d * np.cos(t1) - Bs * np.cos(2 * t1) - 4 * d)
            + Ns * (np.cos(t2) - np.cos(t1))
            + 0.25 * kd * sg * (Bs * np.cos(2 * t2) - Bs * np.cos(2 * t3) - 4 * d * np.cos(t3) - 4 * d * np.cos(t2))
            - Ns * (1 + np.cos(t3)))
    z = np.zeros_like(Bs)
    fk, fcw, pk = (np.where(on, x, 0.0) for x in (fk, fcw, pk))
    angles = tuple(np.where(on, t, 0.0) for t in (t1, t2, t3))
    return fk + z, fcw + z, pk + z, angles


_GL = {n: np.polynomial.legendre.leggauss(n) for n in (32, 64)}


def _df_quadrature(cc: ContactConsts, B: float, model: int) -> tuple[float, float, float]:
    """(f_k, f_c * omega, p_k) by Gauss-Legendre quadrature of eq. 3/4 on every piece between the
    loop's breakpoints. Each piece is a trigonometric polynomial of theta (analytic), so 64 nodes
    per piece are exact to roundoff; the 32-node result is computed too and must agree (self-check)."""
    if not B > cc.d:
        return 0.0, 0.0, 0.0
    t1, t2, t3 = loop_angles(cc, B, model)
    pi = math.pi
    pts = sorted({0.0, t1, t2, pi - t2, t3, pi, pi + t1, pi + t2, 2 * pi - t2, pi + t3, 2 * pi})
    res = {}
    for n, (x, wts) in _GL.items():
        tot = np.zeros(3)
        for lo, hi in zip(pts[:-1], pts[1:]):
            if hi > lo:
                th = 0.5 * (hi - lo) * x + 0.5 * (hi + lo)  # strictly inside the piece
                ff = np.asarray(loop_friction(cc, B, th, model))
                fn = np.asarray(normal_force(cc, B * np.cos(th)))
                w = 0.5 * (hi - lo) * wts
                tot += [np.dot(w, ff * np.cos(th)), -np.dot(w, ff * np.sin(th)), np.dot(w, fn * np.cos(th))]
        res[n] = tot / (pi * B)
    scale = cc.kn
    if np.max(np.abs(res[64] - res[32])) > 1e-12 * scale:
        raise ArithmeticError(f"loop quadrature did not converge at B = {B:g}")
    return float(res[64][0]), float(res[64][1]), float(res[64][2])


def describing_function(params: Mapping[str, Any] | ContactConsts, B: Any, omega: float, model: int = MACROSLIP_DF,
                        projection: int = 1, method: str = "closed") -> DF:
    """Describing function of the macroslip (model 1) or Coulomb (model 2) loop at amplitude B [m]
    (scalar or array) and excitation frequency omega [rad/s] (> 0 needed for f_c, C_eq; with
    omega = 0 they are inf where the loop dissipates). model 3 (time-domain element) reports the
    macroslip DF. method "closed" (vectorised) or "quadrature" (scalar loop)."""
    cc = params if isinstance(params, ContactConsts) else contact_consts(params)
    if model == MACROSLIP_TD:
        model = MACROSLIP_DF
    if model not in (MACROSLIP_DF, COULOMB_DF):
        raise ValueError(f"model must be 1, 2 or 3, got {model!r}")
    if projection not in (1, 2):
        raise ValueError(f"projection must be 1 or 2, got {projection!r}")
    Bv = np.asarray(B, dtype=float)
    B1 = np.atleast_1d(Bv)
    if method == "closed":
        fk, fcw, pk, (t1, t2, t3) = _df_closed(cc, B1, model)
    elif method == "quadrature":
        res = np.array([_df_quadrature(cc, float(b), model) for b in B1]).reshape(-1, 3)
        fk, fcw, pk = res[:, 0], res[:, 1], res[:, 2]
        t1, t2, t3 = (np.atleast_1d(t) for t in loop_angles(cc, B1, model))
    else:
        raise ValueError("method must be 'closed' or 'quadrature'")
    sg, cg = math.sin(cc.gamma), math.cos(cc.gamma)
    Keq = (fk + pk) * sg if projection == 1 else fk * sg + pk * cg  # eq. 12 / consistent
    Cw = fcw * sg  # eq. 13, p_c = 0 (eq. 11)
    with np.errstate(divide="ignore", invalid="ignore"):
        fc = np.where(fcw == 0.0, 0.0, fcw / omega) if omega != 0 else np.where(fcw == 0.0, 0.0, np.inf)
        Ceq = fc * sg
    reg = np.atleast_1d(regime(cc, B1, model))
    out = [fk, fc, pk, Keq, Ceq, reg, t1, t2, t3, fcw, Cw]
    if Bv.ndim == 0:
        out = [int(x[0]) if i == 5 else float(x[0]) for i, x in enumerate(out)]
    else:
        out = [x.reshape(Bv.shape) for x in out]
    return DF(*out)


def jenkins_cycle_dissipation(params: Mapping[str, Any] | ContactConsts, B: float) -> float:
    """Closed-form friction work per cycle, closed integral of F_f dv [J/m * m = N m / (m/m)],
    of the time-domain Jenkins element (model-notes s.2: spring k_d in series with a slider limited
    by mu |F_n(v)|, variable normal load) driven by v = B cos(theta).

    Down stroke from v = B: stick F_f = N* + a (v - B) until F_f = -mu|F_n| at cos(theta) = the
    eq.-5 theta1 argument (the same theta1 as the paper), then slip F_f = -b (v - d) down to v = d,
    open, slip F_f = b (v + d) on the far side; the up stroke is antisymmetric. With
    a = k_d sin g, b = mu k_n cos g, v1 = B cos(theta1):
        closed int F_f dv = a (B - v1)^2 + b (v1 - d)^2 + b (B - d)^2 - 2 b (B - d) (B - v1).
    The paper's loop (eq. 4) holds F_f at +-N* = b (B - d) in slip and lets the stick force exceed
    the current limit in intervals 4 and 9, so its dissipation pi omega B^2 f_c differs.
    Full stick (a <= b) or B <= d: 0."""
    cc = params if isinstance(params, ContactConsts) else contact_consts(params)
    a, b, d = cc.a, cc.b, cc.d
    if not B > d or a <= b:
        return 0.0
    v1 = B * math.cos(loop_angles(cc, B, MACROSLIP_DF)[0])
    return a * (B - v1) ** 2 + b * (v1 - d) ** 2 + b * (B - d) ** 2 - 2 * b * (B - d) * (B - v1)
