"""Periodic steady state of a sampled response: is it reached, when, amplitude, phase, spectrum.

The record is cut into whole excitation periods T from its first sample. Successive periods are
compared (never a fixed settling time): d_k = max over the period of |q_k(s) - q_{k-1}(s)| and the
change of the period maximum of |q|. Because a decaying transient shrinks by a factor r per period,
the distance of period k from the limit cycle is estimated by the geometric tail d_k r / (1 - r)
(r from the last few periods; for an exponential transient this equals the transient itself, so a
slowly decaying transient is not mistaken for convergence). Period k is converged when this
estimate and the period-max change are below `rtol` times the period maximum; the steady state is
reached when the record ends with at least `min_periods` converged periods, and t_steady is the
start of the first of them. A response that repeats only every 2T (subharmonic, the 2-cycle of
MODEL.md section 4) never converges at period T: it is reported as not reached, with a hint.
Amplitude = max |q| over the last period (cubic-spline refined), harmonic amplitude and phase by a
least-squares fit of the first harmonic over whole periods, spectrum by rfft over whole periods.
"""
from __future__ import annotations

import math
from dataclasses import dataclass, field

import numpy as np
from scipy.interpolate import CubicSpline, make_interp_spline

MAX_FIT_PERIODS = 64  # whole periods used for the harmonic fit and the spectrum (the last ones)


@dataclass
class SteadyState:
    reached: bool
    t_steady: float  # start of the steady window [s] (nan if not reached)
    amplitude: float  # max |q| over the last period (spline-refined) [unit of q]
    harmonic_amplitude: float  # first-harmonic amplitude H of the fit q ~ a0 + H sin(w t + phase)
    phase: float  # [rad], in (-pi, pi], relative to sin(w t) with t the absolute time
    mean: float  # a0 of the fit
    frequency: float  # 1 / period [Hz]
    spectrum: tuple[np.ndarray, np.ndarray] = field(repr=False)  # (freq [Hz], single-sided amplitude)
    periods: int = 0  # whole periods in the record
    rel_change: float = math.nan  # last estimated relative distance from the limit cycle
    message: str = ""


def _periods(time: np.ndarray, q: np.ndarray, period: float) -> tuple[np.ndarray, np.ndarray, bool]:
    """Uniform samples per period, shape (P, M), and their times: the raw samples if the sampling is
    uniform and T/dt is an integer (no interpolation error: the recommended way), else a degree-7
    spline resampling (error ~ (w dt)^8: ~1e-9 of the amplitude at 14 samples per cycle of the
    highest harmonic; a signal with kinks interpolates worse and may then not be found steady)."""
    span = time[-1] - time[0]
    P = int(math.floor(span / period * (1 + 1e-12) + 1e-9))
    dt = np.diff(time)
    uniform = len(dt) > 0 and np.ptp(dt) <= 1e-9 * max(dt[0], 1e-300) + 1e-12 * abs(time[-1])
    if uniform:
        m = period / dt[0]
        M = int(round(m))
        if M >= 8 and abs(m - M) < 1e-6:
            w = q[:P * M].reshape(P, M)
            return w, time[:P * M].reshape(P, M), True
    M = max(32, int(math.ceil(period / np.median(dt))))
    spl = make_interp_spline(time, q, k=7)
    tt = time[0] + period * (np.arange(P)[:, None] + np.arange(M)[None, :] / M)
    return spl(tt), tt, False


def _peak_abs(time: np.ndarray, q: np.ndarray, t0: float, t1: float) -> float:
    """max |q| on [t0, t1] of the cubic spline through the samples (extrema at the spline's
    stationary points)."""
    sel = np.nonzero((time >= t0) & (time <= t1))[0]
    lo, hi = max(sel[0] - 3, 0), min(sel[-1] + 4, len(time))
    if hi - lo < 4:
        return float(np.max(np.abs(q[sel])))
    spl = CubicSpline(time[lo:hi], q[lo:hi])
    cand = [t0, t1, *time[sel]]
    roots = spl.derivative().roots(extrapolate=False)
    cand.extend(r for r in np.atleast_1d(roots) if t0 <= r <= t1)
    return float(np.max(np.abs(spl(np.asarray(cand)))))


def _fit(w: np.ndarray, tt: np.ndarray, period: float) -> tuple[float, float, float]:
    """Least squares q ~ a0 + a cos(wt) + b sin(wt) on whole periods: returns (H, phase, a0)."""
    om = 2 * math.pi / period
    t = tt.ravel()
    A = np.column_stack([np.ones_like(t), np.cos(om * t), np.sin(om * t)])
    (a0, a, b), *_ = np.linalg.lstsq(A, w.ravel(), rcond=None)
    return float(math.hypot(a, b)), float(math.atan2(a, b)), float(a0)


