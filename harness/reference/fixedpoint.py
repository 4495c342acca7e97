"""Independent Python reference, part 5: the paper's fixed point A(B) = B (docs/model.md s.4).

A(B) is the steady-state amplitude (max |q| over one excitation period) of the simulation with a
fixed amplitude B (amplitudeMode 1, gating per params, describing-function models) at constant
speed under f_w = Fw0 sin(psi). For fixed B and constant speed the equation of motion is piecewise
linear with constant coefficients, so it is integrated exactly: inside each piece q(t) is the
particular harmonic solution plus a matrix-exponential (two-eigenvalue) homogeneous part; the
switching instants |q| = d are found by sampling q and q' densely (24 samples per fastest period,
so no double crossing can hide between samples) and brentq. Steady state: simulate from rest, then
accelerate with Newton shooting on the period map (q, q') -> (q, q') one period later, accepted
only if the shooting fixed point is attracting (spectral radius < 1) and successive simulated
periods then agree; otherwise the plain simulation continues. `fixed_point` brackets A(B) - B on a
scan over (d, B_max] and refines every root with brentq; `naive_iteration` runs the paper's
procedure B <- A(B) and reports its fixed point or 2-cycle.
"""

from __future__ import annotations

import cmath
import math
from dataclasses import dataclass, field
from typing import Any, Mapping

import numpy as np
from scipy.optimize import brentq

from harness.model.params import validate
from harness.reference.blade import galerkin
from harness.reference.contact import COULOMB_DF, MACROSLIP_DF, contact_consts, describing_function

TWO_PI = 2.0 * math.pi


class _Mode:
    """M q'' + C q' + K q = F sin(w t): particular complex amplitude and eigenvalues."""

    def __init__(self, M: float, C: float, K: float, F: float, w: float):
        self.Z = F / complex(K - M * w * w, w * C)  # q_p = Im(Z e^{i w t})
        disc = cmath.sqrt(C * C - 4.0 * M * K)
        self.l1 = (-C + disc) / (2.0 * M)
        self.l2 = (-C - disc) / (2.0 * M)
        if abs(self.l1 - self.l2) < 1e-9 * abs(self.l1):
            raise ValueError("critically damped piece: not supported by the exact stepper")
        self.w = w
        self.fast = max(w, abs(self.l1.imag), abs(self.l2.imag), 1e-300)


class _Piece:
    """Exact solution of one mode from (t0, q0, v0)."""

    def __init__(self, m: _Mode, t0: float, q0: float, v0: float):
        self.m, self.t0 = m, t0
        e = cmath.exp(1j * m.w * t0)
        qh, vh = q0 - (m.Z * e).imag, v0 - (1j * m.w * m.Z * e).imag
        self.a1 = (vh - m.l2 * qh) / (m.l1 - m.l2)
        self.a2 = qh - self.a1

    def qv(self, t: Any) -> tuple[Any, Any]:
        m = self.m
        t = np.asarray(t, dtype=float)
        tau = t - self.t0
        e = np.exp(1j * m.w * t)
        e1, e2 = np.exp(m.l1 * tau), np.exp(m.l2 * tau)
        q = (m.Z * e).imag + (self.a1 * e1 + self.a2 * e2).real
        v = (1j * m.w * m.Z * e).imag + (self.a1 * m.l1 * e1 + self.a2 * m.l2 * e2).real
        return q, v


