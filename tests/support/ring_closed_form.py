"""The linear ring's forced response written from the model's equations for the tests, sharing no
code with harness/system/linear_ring.py nor with the FMUs.

Blade i, consistent formulation (docs/model.md s.2: q is the tip displacement), constant speed
Omega, omega = EO Omega, constants from the independent Galerkin model of tests/support/modes_galerkin.py:
    M_i q_i'' + C_i q_i' + (Ks_i + Kw_i Omega^2) q_i = g_i F_w0 sin(omega t + phi_i) + F_i,
    phi_i = 2 pi EO i / N (the blades' built-in load; blade i leads blade 0).
Contact j joins blade j (side A, force -F_c) and blade j+1 mod N (side B, force +F_c) on
u_j = q_j - q_{j+1}. The time-domain Jenkins element (docs/model.md s.8, eq. 3 and 14) with gap
d = 0 and a friction limit it never reaches: the normal force F_n = kn cos(g) u (either side,
sigma u > 0 = d), the tangential spring anchored where the shrouds met, at u = 0 (open, the spring
relaxes to w = u sin g, so w = 0 when they meet again), and it sticks while
|F_f| = kd sin(g) |u| <= mu kn cos(g) |u|, i.e. kd tan(g) <= mu kn. Then
    F_c = F_n cos g + F_f sin g = (kn cos^2 g + kd sin^2 g) u = k_c u,   kd = kdRatio kn,
and F_i = -k_c u_i + k_c u_{i-1} = -k_c (2 q_i - q_{i+1} - q_{i-1}). With q_i = Im(Q_i e^{i omega t}):
    (diag(Ks_i + Kw_i Omega^2 - omega^2 M_i + i omega C_i) + k_c L) Q = (g_i F_w0 e^{i phi_i}),
L the ring's Laplacian (N = 2: the two contacts join the same pair, so L = [[2, -2], [-2, 2]]).
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from functools import lru_cache
from typing import Sequence

import numpy as np

from tests.support.modes_galerkin import Modes

CONSISTENT = 2  # the blade FMUs' `formulation` value of the consistent (energy) form


def contact_stiffness(kn: float, kd_ratio: float, gamma: float) -> float:
    """k_c [N/m] of the stuck Jenkins contact without a gap (module docstring)."""
    return kn * math.cos(gamma) ** 2 + kd_ratio * kn * math.sin(gamma) ** 2


@lru_cache(maxsize=64)
def blade(EI: float = 343.0, c: float = 29.8) -> tuple[float, float, float, float, float]:
    """(M, C, Ks, Kw, g) of the one-mode blade, consistent formulation, other parameters at Table 1."""
    M, C, K, K2, g = Modes(1, EI=EI, c=c).matrices()
    return float(M[0, 0]), float(C[0, 0]), float(K[0, 0]), float(K2[0, 0]), float(g[0])


@dataclass(frozen=True)
class LinearRing:
    """N blades (EI factors `ei`), damping c [N s/m2], load F_w0 [N/m], engine order EO, k_c [N/m]."""

    ei: Sequence[float]
    eo: int
    fw0: float
    kc: float
    c: float = 29.8
    direction: int = 1  # -1: the wave turned the other way (phi_i = -2 pi EO i / N), for the tests' checks

    @property
    def n(self) -> int:
        return len(self.ei)

    def constants(self) -> np.ndarray:
        """Rows (M, C, Ks, Kw, g), one column per blade."""
        return np.array([blade(343.0 * f, self.c) for f in self.ei]).T

    def laplacian(self) -> np.ndarray:
        N = self.n
        L = np.zeros((N, N))
        for j in range(N):  # contact j on u_j = q_j - q_{j+1}
            a, b = j, (j + 1) % N
            L[a, a] += 1.0
            L[b, b] += 1.0
            L[a, b] -= 1.0
            L[b, a] -= 1.0
        return L

    def phases(self) -> np.ndarray:
        return self.direction * 2 * math.pi * self.eo * np.arange(self.n) / self.n

    def amplitudes(self, speed: float) -> np.ndarray:
        """Complex Q_i [m] at `speed` [rpm]: q_i(t) = Im(Q_i e^{i omega t})."""
        M, C, Ks, Kw, g = self.constants()
        Om = 2 * math.pi * speed / 60
        w = self.eo * Om
        D = np.diag(Ks + Kw * Om * Om - w * w * M + 1j * w * C) + self.kc * self.laplacian()
        return np.linalg.solve(D, g * self.fw0 * np.exp(1j * self.phases()))


def first_harmonic(t: np.ndarray, q: np.ndarray, omega: float) -> np.ndarray:
    """Complex Q per column of q(t) with q ~ Im(Q e^{i omega t}) + const, by least squares over the
    samples t (exact for a sinusoid plus a constant, whatever the sampling)."""
    A = np.column_stack([np.sin(omega * t), np.cos(omega * t), np.ones_like(t)])
    (a, b, _), *_ = np.linalg.lstsq(A, q, rcond=None)
    return a + 1j * b  # Im((a + i b) e^{i w t}) = a sin + b cos


def last_periods(t: np.ndarray, omega: float, periods: int = 1) -> np.ndarray:
    """Mask of the samples in the last `periods` excitation periods."""
    return t >= t[-1] - periods * 2 * math.pi / omega - 1e-12
