"""Excitation signals: derivatives against closed forms and finite differences, integrals against
quadrature, and fmu_view against a direct evaluation of the Taylor polynomial."""

from __future__ import annotations

import math

import numpy as np
import pytest
from scipy.integrate import quad

from harness.model.excitation import (
    AeroLoad,
    Constant,
    ExcitationError,
    LinearRamp,
    Modulated,
    Stepped,
    fmu_view,
    sin_series,
)

OMEGA_5000 = 3 * 5000 * 2 * math.pi / 60  # EO 3 at 5000 rpm [rad/s]


def test_constant_speed_aero_derivatives_closed_form():
    # d^k/dt^k Fw0 sin(w t) = Fw0 w^k sin(w t + k pi/2); tolerance: a few ulps of Fw0 w^k
    # times the phase magnitude (the phase w t ~ 500 rad carries ~1e-13 absolute rounding).
    f = AeroLoad(100.0, 3, 5000.0)
    t = np.linspace(0.0, 0.3, 37)
    d = f.derivatives(t, 8)
    for k in range(9):
        exact = 100.0 * OMEGA_5000**k * np.sin(OMEGA_5000 * t + k * math.pi / 2)
        np.testing.assert_allclose(d[k], exact, rtol=0, atol=1e-11 * 100.0 * OMEGA_5000**k)
    np.testing.assert_allclose(f(t), d[0], rtol=0, atol=1e-14)


def test_sin_series_matches_closed_form_for_quadratic_phase():
    # psi(s) = a + b s + c s^2: the truncated series of sin(psi) evaluated at small s must match
    # sin(psi(s)) up to the truncation remainder (~ (|b| s + |c| s^2)^9 / 9!) plus rounding (1e-15).
    a, b, c = 0.7, 3.0, -5.0
    p = np.array([[a], [b], [c]] + [[0.0]] * 6)
    S = sin_series(p)[:, 0]
    for s in (1e-3, 1e-2, 5e-2):
        series = sum(S[k] * s**k for k in range(9))
        assert abs(series - math.sin(a + b * s + c * s * s)) < (abs(b) * s + abs(c) * s * s) ** 9 + 1e-15


def test_runup_aero_derivatives_finite_differences():
    # Run-up 3000 -> 7000 rpm over 0.1 s: phase is piecewise quadratic. Check derivatives 1..3 by
    # central differences of the next-lower derivative (step 1e-7 s, error ~ h^2 f''' ~ 1e-14 *
    # w^(k+2) relative to w^k scale: ~1e-7 relative), away from the ramp breakpoints.
    speed = LinearRamp(3000.0, 7000.0, 0.02, 0.12)
    f = AeroLoad(100.0, 3, speed)
    t = np.array([0.01, 0.05, 0.0731, 0.11, 0.15])
    h = 1e-7
    d = f.derivatives(t, 4)
    dp = f.derivatives(t + h, 4)
    dm = f.derivatives(t - h, 4)
    w = 3 * 7000 * 2 * math.pi / 60
    for k in range(1, 5):
        fd = (dp[k - 1] - dm[k - 1]) / (2 * h)
        np.testing.assert_allclose(d[k], fd, rtol=0, atol=1e-6 * 100 * w**k)


def test_runup_phase_is_integral_of_speed():
    # psi(t) = 3 * 2 pi/60 * int_0^t n: compare with adaptive quadrature (tolerance 1e-9 rad).
    speed = LinearRamp(3000.0, 7000.0, 0.02, 0.12)
    f = AeroLoad(100.0, 3, speed)
    for t in (0.0, 0.015, 0.05, 0.12, 0.2):
        ref = 3 * 2 * math.pi / 60 * quad(speed, 0.0, t, points=[0.02, 0.12], epsabs=1e-12)[0]
        assert abs(f.phase(t) - ref) < 1e-9


def test_stepped_levels_and_ramp():
    s = Stepped([1000.0, 2000.0, 500.0], [0.1, 0.1, 0.1], start=0.0, ramp=0.02)
    assert s(0.05) == 1000.0
    assert s(0.11) == pytest.approx(1500.0)
    assert s(0.15) == 2000.0
    assert s(0.25) == 500.0 and s(1.0) == 500.0
    np.testing.assert_allclose(s.breakpoints, [0.1, 0.12, 0.2, 0.22])
    # right-sided derivative at a breakpoint: the slope of the ramp that starts there
    assert s.derivatives(np.array([0.1]), 1)[1, 0] == pytest.approx(1000.0 / 0.02)
    ref = quad(s, 0, 0.3, points=[0.1, 0.12, 0.2, 0.22])[0]
    assert s.integral(0.3) == pytest.approx(ref, rel=1e-12)


def test_fmu_view_is_the_taylor_polynomial_per_step():
    f = AeroLoad(100.0, 3, LinearRamp(4000.0, 6000.0, 0.0, 0.05))
    grid = np.arange(0, 11) * 2e-4
    for order in (0, 1, 8):
        v = fmu_view(f, grid, order)
        np.testing.assert_allclose(v.breakpoints, grid[1:])
        tk = grid[3]
        d = f.derivatives(np.array([tk]), order)[:, 0]
        for s in (0.0, 0.5e-4, 1.9e-4):
            direct = sum(d[j] * s**j / math.factorial(j) for j in range(order + 1))
            assert v(tk + s) == pytest.approx(direct, rel=1e-13, abs=1e-12)
    # order 8 over a 2e-4 s step: the Taylor remainder is (w h)^9/9! * Fw0 ~ 1e-10 (w h = 0.31..0.38)
    v8 = fmu_view(f, grid, 8)
    tt = np.linspace(0, grid[-1], 401)
    assert np.max(np.abs(v8(tt) - f(tt))) < 1e-7
    # held input (order 0) is off by up to Fw0 w h
    v0 = fmu_view(f, grid, 0)
    assert np.max(np.abs(v0(tt) - f(tt))) > 10.0


def test_modulated_closed_form():
    # (a + b t) sin(w t): k-th derivative = (a + b t) w^k sin(wt + k pi/2) + k b w^(k-1) sin(wt + (k-1) pi/2)
    env = LinearRamp(0.0, 1.0, 0.0, 0.1)  # a = 0, b = 10 on (0, 0.1)
    f = Modulated(env, AeroLoad(100.0, 3, 5000.0))
    t = np.array([0.013, 0.05, 0.0999])
    d = f.derivatives(t, 8)
    w, b = OMEGA_5000, 10.0
    for k in range(9):
        exact = 100.0 * (
            b * t * w**k * np.sin(w * t + k * math.pi / 2)
            + k * b * w ** (k - 1) * np.sin(w * t + (k - 1) * math.pi / 2)
        )
        np.testing.assert_allclose(d[k], exact, rtol=0, atol=1e-11 * 100.0 * w**k)
    np.testing.assert_allclose(f.breakpoints, [0.0, 0.1])


def test_errors():
    with pytest.raises(ExcitationError):
        Constant(float("nan"))
    with pytest.raises(ExcitationError):
        LinearRamp(0, 1, 1.0, 1.0)
    with pytest.raises(ExcitationError):
        AeroLoad(100.0, 3, 5000.0).derivatives(np.zeros(1), 9)
    with pytest.raises(ExcitationError):
        Stepped([1.0, 2.0], [0.1])
