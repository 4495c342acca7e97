"""The reference's m-mode reduction against its one-mode reduction, the finite-element beam and closed forms.

The Galerkin frequencies are Rayleigh-Ritz values: they approach the exact ones from above as m
grows. The finite-element model (120 Hermite elements: its own discretisation error on modes 1..3
is at most 1e-8 relative, measured against 240 elements) stands in for the exact values. Measured
relative errors of the m-mode frequencies against it (docs/model.md s.2, "More than one mode"),
modes 1..3 at 10000 rpm: m = 1: 1.15e-3; m = 3: 2.9e-5, 2.8e-5, 1.0e-5; m = 6: 1.20e-6,
1.11e-6, 9.2e-7; at 30000 rpm (the FMU's top speed), m = 6: 4.4e-5, 5.7e-5, 6.0e-5.
"""

from __future__ import annotations

import math

import numpy as np
import pytest

from harness.model.params import ParameterError
from harness.reference.beam_fe import beam_fe
from harness.reference.blade import galerkin
from harness.reference.dynamics import simulate
from harness.reference.modes import modal_galerkin

CONSISTENT = {"formulation": 2}
# bounds on the m = 6 errors of modes 1..3 vs the FE model (measured x ~1.3), per speed [rpm]
M6_TOL = {10000.0: (1.6e-6, 1.5e-6, 1.2e-6), 30000.0: (6e-5, 7.5e-5, 8e-5)}


@pytest.fixture(scope="module")
def fe():
    return beam_fe(CONSISTENT, 120)


def test_one_mode_is_the_consistent_reduction():
    g, mg = galerkin(CONSISTENT, 2), modal_galerkin(CONSISTENT, 1)
    for a, b in (
        (g.M, mg.M),
        (g.C0, mg.C0),
        (g.K0static, mg.K0static),
        (g.K0omega2, mg.K0omega2),
        (g.loadGain, mg.loadGain),
    ):
        assert float(np.ravel(b)[0]) == pytest.approx(a, rel=1e-12)


def test_modes_are_exact_at_rest(fe):
    """The shapes of eq. 20 at the roots of eq. 21 are the exact modes with the tip mass: M and K0static
    diagonal (orthogonality, with the shroud's m0 in M) and omega_i^2 = EI lambda_i^4 / (rho A), equal
    to the finite-element frequencies at rest."""
    p = modal_galerkin(CONSISTENT, 6)
    for mat in (p.M, p.K0static):
        off = mat - np.diag(np.diag(mat))
        assert np.max(np.abs(off)) < 1e-12 * np.max(np.abs(mat))
    EI, rhoA, l = 343.0, 7800 * 4.2e-4, 0.15
    exact = np.sqrt(EI / rhoA) * (p.lambdaL / l) ** 2 / (2 * math.pi)
    np.testing.assert_allclose(p.frequencies_hz(0.0), exact, rtol=1e-12)
    np.testing.assert_allclose(p.frequencies_hz(0.0)[:3], fe.frequencies_hz(0.0, 3), rtol=2e-8)
    assert p.lambdaL[0] == pytest.approx(1.7898556, abs=1e-7)  # docs/model.md s.2


@pytest.mark.parametrize("rpm", sorted(M6_TOL))
def test_galerkin_frequencies_approach_fe_from_above(fe, rpm):
    exact = fe.frequencies_hz(rpm, 3)
    err = np.full((6, 3), np.nan)
    for m in range(1, 7):
        f = modal_galerkin(CONSISTENT, m).frequencies_hz(rpm)[:3]
        err[m - 1, : f.size] = (f - exact[: f.size]) / exact[: f.size]
    for k in range(3):
        col = err[k:, k]  # mode k + 1 exists from m = k + 1 on
        assert np.all(col > -1e-8), f"mode {k + 1} below the FE value: {col}"
        assert np.all(np.diff(col) < 0.0), f"mode {k + 1} not decreasing with m: {col}"
    assert np.all(err[5] < M6_TOL[rpm]), err[5]
    assert err[0, 0] > 10 * err[5, 0]  # one mode is measurably worse


def test_open_contact_forced_response_is_the_complex_solve():
    """Contacts open (d = 1 m): the steady m = 3 response of the time integration is the complex
    3 x 3 solve (K0 - omega^2 M + i omega C0) q = G F_w0; the FE model's tip agrees to the Galerkin error."""
    n, EO = 6000.0, 3
    p = dict(CONSISTENT, d=1.0, c=298.0)  # ten times the damping: settled to < 1e-7 by 0.4 s
    om = EO * 2 * math.pi * n / 60
    T = 2 * math.pi / om
    te = np.linspace(0.4 - T, 0.4, 121)
    r = simulate(p, 0.4, lambda t: 100 * math.sin(om * t), lambda t: n, te, modes=3)
    mg = modal_galerkin(p, 3)
    qa = np.linalg.solve(mg.K0(2 * math.pi * n / 60) - om**2 * mg.M + 1j * om * mg.C0, 100 * mg.loadGain)
    # q(t) = Im(qa e^{i omega t}) for the load F_w0 sin(omega t)
    for i in range(3):
        want = np.imag(qa[i] * np.exp(1j * om * te))
        np.testing.assert_allclose(r[f"modalDisplacement[{i + 1}]"], want, rtol=0, atol=1e-6 * abs(qa).max())
    np.testing.assert_allclose(
        r["tipDisplacement"], np.imag(qa.sum() * np.exp(1j * om * te)), atol=1e-6 * abs(qa.sum())
    )
    np.testing.assert_allclose(
        r["rootMoment"],
        np.imag(mg.EI * (mg.rootCurvature @ qa) * np.exp(1j * om * te)),
        atol=1e-6 * abs(mg.EI * (mg.rootCurvature @ qa)),
    )
    assert abs(beam_fe(p, 120).forced_tip(n, om, 100.0)) == pytest.approx(abs(qa.sum()), rel=2e-4)


@pytest.mark.parametrize("bad", [0, 7, -1, 2.5, True])
def test_modes_outside_range_is_refused(bad):
    with pytest.raises(ParameterError, match=r"modes = .* 1\.\.6"):
        modal_galerkin(CONSISTENT, bad)


def test_printed_formulation_refuses_more_modes():
    with pytest.raises(ParameterError, match="printed"):
        modal_galerkin({"formulation": 1}, 2)
