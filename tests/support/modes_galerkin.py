"""An independent m-mode Galerkin model of the blade for the tests (docs/model.md s.2a): the roots
of eq. 21 by scipy's brentq, the eq. 20 shapes in long double (cosh of lambda l ~ 17 is 1e7: the
plain formula keeps ~1e-12 of phi in 64-bit mantissas), scaled to phi_i(l) = 1, and the consistent
matrices by scipy.integrate.quad, one integral at a time. Nothing here is shared with the C code."""

from __future__ import annotations

import warnings

import numpy as np
from scipy.integrate import IntegrationWarning, quad
from scipy.optimize import brentq

LD = np.longdouble


def roots(R: float, m: int) -> np.ndarray:
    """First m positive roots a = lambda l of 1 + cos a cosh a + R a (cos a sinh a - sin a cosh a)."""
    f = lambda a: 1.0 / np.cosh(a) + np.cos(a) + R * a * (np.cos(a) * np.tanh(a) - np.sin(a))
    grid = np.arange(0.05, 40.0, 0.05)
    vals = f(grid)
    out = []
    for a, b, fa, fb in zip(grid[:-1], grid[1:], vals[:-1], vals[1:]):
        if fa * fb < 0:
            out.append(brentq(f, a, b, xtol=1e-15, rtol=1e-15))
            if len(out) == m:
                break
    return np.array(out)


class Modes:
    def __init__(self, m: int, EI=343.0, rho=7800.0, A=4.2e-4, l=0.15, c=29.8, m0=0.025):
        self.m, self.EI, self.l, self.c, self.m0, self.rhoA = m, EI, l, c, m0, rho * A
        self.aL = roots(m0 / (rho * A * l), m)
        self.lam = [LD(a) / LD(l) for a in self.aL]
        self.tip = [self._raw(i, LD(l), 0) for i in range(m)]

    def _raw(self, i: int, x, k: int):
        """k-th derivative of the unscaled eq. 20 shape of mode i at x (long double)."""
        lam = self.lam[i]
        L = lam * LD(self.l)
        s = (np.sinh(L) + np.sin(L)) / (np.cosh(L) + np.cos(L))
        z = lam * LD(x)
        ch, sh, c, sn = np.cosh(z), np.sinh(z), np.cos(z), np.sin(z)
        d = [s * (ch - c) + sn - sh, s * (sh + sn) + c - ch, s * (ch + c) - sh - sn][k]
        return d * lam**k

    def phi(self, i: int, x: float, k: int = 0) -> float:
        return float(self._raw(i, x, k) / self.tip[i])

    def matrices(self):
        m, l = self.m, self.l
        M, C, K, K2, g = (np.zeros((m, m)), np.zeros((m, m)), np.zeros((m, m)), np.zeros((m, m)), np.zeros(m))
        opts = dict(limit=400, epsabs=0.0, epsrel=1e-13)
        warnings.simplefilter("ignore", IntegrationWarning)  # the off-diagonal ones are 0 to rounding
        for i in range(m):
            g[i] = quad(lambda x: self.phi(i, x), 0.0, l, **opts)[0]
            for j in range(i, m):
                pp = quad(lambda x: self.phi(i, x) * self.phi(j, x), 0.0, l, **opts)[0]
                M[i, j] = self.rhoA * pp + self.m0
                C[i, j] = self.c * pp
                K[i, j] = self.EI * quad(lambda x: self.phi(i, x, 2) * self.phi(j, x, 2), 0.0, l, **opts)[0]
                K2[i, j] = quad(
                    lambda x: (0.5 * self.rhoA * (l * l - x * x) + self.m0 * l) * self.phi(i, x, 1) * self.phi(j, x, 1),
                    0.0,
                    l,
                    **opts,
                )[0]
                for A_ in (M, C, K, K2):
                    A_[j, i] = A_[i, j]
        return M, C, K, K2, g

    def curvature0(self) -> np.ndarray:
        return np.array([self.phi(i, 0.0, 2) for i in range(self.m)])
