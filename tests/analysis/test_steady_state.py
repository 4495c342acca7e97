"""Steady-state detection on synthetic signals whose answer is known in closed form.

The signals are a forced response A sin(w t + phi) plus transients with known envelopes, so the
time at which the distance from the periodic limit falls below rtol is known analytically and the
detector's t_steady can be held to it (within a stated factor of the distance, i.e. a stated
offset in time: a factor 2 in the distance is tau ln 2 in time)."""

from __future__ import annotations

import math

import numpy as np
import pytest
from scipy.optimize import brentq

from harness.analysis import steady_state as ss_mod
from harness.analysis.steady_state import analyze

T = 4e-3  # 250 Hz: the 3 Omega line at 5000 rpm
W = 2 * math.pi / T


def _signal(t, A, phi, modes):
    """q, q' of A sin(W t + phi) + sum E exp(-t/tau) sin(r W t + psi) over modes (E, tau, r, psi);
    r = 0 is a non-oscillating transient E exp(-t/tau) (psi ignored)."""
    q = A * np.sin(W * t + phi)
    v = A * W * np.cos(W * t + phi)
    for E, tau, r, psi in modes:
        env = E * np.exp(-t / tau)
        if r == 0:
            q, v = q + env, v - env / tau
        else:
            q = q + env * np.sin(r * W * t + psi)
            v = v + env * (r * W * np.cos(r * W * t + psi) - np.sin(r * W * t + psi) / tau)
    return q, v


def _kappa(r: float, tau: float, velocity: bool) -> float:
    """Largest relative size of a mode's envelope in the compared channels: q (1), and with the
    velocity q'/W, whose transient envelope is E exp(-t/tau) sqrt(r^2 + 1/(W tau)^2)."""
    return max(1.0, math.hypot(r, 1.0 / (W * tau))) if velocity else 1.0


@pytest.mark.parametrize(
    "r, M, velocity",
    [
        (0.5, 4, True),
        (0.97, 4, True),
        (1.37, 4, True),
        (2.0, 4, True),
        (0.999, 4, True),
        (1.37, 2, True),
        (0.7, 1, True),  # fewer samples per period than the old detector accepted
        (0.5, 40, False),
        (0.97, 40, False),
        (1.37, 8, False),
        (3.3, 40, False),
    ],
)
def test_beating_transient_settles_when_its_envelope_reaches_rtol(r, M, velocity):
    # A free vibration at r W (the natural frequency) decaying with tau beats with the forced
    # response at W: the period-to-period change is |1 - exp((i r W - 1/tau) T)| times the
    # transient, which is not a geometric decay of the change. The distance from the limit cycle is
    # the transient itself, E exp(-t/tau) (times kappa in the velocity channel), so the analytic
    # settling time is t* = tau ln(kappa E / (A rtol)). The detector compares sampled periods, whose
    # sup over M samples sees between ~1/sqrt(2) and 1 of the envelope (two channels, q and q'/W,
    # cover the phase with the velocity; many samples without); it decides per whole period and
    # needs min_periods = 3 converged periods. Stated bound: |t_steady - t*| <= tau ln 2 + 2 T (the
    # estimated distance within a factor 2 of the true one). The former geometric-tail estimate
    # overstated it 50-150x here: t_steady ~ t* + 4 tau.
    A, E, tau, rtol = 1e-4, 1e-4, 0.2, 1e-3
    t_star = tau * math.log(_kappa(r, tau, velocity) * E / (A * rtol))
    t = np.arange(0, t_star + 0.5, T / M)
    q, v = _signal(t, A, 0.3, [(E, tau, r, 0.0)])
    ss = analyze(t, q, T, rtol=rtol, velocity=v if velocity else None)
    assert ss.reached, ss.message
    assert abs(ss.t_steady - t_star) <= tau * math.log(2) + 2 * T, (ss.t_steady, t_star)
    # the fitted contraction per period is the transient's exp(-T/tau) while it was fitted
    if not math.isnan(ss.decay):
        assert ss.decay == pytest.approx(math.exp(-T / tau), abs=1e-3)