class PiecewiseStepper:
    """Exact period-by-period integration of the fixed-B describing-function model at constant speed."""

    def __init__(self, params: Mapping[str, Any], speed_rpm: float, B: float):
        p = validate(params)
        model = int(p["frictionModel"])
        if model not in (MACROSLIP_DF, COULOMB_DF):
            raise ValueError("A(B) needs a describing-function model (frictionModel 1 or 2)")
        if speed_rpm <= 0:
            raise ValueError("speed must be > 0")
        gal = galerkin(p)
        cc = contact_consts(p)
        self.d = cc.d
        Om = TWO_PI * speed_rpm / 60.0
        self.w = int(p["engineOrder"]) * Om
        self.T = TWO_PI / self.w
        F = float(p["Fw0"]) * gal.loadGain
        K0 = gal.K0static + gal.K0omega2 * Om * Om
        df = describing_function(cc, B, self.w, model, int(p["projection"]))
        self.gating = bool(p["gating"])
        self.modes = (_Mode(gal.M, gal.C0, K0, F, self.w), _Mode(gal.M, gal.C0 + df.Ceq, K0 + df.Keq, F, self.w))
        self.switching = self.gating and (df.Keq != 0.0 or df.Ceq != 0.0)

    def initial_g(self, q: float) -> int:
        return 1 if (not self.gating or abs(q) > self.d) else 0

    def _knots(self, pc: _Piece, ta: float, tb: float) -> np.ndarray:
        """Sample times (24 per fastest period) plus the extrema of q between them: q is monotone
        between consecutive knots, so a level crossing cannot hide between them."""
        n = int(math.ceil(24.0 * pc.m.fast * (tb - ta) / TWO_PI)) + 2
        ts = np.linspace(ta, tb, n)
        _, v = pc.qv(ts)
        ext = [
            brentq(lambda t: float(pc.qv(t)[1]), ts[i], ts[i + 1], xtol=1e-16, rtol=4 * np.finfo(float).eps)
            for i in np.nonzero((v[1:] * v[:-1]) < 0)[0]
        ]
        return np.sort(np.concatenate([ts, ext])) if ext else ts

    def _first_event(self, pc: _Piece, g: int, side: int, ta: float, tb: float) -> float | None:
        """First instant in (ta, tb] where the gating flag switches, or None. The switching
        functions are f = q - d (up), -(q + d) (up) when open, -(side q - d) (up) in contact."""
        knots = self._knots(pc, ta, tb)
        q, _ = pc.qv(knots)
        d = self.d
        cands = [(1.0, -d), (-1.0, -d)] if g == 0 else [(-float(side), d)]  # f = c q + off
        best = None
        for c, off in cands:
            val = c * q + off
            hit = np.nonzero((val[:-1] <= 0) & (val[1:] > 0))[0]
            if hit.size == 0:
                continue
            i = int(hit[0])
            f = lambda t: c * float(pc.qv(t)[0]) + off  # noqa: E731
            t = knots[i] if val[i] == 0 else brentq(f, knots[i], knots[i + 1], xtol=1e-16, rtol=4 * np.finfo(float).eps)
            for _ in range(4):  # land on the post-switch side
                if f(t) > 0 or t >= knots[i + 1]:
                    break
                t = np.nextafter(t, np.inf)
            if best is None or t < best:
                best = float(t)
        return best

    def _extrema(self, pc: _Piece, ta: float, tb: float) -> float:
        """max |q| over [ta, tb] of one piece (end points and interior extrema)."""
        q, _ = pc.qv(self._knots(pc, ta, tb))
        return float(np.max(np.abs(q)))

    def advance(
        self, t: float, q: float, v: float, g: int, t_end: float, track: bool = True
    ) -> tuple[float, float, int, float]:
        """Integrate exactly from t to t_end: returns (q, v, g, max |q| over [t, t_end])."""
        qmax = abs(q)
        for _ in range(100000):
            pc = _Piece(self.modes[g], t, q, v)
            side = 1 if q > 0 else -1
            ts = self._first_event(pc, g, side, t, t_end) if self.switching else None
            stop = t_end if ts is None else ts
            if track:
                qmax = max(qmax, self._extrema(pc, t, stop))
            qq, vv = pc.qv(stop)
            q, v = float(qq), float(vv)
            t = stop
            if ts is None:
                return q, v, g, qmax
            g = 1 - g
        raise RuntimeError("more than 100000 switchings in one advance: chattering")

    def trajectory(self, t_eval: np.ndarray) -> np.ndarray:
        """q at the sorted times t_eval >= 0, from rest at t = 0 (for cross-checks)."""
        t, q, v, g = 0.0, 0.0, 0.0, self.initial_g(0.0)
        out = np.empty(len(t_eval))
        for i, te in enumerate(t_eval):
            if te > t:
                q, v, g, _ = self.advance(t, q, v, g, float(te), track=False)
                t = float(te)
            out[i] = q
        return out


