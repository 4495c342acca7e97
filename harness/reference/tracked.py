"""Independent Python reference, part 5: the stability of a harmonic-balance root under the FMU's
tracked-amplitude dynamics (docs/model-notes.md s.3), gating off.

The harmonic balance is the product's (harness/analysis/harmonic_balance.py, slow-flow stability);
this map is the reference's own check of it: built on the reference's Galerkin reduction (blade),
describing functions by quadrature (contact) and the exact piecewise-linear solution of fixedpoint.
"""

from __future__ import annotations

import math
from typing import Any, Iterable, Mapping

import numpy as np
from scipy.optimize import brentq

from harness.model.contact import COULOMB_DF, MACROSLIP_DF
from harness.model.params import validate
from harness.reference.blade import galerkin
from harness.reference.contact import contact_consts, describing_function
from harness.reference.fixedpoint import _Mode, _Piece


def tracked_map_radius(params: Mapping[str, Any] | None, speed_rpm: float, B: float, rel_step: float = 1e-6) -> float:
    """Spectral radius of the tracked-amplitude period map at the HB root B (gating off): the state
    at a period start (q, q'/w, B) is mapped exactly (constant coefficients inside a period: linear
    ODE with K0 + K_eq(B), C0 + C_eq(B), solved in closed form) to (q, q'/w, max |q| over the
    period) one period later. The HB root is a fixed point of this map; radius < 1 means the
    FMU's tracked-amplitude dynamics (model-notes s.3) converge to it after a small perturbation."""
    p = validate(params or {})
    if int(p["frictionModel"]) not in (MACROSLIP_DF, COULOMB_DF):
        raise ValueError("the tracked map needs a describing-function model (frictionModel 1 or 2)")
    gal = galerkin(p)
    cc = contact_consts(p)
    Om = 2 * math.pi * speed_rpm / 60.0
    w = int(p["engineOrder"]) * Om
    T = 2 * math.pi / w
    K0 = gal.K0static + gal.K0omega2 * Om * Om
    M, C0, F = gal.M, gal.C0, float(p["Fw0"]) * gal.loadGain

    def dfKC(b: float) -> tuple[float, float]:
        df = describing_function(cc, b, 1.0, int(p["frictionModel"]), int(p["projection"]))
        return float(df.Keq), float(df.CeqOmega)

    def pmap(x: np.ndarray) -> np.ndarray:
        q0, u0, b = x
        K, Cw = dfKC(float(b))
        mode = _Mode(M, C0 + Cw / w, K0 + K, F, w)
        pc = _Piece(mode, 0.0, q0, u0 * w)
        n = int(math.ceil(48.0 * mode.fast * T / (2 * math.pi))) + 2
        ts = np.linspace(0.0, T, n)
        q, v = pc.qv(ts)
        qmax = float(np.max(np.abs(q)))
        for i in np.nonzero(v[1:] * v[:-1] < 0)[0]:
            te = brentq(lambda t: float(pc.qv(t)[1]), ts[i], ts[i + 1], xtol=1e-18, rtol=4 * np.finfo(float).eps)
            qmax = max(qmax, abs(float(pc.qv(te)[0])))
        return np.array([float(q[-1]), float(v[-1]) / w, qmax])

    K, Cw = dfKC(float(B))
    Z = F / complex(K0 + K - M * w * w, Cw + w * C0)  # q = Im(Z e^{i w t})
    x0 = np.array([Z.imag, (1j * w * Z).imag / w, B])
    J = np.empty((3, 3))
    for j in range(3):
        h = rel_step * B
        xp, xm = x0.copy(), x0.copy()
        xp[j] += h
        xm[j] -= h
        J[:, j] = (pmap(xp) - pmap(xm)) / (2 * h)
    return float(np.max(np.abs(np.linalg.eigvals(J))))


def tracked_radii(params: Mapping[str, Any] | None, solutions: Iterable[Any]) -> list[float]:
    """tracked_map_radius of every solution (anything with .speed [rpm] and .B [m], e.g. HBSolution)."""
    return [tracked_map_radius(params, s.speed, s.B) for s in solutions]
