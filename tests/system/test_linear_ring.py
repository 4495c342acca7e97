"""The ring with linear couplings (harness/system/linear_ring.py): its closed form against the
independent time integration of its ODE, the whole co-simulation pipeline against the closed form, and
Whitehead's bound approached, never exceeded."""

from __future__ import annotations

import math
from dataclasses import replace

import numpy as np
import pytest
from scipy.integrate import solve_ivp

from harness.model.galerkin import galerkin
from harness.model.params import validate
from harness.system import linear_ring as LR
from harness.system.ring import Ring, amplitudes
from harness.system.ring_c import run
from harness.studies.mistuning import whitehead

N, EO, FW0 = 6, 3, 300.0
PATTERN = (1.03, 0.98, 1.0, 0.96, 1.02, 1.01)  # EI factors of a mistuned ring


def _k0(speed: float) -> float:
    g = galerkin(validate({}))
    return g.K0static + g.K0omega2 * (2 * math.pi * speed / 60) ** 2


def _ring(ratio: float, c: float = 298.0, pattern=PATTERN) -> Ring:
    """A mistuned linear ring whose coupling stiffness is `ratio` of the blade's K0 at 5000 rpm."""
    return Ring(
        n=N,
        engine_order=EO,
        fw0=FW0,
        blade={"c": c},
        blade_each=tuple({"EI": 343.0 * f} for f in pattern),
        contact={**LR.LINEAR_CONTACT, "kn": LR.kn_for(ratio * _k0(5000.0))},
        order=2,
    )


def _steady(t: np.ndarray, q: np.ndarray, omega: float) -> np.ndarray:
    return amplitudes(t, q, omega)


def test_coupling_stiffness_of_the_stuck_contact() -> None:
    # kn cos^2 g + kd sin^2 g: at gamma = pi/3, kdRatio 0.6087: 0.25 kn + 0.456 kn
    assert LR.coupling_stiffness({"kn": 1e6}) == pytest.approx(1e6 * (0.25 + 0.75 * 0.608695652173913), rel=1e-12)
    assert LR.coupling_stiffness({"kn": LR.kn_for(5e4)}) == pytest.approx(5e4, rel=1e-12)


def test_closed_form_equals_a_time_integration() -> None:
    # the linear ODE of the ring integrated by scipy (DOP853) from rest, 0.3 s at c = 298 (decay
    # time 2 M / C0 = 0.022 s: the transient is below 1e-5 of the response), independent of the
    # FMUs and of the complex solve
    ring = replace(_ring(0.3), speed=6500.0)
    gs = LR.blade_constants(ring)
    M, C, G = (np.array([getattr(g, a) for g in gs]) for a in ("M", "C0", "loadGain"))
    Om = 2 * math.pi * ring.speed / 60
    K = np.array([g.K0static + g.K0omega2 * Om * Om for g in gs])
    kc = LR.coupling_stiffness(ring.contact)
    phi = 2 * math.pi * EO * np.arange(N) / N

    def rhs(t: float, y: np.ndarray) -> np.ndarray:
        q, v = y[:N], y[N:]
        coupling = kc * (2 * q - np.roll(q, 1) - np.roll(q, -1))
        return np.concatenate([v, (G * FW0 * np.sin(ring.omega * t + phi) - C * v - K * q - coupling) / M])

    T = 2 * math.pi / ring.omega
    t = np.arange(0.0, 0.3, T / 400)
    sol = solve_ivp(rhs, (0.0, t[-1]), np.zeros(2 * N), method="DOP853", rtol=1e-11, atol=1e-16, t_eval=t)
    # max |q| over 400 samples of the last period: at most 1 - cos(pi / 400) = 3e-5 below the peak
    a = _steady(t, sol.y[:N].T, ring.omega)
    cf = LR.response(ring, [ring.speed])[0]
    assert np.max(np.abs(a - cf)) / cf.max() <= 5e-5


@pytest.mark.parametrize("ratio", [0.05, 0.5])
def test_the_co_simulation_pipeline_equals_the_closed_form(ratio: float) -> None:
    # the C loop at h = T / 160 with quadratic extrapolation (the study's numerics): coupling error
    # ~1e-3 of max |q| at the steepest, plus the sampling of max |q| (<= 1.9e-4)
    ring = _ring(ratio)
    lin = LR.LinearRing(ring)
    n_pk = lin.peak((3000.0, 12000.0))[1]
    for n in (0.8 * n_pk, n_pk, 1.2 * n_pk):
        T = 60 / (EO * n)
        r = replace(ring, speed=n, step=round(T / 160 * 1e9) * 1e-9, stop_time=0.25)
        res = run(r)
        a = _steady(res["time"], res["q"], r.omega)
        cf = lin.amplitudes([n])[0]
        assert np.max(np.abs(a - cf)) / cf.max() <= 1e-3, (ratio, n)


def test_stiffness_scales_with_EI() -> None:
    # worst_mistuning scales K0static with the EI factor: the Galerkin reduction agrees
    g1, g2 = galerkin(validate({})), galerkin(validate({"EI": 343.0 * 1.07}))
    assert g2.K0static == pytest.approx(1.07 * g1.K0static, rel=1e-12)
    assert (g2.M, g2.K0omega2, g2.C0, g2.loadGain) == pytest.approx((g1.M, g1.K0omega2, g1.C0, g1.loadGain), rel=1e-12)


def test_whitehead_bound_is_approached_and_never_exceeded() -> None:
    bound = whitehead(N)
    # light damping, coupling 1 % of the blade stiffness: the regime where the bound is sharp
    ring = _ring(0.01, c=3.0, pattern=(1.0,) * N)
    n_t = LR.LinearRing(ring).peak((3000.0, 8000.0), 2000)[1]
    band = (0.9 * n_t, 1.1 * n_t)
    amp, d = LR.worst_mistuning(ring, band, spread=0.1, maxiter=30, popsize=10)
    assert 0.97 * bound <= amp <= bound * (1 + 1e-9), (amp, bound, d)
    # random zero-mean patterns stay below it too
    lin = LR.LinearRing(ring)
    tuned, Ks0 = lin.peak(band)[0], lin.Ks.copy()
    rng = np.random.default_rng(7)
    for _ in range(200):
        z = 0.02 * rng.standard_normal(N)
        lin.Ks = Ks0 * (1 + z - z.mean())
        assert lin.peak(band, 300)[0] / tuned <= bound
