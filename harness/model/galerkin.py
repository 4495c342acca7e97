"""The one-mode Galerkin reduction of the blade (docs/model.md s.2): M, C0, K0(Omega), loadGain.

The product's own (the harmonic balance, the fixed point's linear bound, the ring's energy books and
the mistuning study use it; the FMU computes the same in C, fmu_src/physics/blade.c). The first root
lambda_1 l of the frequency equation (paper eq. 21) is bracketed by a scan and refined with scipy's
brentq; the mode shape of eq. 20 and its derivatives are evaluated in closed form and every
integral (eq. 24, and the energy-form integrals of the consistent formulation) is an adaptive
quadrature (scipy.integrate.quad). The reference (harness/reference/blade.py) derives the same
constants its own way (Chebyshev series, Newton), the tests compare the two and the C.
Formulation 1 (`printed`) follows eq. 26 with U2 = lambda^4 U1 (docs/model.md fixes the printed
U2 = int phi^5); formulation 2 (`consistent`) is the energy form with phi(l) = 1.
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from typing import Any, Mapping

import numpy as np
from scipy.integrate import quad
from scipy.optimize import brentq

from harness.model.params import validate

PRINTED = 1
CONSISTENT = 2


@dataclass(frozen=True)
class Galerkin:
    """Galerkin reduction for one formulation. U1..U5, intPhi and u2 are always the integrals of
    the (unnormalised) mode of eq. 20; M, C0, K0static, K0omega2 and loadGain are those of the
    chosen formulation, so that K0(Omega) = K0static + K0omega2 * Omega^2."""

    formulation: int
    lambdaL: float  # lambda_1 l, first root of eq. 21 [-]
    U1: float  # int phi^2 dx [m]
    U2: float  # int phi phi'''' dx = lambda^4 U1 [1/m^3]
    U3: float  # int x phi phi' dx [-]
    U4: float  # int phi'' phi (l^2 - x^2) dx [m^2]
    U5: float  # int phi phi'' dx [1/m]
    intPhi: float  # int phi dx [m] (u1 = F_w0 intPhi)
    u2: float  # phi(l) [-]
    M: float  # generalized mass [kg]
    C0: float  # generalized viscous damping [N s/m]
    K0static: float  # K0 at Omega = 0 [N/m]
    K0omega2: float  # dK0/d(Omega^2) [kg]
    loadGain: float  # G: generalized load per unit f_w [m]

    def K0(self, Omega: float | np.ndarray) -> float | np.ndarray:
        """K0(Omega) [N/m] for Omega [rad/s]."""
        return self.K0static + self.K0omega2 * Omega * Omega

    def natural_frequency_hz(self, speed_rpm: float) -> float:
        """Contact-free first bending frequency sqrt(K0/M)/(2 pi) [Hz] at speed `speed_rpm` [rpm]."""
        Omega = 2.0 * math.pi * speed_rpm / 60.0
        return math.sqrt((self.K0static + self.K0omega2 * Omega * Omega) / self.M) / (2.0 * math.pi)


def frequency_equation(x: float, R: float) -> float:
    """Left side of eq. 21 at x = lambda l, R = m0 / (rho A l)."""
    return 1.0 + math.cos(x) * math.cosh(x) + R * x * (math.cos(x) * math.sinh(x) - math.sin(x) * math.cosh(x))


def first_root(R: float) -> float:
    """First positive root of eq. 21 (bracketed by a fine scan on (0, pi], refined by brentq)."""
    if R < 0.0:
        raise ValueError("R = m0/(rho A l) must be >= 0")
    xs = np.linspace(1e-3, math.pi, 4001)
    vals = 1.0 + np.cos(xs) * np.cosh(xs) + R * xs * (np.cos(xs) * np.sinh(xs) - np.sin(xs) * np.cosh(xs))  # eq. 21
    idx = np.nonzero(np.sign(vals[1:]) != np.sign(vals[:-1]))[0]
    if idx.size == 0:
        raise ValueError(f"no root of eq. 21 found in (0, pi] for R = {R}")
    i = int(idx[0])
    return float(brentq(frequency_equation, xs[i], xs[i + 1], args=(R,), xtol=1e-15, rtol=1e-15, maxiter=200))


class ModeShape:
    """phi(x) of eq. 20 for a given lambda l, and its derivatives in closed form."""

    def __init__(self, lambdaL: float, l: float):
        self.lam = lambdaL / l
        self.l = l
        self.S = (math.sinh(lambdaL) + math.sin(lambdaL)) / (math.cosh(lambdaL) + math.cos(lambdaL))

    def __call__(self, x: float, order: int = 0) -> float:
        lam, S = self.lam, self.S
        z = lam * x
        ch, sh, c, s = math.cosh(z), math.sinh(z), math.cos(z), math.sin(z)
        if order == 0:
            return S * (ch - c) + s - sh
        if order == 1:
            return lam * (S * (sh + s) + c - ch)
        if order == 2:
            return lam**2 * (S * (ch + c) - s - sh)
        if order == 3:
            return lam**3 * (S * (sh - s) - c - ch)
        if order == 4:
            return lam**4 * (S * (ch - c) + s - sh)
        raise ValueError("order must be 0..4")


def _quad(f, l: float) -> float:
    val, _err = quad(f, 0.0, l, epsabs=0.0, epsrel=1e-13, limit=200)
    return float(val)


def galerkin(params: Mapping[str, Any] | None, formulation: int | None = None) -> Galerkin:
    """Galerkin reduction (docs/model.md s.2) for `formulation` (1 printed, 2 consistent; default: the
    value in params). `params` is completed/validated by harness.model.params.validate()."""
    p = validate(params or {})
    form = int(p["formulation"] if formulation is None else formulation)
    if form not in (PRINTED, CONSISTENT):
        raise ValueError(f"formulation must be 1 or 2, got {formulation!r}")
    EI, rho, A, l, c, m0 = (float(p[k]) for k in ("EI", "rho", "A", "l", "c", "m0"))
    R = m0 / (rho * A * l)
    lamL = first_root(R)
    phi = ModeShape(lamL, l)
    U1 = _quad(lambda x: phi(x) ** 2, l)
    U2 = (lamL / l) ** 4 * U1
    U3 = _quad(lambda x: x * phi(x) * phi(x, 1), l)
    U4 = _quad(lambda x: phi(x, 2) * phi(x) * (l * l - x * x), l)
    U5 = _quad(lambda x: phi(x) * phi(x, 2), l)
    intPhi = _quad(phi, l)
    u2 = phi(l)
    if form == PRINTED:  # eq. 26
        M = rho * A * U1 / u2
        C0 = c * U1 / u2
        K0s = EI * U2 / u2
        K0w = (rho * A * U3 - 0.5 * rho * A * U4 - m0 * l * U5) / u2
        G = intPhi / u2
    else:  # energy form with phi(l) = 1 (docs/model.md s.2, formulation 2)
        n2 = u2 * u2
        M = rho * A * U1 / n2 + m0
        C0 = c * U1 / n2
        K0s = EI * _quad(lambda x: phi(x, 2) ** 2, l) / n2
        K0w = _quad(lambda x: (0.5 * rho * A * (l * l - x * x) + m0 * l) * phi(x, 1) ** 2, l) / n2
        G = intPhi / u2
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
        loadGain=G,
    )