@dataclass
class SteadyState:
    A: float  # steady-state amplitude: max |q| over one period [m]
    converged: bool
    periods: int  # periods simulated (shooting evaluations included)
    spectral_radius: float  # of the period map's Jacobian at the accepted state (nan if none)
    q0: float = 0.0  # periodic state at psi = 2 pi k
    v0: float = 0.0
    subharmonic: int = 1  # steady state period in excitation periods (1: T-periodic)


def steady_amplitude(
    params: Mapping[str, Any],
    speed_rpm: float,
    B: float,
    rtol: float = 1e-9,
    transient_periods: int = 50,
    max_periods: int = 6000,
    window: int = 20,
    max_sub: int = 8,
) -> SteadyState:
    """A(B): steady max |q| over a period of the fixed-B run started from rest (see module doc).

    Plain simulation, period by period. With D_k = the change of the period-start state (q, q'/w)
    over one period relative to the amplitude and rho = (D_k / D_{k-window})^(1/window) the observed
    contraction per period, the distance to the limit is about D_k rho / (1 - rho): converged when
    that is <= rtol for 3 periods in a row, or when D has stagnated at the roundoff floor (<= 1e-10
    and not decreasing over the window). The same test on x_k - x_{k-p} detects a subharmonic
    steady state of period p T (p <= max_sub): then A is the max over those p periods and
    `subharmonic` = p. Every `transient_periods` periods Newton shooting is tried
    as an accelerator (given up after two failures: grazing orbits make the period map non-smooth)."""
    st = PiecewiseStepper(params, speed_rpm, B)
    T, w = st.T, st.w
    k = 0
    q, v = 0.0, 0.0
    g = st.initial_g(q)

    def pmap(x: np.ndarray, k0: int) -> tuple[np.ndarray, float, int]:
        g0 = st.initial_g(float(x[0]))
        q1, v1, g1, m = st.advance(k0 * T, float(x[0]), float(x[1]), g0, (k0 + 1) * T)
        return np.array([q1, v1]), m, g1

    xs: list[tuple[float, float]] = [(q, v)]  # period-start states
    ms: list[float] = []  # max |q| over each period
    streak = [0] * (max_sub + 1)
    failures = 0
    while k < max_periods:
        q, v, g, m = st.advance(k * T, q, v, g, (k + 1) * T)
        k += 1
        xs.append((q, v))
        ms.append(m)
        for per in range(1, max_sub + 1):
            n = len(xs) - 1
            if n < per + window:
                break
            scale = max(max(ms[-per:]), 1e-300)

            def Dp(i: int) -> float:
                return max(abs(xs[i][0] - xs[i - per][0]), abs(xs[i][1] - xs[i - per][1]) / w) / scale

            Dk, Dold = Dp(n), Dp(n - window)
            rho = min((Dk / Dold) ** (1.0 / window), 0.999999) if Dold > 0 and Dk > 0 else 0.0
            est = Dk * rho / (1.0 - rho) if Dk > 0 else 0.0
            floor = Dk <= 1e-10 and max(Dp(i) for i in range(n - window, n + 1)) <= 1e-10
            streak[per] = streak[per] + 1 if (est <= rtol or floor) and Dk <= 1e-3 * rtol**0.5 else 0
            if streak[per] >= 3:
                # report the smallest divisor period that is as converged (a p-periodic orbit is
                # also 2p-periodic and the two tests need not fire in order)
                for sub in range(1, per + 1):
                    if per % sub == 0:
                        if sub == per:
                            break
                        Ds = max(abs(xs[n][0] - xs[n - sub][0]), abs(xs[n][1] - xs[n - sub][1]) / w) / scale
                        if Ds <= max(100.0 * Dk, 1e-10):
                            break
                return SteadyState(max(ms[-sub:]), True, k, math.nan, q, v, sub)
        if k >= transient_periods and k % transient_periods == 0 and failures < 2:
            x, rho_j, evals = _shoot(pmap, np.array([q, v]), k, rtol)
            k += evals
            if x is None:
                failures += 1
                continue
            # verification: successive simulated periods from the shot state agree
            mv = []
            xx = x.copy()
            for j in range(3):
                xx, mj, _ = pmap(xx, k + j)
                mv.append(mj)
            k += 3
            if max(mv) - min(mv) <= rtol * max(mv) and np.allclose(
                xx, x, rtol=0.0, atol=rtol * max(mv) * np.array([1.0, w])
            ):
                return SteadyState(max(mv), True, k, rho_j, float(x[0]), float(x[1]))
            failures += 1
    return SteadyState(ms[-1] if ms else 0.0, False, k, math.nan, q, v)


