"""Independent Python reference, part 2: the shroud contact (paper eq. 1-13, docs/model.md s.3).

Normal force (eq. 3), the macroslip friction loop (eq. 4) and its Coulomb limit (docs/model-notes.md
s.5), and their describing functions f_k, f_c, p_k, K_eq, C_eq by a numerical (Gauss-Legendre)
quadrature of the piecewise loop split at its breakpoints. The breakpoints (the angles of eq. 5)
are found here by root finding on the loop's own switching conditions (brentq), not from the
closed forms: the product's closed-form describing functions (harness/model/contact.py) are what
this checks. The loop is evaluated with v - d = (B - d) - 2 B sin^2(theta/2), accurate as B -> d+.
All per unit v (the contact coordinate), f_c carries 1/omega.
Also: the loop state at a phase (model-notes s.4) and the closed-form cycle dissipation of the
time-domain Jenkins element driven by a prescribed harmonic motion (model-notes s.2), which is not
the paper's loop: see `jenkins_cycle_dissipation`. The contact constants (`ContactConsts`: the
parameters k_n, k_d, mu, gamma, d and their combinations a, b) are the model's definitions.
"""

from __future__ import annotations

import math
from functools import lru_cache
from typing import Any, Mapping

import numpy as np
from scipy.optimize import brentq

from harness.model.contact import (
    COULOMB_DF,
    DF,
    FULL_STICK,
    MACROSLIP_DF,
    OPEN,
    STICK_SLIP,
    ContactConsts,
    contact_consts,
    df_model,
    pack_df,
)


def normal_force(params: Mapping[str, Any] | ContactConsts, v: Any) -> Any:
    """F_n(v) [N], eq. 3 (vectorised)."""
    cc = params if isinstance(params, ContactConsts) else contact_consts(params)
    v = np.asarray(v, dtype=float)
    cg = math.cos(cc.gamma)
    out = np.where(v > cc.d, cc.kn * (v - cc.d) * cg, np.where(v < -cc.d, cc.kn * (v + cc.d) * cg, 0.0))
    return out[()] if out.ndim == 0 else out


def _switch_angle(g, lo: float, hi: float) -> float:
    """The phase in [lo, hi] where the loop condition g changes sign (g(lo) > 0 > g(hi)), to roundoff."""
    return float(brentq(g, lo, hi, xtol=1e-300, rtol=4 * np.finfo(float).eps, maxiter=400))


@lru_cache(maxsize=4096)  # the quadrature and the loop ask for the same amplitude's angles many times
def _angles_at(cc: ContactConsts, B: float, model: int) -> tuple[float, float, float]:
    """theta1, theta2, theta3 of the down stroke v = B cos(theta), theta in [0, pi], B > d, from the
    loop's conditions (sin^2 forms of v: v - B = -2 B s, v - d = e - 2 B s, s = sin^2(theta/2)):
    theta2: the gap opens, v = d; theta1: the stick force a (v - B) + N* reaches -N*, N* = b (B - d);
    theta3 = pi - phi3: on the far side the stick force a (v + d) reaches -N*, v = -B cos(phi3)."""
    a, b, d = cc.a, cc.b, cc.d
    e = B - d
    sin2 = lambda t: math.sin(0.5 * t) ** 2  # noqa: E731
    t2 = _switch_angle(lambda t: e - 2.0 * B * sin2(t), 0.0, math.pi)
    if model == COULOMB_DF:  # slips at once: theta1 = 0, theta3 = pi - theta2
        return 0.0, t2, math.pi - t2
    t1 = _switch_angle(lambda t: 2.0 * b * e - 2.0 * (a + b) * B * sin2(t), 0.0, math.pi)
    # far side: a (v + d) + N* = a (2 B sin^2(phi/2) - e) + b e, negative at phi = 0 unless a <= b
    g3 = lambda ph: -(a * (2.0 * B * sin2(ph) - e) + b * e)  # noqa: E731
    phi3 = _switch_angle(g3, 0.0, t2) if a > b else 0.0
    return t1, t2, math.pi - phi3


