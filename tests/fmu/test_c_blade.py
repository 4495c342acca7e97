"""Tests of fmu_src/physics/blade.c (Galerkin reduction, paper eq. 19-27, docs/model.md s.2) through ctypes.

Two independent references: (1) the check values printed in docs/model.md s.2, compared to half a unit
of their last printed digit (the strictest comparison the printed digits allow); (2) a numpy/scipy
computation written here: scipy.optimize.brentq on eq. 21 in its plain cos/cosh form,
scipy.integrate.quad of phi (eq. 20) and its analytic derivatives, compared at several tip masses to
1e-9 relative (the C code uses power series and Gauss-Legendre quadrature, so agreement is limited
only by quad's ~1e-13 accuracy). Invalid inputs must give a nonzero return code.
"""

from __future__ import annotations

import math
from decimal import Decimal

import numpy as np
import pytest
from scipy.integrate import quad
from scipy.optimize import brentq

from tests.support.cphysics import FORMULATION_CONSISTENT, FORMULATION_PRINTED, PhysicsLib

DEFAULTS = dict(EI=343.0, rho=7800.0, A=4.2e-4, l=0.15, c=29.8, m0=0.025)
FW0 = 100.0  # N/m, Table 1 (only enters u1)
REF_RTOL = 1e-9


@pytest.fixture(scope="module")
def phys(physics_lib) -> PhysicsLib:
    return PhysicsLib(physics_lib)


def reference(EI: float, rho: float, A: float, l: float, c: float, m0: float) -> dict[str, dict[str, float]]:
    """Independent reduction: brentq on eq. 21, quad of eq. 20 expressions (docs/model.md s.2)."""
    R = m0 / (rho * A * l)

    def freq(a: float) -> float:  # eq. 21, as printed
        return 1 + math.cos(a) * math.cosh(a) + R * a * (math.cos(a) * math.sinh(a) - math.sin(a) * math.cosh(a))

    grid = np.linspace(1e-6, 1.9, 4000)
    vals = np.array([freq(a) for a in grid])
    k = int(np.argmax(vals <= 0))
    assert vals[k] <= 0 < vals[k - 1]
    aL = brentq(freq, grid[k - 1], grid[k], xtol=1e-15, rtol=4 * np.finfo(float).eps, maxiter=500)
    lam = aL / l
    s = (math.sinh(aL) + math.sin(aL)) / (math.cosh(aL) + math.cos(aL))

    def phi(x: float) -> float:
        z = lam * x
        return s * (math.cosh(z) - math.cos(z)) + math.sin(z) - math.sinh(z)

    def d1(x: float) -> float:
        z = lam * x
        return lam * (s * (math.sinh(z) + math.sin(z)) + math.cos(z) - math.cosh(z))

    def d2(x: float) -> float:
        z = lam * x
        return lam**2 * (s * (math.cosh(z) + math.cos(z)) - math.sin(z) - math.sinh(z))

    def q(f) -> float:
        return quad(f, 0.0, l, epsabs=0.0, epsrel=1e-13, limit=200)[0]

    U1 = q(lambda x: phi(x) ** 2)
    U = dict(
        lambdaL=aL,
        U1=U1,
        U2=lam**4 * U1,
        U3=q(lambda x: x * phi(x) * d1(x)),
        U4=q(lambda x: d2(x) * phi(x) * (l * l - x * x)),
        U5=q(lambda x: phi(x) * d2(x)),
        intPhi=q(phi),
        u2=phi(l),
    )
    u2, rA = U["u2"], rho * A
    printed = dict(
        U,
        M=rA * U1 / u2,
        C0=c * U1 / u2,
        K0static=EI * U["U2"] / u2,
        K0omega2=(rA * U["U3"] - 0.5 * rA * U["U4"] - m0 * l * U["U5"]) / u2,
        loadGain=U["intPhi"] / u2,
    )
    consistent = dict(
        U,
        M=rA * U1 / u2**2 + m0,
        C0=c * U1 / u2**2,
        K0static=EI * q(lambda x: d2(x) ** 2) / u2**2,
        K0omega2=q(lambda x: (0.5 * rA * (l * l - x * x) + m0 * l) * d1(x) ** 2) / u2**2,
        loadGain=U["intPhi"] / u2,
    )
    return {"printed": printed, "consistent": consistent}


def rel_err(a: float, b: float) -> float:
    return abs(a - b) / abs(b)


# docs/model.md s.2 check values, as printed (strings keep the printed digits).
CHECK_PRINTED = {
    "lambdaL": "1.7898556",
    "U1": "0.239957",
    "U2": "4864.53",
    "U3": "0.364953",
    "U4": "0.154610",
    "U5": "9.92558",
    "u1": "14.8207",
    "u2": "2.542784",
    "M": "0.309149",
    "C0": "2.81216",
    "K0static": "656184",
    "K0omega2": "0.355953",
}
CHECK_CONSISTENT = {"M": "0.146579", "C0": "1.10594", "K0static": "311121", "K0omega2": "0.174944"}


def half_unit(printed: str) -> float:
    """Half a unit in the last printed digit: the tolerance the printed digits allow."""
    return 0.5 * 10.0 ** Decimal(printed).as_tuple().exponent


