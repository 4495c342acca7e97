"""The reference's Galerkin reduction (harness.reference.blade: Newton on eq. 21, Chebyshev-series
integrals) against the product's (harness.model.galerkin: brentq, adaptive quadrature) and the
docs/model.md check values. Two independent derivations of the same constants: they must agree to
1e-12 relative (measured: within 2e-15 on these cases)."""

from __future__ import annotations

import math

import pytest

from harness.model import galerkin as product
from harness.reference import blade as reference

FIELDS = ("lambdaL", "U1", "U2", "U3", "U4", "U5", "intPhi", "u2", "M", "C0", "K0static", "K0omega2", "loadGain")
CASES = [{}, {"m0": 0.0}, {"m0": 0.1}, {"l": 0.3, "EI": 100.0}, {"rho": 2700.0, "A": 1e-4, "c": 10.0}]


@pytest.mark.parametrize("formulation", [1, 2])
@pytest.mark.parametrize("params", CASES)
def test_reference_equals_product(params: dict, formulation: int) -> None:
    r, p = reference.galerkin(params, formulation), product.galerkin(params, formulation)
    for name in FIELDS:
        assert getattr(r, name) == pytest.approx(getattr(p, name), rel=1e-12, abs=0), name


def test_docs_check_values() -> None:
    """docs/model.md s.2 (printed to 6-8 digits): lambda_1 l, M and K0 of both formulations."""
    g1, g2 = reference.galerkin({}, 1), reference.galerkin({}, 2)
    assert abs(g1.lambdaL - 1.7898556) <= 5e-8 and abs(g1.M - 0.309149) <= 5e-7
    assert abs(g1.K0static - 656184) <= 0.5 and abs(g2.M - 0.146579) <= 5e-7 and abs(g2.K0static - 311121) <= 0.5


def test_root_is_the_clamped_free_cantilever_without_tip_mass() -> None:
    assert abs(reference.root(0.0) - 1.8751040687119611) < 1e-14
    assert abs(reference.eq21(reference.root(0.5), 0.5)[0]) < 1e-13
    with pytest.raises(ValueError):
        reference.root(-1.0)


def test_mode_derivatives_by_the_cycle() -> None:
    """phi(0) = phi'(0) = 0 and phi''(l) = 0 (clamped root, free tip), and phi'' against a central
    difference of phi'."""
    lamL, l = reference.root(0.2), 0.15
    assert abs(reference.mode(lamL, l, 0.0, 0)) < 1e-15 and abs(reference.mode(lamL, l, 0.0, 1)) < 1e-13
    assert abs(reference.mode(lamL, l, l, 2)) < 1e-10 * (lamL / l) ** 2
    h, x = 1e-6, 0.07
    fd = (reference.mode(lamL, l, x + h, 1) - reference.mode(lamL, l, x - h, 1)) / (2 * h)
    assert fd == pytest.approx(float(reference.mode(lamL, l, x, 2)), rel=1e-7)
    assert math.isfinite(float(reference.mode(lamL, l, x, 4)))