def loop_angles(params: Mapping[str, Any] | ContactConsts, B: Any, model: int = MACROSLIP_DF) -> tuple[Any, Any, Any]:
    """theta1, theta2, theta3 of eq. 5 for amplitude B > d (Coulomb: theta1 = 0, theta3 = pi - theta2),
    by root finding (`_angles_at`). In full stick (a <= b) theta3 = pi. Where B <= d all three are 0."""
    cc = params if isinstance(params, ContactConsts) else contact_consts(params)
    Bv = np.asarray(B, dtype=float)
    out = np.zeros((3,) + Bv.shape)
    for idx in np.ndindex(Bv.shape):
        if Bv[idx] > cc.d:
            out[(slice(None),) + idx] = _angles_at(cc, float(Bv[idx]), model)
    if Bv.ndim == 0:
        return float(out[0]), float(out[1]), float(out[2])
    return out[0], out[1], out[2]


def regime(params: Mapping[str, Any] | ContactConsts, B: Any, model: int = MACROSLIP_DF) -> Any:
    """0 open (B <= d), 1 stick-slip, 2 full stick (macroslip that never slips: a <= b)."""
    cc = params if isinstance(params, ContactConsts) else contact_consts(params)
    Bv = np.asarray(B, dtype=float)
    out = np.where(Bv > cc.d, FULL_STICK if (model != COULOMB_DF and cc.a < cc.b) else STICK_SLIP, OPEN)
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
    a, b = cc.a, cc.b
    vmd, vpd = _loop_gaps(cc, B, th)  # v - d, v + d [m], accurate as B -> d+
    if model == MACROSLIP_DF and cc.full_stick:
        out = np.where(vmd > 0.0, a * vmd, np.where(vpd < 0.0, a * vpd, 0.0))
        return out[()] if out.ndim == 0 else out
    t1, t2, t3 = loop_angles(cc, B, model)
    Ns = b * (B - cc.d)
    # Interval edges of eq. 4, [edge_i, edge_{i+1}); interval 10 is closed at 2 pi.
    # a (v -+ B) + b (v -+ d) is k_d (Delta_u -+ B sin g) + mu k_n cos g (v -+ d) of eq. 4.
    pieces = [
        -2.0 * a * B * np.sin(0.5 * th) ** 2 + b * vmd,  # 1 (v - B = -2 B sin^2(theta/2))
        -Ns + 0.0 * th,  # 2
        0.0 * th,  # 3
        a * vpd,  # 4
        -Ns + 0.0 * th,  # 5
        2.0 * a * B * np.cos(0.5 * th) ** 2 + b * vpd,  # 6 (v + B = 2 B cos^2(theta/2))
        Ns + 0.0 * th,  # 7
        0.0 * th,  # 8
        a * vmd,  # 9
        Ns + 0.0 * th,  # 10
    ]
    idx = loop_interval(cc, B, th, model, angles=(t1, t2, t3))
    out = np.choose(idx - 1, pieces)
    return out[()] if out.ndim == 0 else out


def loop_interval(
    cc: ContactConsts, B: float, theta: Any, model: int = MACROSLIP_DF, angles: tuple[float, float, float] | None = None
) -> np.ndarray:
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