def test_decaying_transient_settling_time_matches_envelope():
    # q = A sin(w t + 0.3) + E exp(-t/tau): the distance from the limit cycle is E exp(-t/tau), so
    # the analytic settling time for rtol is t* = tau ln(E / (A rtol)). The detector decides per
    # whole period, so t_steady is the first period start with E exp(-t_k/tau) <= rtol max|q_k|:
    # within one period after t* (the period max is A plus the small transient, hence "within").
    A, E, tau, rtol = 1e-4, 3e-4, 0.05, 1e-4
    t = np.arange(0, 1.0, 1e-4)
    q = A * np.sin(W * t + 0.3) + E * np.exp(-t / tau)
    ss = analyze(t, q, T, rtol=rtol)
    t_star = tau * math.log(E / (A * rtol))
    assert ss.reached, ss.message
    assert t_star - 1e-9 <= ss.t_steady <= t_star + T + 1e-9, (ss.t_steady, t_star)
    # amplitude and phase of the limit cycle: the fit window (the last 64 periods, from 0.744 s)
    # still holds a transient of E exp(-0.744/tau) ~ 1e-10 = 1e-6 A, part of which projects on the
    # first harmonic: tolerance 1e-6.
    assert ss.harmonic_amplitude == pytest.approx(A, rel=1e-6)
    assert ss.phase == pytest.approx(0.3, abs=1e-6)
    assert ss.amplitude == pytest.approx(A, rel=1e-5)  # spline peak refinement, 40 samples/period


def test_two_transients_slow_real_and_fast_beating():
    # A slow non-oscillating transient (tau1) under a ten times larger beating one (tau2 < tau1):
    # three multipliers, the recurrence needs order 3. True distance d(t) lies between the larger
    # of the two envelopes and their sum (kappa for the velocity channel); t_lo and t_hi are where
    # those bounds reach rtol. Stated bound as above: t_lo - tau1 ln 2 - 2T <= t_steady <= t_hi + 2T.
    A, rtol = 1e-4, 1e-3
    modes = [(1e-5, 0.3, 0, 0.0), (1e-4, 0.1, 1.6, 0.4)]
    k2 = _kappa(1.6, 0.1, True)
    env = [lambda t: 1e-5 * math.exp(-t / 0.3), lambda t: k2 * 1e-4 * math.exp(-t / 0.1)]
    t_lo = brentq(lambda t: max(f(t) for f in env) - rtol * A, 0.0, 5.0)
    t_hi = brentq(lambda t: sum(f(t) for f in env) - rtol * A, 0.0, 5.0)
    t = np.arange(0, t_hi + 0.5, T / 4)
    q, v = _signal(t, A, -1.0, modes)
    ss = analyze(t, q, T, rtol=rtol, velocity=v)
    assert ss.reached, ss.message
    assert t_lo - 0.3 * math.log(2) - 2 * T <= ss.t_steady <= t_hi + 2 * T, (ss.t_steady, t_lo, t_hi)


def test_velocity_sees_a_transient_the_samples_of_q_miss():
    # 4 samples per period at the phases 0, pi/2, pi, 3 pi/2 of a transient at exactly 2 W: sin is
    # zero at every sample, so q alone cannot see it (declared steady at once: the reason the
    # drivers always pass q'); its velocity is not zero there, so with q' the settling time is the
    # envelope's (kappa = 2), within the bound of the test above.
    A, E, tau, rtol = 1e-4, 1e-4, 0.2, 1e-3
    t = np.arange(0, 2.5, T / 4)
    q, v = _signal(t, A, 0.3, [(E, tau, 2.0, 0.0)])
    blind = analyze(t, q, T, rtol=rtol)
    assert blind.reached and blind.t_steady < 0.1
    ss = analyze(t, q, T, rtol=rtol, velocity=v)
    t_star = tau * math.log(_kappa(2.0, tau, True) * E / (A * rtol))
    assert abs(ss.t_steady - t_star) <= tau * math.log(2) + 2 * T, (ss.t_steady, t_star)


