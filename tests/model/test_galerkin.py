"""The Galerkin reduction (harness.model.galerkin) against docs/model.md s.2, independent checks and the reference.

The docs/model.md check values are an independent computation printed with 6-8 significant digits; we
compare with a tolerance of half a unit in the last printed digit (i.e. the printed digits must be
exactly the rounded value), which is 1e-7..2e-6 relative depending on the number. The other checks
are physics identities that do not use the reduction's own formulas: the classical cantilever root,
the boundary conditions of the exact mode, integration by parts, and the Rayleigh quotient of an
exact eigenmode.
"""

from __future__ import annotations

import math
from decimal import Decimal

import numpy as np
import pytest
from scipy.integrate import quad
from scipy.optimize import brentq

from harness.model.galerkin import ModeShape, first_root, frequency_equation, galerkin


def half_ulp(printed: str) -> float:
    """Half a unit in the last printed digit of a decimal string."""
    exp = Decimal(printed).as_tuple().exponent
    return 0.5 * 10.0 ** int(exp)


PRINTED = {  # docs/model.md s.2, formulation 1 (printed)
    "lambdaL": "1.7898556",
    "U1": "0.239957",
    "U2": "4864.53",
    "U3": "0.364953",
    "U4": "0.154610",
    "U5": "9.92558",
    "u2": "2.542784",
    "M": "0.309149",
    "C0": "2.81216",
    "K0static": "656184",
    "K0omega2": "0.355953",
}
CONSISTENT = {"M": "0.146579", "C0": "1.10594", "K0static": "311121", "K0omega2": "0.174944"}


@pytest.mark.parametrize("name", sorted(PRINTED))
def test_printed_check_values(name: str) -> None:
    g = galerkin({}, 1)
    assert abs(getattr(g, name) - float(PRINTED[name])) <= half_ulp(PRINTED[name]) * (1 + 1e-9)


def test_u1_check_value() -> None:
    g = galerkin({}, 1)
    u1 = 100.0 * g.intPhi  # u1 = F_w0 int phi, F_w0 = 100 N/m
    assert abs(u1 - 14.8207) <= half_ulp("14.8207")


@pytest.mark.parametrize("name", sorted(CONSISTENT))
def test_consistent_check_values(name: str) -> None:
    g = galerkin({}, 2)
    assert abs(getattr(g, name) - float(CONSISTENT[name])) <= half_ulp(CONSISTENT[name]) * (1 + 1e-9)


@pytest.mark.parametrize("formulation,rpm", [(1, "4966"), (2, "4979")])
def test_resonance_crossing(formulation: int, rpm: str) -> None:
    """3 Omega = omega_1(Omega): docs/model.md gives the crossing to the nearest rpm."""
    g = galerkin({}, formulation)
    f = lambda n: 3 * 2 * math.pi * n / 60 - math.sqrt(g.K0(2 * math.pi * n / 60) / g.M)  # noqa: E731
    assert abs(brentq(f, 1000, 10000) - float(rpm)) <= 0.5


def test_first_bending_frequency_at_rest() -> None:
    for form in (1, 2):
        assert abs(galerkin({}, form).natural_frequency_hz(0.0) - 231.9) <= 0.05


def test_classical_cantilever_root() -> None:
    """Without a tip mass eq. 21 is 1 + cos x cosh x = 0: first root 1.8751040687119611."""
    assert abs(first_root(0.0) - 1.8751040687119611) < 1e-13


@pytest.mark.parametrize("m0", [0.0, 0.02, 0.025, 0.1])
def test_mode_is_exact(m0: float) -> None:
    """phi(0) = phi'(0) = 0, phi''(l) = 0 and the tip shear balances the tip-mass inertia:
    EI phi'''(l) = -m0 omega^2 phi(l) with omega^2 = EI lambda^4 / (rho A)."""
    rho, A, l = 7800.0, 4.2e-4, 0.15
    lamL = first_root(m0 / (rho * A * l))
    assert abs(frequency_equation(lamL, m0 / (rho * A * l))) < 1e-12
    phi = ModeShape(lamL, l)
    lam = lamL / l
    scale = [abs(phi(l, k)) for k in range(4)]
    assert abs(phi(0.0)) <= 1e-14 * scale[0]
    assert abs(phi(0.0, 1)) <= 1e-14 * scale[1]
    assert abs(phi(l, 2)) <= 1e-12 * lam**2 * scale[0]
    assert abs(phi(l, 3) + m0 / (rho * A) * lam**4 * phi(l)) <= 1e-11 * lam**3 * scale[0]


def test_integration_by_parts() -> None:
    """U5 = [phi phi']_0^l - int phi'^2 and U2 = int phi''^2 + boundary terms (independent quadratures)."""
    g = galerkin({}, 1)
    l = 0.15
    phi = ModeShape(g.lambdaL, l)
    i_d1 = quad(lambda x: phi(x, 1) ** 2, 0, l, epsabs=0, epsrel=1e-13)[0]
    assert g.U5 == pytest.approx(phi(l) * phi(l, 1) - i_d1, rel=1e-11)
    # int phi phi'''' = [phi phi''' - phi' phi'']_0^l + int phi''^2, and phi''(l) = 0
    i_d2 = quad(lambda x: phi(x, 2) ** 2, 0, l, epsabs=0, epsrel=1e-13)[0]
    assert g.U2 == pytest.approx(phi(l) * phi(l, 3) + i_d2, rel=1e-10)


@pytest.mark.parametrize("m0", [0.02, 0.1])
def test_consistent_rayleigh_quotient_is_exact(m0: float) -> None:
    """For the exact eigenmode the energy-form K0(0)/M equals omega_1^2 = EI lambda^4/(rho A)."""
    p = {"m0": m0}
    g = galerkin(p, 2)
    lam = g.lambdaL / 0.15
    assert g.K0static / g.M == pytest.approx(343.0 * lam**4 / (7800.0 * 4.2e-4), rel=1e-10)


def test_load_gain_same_in_both_formulations() -> None:
    g1, g2 = galerkin({}, 1), galerkin({}, 2)
    assert g1.loadGain == pytest.approx(g1.intPhi / g1.u2, rel=1e-15)
    assert g2.loadGain == pytest.approx(g1.loadGain, rel=1e-15)
    # trapezoid on 20001 points: independent of quad; error ~ 1e-9 relative
    x = np.linspace(0, 0.15, 20001)
    phi = ModeShape(g1.lambdaL, 0.15)
    vals = np.array([phi(xi) for xi in x])
    assert np.trapezoid(vals, x) / phi(0.15) == pytest.approx(g1.loadGain, rel=1e-8)


def test_bad_formulation() -> None:
    with pytest.raises(ValueError):
        galerkin({}, 3)
