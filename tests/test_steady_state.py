"""Steady-state detection on synthetic signals with known answers."""
from __future__ import annotations

import math

import numpy as np
import pytest

from harness.steady_state import analyze

T = 4e-3  # 250 Hz: the 3 Omega line at 5000 rpm
W = 2 * math.pi / T


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


def test_slow_oscillating_transient_not_declared_early():
    # A near-resonant free vibration (frequency 0.97 of the forcing) decaying slowly: successive
    # periods differ little (the transient's phase turns slowly), yet the distance from the limit
    # cycle is E exp(-t/tau). Detection must not come before the envelope reaches rtol.
    A, E, tau, rtol = 1e-4, 1e-4, 0.2, 1e-4
    t = np.arange(0, 3.0, 1e-4)
    q = A * np.sin(W * t) + E * np.exp(-t / tau) * np.sin(0.97 * W * t)
    ss = analyze(t, q, T, rtol=rtol)
    t_env = tau * math.log(E / (A * rtol))
    assert ss.reached
    assert ss.t_steady >= t_env - 2 * T


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
    peak = np.max(np.abs(2.0 * np.sin(2 * math.pi / period * tf - 1.0)
                         + 0.5 * np.cos(3 * 2 * math.pi / period * tf) + 0.1))
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