def _shoot(pmap, x0: np.ndarray, k0: int, rtol: float, maxiter: int = 12) -> tuple[np.ndarray | None, float, int]:
    """Newton on P(x) - x = 0 with a forward-difference Jacobian. Returns (x*, spectral radius,
    period evaluations) with x* None if it fails or the fixed point is not attracting."""
    x = x0.copy()
    evals = 0
    scale = np.array([max(abs(x[0]), 1e-12), max(abs(x[1]), 1e-9)])
    J = np.eye(2)
    for _ in range(maxiter):
        Px, _, _ = pmap(x, k0)
        evals += 1
        r = Px - x
        J = np.empty((2, 2))
        for j in range(2):
            h = 1e-7 * scale[j]
            xh = x.copy()
            xh[j] += h
            J[:, j] = (pmap(xh, k0)[0] - Px) / h
            evals += 1
        try:
            dx = np.linalg.solve(J - np.eye(2), -r)
        except np.linalg.LinAlgError:
            return None, math.nan, evals
        x = x + dx
        if np.all(np.abs(dx) <= 1e-3 * rtol * scale) and np.all(np.abs(r) <= 10 * rtol * scale):
            rho = float(np.max(np.abs(np.linalg.eigvals(J))))
            return (x if rho < 1.0 else None), rho, evals
    return None, math.nan, evals


@dataclass
class FixedPointRoot:
    B: float  # root of A(B) = B [m]
    converged: bool  # A(B) reached a steady state at the root and brentq converged
    open: bool  # the contact-free root B <= d (A = linear amplitude)
    slope: float  # dA/dB at the root: the naive iteration converges locally iff |slope| < 1


@dataclass
class FixedPointResult:
    speed: float  # [rpm]
    roots: list[FixedPointRoot]
    scan_B: np.ndarray  # scanned B [m]
    scan_A: np.ndarray  # A(B) on the scan [m]
    scan_converged: np.ndarray  # steady state reached for each scanned B
    naive: dict = field(default_factory=dict)  # naive iteration: 'sequence', 'fixed' or 'cycle' (or None)