def _loop_gaps(cc: ContactConsts, B: float, th: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """(v - d, v + d) [m] at phases th for v = B cos(th), written as (B - d) - 2 B sin^2(th/2) and
    2 B cos^2(th/2) - (B - d): no cancellation when B -> d+ (v - d is then tiny next to v and d)."""
    e = B - cc.d
    return e - 2.0 * B * np.sin(0.5 * th) ** 2, 2.0 * B * np.cos(0.5 * th) ** 2 - e


_GL = {n: np.polynomial.legendre.leggauss(n) for n in (32, 64)}


def _df_quadrature(cc: ContactConsts, B: float, model: int) -> tuple[float, float, float]:
    """(f_k, f_c * omega, p_k) by Gauss-Legendre quadrature of eq. 3/4 on every piece between the
    loop's breakpoints. Each piece is a trigonometric polynomial of theta (analytic), so 64 nodes
    per piece are exact to roundoff; the 32-node result is computed too and must agree to 1e-12 of
    the integral of the absolute integrand (self-check). F_f and F_n are evaluated with
    v -+ d = (B - d) - 2 B sin^2(theta/2) etc. (`_loop_gaps`), accurate as B -> d+."""
    if not B > cc.d:
        return 0.0, 0.0, 0.0
    t1, t2, t3 = loop_angles(cc, B, model)
    pi = math.pi
    kcg = cc.kn * math.cos(cc.gamma)
    pts = sorted({0.0, t1, t2, pi - t2, t3, pi, pi + t1, pi + t2, 2 * pi - t2, pi + t3, 2 * pi})
    lo, hi = np.array(pts[:-1]), np.array(pts[1:])
    lo, hi = lo[hi > lo], hi[hi > lo]
    res, mag = {}, {}
    for n, (x, wts) in _GL.items():  # all pieces at once: nodes (piece, node), strictly inside
        th = (0.5 * (hi - lo)[:, None] * x + 0.5 * (hi + lo)[:, None]).ravel()
        w = (0.5 * (hi - lo)[:, None] * wts).ravel()
        ff = np.asarray(loop_friction(cc, B, th, model))
        vmd, vpd = _loop_gaps(cc, B, th)
        fn = np.where(vmd > 0.0, kcg * vmd, np.where(vpd < 0.0, kcg * vpd, 0.0))  # eq. 3
        terms = np.array([ff * np.cos(th), -ff * np.sin(th), fn * np.cos(th)])
        res[n], mag[n] = terms @ w / (pi * B), np.abs(terms) @ w / (pi * B)
    if np.any(np.abs(res[64] - res[32]) > 1e-12 * mag[64]):
        raise ArithmeticError(f"loop quadrature did not converge at B = {B:g}")
    return float(res[64][0]), float(res[64][1]), float(res[64][2])


def describing_function(
    params: Mapping[str, Any] | ContactConsts, B: Any, omega: float, model: int = MACROSLIP_DF, projection: int = 1
) -> DF:
    """Describing function of the macroslip (model 1) or Coulomb (model 2) loop at amplitude B [m]
    (scalar or array) and excitation frequency omega [rad/s] (> 0 needed for f_c, C_eq). model 3
    (time-domain element) reports the macroslip DF. By quadrature of the loop (`_df_quadrature`),
    one amplitude at a time; the record is packed as the model's (`pack_df`)."""
    cc = params if isinstance(params, ContactConsts) else contact_consts(params)
    model = df_model(model, projection)
    B1 = np.atleast_1d(np.asarray(B, dtype=float))
    res = np.array([_df_quadrature(cc, float(b), model) for b in B1]).reshape(-1, 3)
    fk, fcw, pk = res[:, 0], res[:, 1], res[:, 2]
    sg = math.sin(cc.gamma)
    Keq = (fk + pk) * sg if projection == 1 else fk * sg + pk * math.cos(cc.gamma)  # eq. 12 / 2nd projection
    return pack_df(
        B,
        omega,
        sg,
        fk,
        fcw,
        pk,
        Keq,
        fcw * sg,
        np.atleast_1d(regime(cc, B1, model)),
        tuple(np.atleast_1d(t) for t in loop_angles(cc, B1, model)),
    )


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
    e = B - d
    Bv1 = 2.0 * b * e / (a + b)  # B - v1 = B (1 - cos theta1) (eq. 5, half-angle form); v1 - d = e - Bv1
    return a * Bv1**2 + b * (e - Bv1) ** 2 + b * e**2 - 2 * b * e * Bv1
