"""Independent Python reference, part 1: the one-mode Galerkin reduction of the blade (docs/model.md s.2).

Derived its own way, sharing no code with the product's reduction (harness/model/galerkin.py:
scan + brentq, adaptive quadrature) nor with the C FMU (fmu_src/physics/blade.c): the first root
lambda_1 l of eq. 21 by a safeguarded Newton iteration on its analytic derivative; the mode of
eq. 20 from the derivative cycle of (cosh, sinh, cos, sin); every integral as the exact integral of
a Chebyshev interpolant of the integrand (Clenshaw-Curtis), whose last coefficients must be
roundoff (below 1e-13 of the largest). The result is the product's `Galerkin` record (a plain container).
Formulation 1 (`printed`) follows eq. 26 with U2 = lambda^4 U1; formulation 2 (`consistent`) is
the energy form with phi(l) = 1.
"""

from __future__ import annotations

import math
from typing import Any, Callable, Mapping

import numpy as np
from numpy.polynomial import chebyshev

from harness.model.galerkin import Galerkin
from harness.model.params import validate

_DEGREE = 32  # Chebyshev degree of every integrand (entire in x: coefficients reach roundoff by ~20)


def eq21(x: float, R: float) -> tuple[float, float]:
    """Eq. 21 at x = lambda l, R = m0 / (rho A l), and its derivative in x."""
    c, s, ch, sh = math.cos(x), math.sin(x), math.cosh(x), math.sinh(x)
    odd = c * sh - s * ch
    return 1.0 + c * ch + R * x * odd, (1.0 + R) * odd - 2.0 * R * x * s * sh


def root(R: float) -> float:
    """First positive root of eq. 21: Newton from the bracket (0, pi] (f(0+) = 2 > 0 > f(pi)), with
    a bisection step whenever Newton leaves the bracket."""
    if R < 0.0:
        raise ValueError("R = m0/(rho A l) must be >= 0")
    lo, hi = 1e-6, math.pi
    x = 1.875  # the clamped-free root (R = 0); a tip mass only lowers it
    for _ in range(200):
        f, df = eq21(x, R)
        if f > 0.0:
            lo = x
        else:
            hi = x
        step = f / df if df != 0.0 else math.inf
        nxt = x - step
        if not lo < nxt < hi:
            nxt = 0.5 * (lo + hi)
        if abs(nxt - x) <= 1e-16 * x:
            return nxt
        x = nxt
    raise ArithmeticError(f"Newton on eq. 21 did not converge for R = {R}")


def mode(lambdaL: float, l: float, x: np.ndarray, order: int) -> np.ndarray:
    """d^order phi / dx^order of eq. 20, phi = S (cosh z - cos z) + sin z - sinh z, z = lambda x:
    d/dz maps cosh -> sinh -> cosh and cos -> -sin -> -cos -> sin -> cos."""
    lam = lambdaL / l
    S = (math.sinh(lambdaL) + math.sin(lambdaL)) / (math.cosh(lambdaL) + math.cos(lambdaL))
    z = lam * np.asarray(x, dtype=float)
    hyp = (np.cosh(z), np.sinh(z))
    trig = (np.cos(z), -np.sin(z), -np.cos(z), np.sin(z))  # k-th derivative of cos z
    # phi = S cosh - S cos + sin - sinh, with sin = d/dz(-cos) shifted by one in the cycle
    val = S * hyp[order % 2] - S * trig[order % 4] - trig[(order + 1) % 4] - hyp[(order + 1) % 2]
    return lam**order * val


def integral(f: Callable[[np.ndarray], np.ndarray], l: float) -> float:
    """int_0^l f(x) dx as the exact integral of f's Chebyshev interpolant of degree _DEGREE."""
    series = chebyshev.Chebyshev.interpolate(f, _DEGREE, domain=[0.0, l])
    coef = np.abs(series.coef)
    if coef[-8:].max() > 1e-13 * coef.max():  # the tail must be roundoff (~1e-15 of the largest)
        raise ArithmeticError("the Chebyshev interpolant of a Galerkin integrand did not converge")
    prim = series.integ()
    return float(prim(l) - prim(0.0))


def galerkin(params: Mapping[str, Any] | None, formulation: int | None = None) -> Galerkin:
    """Galerkin reduction (docs/model.md s.2) for `formulation` (1 printed, 2 consistent; default: the
    value in params), params completed by harness.model.params.validate()."""
    p = validate(params or {})
    form = int(p["formulation"] if formulation is None else formulation)
    if form not in (1, 2):
        raise ValueError(f"formulation must be 1 or 2, got {formulation!r}")
    EI, rho, A, l, c, m0 = (float(p[k]) for k in ("EI", "rho", "A", "l", "c", "m0"))
    lamL = root(m0 / (rho * A * l))

    def phi(k: int) -> Callable[[np.ndarray], np.ndarray]:
        return lambda x: mode(lamL, l, x, k)

    U1 = integral(lambda x: phi(0)(x) ** 2, l)
    U3 = integral(lambda x: x * phi(0)(x) * phi(1)(x), l)
    U4 = integral(lambda x: phi(2)(x) * phi(0)(x) * (l * l - x * x), l)
    U5 = integral(lambda x: phi(0)(x) * phi(2)(x), l)
    intPhi = integral(phi(0), l)
    u2 = float(mode(lamL, l, np.array(l), 0))
    U2 = (lamL / l) ** 4 * U1
    if form == 1:  # eq. 26
        M, C0, K0s = rho * A * U1 / u2, c * U1 / u2, EI * U2 / u2
        K0w = (rho * A * U3 - 0.5 * rho * A * U4 - m0 * l * U5) / u2
    else:  # energy form, phi(l) = 1
        n2 = u2 * u2
        M, C0 = rho * A * U1 / n2 + m0, c * U1 / n2
        K0s = EI * integral(lambda x: phi(2)(x) ** 2, l) / n2
        K0w = integral(lambda x: (0.5 * rho * A * (l * l - x * x) + m0 * l) * phi(1)(x) ** 2, l) / n2
    return Galerkin(
        formulation=form,
        lambdaL=lamL,
        U1=U1,
        U2=U2,
        U3=U3,
        U4=U4,
        U5=U5,
        intPhi=intPhi,
        u2=u2,
        M=M,
        C0=C0,
        K0static=K0s,
        K0omega2=K0w,
        loadGain=intPhi / u2,
    )
