"""One-harmonic balance of the blade (docs/model.md s.5), gating off: the amplitude-speed curves'
`hb` method and the seeds of the periodic-orbit search.

B = F / |K0(Omega) + K_eq(B) - M w^2 + i (w C0 + w C_eq(B))| with F = Fw0 * loadGain and
w = engineOrder * Omega. Note w C_eq(B) = sin(g) f_c(B) w does not depend on w, so the describing
function is evaluated once on a B grid for a whole speed curve. All roots in (0, B_max] are found:
the open branch (B <= d, linear response) and every sign change of the residual
R(B) = B |D(B)| - F on a dense log grid of B - d, refined by a vectorised Illinois regula falsi
(bracketing, superlinear) to ~1e-14 relative. Stability is the slow-flow (first-order averaging)
criterion of an oscillator with amplitude-dependent stiffness and damping, see `stability`.
Built on the product's Galerkin reduction and closed-form describing functions (harness/model);
the reference checks it through the FMU (shooting orbits against HB roots) and its own
tracked-amplitude map (harness/reference/tracked.py).
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from functools import lru_cache
from typing import Any, Mapping, Sequence

import numpy as np

from harness.model.contact import COULOMB_DF, MACROSLIP_DF, contact_consts, describing_function
from harness.model.galerkin import galerkin
from harness.model.params import validate


@dataclass(frozen=True)
class HBSolution:
    """One harmonic-balance solution at one speed."""

    B: float  # amplitude of q [m]
    phase: float  # phase of q relative to the load sin(psi) [rad], q = B sin(psi + phase)
    stable: bool  # slow-flow stability (see `stability`)
    open: bool  # True on the contact-free branch B <= d
    speed: float  # rotor speed [rpm]


class _HBModel:
    """Constants and the vectorised residual for one parameter set."""

    def __init__(self, params: Mapping[str, Any]):
        p = validate(params)
        model = int(p["frictionModel"])
        if model not in (MACROSLIP_DF, COULOMB_DF):
            raise ValueError("harmonic balance needs a describing-function model (frictionModel 1 or 2)")
        self.model, self.proj = model, int(p["projection"])
        self.gal = galerkin(p)
        self.cc = contact_consts(p)
        self.EO = int(p["engineOrder"])
        self.F = float(p["Fw0"]) * self.gal.loadGain  # generalized load amplitude [N]
        self.d = self.cc.d

    def dfKC(self, B: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
        """(K_eq(B) [N/m], w C_eq(B) [N/m]) at amplitudes B (0 where B <= d)."""
        df = describing_function(self.cc, B, 1.0, self.model, self.proj)
        return np.asarray(df.Keq), np.asarray(df.CeqOmega)

    def lin(self, rpm: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
        """(K0 - M w^2 [N/m], w C0 [N/m]) at speeds rpm."""
        Om = 2 * math.pi * np.asarray(rpm, dtype=float) / 60.0
        w = self.EO * Om
        return self.gal.K0static + self.gal.K0omega2 * Om * Om - self.gal.M * w * w, w * self.gal.C0

    def residual(self, B: np.ndarray, re0: np.ndarray, im0: np.ndarray) -> np.ndarray:
        K, Cw = self.dfKC(B)
        return B * np.hypot(re0 + K, im0 + Cw) - self.F


def _illinois(
    fun, a: np.ndarray, b: np.ndarray, fa: np.ndarray, fb: np.ndarray, rtol: float = 1e-14, maxiter: int = 200
) -> np.ndarray:
    """Vectorised Illinois regula falsi on brackets [a, b] with fa * fb <= 0."""
    a, b, fa, fb = (np.array(x, dtype=float) for x in (a, b, fa, fb))
    side = np.zeros(a.shape, dtype=int)
    x = b.copy()
    for _ in range(maxiter):
        width = np.abs(b - a)
        done = (width <= rtol * np.abs(b)) | (fa == 0) | (fb == 0)
        if done.all():
            break
        denom = fb - fa
        x = np.where(denom != 0, (a * fb - b * fa) / np.where(denom != 0, denom, 1.0), 0.5 * (a + b))
        x = np.where((x <= np.minimum(a, b)) | (x >= np.maximum(a, b)), 0.5 * (a + b), x)
        fx = fun(x)
        left = np.sign(fx) == np.sign(fa)  # root in [x, b]: replace a
        nd = ~done
        # Illinois: halve the retained end's value when the same end is kept twice
        new_a = np.where(nd & left, x, a)
        new_fa = np.where(nd & left, fx, fa)
        new_b = np.where(nd & ~left, x, b)
        new_fb = np.where(nd & ~left, fx, fb)
        new_fb = np.where(nd & left & (side == 1), new_fb * 0.5, new_fb)
        new_fa = np.where(nd & ~left & (side == -1), new_fa * 0.5, new_fa)
        side = np.where(nd, np.where(left, 1, -1), side)
        a, fa, b, fb = new_a, new_fa, new_b, new_fb
    return np.where(np.abs(fa) < np.abs(fb), a, b)


def _B_grid(d: float, B_max: float, n_scan: int) -> np.ndarray:
    lo = max(d, 1e-12) * 1e-9
    if d > 0:
        return d + np.geomspace(lo, max(B_max - d, 2 * lo), n_scan)
    return np.geomspace(B_max * 1e-9, B_max, n_scan)


def stability(hb: _HBModel, B: np.ndarray, rpm: np.ndarray) -> np.ndarray:
    """Slow-flow stability of HB roots (B > d). With q = Re(A e^{i w t}), first-order averaging gives
    2 i w M A' = F - D(|A|) A, D(a) = K0 - M w^2 + K_eq(a) + i (w C0 + w C_eq(a)). The Jacobian at a
    root has det > 0 iff d(a |D(a)|)/da > 0 (the residual's slope: the turning-point criterion) and
    trace < 0 iff d(a^2 (w C0 + w C_eq(a)))/da > 0 (dissipation per cycle growing with a). Stable iff
    both hold. Derivatives by central differences with step 1e-7 a (one-sided next to d)."""
    re0, im0 = hb.lin(rpm)
    h = 1e-7 * B
    lo = np.maximum(B - h, hb.d + 0.5 * (B - hb.d))
    hi = B + h

    def R(x: np.ndarray) -> np.ndarray:
        return hb.residual(x, re0, im0)

    def Dis(x: np.ndarray) -> np.ndarray:
        _, Cw = hb.dfKC(x)
        return x * x * (im0 + Cw)

    slope = (R(hi) - R(lo)) / (hi - lo)
    trace = (Dis(hi) - Dis(lo)) / (hi - lo)
    return (slope > 0) & (trace > 0)


def harmonic_balance(
    params: Mapping[str, Any] | None,
    speed_rpm: float | Sequence[float] | np.ndarray,
    B_max: float | None = None,
    n_scan: int = 800,
) -> list[HBSolution] | list[list[HBSolution]]:
    """All one-harmonic solutions (gating off) at `speed_rpm` (scalar -> list[HBSolution] sorted by B;
    array -> one such list per speed). B_max defaults to F/(w C0), an upper bound of every root
    since w C_eq >= 0. Roots closer together than the scan resolution (n_scan log points of B - d
    from 1e-9 d to B_max) can be missed, i.e. only right at a fold. `stable` is the slow-flow
    criterion (see `stability`)."""
    hb = _HBModel(params or {})
    scalar = np.ndim(speed_rpm) == 0
    rpm = np.atleast_1d(np.asarray(speed_rpm, dtype=float))
    if np.any(rpm <= 0):
        raise ValueError("harmonic balance needs speed > 0")
    re0, im0 = hb.lin(rpm)
    bmax = np.full(rpm.shape, float(B_max)) if B_max is not None else hb.F / im0 * (1 + 1e-9)
    d = hb.d
    result: list[list[HBSolution]] = [[] for _ in rpm]
    # open branch: linear response below the gap
    Blin = hb.F / np.hypot(re0, im0)
    for i in np.nonzero((Blin <= d) & (Blin <= bmax))[0]:
        result[i].append(HBSolution(float(Blin[i]), float(-math.atan2(im0[i], re0[i])), True, True, float(rpm[i])))
    # contact branch: scan + bracketing on a grid shared by all speeds
    if np.any(bmax > d):
        grid = _B_grid(d, float(bmax.max()), n_scan)
        K, Cw = hb.dfKC(grid)
        R = grid[None, :] * np.hypot(re0[:, None] + K[None, :], im0[:, None] + Cw[None, :]) - hb.F
        valid = grid[None, :] <= bmax[:, None]
        sgn = np.sign(R)
        ch = (sgn[:, 1:] * sgn[:, :-1] <= 0) & (sgn[:, 1:] != sgn[:, :-1]) & valid[:, 1:]
        si, gj = np.nonzero(ch)
        if si.size:
            a, b = grid[gj], grid[gj + 1]
            fa, fb = R[si, gj], R[si, gj + 1]
            r0, i0 = re0[si], im0[si]
            roots = _illinois(lambda x: hb.residual(x, r0, i0), a, b, fa, fb)
            stab = stability(hb, roots, rpm[si])
            Kr, Cr = hb.dfKC(roots)
            ph = -np.arctan2(i0 + Cr, r0 + Kr)
            for k in range(roots.size):
                result[si[k]].append(HBSolution(float(roots[k]), float(ph[k]), bool(stab[k]), False, float(rpm[si[k]])))
    for i, lst in enumerate(result):
        lst.sort(key=lambda s: s.B)
        # a residual exactly 0 on a grid point brackets the same root twice: keep one
        result[i] = [s for j, s in enumerate(lst) if j == 0 or s.B - lst[j - 1].B > 1e-12 * s.B]
    return result[0] if scalar else result


@lru_cache(maxsize=32)
def _hb_model(items: tuple) -> _HBModel:
    """The HB model of a parameter set (its Galerkin constants take ~7 ms), cached per process."""
    return _HBModel(dict(items))


def linear_orbit(params: Mapping[str, Any] | None, speed_rpm: float, B: float | None) -> tuple[float, float]:
    """(q, q') at load phase 0 of the T-periodic response of the blade linearised at amplitude B
    (K0 + K_eq(B), C0 + C_eq(B), gating off; B None or <= d: contact-free): q = Im(Z e^{i w t}),
    Z = F / (K0 + K_eq - M w^2 + i w (C0 + C_eq)). The exact periodic orbit of the ungated fixed-B
    model (a linear ODE) and the one-harmonic guess that starts shooting elsewhere."""
    q, v = linear_orbits(params, speed_rpm, np.array([0.0 if B is None else float(B)]))
    return float(q[0]), float(v[0])


def linear_orbits(params: Mapping[str, Any] | None, speed_rpm: float, B: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """linear_orbit at every amplitude of the array B at once (B <= d: contact-free)."""
    hb = _hb_model(tuple(sorted(validate(params or {}).items())))
    re0, im0 = hb.lin(np.array([float(speed_rpm)]))
    K, Cw = hb.dfKC(np.asarray(B, dtype=float))
    Z = hb.F / ((re0[0] + K) + 1j * (im0[0] + Cw))
    w = hb.EO * 2 * math.pi * float(speed_rpm) / 60.0
    return Z.imag, (1j * w * Z).imag
