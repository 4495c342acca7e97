"""The shroud contact's describing functions (paper eq. 5, 7-13, docs/model.md s.3) in closed form.

The product's own: the harmonic balance (harness/analysis/harmonic_balance.py) and the energy books
use it (the FMU computes the same in C, fmu_src/physics/contact.c). Contact constants from the
parameters, the loop angles of eq. 5 and f_k, f_c, p_k, K_eq, C_eq vectorised over the amplitude B:
the printed closed forms (eq. 7, eq. 8 with the docs/model.md fix, eq. 10; full stick; Coulomb)
rewritten with half-angle identities (1 - cos theta2 = (B - d)/B, ...) and the bracket differences
expanded analytically, so they stay accurate as B -> d+. All per unit v (the contact coordinate),
f_c carries 1/omega. The reference (harness/reference/contact.py) integrates the friction loop of
eq. 4 numerically, with its own loop angles; the tests compare the two and the C.
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from typing import Any, Mapping

import numpy as np

from harness.model.params import validate

OPEN, STICK_SLIP, FULL_STICK = 0, 1, 2  # regime (docs/model.md s.3)
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
        """k_d tan(gamma) < mu k_n (docs/model.md s.3): the loop never slips."""
        return self.kd * math.tan(self.gamma) < self.mu * self.kn


def contact_consts(params: Mapping[str, Any]) -> ContactConsts:
    p = validate(params)
    kn = float(p["kn"])
    return ContactConsts(
        kn=kn, kd=float(p["kdRatio"]) * kn, mu=float(p["mu"]), gamma=float(p["gamma"]), d=float(p["d"])
    )


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


def _x_minus_sin(x: Any) -> np.ndarray:
    """x - sin(x) without cancellation: its Taylor series for |x| < 1 (terms to x^23/23!, below
    1e-22 there), the direct difference otherwise (loses at most a factor 6 of roundoff)."""
    x = np.asarray(x, dtype=float)
    x2 = x * x
    series = np.zeros_like(x)
    for k in range(11, 0, -1):  # sum_{k>=1} (-1)^(k+1) x^(2k+1) / (2k+1)!, Horner in x^2
        series = 1.0 / math.factorial(2 * k + 1) * (-1.0) ** (k + 1) + x2 * series
    series = series * x2 * x
    return np.where(np.abs(x) < 1.0, series, x - np.sin(x))


def _angle(ver: Any) -> np.ndarray:
    """The angle t in [0, pi] with 1 - cos(t) = ver (half-angle form: t = 2 asin(sqrt(ver / 2)),
    accurate to relative roundoff for small t). ver is clipped to [0, 2] (eq.-5 arguments that leave
    [-1, 1] in full stick)."""
    return 2.0 * np.arcsin(np.sqrt(np.clip(ver, 0.0, 2.0) / 2.0))


@dataclass(frozen=True)
class _Angles:
    """The eq.-5 angles written near the gap without cancellation. With e = B - d,
    a = k_d sin g, b = mu k_n cos g (so k_d tan g / (mu k_n) = a / b):
        1 - cos(theta2) = e / B                  (cos theta2 = d / B)
        1 - cos(theta1) = 2 b e / ((a + b) B)     (eq. 5: cos theta1 = (kdt B + 2 mkn d - mkn B) / ((kdt + mkn) B))
        1 - cos(phi3)   = (a - b) e / (a B),  phi3 = pi - theta3  (cos theta3 = -(d kdt + mkn e) / (B kdt))
    and the exact differences cos(theta1) - cos(theta2) = (a - b) e / ((a + b) B),
    cos(phi3) - cos(theta2) = b e / (a B). Coulomb: theta1 = 0, phi3 = theta2."""

    t1: np.ndarray
    t2: np.ndarray
    phi3: np.ndarray
    ver1: np.ndarray  # 1 - cos(theta1)
    ver2: np.ndarray  # 1 - cos(theta2)
    ver3: np.ndarray  # 1 - cos(phi3)
    d21: np.ndarray  # cos(theta1) - cos(theta2)
    d23: np.ndarray  # cos(phi3) - cos(theta2)


def _angles(cc: ContactConsts, B: np.ndarray, model: int) -> _Angles:
    """Half-angle forms of eq. 5 for amplitudes B > d (vectorised; callers mask B <= d)."""
    a, b, d = cc.a, cc.b, cc.d
    e = B - d
    ver2 = e / B
    if model == COULOMB_DF:
        ver1, ver3 = np.zeros_like(B), ver2
        d21, d23 = ver2, np.zeros_like(B)
    else:
        ver1 = 2.0 * b * e / ((a + b) * B)
        ver3 = np.maximum((a - b) * e / (a * B), 0.0)
        d21, d23 = (a - b) * e / ((a + b) * B), b * e / (a * B)
    return _Angles(_angle(ver1), _angle(ver2), _angle(ver3), ver1, ver2, ver3, d21, d23)


def loop_angles(params: Mapping[str, Any] | ContactConsts, B: Any, model: int = MACROSLIP_DF) -> tuple[Any, Any, Any]:
    """theta1, theta2, theta3 of eq. 5 for amplitude B > d (Coulomb: theta1 = 0, theta3 = pi - theta2),
    from the half-angle forms of `_Angles` (accurate as B -> d+). In full stick the eq.-5 arguments
    leave [-1, 1]; the clipped values are returned (theta1 = theta2, theta3 = pi in the limit
    k_d tan g = mu k_n). Where B <= d all three are 0."""
    cc = params if isinstance(params, ContactConsts) else contact_consts(params)
    Bv = np.asarray(B, dtype=float)
    on = Bv > cc.d
    ang = _angles(cc, np.where(on, Bv, 2.0 * cc.d + 1.0), model)
    th1, th2, th3 = (np.where(on, t, 0.0) for t in (ang.t1, ang.t2, math.pi - ang.phi3))
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


def _cos_moment(tb: np.ndarray, D: np.ndarray) -> np.ndarray:
    """int_{tb-D}^{tb} (cos x - cos tb) cos x dx for 0 <= D <= tb <= pi/2. With x = tb - y:
    cos x - cos tb = sin(tb) sin(y) - cos(tb) (1 - cos y), cos x = cos(tb) cos(y) + sin(tb) sin(y), so
        = sin tb cos tb cos D (1 - cos D) + sin^2 tb (2D - sin 2D)/4 - cos^2 tb J(D),
        J(D) = int_0^D (1 - cos y) cos y dy = (sin D (1 - cos D) - (D - sin D)) / 2.
    The two positive terms outweigh the negative one at least 2:1 (D <= tb): nothing cancels."""
    st, ct = np.sin(tb), np.cos(tb)
    verD = 2.0 * np.sin(0.5 * D) ** 2
    J = 0.5 * (np.sin(D) * verD - _x_minus_sin(D))
    return st * ct * np.cos(D) * verD + st * st * _x_minus_sin(2.0 * D) / 4.0 - ct * ct * J


def _df_closed(cc: ContactConsts, B: np.ndarray, model: int) -> tuple[np.ndarray, np.ndarray, np.ndarray, tuple]:
    """(f_k, f_c * omega, p_k) in closed form, vectorised over B (zero where B <= d).

    Eq. 7, 8 (docs/model.md fix) and 10 rewritten so that nothing cancels as B -> d+ (where the printed
    brackets subtract terms ~ k_n B to leave ~ k_n (B - d)^{3/2} / B^{1/2} or less). With
    e = B - d, a = k_d sin g, b = mu k_n cos g, N* = b e and the half-angle forms of `_Angles`:
    - p_k (eq. 10) with d = B cos theta2: p_k = k_n cos g (2 theta2 - sin 2 theta2) / pi.
    - f_c omega (eq. 8 fixed) = -(1/(pi B)) closed int F_f sin = (2/(pi B^2)) int F_f dv over the down
      stroke (v from B to -B), F_f affine in v on each interval: interval 1 (F_f from +N* to -N*
      along v in [v1, B], B - v1 = 2 b e / (a + b)) gives 0, interval 2: -N* (e - (B - v1)),
      interval 4 (F_f = a (v + d) from 0 to -N*): -N*^2 / (2 a), interval 5: -N* (a - b) e / a:
          f_c omega = (2 b e^2 / (pi B^2)) [ (a - b)/(a + b) + (2 a - b)/(2 a) ]
      (a -> infinity: 4 N* (B - d) / (pi B^2), the Coulomb value).
    - f_k (eq. 7) = (2/(pi B)) int_0^pi F_f cos, interval by interval:
      1: (a + b) B (theta1 - sin theta1) / 2; 2: -N* (sin theta2 - sin theta1) with
      sin theta2 - sin theta1 = (cos theta1 - cos theta2) cot((theta1 + theta2)/2);
      4: a B int_{phi3}^{theta2} (cos phi - cos theta2) cos phi dphi (`_cos_moment`); 5: N* sin phi3.
    The test suite checks these against the printed eq. 7/8 away from the gap and against the
    quadrature of eq. 3/4 everywhere."""
    cg = math.cos(cc.gamma)
    a, b, kn, d = cc.a, cc.b, cc.kn, cc.d
    on = B > d
    Bs = np.where(on, B, 2.0 * d + 1.0)  # dummy amplitude where open (results masked below)
    ang = _angles(cc, Bs, model)
    pk = kn * cg * _x_minus_sin(2.0 * ang.t2) / math.pi  # eq. 10
    if model == COULOMB_DF:  # model-notes s.5: 4 N* (1 - d/B) / (pi B)
        fk = np.zeros_like(Bs)
        fcw = 4.0 * b * ang.ver2**2 / math.pi
    elif cc.full_stick:  # docs/model.md s.3: elastic, no dissipation
        fk = cc.kd * math.tan(cc.gamma) / kn * pk
        fcw = np.zeros_like(Bs)
    else:
        Ns_B = b * ang.ver2  # N* / B [N/m]
        D = 2.0 * np.arcsin(np.minimum(ang.d23 / (2.0 * np.sin(0.5 * (ang.t2 + ang.phi3))), 1.0))  # theta2 - phi3
        fk = (
            2.0
            / math.pi
            * (  # eq. 7
                0.5 * (a + b) * _x_minus_sin(ang.t1)
                - Ns_B * ang.d21 / np.tan(0.5 * (ang.t1 + ang.t2))
                + a * _cos_moment(ang.t2, D)
                + Ns_B * np.sin(ang.phi3)
            )
        )
        fcw = 2.0 * b * ang.ver2**2 / math.pi * ((a - b) / (a + b) + (2.0 * a - b) / (2.0 * a))  # eq. 8 fixed
    fk, fcw, pk = (np.where(on, x, 0.0) for x in (fk, fcw, pk))
    angles = tuple(np.where(on, t, 0.0) for t in (ang.t1, ang.t2, math.pi - ang.phi3))
    return fk, fcw, pk, angles


def df_model(model: int, projection: int) -> int:
    """The describing-function model of frictionModel `model` (3, the time-domain element, reports
    the macroslip DF), after checking model and projection."""
    if model not in (MACROSLIP_DF, COULOMB_DF, MACROSLIP_TD):
        raise ValueError(f"model must be 1, 2 or 3, got {model!r}")
    if projection not in (1, 2):
        raise ValueError(f"projection must be 1 or 2, got {projection!r}")
    return MACROSLIP_DF if model == MACROSLIP_TD else model


def pack_df(
    B: Any,
    omega: float,
    sin_gamma: float,
    fk: np.ndarray,
    fcw: np.ndarray,
    pk: np.ndarray,
    Keq: np.ndarray,
    Cw: np.ndarray,
    reg: np.ndarray,
    angles: tuple,
) -> DF:
    """The DF record in B's shape (scalars for scalar B) from per-amplitude arrays; f_c = (f_c omega)
    / omega and C_eq = f_c sin(gamma) (inf where omega = 0 and the loop dissipates)."""
    Bv = np.asarray(B, dtype=float)
    with np.errstate(divide="ignore", invalid="ignore"):
        fc = np.where(fcw == 0.0, 0.0, fcw / omega) if omega != 0 else np.where(fcw == 0.0, 0.0, np.inf)
        Ceq = fc * sin_gamma
    out = [fk, fc, pk, Keq, Ceq, reg, *angles, fcw, Cw]
    if Bv.ndim == 0:
        out = [int(x[0]) if i == 5 else float(x[0]) for i, x in enumerate(out)]
    else:
        out = [x.reshape(Bv.shape) for x in out]
    return DF(*out)


def describing_function(
    params: Mapping[str, Any] | ContactConsts, B: Any, omega: float, model: int = MACROSLIP_DF, projection: int = 1
) -> DF:
    """Describing function of the macroslip (model 1) or Coulomb (model 2) loop at amplitude B [m]
    (scalar or array) and excitation frequency omega [rad/s] (> 0 needed for f_c, C_eq; with
    omega = 0 they are inf where the loop dissipates). model 3 (time-domain element) reports the
    macroslip DF."""
    cc = params if isinstance(params, ContactConsts) else contact_consts(params)
    model = df_model(model, projection)
    B1 = np.atleast_1d(np.asarray(B, dtype=float))
    fk, fcw, pk, angles = _df_closed(cc, B1, model)
    sg, cg = math.sin(cc.gamma), math.cos(cc.gamma)
    Keq = (fk + pk) * sg if projection == 1 else fk * sg + pk * cg  # eq. 12 / consistent
    Cw = fcw * sg  # eq. 13, p_c = 0 (eq. 11)
    return pack_df(B, omega, sg, fk, fcw, pk, Keq, Cw, np.atleast_1d(regime(cc, B1, model)), angles)