def test_slow_oscillating_transient_not_declared_early():
    # A near-resonant free vibration (frequency 0.97 of the forcing) decaying slowly: successive
    # periods differ little (the transient's phase turns slowly), yet the distance from the limit
    # cycle is E exp(-t/tau). Detection must not come before the envelope reaches rtol (within the
    # factor sqrt(2) of sampling: tau ln sqrt(2)), nor much after it.
    A, E, tau, rtol = 1e-4, 1e-4, 0.2, 1e-4
    t = np.arange(0, 3.0, 1e-4)
    q = A * np.sin(W * t) + E * np.exp(-t / tau) * np.sin(0.97 * W * t)
    ss = analyze(t, q, T, rtol=rtol)
    t_env = tau * math.log(E / (A * rtol))
    assert ss.reached
    assert t_env - tau * math.log(math.sqrt(2)) - 2 * T <= ss.t_steady <= t_env + tau * math.log(2) + 2 * T


def test_quasi_periodic_and_growing_responses_never_converge():
    # an undamped second frequency (quasi-periodic: multiplier on the unit circle) and a slowly
    # growing one: the fitted recurrence has a root with |z| >= 1, so no distance is finite
    t = np.arange(0, 1.0, T / 4)
    for r, tau in ((1.37, math.inf), (0.8, -0.5)):
        q, v = _signal(t, 1e-4, 0.0, [(1e-6, tau, r, 0.0)])
        ss = analyze(t, q, T, rtol=1e-3, velocity=v)
        assert not ss.reached and not ss.rel_change <= 1e-3, (r, ss.message)


def test_few_window_fast_path_equals_the_batched_fit():
    # a few windows are fitted in plain floats (orders 1-2), longer scans batch them in numpy:
    # the same formulas, so the same distances and decays to rounding, on windows of a decaying
    # rotating pair plus a real mode (order 3), of pure rotation (order 2), and of noise (no fit)
    rng = np.random.default_rng(7)
    k = np.arange(10)[:, None]
    z = (0.97 * np.exp(0.4j)) ** k * np.array([1.0 + 0.5j, -0.3 + 1j, 0.2 - 0.7j, 1.0])
    windows = np.stack(
        [
            z.real,
            (z + 0.3 * 0.9**k).real,
            rng.normal(size=(10, 4)),
            (0.5 * z).imag,
            ((-0.8) ** k * np.ones((10, 4))),
            z.real + 1e-3 * rng.normal(size=(10, 4)),
        ]
    )
    d_batch, rho_batch = ss_mod._distance(windows)  # 6 windows: the batched path
    for b in range(len(windows)):
        d1, rho1 = ss_mod._distance(windows[b : b + 1])  # 1 window: the plain-float path
        assert d1[0] == pytest.approx(d_batch[b], rel=1e-9), b
        assert rho1[0] == pytest.approx(rho_batch[b], rel=1e-9, nan_ok=True), b


def test_two_samples_per_period_amplitude_and_phase_from_q_and_velocity():
    # With 2 samples per period q alone cannot separate a0, cos and sin; q'/W joins the fit, exact
    # for a harmonic response. The Hermite peak at 2 samples per period is coarse: amplitude only
    # bounded (the drivers take the FMU's exact period maximum instead).
    t = np.arange(0, 0.2, T / 2)
    q, v = _signal(t, 2e-5, -0.7, [])
    ss = analyze(t, q + 1e-6, T, rtol=1e-3, velocity=v)
    assert ss.reached
    assert ss.harmonic_amplitude == pytest.approx(2e-5, rel=1e-9)
    assert ss.phase == pytest.approx(-0.7, abs=1e-9)
    assert ss.mean == pytest.approx(1e-6, rel=1e-9)