def _spectrum(w: np.ndarray, dt: float, periodic: bool) -> tuple[np.ndarray, np.ndarray]:
    """Single-sided amplitude spectrum of the concatenated periods. Steady (periodic) window:
    rectangular window, exact for the harmonics of T because the window holds whole periods (no
    leakage). Not steady: a Hann window against leakage, amplitudes divided by its coherent gain."""
    x = w.ravel()
    n = len(x)
    win = np.ones(n) if periodic else np.hanning(n)
    X = np.fft.rfft(x * win)
    amp = np.abs(X) * 2.0 / np.sum(win)
    amp[0] /= 2.0
    if n % 2 == 0:
        amp[-1] /= 2.0
    return np.fft.rfftfreq(n, dt), amp


def _converged_flags(w: np.ndarray, rtol: float, min_periods: int) -> tuple[np.ndarray, np.ndarray]:
    P = w.shape[0]
    scale = np.max(np.abs(w), axis=1)
    d = np.max(np.abs(np.diff(w, axis=0)), axis=1)  # d[k-1] = change from period k-1 to k
    dmax = np.abs(np.diff(scale))
    est = np.full(P, np.inf)
    # Changes below `floor` are rounding/interpolation noise: accepted as they are (no tail
    # estimate: noise has no geometric decay). The price: a transient decaying slower than
    # r = 0.999 per period whose change is below the floor would be missed.
    floor = 1e-3 * rtol * max(float(np.max(scale)), 1e-300)
    for k in range(1, P):
        dk = d[k - 1]
        if dk <= floor:
            est[k] = dk
            continue
        m = min(min_periods, k - 1)
        if m < 1 or d[k - 1 - m] <= floor:
            continue
        r = (dk / d[k - 1 - m]) ** (1.0 / m)
        if r < 1.0 - 1e-9:
            est[k] = dk * r / (1.0 - r)
    rel = np.full(P, np.inf)
    ok = scale[1:] > 0
    rel[1:][ok] = np.maximum(est[1:][ok], dmax[ok]) / scale[1:][ok]
    rel[1:][~ok] = np.where(est[1:][~ok] == 0, 0.0, np.inf)
    return rel <= rtol, rel


def _subharmonic_hint(w: np.ndarray, rtol: float) -> str:
    P = w.shape[0]
    for m in (2, 3, 4):
        if P >= 3 * m:
            a, b = w[-m:], w[-2 * m:-m]
            if np.max(np.abs(a - b)) <= max(10 * rtol, 1e-3) * np.max(np.abs(a)):
                return f" The last {2 * m} periods repeat every {m} periods: a subharmonic ({m}T) response."
    return ""


def analyze(time, q, period: float, *, rtol: float = 1e-4, min_periods: int = 3) -> SteadyState:
    """Periodic steady state of q(time) at excitation period `period` [s] (see the module doc)."""
    time = np.asarray(time, dtype=float)
    q = np.asarray(q, dtype=float)
    if not (period > 0 and math.isfinite(period)):
        raise ValueError(f"period = {period!r} must be a positive number of seconds")
    if time.ndim != 1 or time.shape != q.shape or len(time) < 2 or np.any(np.diff(time) <= 0):
        raise ValueError("time and q must be 1-D of equal length with strictly increasing time")
    P_avail = int(math.floor((time[-1] - time[0]) / period * (1 + 1e-12) + 1e-9))
    freq = 1.0 / period
    if P_avail < 2:
        return SteadyState(False, math.nan, math.nan, math.nan, math.nan, math.nan, freq,
                           (np.zeros(0), np.zeros(0)), P_avail, math.inf,
                           f"record of {time[-1] - time[0]:.4g} s holds {P_avail} whole period(s) of {period:.4g} s;"
                           " need at least 2: run longer")
    w, tt, raw = _periods(time, q, period)
    P, M = w.shape
    conv, rel = _converged_flags(w, rtol, min_periods)
    run = 0
    while run < P and conv[P - 1 - run]:
        run += 1
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
               f"period(s) of {min_periods} needed (last relative change {rel[-1]:.3g}, rtol {rtol:g}); "
               "run longer." + _subharmonic_hint(w, rtol))
    H, ph, a0 = _fit(w[-n_fit:], tt[-n_fit:], period)
    spec = _spectrum(w[-n_fit:], period / M, reached)
    amp = _peak_abs(time, q, float(tt[-1, 0]), float(tt[-1, 0] + period))
    return SteadyState(reached, t_steady, amp, H, ph, a0, freq, spec, P, float(rel[-1]), msg)
