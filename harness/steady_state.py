"""Periodic steady state of a sampled response: is it reached, when, amplitude, phase, spectrum.

The record is cut into whole excitation periods T from its first sample; period k becomes one
vector x_k (the samples of q in that period, plus optional further state channels such as q' or a
tracked amplitude, each scaled by its own maximum over the last period). Near a stable periodic
limit x_inf the period map is linear, so x_k - x_inf = sum_j c_j lambda_j^k over the Floquet
multipliers lambda_j of the transient, which are complex when the transient oscillates at a
frequency other than the excitation (a free vibration at the natural frequency beats with the
forced response: that is not a geometric decay of the period-to-period change). The differences
D_k = x_k - x_{k-1} then obey a short linear recurrence D_{k+1} = a_1 D_k + ... + a_p D_{k-p+1}
with the same multipliers as roots. It is fitted by least squares over the last few periods (all
samples and channels at once, orders p = 1..4, the lowest order that explains the differences),
and the distance from the limit is the exactly summed tail of the fitted recurrence,
x_inf - x_k = sum_{m>k} D_m (minimal polynomial extrapolation), plus the unexplained part of the
differences as a geometric tail. A fitted multiplier on or outside the unit circle (growth,
subharmonic, quasi-periodic) or a recurrence that does not fit (irregular response) means: not
converging. Period k is converged when the estimated distance is below `rtol` (sup norm over the
samples, relative to each channel's maximum); the steady state is reached when the record ends
with at least `min_periods` converged periods, and t_steady is the start of the first of them.
Works with any whole number of raw samples per period (4 is enough, no interpolation); other
sampling is resampled with a degree-7 spline. Amplitude = max |q| over the last period (cubic
Hermite through q and q' when the velocity is given, else a cubic spline through q), harmonic
amplitude and phase by a least-squares fit of the first harmonic over whole periods, spectrum by
rfft over whole periods.
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
        return x[:P * M].reshape(P, M), time[:P * M].reshape(P, M)
    tt = time[0] + period * (np.arange(P)[:, None] + np.arange(M)[None, :] / M)
    return make_interp_spline(time, x, k=min(7, len(time) - 1))(tt), tt


# ---------------------------------------------------------------------------------------------
# Distance from the limit cycle
# ---------------------------------------------------------------------------------------------
def _fit_order(Dw: np.ndarray, p: int) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """Fit D_{j+1} = sum_{i<p} a_i D_{j-i} on each window of Dw (shape (B, W, n): B windows of W
    scaled period differences, oldest first) by least squares over all equations and samples.
    Returns per window the relative residual, the estimated sup-norm distance of the period after
    the window's last difference from the limit, and the spectral radius of the recurrence.
    Orders 1 and 2 in closed form (the common cases, and cheap: this runs at every decision)."""
    B, W, n = Dw.shape
    y = Dw[:, p:].reshape(B, -1)
    X = [Dw[:, p - 1 - i:W - 1 - i].reshape(B, -1) for i in range(p)]  # regressor i: D_{j-i}
    # normal equations with a ridge of 1e-12 of the trace: the least-squares solution where the
    # differences span p directions, a bounded one where they span fewer (then any solution
    # reproduces the sequence)
    G = np.array([[np.einsum("br,br->b", X[i], X[k]) for k in range(p)] for i in range(p)])  # (p, p, B)
    rhs = np.array([np.einsum("br,br->b", X[i], y) for i in range(p)])  # (p, B)
    ridge = 1e-12 * sum(G[i, i] for i in range(p)) + 1e-300
    with np.errstate(divide="ignore", invalid="ignore", over="ignore"):
        if p == 1:
            a = (rhs / (G[0, 0] + ridge))[None].reshape(1, B)
            rho = np.abs(a[0])
            tail = a[0] / (1.0 - a[0])
            g = tail[None]
        elif p == 2:
            g11, g22, g12 = G[0, 0] + ridge, G[1, 1] + ridge, G[0, 1]
            det = g11 * g22 - g12 * g12
            a = np.array([(rhs[0] * g22 - rhs[1] * g12) / det, (g11 * rhs[1] - g12 * rhs[0]) / det])
            disc = a[0] ** 2 + 4 * a[1]  # roots of z^2 - a1 z - a2
            sq = np.sqrt(np.abs(disc))
            rho = np.where(disc >= 0, 0.5 * (np.abs(a[0]) + sq), np.sqrt(np.abs(a[1])))
            # tail of the recurrence: (a1 + a2) D_K + a2 D_{K-1}, over (1 - a1 - a2)
            g = np.array([a[0] + a[1], a[1]]) / (1.0 - a[0] - a[1])
        else:
            Gm = np.moveaxis(G, 2, 0) + ridge[:, None, None] * np.eye(p)
            a = np.linalg.solve(Gm, rhs.T[:, :, None])[:, :, 0].T  # (p, B)
            # companion matrix C; the tail sum_{m>=1} D_{K+m} = sum_i g_i D_{K-i}, g = e1' C (I - C)^-1
            C = np.zeros((B, p, p))
            C[:, 0, :] = a.T
            C[:, np.arange(1, p), np.arange(p - 1)] = 1.0
            rho = np.max(np.abs(np.linalg.eigvals(C)), axis=1)
            Mt = np.swapaxes(np.eye(p) - C, 1, 2)
            Mt[~(rho < 1.0 - 1e-12)] = np.eye(p)
            g = np.linalg.solve(Mt, a.T[:, :, None])[:, :, 0].T
    res = y - sum(a[i][:, None] * X[i] for i in range(p))
    yn = np.sqrt(np.einsum("br,br->b", y, y))
    r = np.sqrt(np.einsum("br,br->b", res, res)) / np.where(yn > 0, yn, 1.0)
    ok = np.isfinite(rho) & (rho < 1.0 - 1e-12) & np.all(np.isfinite(g), axis=0)
    S = sum(g[i][:, None] * Dw[:, W - 1 - i] for i in range(p))
    # the part of the last difference the recurrence does not explain, taken as a geometric tail
    unexplained = np.max(np.abs(res[:, -n:]), axis=1) / np.maximum(1.0 - np.where(ok, rho, 0.0), 1e-3)
    with np.errstate(invalid="ignore"):
        dist = np.where(ok, np.max(np.abs(S), axis=1) + unexplained, np.inf)
    return np.where(np.isfinite(r), r, np.inf), dist, rho


def _distance(Dw: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """Estimated distance from the limit and fitted decay per period for each window of Dw (see
    `_fit_order`): the lowest order whose residual is below FIT_OK; a higher order replaces a
    lower one only where it explains clearly more; inf where even the best leaves FIT_BAD."""
    B, W, _ = Dw.shape
    best_r = np.full(B, np.inf)
    best_d = np.full(B, np.inf)
    best_rho = np.full(B, np.nan)
    for p in range(1, min(MAX_ORDER, (W - 1) // 2) + 1):
        open_ = best_r > FIT_OK
        if not np.any(open_):
            break
        r, dist, rho = _fit_order(Dw, p)
        adopt = open_ & ((r <= FIT_OK) | (r < 0.5 * best_r))
        best_r = np.where(adopt, r, best_r)
        best_d = np.where(adopt, dist, best_d)
        best_rho = np.where(adopt, rho, best_rho)
    return np.where(best_r <= FIT_BAD, best_d, np.inf), best_rho


def _distances(X: np.ndarray, floor: float, stop: float, first: int) -> tuple[np.ndarray, np.ndarray]:
    """Estimated relative distance from the limit cycle of the periods that decide the final
    converged run (X: scaled period rows, shape (P, n)) and the fitted decay per period (nan where
    not fitted). Evaluated backwards from the last period in blocks (`first` periods, then doubling)
    until a period's distance exceeds `stop` or the record starts; earlier entries stay inf. A
    period needs WINDOW differences before it for a fit; earlier ones count only when quiet."""
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
        if not np.all(rel[ks] <= stop):
            break
        hi, block = ks[0], 2 * block
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


def decide(q_rows: np.ndarray, v_rows: np.ndarray | None, omega: float, *, rtol: float,
           min_periods: int) -> tuple[bool, float, float]:
    """The steady-state decision of `analyze` alone, for raw period rows (shape (P, M): M uniform
    samples per period starting at a period start; v_rows the velocity samples or None):
    (reached, estimated relative distance of the last period from the limit, fitted decay per
    period). Cheap: what a driver calls between chunks of simulation."""
    X = _state_rows(q_rows, None if v_rows is None else v_rows / omega)
    rel, decay = _distances(X, NOISE * rtol, rtol, min_periods)
    return _run_length(rel, rtol) >= min_periods, float(rel[-1]), float(decay[-1])


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
            best = max(best, float(np.max(np.abs(q0[ok] + m0[ok] * s_ + c2[ok] * s_ ** 2 + c3[ok] * s_ ** 3))))
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
    the samples of q'/w, or None).
    With fewer than 3 samples per period q alone cannot separate the three terms: then the
    velocity samples join as q'/w ~ -a sin(wt) + b cos(wt) (exact for a harmonic response; with
    higher harmonics both estimates are aliased); without them nan."""
    om = 2 * math.pi / period
    t = tt.ravel()
    A = np.column_stack([np.ones_like(t), np.cos(om * t), np.sin(om * t)])
    y = w.ravel()
    if w.shape[1] < 3:
        if wv is None:
            return math.nan, math.nan, float(np.mean(w))
        A = np.vstack([A, np.column_stack([np.zeros_like(t), -np.sin(om * t), np.cos(om * t)])])
        y = np.concatenate([y, wv.ravel()])
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
            a, b = w[-m:], w[-2 * m:-m]
            if np.max(np.abs(a - b)) <= max(10 * rtol, 1e-3) * np.max(np.abs(a)):
                return f" The last {2 * m} periods repeat every {m} periods: a subharmonic ({m}T) response."
    return ""


