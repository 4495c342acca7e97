"""Independent check of the m-mode reduction: a finite-element model of the rotating cantilever with tip mass.

Euler-Bernoulli beam on [0, l], clamped at x = 0, n equal Hermite-cubic elements (nodal
displacement w and slope w'), consistent mass rho A, bending stiffness EI, the shroud m0 lumped on
the tip displacement, and the centrifugal stiffening of the axial force of the rotating blade and
tip mass, N(x) = Omega^2 (rho A (l^2 - x^2) / 2 + m0 l) (the tension of eq. 16), as the geometric
stiffness int N w' w' dx. Element matrices by 4-point Gauss-Legendre quadrature (exact: N is
quadratic, the shape functions cubic). Conforming elements: the frequencies converge from above
with n (like h^4), so enough elements bound the Galerkin error from the same side. The natural
frequencies are the generalized eigenvalues of (K, M) (scipy.linalg.eigh); the forced response to a
uniform load f_w (per unit length) a linear solve. Nothing here comes from eq. 20 or eq. 21.
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from typing import Any, Mapping

import numpy as np
from scipy.linalg import eigh

from harness.model.params import validate

_GAUSS = np.polynomial.legendre.leggauss(4)


def _hermite(xi: np.ndarray, h: float) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """Hermite cubics on an element of length h at xi in [0, 1]: values, d/dx, d2/dx2, each (4, len(xi));
    DOFs (w_a, w'_a, w_b, w'_b)."""
    x = np.asarray(xi, dtype=float)
    N = np.array([1 - 3 * x**2 + 2 * x**3, h * (x - 2 * x**2 + x**3), 3 * x**2 - 2 * x**3, h * (-(x**2) + x**3)])
    dN = np.array([-6 * x + 6 * x**2, h * (1 - 4 * x + 3 * x**2), 6 * x - 6 * x**2, h * (-2 * x + 3 * x**2)]) / h
    d2N = np.array([-6 + 12 * x, h * (-4 + 6 * x), 6 - 12 * x, h * (-2 + 6 * x)]) / h**2
    return N, dN, d2N


@dataclass(frozen=True)
class BeamFE:
    """Assembled matrices of the clamped beam (the root's two DOFs removed)."""

    M: np.ndarray  # mass [kg, kg m, kg m^2 blocks]
    C: np.ndarray  # viscous damping c per unit length on the displacement field
    K: np.ndarray  # bending stiffness
    Kw: np.ndarray  # geometric stiffness per Omega^2
    f: np.ndarray  # consistent load of a uniform unit load per unit length
    tip: int  # index of the tip displacement
    EI: float
    h: float  # element length [m]

    def K0(self, speed_rpm: float) -> np.ndarray:
        Om = 2.0 * math.pi * speed_rpm / 60.0
        return self.K + self.Kw * Om * Om

    def frequencies_hz(self, speed_rpm: float, count: int = 6) -> np.ndarray:
        """The `count` lowest natural frequencies [Hz] at speed `speed_rpm` [rpm]."""
        # as the largest eigenvalues 1/omega^2 of (M, K): K's condition grows like n^4, and the lowest
        # eigenvalues of (K, M) lose ~eps n^4 of their value (1e-5 at 240 elements); these do not
        n = self.M.shape[0]
        inv = eigh(self.M, self.K0(speed_rpm), eigvals_only=True, subset_by_index=[n - count, n - 1])
        return np.sort(1.0 / np.sqrt(inv)) / (2.0 * math.pi)

    def forced_tip(self, speed_rpm: float, omega: float, Fw0: float) -> complex:
        """Complex tip amplitude of the steady response to f_w = Fw0 sin(omega t) (contacts open)."""
        Z = self.K0(speed_rpm) - omega**2 * self.M + 1j * omega * self.C
        return complex(np.linalg.solve(Z, Fw0 * self.f)[self.tip])

    def root_moment(self, u: np.ndarray) -> Any:
        """EI w''(0) [N m] from the DOFs u of the first element (its root DOFs are 0)."""
        _, _, d2N = _hermite(np.array([0.0]), self.h)
        return self.EI * (d2N[2, 0] * u[0] + d2N[3, 0] * u[1])


def beam_fe(params: Mapping[str, Any] | None, elements: int = 60) -> BeamFE:
    """The finite-element model for the blade parameters (EI, rho, A, l, c, m0) of params."""
    p = dict(params or {})
    p.pop("modes", None)
    p = validate(p)
    EI, rho, A, l, c, m0 = (float(p[k]) for k in ("EI", "rho", "A", "l", "c", "m0"))
    n = int(elements)
    h = l / n
    xi, wq = 0.5 * (_GAUSS[0] + 1.0), 0.5 * _GAUSS[1]
    N, dN, d2N = _hermite(xi, h)
    me = h * (N * wq) @ N.T
    ke = h * (d2N * wq) @ d2N.T
    fe = h * N @ wq
    dof = 2 * (n + 1)
    M, K, Kw = (np.zeros((dof, dof)) for _ in range(3))
    f = np.zeros(dof)
    for e in range(n):
        x = (e + xi) * h
        tension = 0.5 * rho * A * (l * l - x * x) + m0 * l  # N(x) / Omega^2
        kg = h * (dN * (wq * tension)) @ dN.T
        s = slice(2 * e, 2 * e + 4)
        M[s, s] += rho * A * me
        K[s, s] += EI * ke
        Kw[s, s] += kg
        f[s] += fe
    M[2 * n, 2 * n] += m0  # lumped shroud on the tip displacement
    C = np.zeros_like(M)
    for e in range(n):
        s = slice(2 * e, 2 * e + 4)
        C[s, s] += c * me
    keep = slice(2, dof)  # clamped root: w(0) = w'(0) = 0
    return BeamFE(M[keep, keep], C[keep, keep], K[keep, keep], Kw[keep, keep], f[keep], 2 * n - 2, EI, h)
