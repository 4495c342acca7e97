"""Independent Python reference: the m-mode Galerkin reduction of the blade (paper eq. 19-21, consistent form).

v(x, t) = sum_i psi_i(x) q_i(t), psi_i = phi_i / phi_i(l) with phi_i the eq.-20 shape of the i-th
root of eq. 21, so that every psi_i(l) = 1 and the physical tip displacement is sum_i q_i. The
energy (consistent) form of docs/model.md s.2 for every pair (i, j):
    M_ij   = rho A int psi_i psi_j dx + m0 psi_i(l) psi_j(l)
    C0_ij  = c int psi_i psi_j dx
    K0s_ij = EI int psi_i'' psi_j'' dx
    K0w_ij = int (rho A (l^2 - x^2) / 2 + m0 l) psi_i' psi_j' dx   (centrifugal tension, eq. 16)
    G_i    = int psi_i dx                                             (load per unit f_w)
and the root bending moment EI v''(0, t) = EI sum_i psi_i''(0) q_i.
Derived here, not taken from the product: the k-th root of eq. 21 lies in ((k-1) pi, k pi) (the
function divided by cosh alternates in sign at the multiples of pi) and is found by bisection +
Newton on that scaled function; eq. 20 is evaluated in a cancellation-free form,
S cosh z - sinh z = (S - 1) cosh z + exp(-z) with S - 1 = (sin L - cos L - exp(-L)) / (cosh L + cos L),
because S -> 1 and cosh z ~ 1e7 for the sixth mode; every integral is the exact integral of a
Chebyshev interpolant whose tail must be roundoff. The printed formulation (eq. 26) treats q as
the tip displacement of one mode and has no consistent m-mode form: m > 1 refuses it.
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from typing import Any, Mapping

import numpy as np
from numpy.polynomial import chebyshev

from harness.model.params import ParameterError, specs, validate

MAX_MODES = 6
_DEGREE = 128  # Chebyshev degree: products of two sixth modes oscillate like sin(35 x / l)


def split_modes(params: Mapping[str, Any] | None, modes: int | None = None) -> tuple[dict[str, Any], int]:
    """(validated params, m): m from the argument, else params["modes"], else 1; checked 1..6.
    `modes` is dropped before validate() where the model description does not know it yet."""
    p = dict(params or {})
    m = p.get("modes", 1) if modes is None else modes
    if "modes" not in specs():
        p.pop("modes", None)
    if isinstance(m, bool) or not isinstance(m, (int, np.integer)) or not 1 <= int(m) <= MAX_MODES:
        raise ParameterError(f"modes = {m!r} outside the range 1..{MAX_MODES}")
    p = validate(p)
    if "modes" in p:
        p["modes"] = int(m)
    return p, int(m)


def _scaled_eq21(x: float, R: float) -> tuple[float, float]:
    """Eq. 21 divided by cosh x, and its derivative in x (bounded for large x)."""
    c, s, th, sech = math.cos(x), math.sin(x), math.tanh(x), 1.0 / math.cosh(x)
    f = sech + c + R * x * (c * th - s)
    df = -sech * th - s + R * (c * th - s) + R * x * (-s * th + c * sech * sech - c)
    return f, df


def root_k(R: float, k: int) -> float:
    """The k-th positive root lambda_k l of eq. 21, inside ((k-1) pi, k pi): bisection to a bracket of
    1e-3, then Newton kept inside the bracket."""
    if R < 0.0:
        raise ValueError("R = m0/(rho A l) must be >= 0")
    lo, hi = (k - 1) * math.pi + (1e-9 if k == 1 else 0.0), k * math.pi
    flo = _scaled_eq21(lo, R)[0]
    if flo * _scaled_eq21(hi, R)[0] >= 0.0:
        raise ArithmeticError(f"eq. 21 has no sign change in ({lo:g}, {hi:g}) for R = {R}")
    while hi - lo > 1e-3:
        mid = 0.5 * (lo + hi)
        fm = _scaled_eq21(mid, R)[0]
        lo, hi, flo = (mid, hi, fm) if fm * flo > 0.0 else (lo, mid, flo)
    x = 0.5 * (lo + hi)
    for _ in range(100):
        f, df = _scaled_eq21(x, R)
        nxt = x - f / df
        if not lo <= nxt <= hi:
            nxt = 0.5 * (lo + hi)
        if abs(nxt - x) <= 4e-16 * x:
            return nxt
        if f * flo > 0.0:
            lo = x
        else:
            hi = x
        x = nxt
    raise ArithmeticError(f"Newton on eq. 21 did not converge for root {k}, R = {R}")


def shape(lambdaL: float, l: float, x: Any, order: int) -> np.ndarray:
    """d^order phi / dx^order of eq. 20 (unnormalised), cancellation-free (module doc)."""
    L = lambdaL
    lam = L / l
    S = (math.sinh(L) + math.sin(L)) / (math.cosh(L) + math.cos(L))
    Sm1 = (math.sin(L) - math.cos(L) - math.exp(-L)) / (math.cosh(L) + math.cos(L))
    z = lam * np.asarray(x, dtype=float)
    hyp = np.cosh(z) if order % 2 == 0 else np.sinh(z)
    # derivatives of cos z and sin z cycle with period 4
    dcos = (np.cos(z), -np.sin(z), -np.cos(z), np.sin(z))[order % 4]
    dsin = (np.sin(z), np.cos(z), -np.sin(z), -np.cos(z))[order % 4]
    return lam**order * (Sm1 * hyp + (-1) ** order * np.exp(-z) - S * dcos + dsin)


def _integral(f: Any, l: float) -> float:
    series = chebyshev.Chebyshev.interpolate(f, _DEGREE, domain=[0.0, l])
    coef = np.abs(series.coef)
    if coef[-16:].max() > 1e-13 * coef.max():
        raise ArithmeticError("the Chebyshev interpolant of a modal integrand did not converge")
    prim = series.integ()
    return float(prim(l) - prim(0.0))


@dataclass(frozen=True)
class ModalGalerkin:
    """m-mode reduction, modes normalised to psi_i(l) = 1 (tip displacement = sum q_i)."""

    lambdaL: np.ndarray  # roots of eq. 21, (m,)
    M: np.ndarray  # (m, m) [kg]
    C0: np.ndarray  # (m, m) [N s/m]
    K0static: np.ndarray  # (m, m) [N/m]
    K0omega2: np.ndarray  # (m, m) [kg]
    loadGain: np.ndarray  # G_i = int psi_i dx [m], (m,)
    rootCurvature: np.ndarray  # psi_i''(0) [1/m^2], (m,)
    EI: float

    @property
    def m(self) -> int:
        return int(self.lambdaL.size)

    def K0(self, Omega: float) -> np.ndarray:
        return self.K0static + self.K0omega2 * (Omega * Omega)

    def frequencies_hz(self, speed_rpm: float) -> np.ndarray:
        """Contact-free natural frequencies [Hz] at speed `speed_rpm` [rpm]: the generalized eigenvalues of
        (K0, M), ascending."""
        Om = 2.0 * math.pi * speed_rpm / 60.0
        Lc = np.linalg.cholesky(self.M)
        Li = np.linalg.inv(Lc)
        w2 = np.linalg.eigvalsh(Li @ self.K0(Om) @ Li.T)
        return np.sqrt(np.sort(w2)) / (2.0 * math.pi)

    def root_moment(self, q: np.ndarray) -> np.ndarray:
        """EI sum_i psi_i''(0) q_i [N m] (q: (m,) or (m, n))."""
        return self.EI * (self.rootCurvature @ np.asarray(q))


def modal_galerkin(params: Mapping[str, Any] | None, modes: int | None = None) -> ModalGalerkin:
    """The m-mode consistent reduction (module doc) for params (m from `modes` or params["modes"])."""
    p, m = split_modes(params, modes)
    if int(p["formulation"]) != 2 and m > 1:
        raise ParameterError(
            f"formulation = {p['formulation']} (printed) with modes = {m}: the printed eq. 26 treats"
            " q as the tip displacement of one mode; use formulation 2 (consistent) for modes > 1"
        )
    EI, rho, A, l, c, m0 = (float(p[k]) for k in ("EI", "rho", "A", "l", "c", "m0"))
    R = m0 / (rho * A * l)
    lams = np.array([root_k(R, k) for k in range(1, m + 1)])
    tips = np.array([float(shape(L, l, l, 0)) for L in lams])

    def psi(i: int, order: int) -> Any:
        return lambda x: shape(lams[i], l, x, order) / tips[i]

    M, C0, Ks, Kw = (np.zeros((m, m)) for _ in range(4))
    for i in range(m):
        for j in range(i, m):
            mass = _integral(lambda x: psi(i, 0)(x) * psi(j, 0)(x), l)
            M[i, j] = M[j, i] = rho * A * mass + m0  # psi(l) = 1 for both
            C0[i, j] = C0[j, i] = c * mass
            Ks[i, j] = Ks[j, i] = EI * _integral(lambda x: psi(i, 2)(x) * psi(j, 2)(x), l)
            Kw[i, j] = Kw[j, i] = _integral(
                lambda x: (0.5 * rho * A * (l * l - x * x) + m0 * l) * psi(i, 1)(x) * psi(j, 1)(x), l
            )
    G = np.array([_integral(psi(i, 0), l) for i in range(m)])
    curv = np.array([float(psi(i, 2)(0.0)) for i in range(m)])
    return ModalGalerkin(lams, M, C0, Ks, Kw, G, curv, EI)