def _channel(x, n: int, name: str) -> np.ndarray:
    x = np.asarray(x, dtype=float)
    if x.shape != (n,):
        raise ValueError(f"{name} must be 1-D with one value per time sample ({n}), got shape {x.shape}")
    return x


def analyze(time, q, period: float, *, rtol: float = 1e-4, min_periods: int = 3, velocity=None,
            states: Sequence | None = None) -> SteadyState:
    """Periodic steady state of q(time) at excitation period `period` [s] (see the module doc).

    velocity: samples of dq/dt (optional): compared period to period like q and used for the exact
    Hermite peak. states: further sampled state signals (e.g. a tracked amplitude) that must repeat
    too. All channels are sampled at `time`."""
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
        return SteadyState(False, math.nan, math.nan, math.nan, math.nan, math.nan, freq,
                           (np.zeros(0), np.zeros(0)), P_avail, math.inf,
                           f"record of {time[-1] - time[0]:.4g} s holds {P_avail} whole period(s) of {period:.4g} s;"
                           " need at least 2: run longer")
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
        msg = (f"no periodic steady state at period {period:.4g} s: the record ends with {run} converged "
               f"period(s) of {min_periods} needed (estimated distance from the limit {rel[-1]:.3g}, "
               f"rtol {rtol:g}); run longer." + _subharmonic_hint(w, rtol))
    H, ph, a0 = _fit(w[-n_fit:], tt[-n_fit:], period, None if wv is None else wv[-n_fit:])
    spec = _spectrum(w[-n_fit:], period / M, reached)
    amp = _peak_abs(time, q, v, float(tt[-1, 0]), float(tt[-1, 0] + period))
    return SteadyState(reached, t_steady, amp, H, ph, a0, freq, spec, P, float(rel[-1]), msg,
                       float(decay[-1]), M)
