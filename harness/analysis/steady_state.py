"""Periodic steady state of a sampled response: is it reached, when, amplitude, phase, spectrum.

The record is cut into whole excitation periods T; period k becomes a state vector x_k (its
samples of q and, if given, q'/w, in units of the amplitude; further smooth state channels by
their own maximum). Near a stable periodic limit x_inf the period map is linear: x_k - x_inf is a
sum of c_j lambda_j^k over the transient's Floquet multipliers, complex when the transient
oscillates at another frequency than the excitation (a free vibration beating with the forced
response is not a geometric decay of the period-to-period change). So the differences
D_k = x_k - x_{k-1} obey a short linear recurrence with those multipliers as roots; it is fitted by
least squares over the last WINDOW periods (orders 1..4, the lowest that explains them), and the
distance from the limit is its exactly summed tail, x_inf - x_k = sum_{m>k} D_m (minimal polynomial
extrapolation), plus the unexplained rest as a geometric tail. A root on or outside the unit
circle (growth, subharmonic, quasi-periodic) or no fitting recurrence (irregular) means: not
converging. The steady state is reached when the record ends with `min_periods` periods whose
estimated sup-norm distance is below `rtol`; t_steady is the start of the first of them. Any whole
number of raw samples per period works (one, with q': the Poincare section of the period map);
other sampling is resampled by a degree-7 spline. `analyze` gives the decision, the amplitude
(max |q| of the last period: Hermite through q, q' or a spline through q; below 3 samples per
period the largest sqrt(q^2 + (q'/w)^2)), the first-harmonic fit and the spectrum over whole
periods.
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field
from typing import Sequence

import numpy as np
from scipy.interpolate import CubicSpline, make_interp_spline

MAX_FIT_PERIODS = 64  # whole periods used for the harmonic fit and the spectrum (the last ones)
MAX_ORDER = 4  # highest order of the fitted recurrence (state dimension of the period map seen)
WINDOW = 10  # period differences the recurrence is fitted on (>= 2 MAX_ORDER + 1)
FIT_OK = 0.02  # relative residual under which an order explains the differences
FIT_BAD = 0.5  # relative residual of the best order above which the response is called irregular
NOISE = 1e-3  # differences below NOISE * rtol of the scale are taken as converged without a fit


@dataclass
class SteadyState:
    reached: bool
    t_steady: float  # start of the steady window [s] (nan if not reached)
    amplitude: float  # max |q| over the last period (Hermite/spline-refined) [unit of q]
    harmonic_amplitude: float  # first-harmonic amplitude H of the fit q ~ a0 + H sin(w t + phase)
    phase: float  # [rad], in (-pi, pi], relative to sin(w t) with t the absolute time
    mean: float  # a0 of the fit
    frequency: float  # 1 / period [Hz]
    spectrum: tuple[np.ndarray, np.ndarray] = field(repr=False)  # (freq [Hz], single-sided amplitude)
    periods: int = 0  # whole periods in the record
    rel_change: float = math.nan  # estimated relative distance of the last period from the limit cycle
    message: str = ""
    decay: float = math.nan  # fitted contraction of the transient per period (largest |multiplier|) at the end
    samples_per_period: int = 0  # samples per period the decision was made on


# ---------------------------------------------------------------------------------------------
# Periods as rows
# ---------------------------------------------------------------------------------------------
def _layout(time: np.ndarray, period: float) -> tuple[int, int, bool]:
    """(whole periods P, samples per period M, raw): raw when the sampling is uniform and T/dt is a
    whole number (no interpolation: the recommended way, any M >= 1)."""
    span = time[-1] - time[0]
    P = int(math.floor(span / period * (1 + 1e-12) + 1e-9))
    dt = np.diff(time)
    uniform = len(dt) > 0 and np.ptp(dt) <= 1e-9 * max(dt[0], 1e-300) + 1e-12 * abs(time[-1])
    if uniform:
        m = period / dt[0]
        M = int(round(m))
        if M >= 1 and abs(m - M) < 1e-6 * max(1.0, m):
            return P, M, True
    return P, max(32, int(math.ceil(period / np.median(dt)))), False


def _rows(time: np.ndarray, x: np.ndarray, period: float, P: int, M: int, raw: bool) -> tuple[np.ndarray, np.ndarray]:
    """Samples per period, shape (P, M), and their times. Not raw: a degree-7 spline resampling
    (error ~ (w dt)^8: ~1e-9 of the amplitude at 14 samples per cycle of the highest harmonic; a
    signal with kinks interpolates worse and may then not be found steady)."""
    if raw:
        return x[: P * M].reshape(P, M), time[: P * M].reshape(P, M)
    tt = time[0] + period * (np.arange(P)[:, None] + np.arange(M)[None, :] / M)
    return make_interp_spline(time, x, k=min(7, len(time) - 1))(tt), tt


# ---------------------------------------------------------------------------------------------
# Distance from the limit cycle
# ---------------------------------------------------------------------------------------------
def _tr(L: np.ndarray, i0: int, k0: int, m: int) -> np.ndarray:
    """sum_{j<m} L[:, i0 + j, k0 + j]: a sum of inner products D_{i0+j} . D_{k0+j} per window."""
    return np.einsum("bii->b", L[:, i0 : i0 + m, k0 : k0 + m])


def _fit_order(Dw: np.ndarray, L: np.ndarray, p: int) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """Fit D_{j+1} = sum_{i<p} a_i D_{j-i} on each window of Dw (shape (B, W, n): B windows of W
    scaled period differences, oldest first; L their inner products, (B, W, W)) by least squares
    over all equations and samples. Returns per window the relative residual, the estimated
    sup-norm distance of the period after the window's last difference from the limit, and the
    spectral radius of the recurrence. Orders 1 and 2 in closed form (the common cases).
    Call under np.errstate(all="ignore"): singular fits give inf/nan, caught below."""
    B, W, n = Dw.shape
    m = W - p  # equations D_j = sum_i a_i D_{j-1-i}, j = p .. W-1
    G = np.empty((B, p, p))
    for i in range(p):
        for k in range(i, p):
            G[:, i, k] = G[:, k, i] = _tr(L, p - 1 - i, p - 1 - k, m)
    rhs = np.stack([_tr(L, p, p - 1 - i, m) for i in range(p)], axis=1)  # (B, p)
    yy = _tr(L, p, p, m)
    # normal equations with a ridge of 1e-12 of the trace: the least-squares solution where the
    # differences span p directions, a bounded one where they span fewer (then any solution
    # reproduces the sequence)
    ridge = 1e-12 * np.einsum("bii->b", G) + 1e-300
    if p == 1:
        a = rhs / (G[:, 0] + ridge[:, None])
        rho = np.abs(a[:, 0])
        g = a / (1.0 - a)
    elif p == 2:
        g11, g22, g12 = G[:, 0, 0] + ridge, G[:, 1, 1] + ridge, G[:, 0, 1]
        det = g11 * g22 - g12 * g12
        a1 = (rhs[:, 0] * g22 - rhs[:, 1] * g12) / det
        a2 = (g11 * rhs[:, 1] - g12 * rhs[:, 0]) / det
        a = np.stack([a1, a2], axis=1)
        disc = a1 * a1 + 4 * a2  # roots of z^2 - a1 z - a2
        rho = np.where(disc >= 0, 0.5 * (np.abs(a1) + np.sqrt(np.abs(disc))), np.sqrt(np.abs(a2)))
        # tail of the recurrence: ((a1 + a2) D_K + a2 D_{K-1}) / (1 - a1 - a2)
        g = np.stack([a1 + a2, a2], axis=1) / (1.0 - a1 - a2)[:, None]
    else:
        a = np.linalg.solve(G + ridge[:, None, None] * np.eye(p), rhs[:, :, None])[:, :, 0]
        # companion matrix C; the tail sum_{m>=1} D_{K+m} = sum_i g_i D_{K-i}, g = e1' C (I - C)^-1
        C = np.zeros((B, p, p))
        C[:, 0, :] = a
        C[:, np.arange(1, p), np.arange(p - 1)] = 1.0
        rho = np.max(np.abs(np.linalg.eigvals(C)), axis=1)
        Mt = np.swapaxes(np.eye(p) - C, 1, 2)
        Mt[~(rho < 1.0 - 1e-12)] = np.eye(p)
        g = np.linalg.solve(Mt, a[:, :, None])[:, :, 0]
    # squared residual from the normal equations (relative accuracy ~1e-8 of r: enough for the
    # FIT_OK / FIT_BAD thresholds)
    Ga = np.matmul(G, a[:, :, None])[:, :, 0]
    rr = yy - np.sum(a * (2 * rhs - Ga), axis=1)
    r = np.sqrt(np.maximum(rr, 0.0) / np.where(yy > 0, yy, 1.0))
    last = Dw[:, W - 1 - np.arange(p + 1)]  # D_K, D_{K-1}, ..., D_{K-p}
    res_last = last[:, 0] - np.matmul(a[:, None, :], last[:, 1:])[:, 0]
    ok = (rho < 1.0 - 1e-12) & np.all(np.isfinite(g), axis=1)
    S = np.matmul(np.where(ok[:, None], g, 0.0)[:, None, :], last[:, :p])[:, 0]
    # the part of the last difference the recurrence does not explain, taken as a geometric tail
    unexplained = np.max(np.abs(res_last), axis=1) / np.maximum(1.0 - np.where(ok, rho, 0.0), 1e-3)
    dist = np.where(ok, np.max(np.abs(S), axis=1) + unexplained, np.inf)
    return np.where(np.isfinite(r), r, np.inf), dist, rho


def _fit_low_scalar(D: list, L: list, p: int) -> tuple[float, float, float]:
    """`_fit_order` for one window and p = 1 or 2 in plain floats (D: the W difference rows, L
    their inner products, as lists): the same formulas, without numpy's per-call cost (a short
    record has a few windows)."""
    W = len(D)
    m = W - p

    def tr(i0: int, k0: int) -> float:
        return sum(L[i0 + j][k0 + j] for j in range(m))

    if p == 1:
        g11, r1, yy = tr(0, 0), tr(1, 0), tr(1, 1)
        ridge = 1e-12 * g11 + 1e-300
        a1 = r1 / (g11 + ridge)
        rr = yy - a1 * (2 * r1 - a1 * g11)
        rho = abs(a1)
        coef = [a1]
        gains = [a1 / (1.0 - a1)] if rho < 1.0 - 1e-12 else None
    else:
        g11, g22, g12 = tr(1, 1), tr(0, 0), tr(1, 0)
        r1, r2, yy = tr(2, 1), tr(2, 0), tr(2, 2)
        ridge = 1e-12 * (g11 + g22) + 1e-300
        det = (g11 + ridge) * (g22 + ridge) - g12 * g12
        if not det > 0:
            return math.inf, math.inf, math.nan
        a1 = (r1 * (g22 + ridge) - r2 * g12) / det
        a2 = ((g11 + ridge) * r2 - g12 * r1) / det
        rr = yy - a1 * (2 * r1 - (a1 * g11 + a2 * g12)) - a2 * (2 * r2 - (a1 * g12 + a2 * g22))
        disc = a1 * a1 + 4 * a2
        rho = 0.5 * (abs(a1) + math.sqrt(disc)) if disc >= 0 else math.sqrt(abs(a2))
        coef = [a1, a2]
        den = 1.0 - a1 - a2
        gains = [(a1 + a2) / den, a2 / den] if rho < 1.0 - 1e-12 and den != 0 else None
    r = math.sqrt(max(rr, 0.0) / yy) if yy > 0 else 0.0
    if gains is None or not all(math.isfinite(x) for x in gains):
        return r, math.inf, rho
    last = D[W - 1]
    res = [last[c] - sum(coef[i] * D[W - 2 - i][c] for i in range(p)) for c in range(len(last))]
    S = [sum(gains[i] * D[W - 1 - i][c] for i in range(p)) for c in range(len(last))]
    unexplained = max(abs(x) for x in res) / max(1.0 - rho, 1e-3)
    return r, max(abs(x) for x in S) + unexplained, rho


def _distance(Dw: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """Estimated distance from the limit and fitted decay per period for each window of Dw (see
    `_fit_order`): the lowest order whose residual is below FIT_OK; a higher order replaces a
    lower one only where it explains clearly more; inf where even the best leaves FIT_BAD
    (orders 3-4 are tried only where orders 1-2 leave less than FIT_BAD)."""
    B, W, n = Dw.shape
    L = np.matmul(Dw, np.swapaxes(Dw, 1, 2))  # inner products of the differences, (B, W, W)
    if B <= 4 and n <= 16:
        return _distance_few(Dw, L)
    best_r = np.full(B, np.inf)
    best_d = np.full(B, np.inf)
    best_rho = np.full(B, np.nan)
    with np.errstate(all="ignore"):
        for p in range(1, min(MAX_ORDER, (W - 1) // 2) + 1):
            # still open: no order explains the window yet; orders above 2 only where orders 1-2
            # found some structure (an irregular response has none at any order: cheaper decisions)
            open_ = (best_r > FIT_OK) & ((p <= 2) | (best_r <= FIT_BAD))
            if not np.any(open_):
                break
            r, dist, rho = _fit_order(Dw, L, p)
            adopt = open_ & ((r <= FIT_OK) | (r < 0.5 * best_r))
            best_r = np.where(adopt, r, best_r)
            best_d = np.where(adopt, dist, best_d)
            best_rho = np.where(adopt, rho, best_rho)
    return np.where(best_r <= FIT_BAD, best_d, np.inf), best_rho


def _distance_few(Dw: np.ndarray, L: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """`_distance` for a few small windows: orders 1-2 in plain floats, 3-4 batched as usual."""
    B, W, _ = Dw.shape
    out_d, out_rho = np.full(B, np.inf), np.full(B, np.nan)
    Dl, Ll = Dw.tolist(), L.tolist()
    with np.errstate(all="ignore"):
        for b in range(B):
            best = (math.inf, math.inf, math.nan)
            for p in range(1, min(MAX_ORDER, (W - 1) // 2) + 1):
                if best[0] <= FIT_OK or (p > 2 and best[0] > FIT_BAD):
                    break
                if p <= 2:
                    cand = _fit_low_scalar(Dl[b], Ll[b], p)
                else:
                    r, d, rho = _fit_order(Dw[b : b + 1], L[b : b + 1], p)
                    cand = (float(r[0]), float(d[0]), float(rho[0]))
                if cand[0] <= FIT_OK or cand[0] < 0.5 * best[0]:
                    best = cand
            if best[0] <= FIT_BAD:
                out_d[b] = best[1]
            out_rho[b] = best[2]
    return out_d, out_rho


def _distances(
    X: np.ndarray, floor: float, stop: float, first: int, extend: bool = True
) -> tuple[np.ndarray, np.ndarray]:
    """Estimated relative distance from the limit cycle of the periods that decide the final
    converged run (X: scaled period rows, shape (P, n)) and the fitted decay per period (nan where
    not fitted). Evaluated backwards from the last period: the last `first` periods, then (if they
    are all within `stop` and `extend`) all earlier ones at once; where that first block fails,
    earlier entries stay inf. A period needs WINDOW differences before it for a fit; earlier ones
    count only when quiet."""
    P = X.shape[0]
    rel = np.full(P, np.inf)
    decay = np.full(P, np.nan)
    if P < 2:
        return rel, decay
    D = np.diff(X, axis=0)  # D[k-1] = x_k - x_{k-1}
    dsup = np.max(np.abs(D), axis=1)
    hi, block = P, max(1, first)
    while hi > 1:
        ks = np.arange(max(1, hi - block), hi)
        quiet = dsup[ks - 1] <= floor  # rounding noise: taken as it is (noise has no recurrence)
        rel[ks[quiet]] = dsup[ks[quiet] - 1]
        fit = ks[~quiet & (ks >= WINDOW)]
        if len(fit):
            idx = fit[:, None] - WINDOW + np.arange(WINDOW)[None, :]
            rel[fit], decay[fit] = _distance(D[idx])
        if not extend or not np.all(rel[ks] <= stop):
            break
        hi, block = ks[0], P  # the deciding periods converged: the run's start, in one batch
    return rel, decay


def _state_rows(w: np.ndarray, wv: np.ndarray | None, extra: Sequence[np.ndarray] = ()) -> np.ndarray:
    """The state vector of each period (rows), in units of the amplitude: q and q'/omega (wv)
    scaled by the largest sqrt(q^2 + (q'/omega)^2) over the last period's samples (the amplitude
    of a harmonic response whatever the sampling phase); without the velocity, q by its largest
    sample (a fair amplitude only with several samples per period); other channels by their own
    maximum. A channel whose last period is zero but which moved is scaled to huge (its limit
    would be zero: any change is infinitely large relative to it)."""
    amp = float(np.max(np.abs(w[-1]) if wv is None else np.hypot(w[-1], wv[-1])))
    chans = [(w, amp)] + ([] if wv is None else [(wv, amp)]) + [(c, float(np.max(np.abs(c[-1])))) for c in extra]
    cols = []
    for c, sc in chans:
        if sc > 0:
            cols.append(c / sc)
        elif np.any(c != 0):
            cols.append(c * 1e300)
    return np.concatenate(cols, axis=1) if cols else np.zeros((w.shape[0], 1))


def _run_length(rel: np.ndarray, rtol: float) -> int:
    """Number of periods at the end of the record whose estimated distance is <= rtol."""
    bad = np.nonzero(~(rel <= rtol))[0]
    return len(rel) - (int(bad[-1]) + 1 if len(bad) else 0)


# ---------------------------------------------------------------------------------------------
# Amplitude, harmonic fit, spectrum
# ---------------------------------------------------------------------------------------------
def hermite_peak(t: np.ndarray, q: np.ndarray, v: np.ndarray) -> float:
    """max |q| of the piecewise cubic Hermite interpolant through (t, q, q') (stationary points solved)."""
    h = np.diff(t)
    q0, q1, m0, m1 = q[:-1], q[1:], v[:-1] * h, v[1:] * h
    # p(s) = q0 + m0 s + c2 s^2 + c3 s^3 on s in [0, 1];  p'(s) = 3 c3 s^2 + 2 c2 s + m0 = 0
    c2 = 3 * (q1 - q0) - 2 * m0 - m1
    c3 = 2 * (q0 - q1) + m0 + m1
    a, b, c = 3 * c3, 2 * c2, m0
    quad = np.abs(a) > 1e-14 * (np.abs(b) + np.abs(c) + 1e-300)
    with np.errstate(divide="ignore", invalid="ignore"):
        sq = np.sqrt(np.where(b * b - 4 * a * c >= 0, b * b - 4 * a * c, np.nan))
        roots = (np.where(quad, (-b + sq) / (2 * a), -c / b), np.where(quad, (-b - sq) / (2 * a), np.nan))
    best = float(np.max(np.abs(q)))
    for s in roots:
        ok = np.isfinite(s) & (s > 0) & (s < 1)
        if np.any(ok):
            s_ = s[ok]
            best = max(best, float(np.max(np.abs(q0[ok] + m0[ok] * s_ + c2[ok] * s_**2 + c3[ok] * s_**3))))
    return best


def _peak_abs(time: np.ndarray, q: np.ndarray, v: np.ndarray | None, t0: float, t1: float) -> float:
    """max |q| on [t0, t1]: the cubic Hermite interpolant through (q, q') when the velocity is known
    (error ~ (w dt)^4 / 384 of the amplitude: 6e-5 at 16 samples per cycle), else the cubic spline
    through q (extrema at the spline's stationary points)."""
    tol = 1e-9 * max(t1 - t0, 1e-300)
    sel = np.nonzero((time >= t0 - tol) & (time <= t1 + tol))[0]
    if v is not None:
        return hermite_peak(time[sel], q[sel], v[sel])
    lo, hi = max(sel[0] - 3, 0), min(sel[-1] + 4, len(time))
    if hi - lo < 4:
        return float(np.max(np.abs(q[sel])))
    spl = CubicSpline(time[lo:hi], q[lo:hi])
    cand = [t0, t1, *time[sel]]
    roots = spl.derivative().roots(extrapolate=False)
    cand.extend(r for r in np.atleast_1d(roots) if t0 <= r <= t1)
    return float(np.max(np.abs(spl(np.asarray(cand)))))


def _fit(w: np.ndarray, tt: np.ndarray, period: float, wv: np.ndarray | None) -> tuple[float, float, float]:
    """Least squares q ~ a0 + a cos(wt) + b sin(wt) on whole periods: returns (H, phase, a0) (wv:
    the samples of q'/w, or None). With fewer than 3 samples per period q alone cannot separate
    the three terms: then the velocity samples join as q'/w ~ -a sin(wt) + b cos(wt) (exact for a
    harmonic response; with higher harmonics both estimates are aliased); with one sample per
    period (one phase) a0 is not separable either and is taken as 0 (reported nan); without the
    velocity, nan."""
    om = 2 * math.pi / period
    t = tt.ravel()
    A = np.column_stack([np.ones_like(t), np.cos(om * t), np.sin(om * t)])
    y = w.ravel()
    if w.shape[1] < 3:
        if wv is None:
            return math.nan, math.nan, float(np.mean(w))
        A = np.vstack([A, np.column_stack([np.zeros_like(t), -np.sin(om * t), np.cos(om * t)])])
        y = np.concatenate([y, wv.ravel()])
        if w.shape[1] == 1:
            (a, b), *_ = np.linalg.lstsq(A[:, 1:], y, rcond=None)
            return float(math.hypot(a, b)), float(math.atan2(a, b)), math.nan
    (a0, a, b), *_ = np.linalg.lstsq(A, y, rcond=None)
    return float(math.hypot(a, b)), float(math.atan2(a, b)), float(a0)


def _spectrum(w: np.ndarray, dt: float, periodic: bool) -> tuple[np.ndarray, np.ndarray]:
    """Single-sided amplitude spectrum of the concatenated periods. Steady (periodic) window:
    rectangular window, exact for the harmonics of T because the window holds whole periods (no
    leakage). Not steady: a Hann window against leakage, amplitudes divided by its coherent gain."""
    x = w.ravel()
    n = len(x)
    win = np.ones(n) if periodic else np.hanning(n)
    X = np.fft.rfft(x * win)
    amp = np.abs(X) * 2.0 / max(float(np.sum(win)), 1e-300)
    amp[0] /= 2.0
    if n % 2 == 0:
        amp[-1] /= 2.0
    return np.fft.rfftfreq(n, dt), amp


def _subharmonic_hint(w: np.ndarray, rtol: float) -> str:
    P = w.shape[0]
    for m in (2, 3, 4):
        if P >= 3 * m:
            a, b = w[-m:], w[-2 * m : -m]
            if np.max(np.abs(a - b)) <= max(10 * rtol, 1e-3) * np.max(np.abs(a)):
                return f" The last {2 * m} periods repeat every {m} periods: a subharmonic ({m}T) response."
    return ""


def _channel(x, n: int, name: str) -> np.ndarray:
    x = np.asarray(x, dtype=float)
    if x.shape != (n,):
        raise ValueError(f"{name} must be 1-D with one value per time sample ({n}), got shape {x.shape}")
    return x


def analyze(
    time, q, period: float, *, rtol: float = 1e-4, min_periods: int = 3, velocity=None, states: Sequence | None = None
) -> SteadyState:
    """Periodic steady state of q(time) at excitation period `period` [s] (see the module doc).

    velocity: samples of dq/dt (optional, recommended): q'/w is compared period to period with q
    (a transient at a multiple of the sampling rate is invisible in q alone) and gives the Hermite
    peak. states: further sampled state signals that must repeat too; they must be smooth
    functions of the state (a piecewise-constant period maximum such as the FMU's tracked
    `amplitude` is not: it changes at its own instants). All channels are sampled at `time`."""
    time = np.asarray(time, dtype=float)
    q = np.asarray(q, dtype=float)
    if not (period > 0 and math.isfinite(period)):
        raise ValueError(f"period = {period!r} must be a positive number of seconds")
    if not (rtol > 0 and math.isfinite(rtol)):
        raise ValueError(f"rtol = {rtol!r} must be a positive number")
    if time.ndim != 1 or time.shape != q.shape or len(time) < 2 or np.any(np.diff(time) <= 0):
        raise ValueError("time and q must be 1-D of equal length with strictly increasing time")
    v = None if velocity is None else _channel(velocity, len(time), "velocity")
    extra = [_channel(s, len(time), "each entry of states") for s in (states or [])]
    P_avail = int(math.floor((time[-1] - time[0]) / period * (1 + 1e-12) + 1e-9))
    freq = 1.0 / period
    if P_avail < 2:
        return SteadyState(
            False,
            math.nan,
            math.nan,
            math.nan,
            math.nan,
            math.nan,
            freq,
            (np.zeros(0), np.zeros(0)),
            P_avail,
            math.inf,
            f"record of {time[-1] - time[0]:.4g} s holds {P_avail} whole period(s) of {period:.4g} s;"
            " need at least 2: run longer",
        )
    P, M, raw = _layout(time, period)
    w, tt = _rows(time, q, period, P, M, raw)
    om = 2 * math.pi / period
    wv = None if v is None else _rows(time, v, period, P, M, raw)[0] / om
    X = _state_rows(w, wv, [_rows(time, x, period, P, M, raw)[0] for x in extra])
    rel, decay = _distances(X, NOISE * rtol, rtol, min_periods)
    run = _run_length(rel, rtol)
    reached = run >= min_periods
    if reached:
        k0 = P - run
        t_steady = float(tt[k0, 0])
        n_fit = min(run, MAX_FIT_PERIODS)
        msg = f"periodic after {t_steady:.4g} s (last {run} of {P} periods within rtol {rtol:g})"
    else:
        t_steady = math.nan
        n_fit = min(P, 8)
        msg = (
            f"no periodic steady state at period {period:.4g} s: the record ends with {run} converged "
            f"period(s) of {min_periods} needed (estimated distance from the limit {rel[-1]:.3g}, "
            f"rtol {rtol:g}); run longer." + _subharmonic_hint(w, rtol)
        )
    H, ph, a0 = _fit(w[-n_fit:], tt[-n_fit:], period, None if wv is None else wv[-n_fit:])
    spec = _spectrum(w[-n_fit:], period / M, reached)
    if M >= 3 or wv is None:
        amp = _peak_abs(time, q, v, float(tt[-1, 0]), float(tt[-1, 0] + period))
    else:  # too few samples for an interpolant: the harmonic amplitude seen at each sample
        amp = float(np.max(np.hypot(w[-1], wv[-1])))
    return SteadyState(reached, t_steady, amp, H, ph, a0, freq, spec, P, float(rel[-1]), msg, float(decay[-1]), M)