def fixed_point(
    params: Mapping[str, Any] | None,
    speed_rpm: float,
    B_max: float | None = None,
    n_scan: int = 24,
    naive_start: float | None = None,
    naive_iter: int = 30,
    rtol: float = 1e-9,
    horizon: float | None = None,
) -> FixedPointResult:
    """All roots of A(B) = B over (d, B_max] (scan + brentq) plus the open root when the linear
    amplitude is <= d; and the naive iteration B <- A(B) from `naive_start` (default params B),
    with the steady-state A (horizon None) or the paper's literal finite-horizon A (horizon [s])."""
    p = validate(params or {})
    gal = galerkin(p)
    cc = contact_consts(p)
    d = cc.d
    w = int(p["engineOrder"]) * TWO_PI * speed_rpm / 60.0
    F = float(p["Fw0"]) * gal.loadGain
    if B_max is None:
        B_max = F / (w * gal.C0)
    cache: dict[float, SteadyState] = {}

    def A(B: float) -> SteadyState:
        if B not in cache:
            cache[B] = steady_amplitude(p, speed_rpm, B, rtol=rtol)
        return cache[B]

    roots: list[FixedPointRoot] = []
    lin = A(d if d > 0 else 1e-300)  # B <= d: no contact force, the linear response
    if lin.A <= d:
        roots.append(FixedPointRoot(lin.A, lin.converged, True, 0.0))
    Bs = d + np.geomspace(1e-3 * max(d, 1e-9), B_max - d, n_scan) if B_max > d else np.array([])
    ss = [A(float(b)) for b in Bs]
    As = np.array([s.A for s in ss])
    conv = np.array([s.converged for s in ss], dtype=bool)
    r = As - Bs
    for i in np.nonzero(np.sign(r[1:]) != np.sign(r[:-1]))[0]:
        try:
            b = brentq(lambda x: A(x).A - x, Bs[i], Bs[i + 1], xtol=1e-13, rtol=1e-10, maxiter=60)
            ok = A(b).converged
        except (RuntimeError, ValueError):
            b, ok = 0.5 * (Bs[i] + Bs[i + 1]), False
        h = 1e-5 * b
        slope = (A(b + h).A - A(b - h).A) / (2 * h) if b - h > d else math.nan
        # a jump of A (coexisting attractors) can also change the sign: flag it as not converged
        jump = abs(A(b).A - b) > 1e-6 * b
        roots.append(FixedPointRoot(float(b), bool(ok and not jump), False, float(slope)))
    res = FixedPointResult(float(speed_rpm), roots, Bs, As, conv)
    if horizon is None:
        res.naive = naive_iteration(A, float(p["B"]) if naive_start is None else naive_start, naive_iter)
    else:
        res.naive = naive_iteration(
            lambda b: finite_horizon_amplitude(p, speed_rpm, b, horizon),
            float(p["B"]) if naive_start is None else naive_start,
            naive_iter,
        )
    return res


def finite_horizon_amplitude(
    params: Mapping[str, Any], speed_rpm: float, B: float, horizon: float = 0.2
) -> SteadyState:
    """The paper's literal A(B): max |q| over the last full excitation period ending at or before
    `horizon` seconds of the fixed-B run from rest ('integrate 0.2 s, take the amplitude')."""
    st = PiecewiseStepper(params, speed_rpm, B)
    n = max(1, int(math.floor(horizon / st.T * (1 + 1e-12))))
    q, v, g, m = 0.0, 0.0, st.initial_g(0.0), 0.0
    for k in range(n):
        q, v, g, m = st.advance(k * st.T, q, v, g, (k + 1) * st.T)
    return SteadyState(m, False, n, math.nan, q, v)


def naive_iteration(A, B0: float, n_iter: int = 30, tol: float = 1e-6, tail: int = 10) -> dict:
    """The paper's procedure B_{j+1} = A(B_j) from B0. Returns 'sequence' and either 'fixed' (the
    limit, if successive iterates agree to tol) or 'cycle' = ((low_min, low_max), (high_min,
    high_max)) when the last `tail` iterates alternate between two separated bands and the jumps
    between them do not shrink (a 2-cycle, exact or noisy: A is very steep near the low band, so
    the high band wanders), else neither (e.g. a slowly converging alternation)."""
    seq = [B0]
    for _ in range(n_iter):
        seq.append(A(seq[-1]).A)
        if abs(seq[-1] - seq[-2]) <= tol * seq[-1]:
            return {"sequence": seq, "fixed": seq[-1], "cycle": None}
    last = seq[-tail:]
    ev, od = last[0::2], last[1::2]
    lo, hi = (ev, od) if max(ev) < min(od) else ((od, ev) if max(od) < min(ev) else (None, None))
    # a converging alternation also has separated bands: require that the jumps do not shrink
    not_shrinking = abs(last[-1] - last[-2]) >= 0.5 * abs(last[1] - last[0])
    cycle = ((min(lo), max(lo)), (min(hi), max(hi))) if lo is not None and not_shrinking else None
    return {"sequence": seq, "fixed": None, "cycle": cycle}