@pytest.mark.parametrize(
    "formulation,checks", [(FORMULATION_PRINTED, CHECK_PRINTED), (FORMULATION_CONSISTENT, CHECK_CONSISTENT)]
)
def test_model_md_check_values(phys: PhysicsLib, formulation: int, checks: dict[str, str]) -> None:
    rc, red = phys.blade_reduce(formulation, **DEFAULTS)
    assert rc == 0
    got = red.as_dict()
    got["u1"] = FW0 * got["intPhi"]
    for name, printed in checks.items():
        assert abs(got[name] - float(printed)) <= half_unit(printed), (name, got[name], printed)


def test_model_md_frequencies(phys: PhysicsLib) -> None:
    """231.9 Hz at rest; 3 Omega = omega_1 near 4966 rpm (printed) / 4979 rpm (consistent)."""
    for formulation, rpm in ((FORMULATION_PRINTED, "4966"), (FORMULATION_CONSISTENT, "4979")):
        rc, red = phys.blade_reduce(formulation, **DEFAULTS)
        assert rc == 0
        f0 = math.sqrt(red.K0static / red.M) / (2 * math.pi)
        assert abs(f0 - 231.9) <= half_unit("231.9")
        omega2 = red.K0static / (9.0 * red.M - red.K0omega2)  # K0(W) = M (3 W)^2
        n = math.sqrt(omega2) * 60.0 / (2 * math.pi)
        assert abs(n - float(rpm)) <= 0.5, (formulation, n)


@pytest.mark.parametrize("m0", [0.0, 0.02, 0.025, 0.05, 0.1, 2.0])
def test_against_independent_quadrature(phys: PhysicsLib, m0: float) -> None:
    params = dict(DEFAULTS, m0=m0)
    ref = reference(**params)
    for formulation, key in ((FORMULATION_PRINTED, "printed"), (FORMULATION_CONSISTENT, "consistent")):
        rc, red = phys.blade_reduce(formulation, **params)
        assert rc == 0
        got = red.as_dict()
        for name, value in ref[key].items():
            assert rel_err(got[name], value) <= REF_RTOL, (key, name, got[name], value)
        assert phys.blade_k0(red, 523.6) == pytest.approx(value_k0(ref[key], 523.6), rel=REF_RTOL)


def value_k0(ref: dict[str, float], omega: float) -> float:
    return ref["K0static"] + ref["K0omega2"] * omega**2


def test_plain_cantilever_root(phys: PhysicsLib) -> None:
    """R = 0: 1 + cos a cosh a = 0, first root 1.875104068711961 (classical value)."""
    rc, red = phys.blade_reduce(FORMULATION_PRINTED, **dict(DEFAULTS, m0=0.0))
    assert rc == 0
    assert red.lambdaL == pytest.approx(1.875104068711961, rel=1e-14)


def test_mode_identities(phys: PhysicsLib) -> None:
    """Identities by integration by parts (phi(0) = phi'(0) = 0): U3 = (l u2^2 - U1)/2."""
    for m0 in (0.0, 0.025, 0.1, 10.0):
        rc, red = phys.blade_reduce(FORMULATION_PRINTED, **dict(DEFAULTS, m0=m0))
        assert rc == 0
        assert red.U3 == pytest.approx((DEFAULTS["l"] * red.u2**2 - red.U1) / 2, rel=1e-13)


def test_heavy_tip_mass_limit(phys: PhysicsLib) -> None:
    """R >> 1: eq. 21 tends to 2 - (2/3) R a^4, so lambda l -> (3/R)^(1/4) (massless beam + tip mass)."""
    m0 = 1e6
    rc, red = phys.blade_reduce(FORMULATION_CONSISTENT, **dict(DEFAULTS, m0=m0))
    assert rc == 0
    R = m0 / (DEFAULTS["rho"] * DEFAULTS["A"] * DEFAULTS["l"])
    assert red.lambdaL == pytest.approx((3.0 / R) ** 0.25, rel=1e-6)
    # static tip stiffness of a cantilever 3 EI / l^3 (the consistent K0 is the tip stiffness)
    assert red.K0static == pytest.approx(3 * DEFAULTS["EI"] / DEFAULTS["l"] ** 3, rel=1e-6)


BAD = [("EI", 0.0), ("EI", -1.0), ("rho", 0.0), ("A", -4e-4), ("l", 0.0), ("c", -1e-9), ("m0", -1e-9)]
BAD += [(name, v) for name in DEFAULTS for v in (math.nan, math.inf, -math.inf)]


@pytest.mark.parametrize("name,value", BAD)
def test_invalid_inputs(phys: PhysicsLib, name: str, value: float) -> None:
    for formulation in (FORMULATION_PRINTED, FORMULATION_CONSISTENT):
        rc, _ = phys.blade_reduce(formulation, **dict(DEFAULTS, **{name: value}))
        assert rc != 0


def test_invalid_formulation_and_null(phys: PhysicsLib) -> None:
    for formulation in (0, 3, -1):
        rc, _ = phys.blade_reduce(formulation, **DEFAULTS)
        assert rc != 0
    assert phys.lib.bladeReduce(None, FORMULATION_PRINTED, None) != 0


def test_zero_damping_allowed(phys: PhysicsLib) -> None:
    rc, red = phys.blade_reduce(FORMULATION_PRINTED, **dict(DEFAULTS, c=0.0))
    assert rc == 0 and red.C0 == 0.0 and red.M > 0
