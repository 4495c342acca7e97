"""The ring with linear couplings and its closed-form forced response: an N x N complex solve per
speed. It checks the whole ring pipeline where the answer is known, and it is the setting of
Whitehead's bound.

With the gap d = 0 and a friction coefficient the contact never reaches (mu large), the ShroudContact
element is a linear spring on u_j = q_j - q_{j+1} (docs/model.md s.8; eq. 3 and 14):
    F_c = F_n cos g + F_f sin g = (kn cos^2 g + kd sin^2 g) u = k_c u,   kd = kdRatio kn.
Blade i (one-mode Galerkin constants of harness.model.galerkin, constant speed Omega, omega = EO Omega):
    M_i q_i'' + C_i q_i' + K_i(Omega) q_i + k_c (2 q_i - q_{i-1} - q_{i+1}) = G_i F_w0 sin(omega t + phi_i),
    phi_i = 2 pi EO i / N (the travelling wave). The steady state q_i = Im(Q_i e^{i omega t}) solves
    (diag(K_i - omega^2 M_i + i omega C_i) + k_c L) Q = (G_i F_w0 e^{i phi_i}),  L the ring's Laplacian,
and the blade amplitudes are |Q_i|.
"""

from __future__ import annotations

import math
from typing import Any, Mapping, Sequence

import numpy as np
from scipy.optimize import differential_evolution, minimize_scalar

from harness.model.galerkin import galerkin
from harness.model.params import validate
from harness.system.ring import Ring

# contact parameters that make ShroudContact a linear spring: no gap, friction never reached
LINEAR_CONTACT = {"d": 0.0, "mu": 1e6}
BLADE_KEYS = ("EI", "rho", "A", "l", "c", "m0", "formulation")


def coupling_stiffness(contact: Mapping[str, Any]) -> float:
    """k_c = kn cos^2(gamma) + kdRatio kn sin^2(gamma) [N/m] of a stuck contact without a gap."""
    p = validate({k: v for k, v in contact.items() if k in ("kn", "kdRatio", "gamma")})
    kn, g = float(p["kn"]), float(p["gamma"])
    return kn * math.cos(g) ** 2 + float(p["kdRatio"]) * kn * math.sin(g) ** 2


def kn_for(k_c: float, contact: Mapping[str, Any] | None = None) -> float:
    """The kn [N/m] that gives the coupling stiffness k_c with the contact's kdRatio and gamma."""
    return k_c / coupling_stiffness({**dict(contact or {}), "kn": 1.0})


def blade_constants(ring: Ring) -> list:
    """The Galerkin constants (harness.model.galerkin.Galerkin) of every blade of the ring."""
    return [
        galerkin(validate({k: v for k, v in ring.blade_params(i).items() if k in BLADE_KEYS})) for i in range(ring.n)
    ]


class LinearRing:
    """The linear ring's matrices, built once: `amplitudes(speeds)` solves for many speeds at once."""

    def __init__(self, ring: Ring):
        c = dict(ring.contact)
        bad = {k: c.get(k) for k, v in LINEAR_CONTACT.items() if c.get(k) != v}
        if bad:
            raise ValueError(f"the closed form needs the linear contact {LINEAR_CONTACT}, the ring has {bad}")
        N, self.eo = ring.n, ring.engine_order
        gs = blade_constants(ring)
        self.M, self.C, self.Ks, self.Kw = (
            np.array([getattr(g, a) for g in gs]) for a in ("M", "C0", "K0static", "K0omega2")
        )
        eye = np.eye(N)
        self.KL = coupling_stiffness(c) * (
            2 * eye - np.roll(eye, 1, axis=1) - np.roll(eye, -1, axis=1)
        )  # N = 2: two contacts
        self.force = np.array(
            [g.loadGain * ring.fw0 * np.exp(2j * math.pi * self.eo * i / N) for i, g in enumerate(gs)]
        )

    def amplitudes(self, speeds: Sequence[float] | np.ndarray) -> np.ndarray:
        """|Q_i| [m] per speed [rpm] (rows) and blade (columns)."""
        Om = 2 * math.pi * np.atleast_1d(np.asarray(speeds, dtype=float)) / 60
        w = self.eo * Om
        diag = self.Ks + self.Kw * (Om * Om)[:, None] - (w * w)[:, None] * self.M + 1j * w[:, None] * self.C
        D = self.KL[None] + diag[:, :, None] * np.eye(len(self.M))[None]
        return np.abs(np.linalg.solve(D, np.broadcast_to(self.force, diag.shape)[..., None])[..., 0])

    def peak(self, band: tuple[float, float], points: int = 400) -> tuple[float, float]:
        """(largest blade amplitude [m], its speed [rpm]) over the band: a scan, then Brent's
        bounded search between the scan's neighbours of its largest point."""
        speeds = np.linspace(band[0], band[1], points)
        a = self.amplitudes(speeds).max(axis=1)
        k = int(np.argmax(a))
        lo, hi = speeds[max(k - 1, 0)], speeds[min(k + 1, points - 1)]
        r = minimize_scalar(
            lambda n: -self.amplitudes(n).max(), bounds=(lo, hi), method="bounded", options={"xatol": 1e-6}
        )
        return -float(r.fun), float(r.x)


def response(ring: Ring, speeds: Sequence[float] | np.ndarray) -> np.ndarray:
    """|Q_i| [m] per speed [rpm] (rows) and blade (columns) of the linear ring (`ring.contact` with
    LINEAR_CONTACT on top)."""
    return LinearRing(ring).amplitudes(speeds)


def worst_mistuning(
    ring: Ring, band: tuple[float, float], spread: float = 0.1, seed: int = 1, maxiter: int = 60, popsize: int = 15
) -> tuple[float, np.ndarray]:
    """The largest amplification over zero-mean stiffness patterns EI_i = EI (1 + d_i), |d_i| <=
    spread (before removing the mean), found by differential evolution (scipy): (amplification =
    the mistuned ring's peak over `band` / the tuned ring's, d). Zero mean, as in Whitehead's
    setting: a shift of the mean stiffness moves the resonance, which is not an amplification.
    K0static is proportional to EI (the mode shape depends on m0 / (rho A l) only), so a pattern
    scales the tuned blades' K0static."""
    lin = LinearRing(ring)
    tuned = lin.peak(band)[0]
    Ks0 = lin.Ks.copy()

    def negative_amplification(x: np.ndarray) -> float:
        lin.Ks = Ks0 * (1 + x - np.mean(x))
        return -lin.peak(band, 600)[0] / tuned

    best = differential_evolution(
        negative_amplification,
        [(-spread, spread)] * ring.n,
        maxiter=maxiter,
        popsize=popsize,
        seed=seed,
        tol=1e-8,
        polish=True,
    )
    return -float(best.fun), best.x - np.mean(best.x)