def test_hermite_amplitude_with_velocity_within_its_error_bound():
    # cubic Hermite interpolation of sin with step h errs by at most (W h)^4 / 384 of the amplitude
    for M in (8, 16):
        t = np.arange(0, 0.1, T / M)
        q, v = _signal(t, 1.0, 0.123, [])
        ss = analyze(t, q, T, velocity=v)
        assert abs(ss.amplitude - 1.0) <= (2 * math.pi / M) ** 4 / 384


def test_subharmonic_is_not_periodic_at_base_period():
    # period-2 response (the 2-cycle): q repeats every 2T, not every T.
    t = np.arange(0, 0.5, 1e-4)
    q = np.sin(W * t) + 0.3 * np.sin(W * t / 2)
    ss = analyze(t, q, T)
    assert not ss.reached
    assert "subharmonic (2T)" in ss.message
    assert analyze(t, q, 2 * T).reached  # ...but it is periodic at 2T


def test_nonaligned_sampling_amplitude_phase_spectrum():
    # period not a multiple of the sample step: degree-7 spline resampling. Two harmonics with known
    # amplitudes: the spectrum lines at f and 3f must carry them (resampling error ~1e-9 here;
    # tolerance 1e-6 for the amplitudes, 1e-5 for the cubic-spline peak).
    period = 1 / 237.3
    t = np.arange(0, 0.3, 1e-4)
    q = 2.0 * np.sin(2 * math.pi / period * t - 1.0) + 0.5 * np.cos(3 * 2 * math.pi / period * t) + 0.1
    ss = analyze(t, q, period)
    assert ss.reached
    assert ss.harmonic_amplitude == pytest.approx(2.0, rel=1e-6)
    assert ss.phase == pytest.approx(-1.0, abs=1e-6)
    assert ss.mean == pytest.approx(0.1, abs=1e-6)
    f, a = ss.spectrum
    i1 = np.argmin(np.abs(f - 237.3))
    i3 = np.argmin(np.abs(f - 3 * 237.3))
    assert f[i1] == pytest.approx(237.3, rel=1e-9)
    assert a[i1] == pytest.approx(2.0, rel=1e-6)
    assert a[i3] == pytest.approx(0.5, rel=1e-6)
    assert a[0] == pytest.approx(0.1, abs=1e-6)
    others = np.delete(a, [0, i1, i3])
    assert np.max(others) < 1e-6  # whole periods, rectangular window: no leakage
    # peak of q over a period, found numerically on a fine grid (independent of the spline)
    tf = np.linspace(0, period, 200001)
    peak = np.max(
        np.abs(2.0 * np.sin(2 * math.pi / period * tf - 1.0) + 0.5 * np.cos(3 * 2 * math.pi / period * tf) + 0.1)
    )
    assert ss.amplitude == pytest.approx(peak, rel=1e-5)


def test_growing_or_short_record_not_reached():
    t = np.arange(0, 0.2, 1e-4)
    q = (1 + 5 * t) * np.sin(W * t)  # amplitude still growing
    ss = analyze(t, q, T)
    assert not ss.reached and math.isnan(ss.t_steady)
    assert "run longer" in ss.message
    short = analyze(t[:50], q[:50], T)
    assert not short.reached and "whole period" in short.message


def test_zero_signal_is_steady():
    t = np.arange(0, 0.05, 1e-4)
    ss = analyze(t, np.zeros_like(t), T)
    assert ss.reached and ss.amplitude == 0.0


def test_bad_arguments():
    t = np.arange(0, 0.05, 1e-4)
    with pytest.raises(ValueError):
        analyze(t, np.zeros_like(t), -1.0)
    with pytest.raises(ValueError):
        analyze(t[::-1], np.zeros_like(t), T)
    with pytest.raises(ValueError, match="velocity"):
        analyze(t, np.zeros_like(t), T, velocity=np.zeros(3))
    with pytest.raises(ValueError, match="rtol"):
        analyze(t, np.zeros_like(t), T, rtol=0.0)
