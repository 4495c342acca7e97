"""Periodic orbits by shooting through the FMU (harness.analysis.periodic): each result against an
independent computation.

- ungated fixed B (a linear ODE): the orbit equals the closed-form harmonic response
  (harness.analysis.harmonic_balance.linear_orbit, complex arithmetic) and the multipliers equal
  exp(lambda T), lambda the eigenvalues of M s^2 + (C0 + C_eq) s + K0 + K_eq (reference Galerkin
  constants and describing function): 1e-8 at maxStep 2.5e-6 s (RK4 error ~1e-10);
- orbits equal long transient runs of the FMU that settle onto them (1e-8 of the amplitude, same
  maxStep): contact-free at 3000 rpm from rest, and the gated fixed-B contact orbit at 7000 rpm
  started 1 % off it;
- every root of A(B) = B (fixedPoint) at several speeds of the base case above 6000 rpm and at
  points of the gap, angle and k_n studies equals a root found independently: the reference's
  exact piecewise-linear period map (harness.reference.fixedpoint.PiecewiseStepper) with its own
  Newton for the fixed-B orbit on a dense B grid and brentq on A(B) - B (1e-5 relative: the
  FMU's RK4 vs the exact solution, through the slope of A(B) - B);
- the FMU started on each reported stable orbit (tracked amplitude, Jenkins element) stays on it.
"""

from __future__ import annotations

import cmath
import math

import numpy as np
import pytest
from scipy.optimize import brentq

from harness.analysis.periodic.period_map import PeriodMap, omega
from harness.analysis.harmonic_balance import harmonic_balance, linear_orbit
from harness.analysis.periodic.branches import orbits_at
from harness.analysis.periodic.shooting import shoot
from harness.reference.blade import galerkin
from harness.reference.contact import contact_consts, describing_function
from harness.reference.fixedpoint import PiecewiseStepper
from harness.reference.tracked import tracked_radii

FINE = {"maxStep": 2.5e-6}


def test_ungated_fixed_b_orbit_and_multipliers_equal_closed_form(fmu):
    p = dict(FINE, gating=False, B=4.3e-5)
    n = 7000.0
    pm = PeriodMap(fmu, p, "fixedB")
    orb = shoot(pm, np.zeros(2), n)
    assert orb is not None
    w = omega(pm.p, n)
    q0, v0 = linear_orbit(pm.p, n, 4.3e-5)
    S = math.hypot(q0, v0 / w)
    assert abs(orb.x[0] - q0) <= 1e-8 * S and abs(orb.x[1] - v0) <= 1e-8 * S * w
    # multipliers: exp(lambda T) of the linear ODE with the describing function at B
    g = galerkin(pm.p)
    df = describing_function(contact_consts(pm.p), 4.3e-5, w, 1, 1)
    Om = w / 3
    M, c, k = g.M, g.C0 + float(df.Ceq), g.K0static + g.K0omega2 * Om * Om + float(df.Keq)
    T = 2 * math.pi / w
    lam = complex(-c / (2 * M), math.sqrt(k / M - (c / (2 * M)) ** 2))
    expected = sorted([cmath.exp(lam * T), cmath.exp(lam.conjugate() * T)], key=lambda z: z.imag)
    got = sorted(orb.multipliers, key=lambda z: z.imag)
    assert max(abs(a - b) for a, b in zip(got, expected)) <= 1e-8
    assert orb.stable and orb.label == "stable"


def _period_end_states(fmu, params, n, periods, steps=8):
    T = 60.0 / (int(params.get("engineOrder", 3)) * n)
    r = fmu.run(
        params,
        periods * T,
        T / steps,
        speed_rpm=n,
        outputs=["tipDisplacement", "tipVelocity"],
        sample_every=steps,
        input_fit="chebyshev",
        carry_values=True,
    )
    return r


def test_orbit_equals_settled_transient_from_rest(fmu):
    n = 3000.0  # contact-free: |mu| = exp(-C0 T / 2M) = 0.97 per period, 900 periods -> 1e-12
    pm = PeriodMap(fmu, dict(FINE, amplitudeMode=1), "fixedB")
    orb = shoot(pm, np.zeros(2), n)
    r = _period_end_states(fmu, dict(FINE, amplitudeMode=1), n, 900)
    w = omega(pm.p, n)
    assert abs(r["tipDisplacement"][-1] - orb.x[0]) <= 1e-8 * orb.amplitude
    assert abs(r["tipVelocity"][-1] - orb.x[1]) <= 1e-8 * orb.amplitude * w


def test_gated_contact_orbit_equals_transient_started_near_it(fmu):
    # the contact root of A(B) = B at 7000 rpm (~0.0427 mm; unstable in the tracked model) is an
    # attracting orbit of the gated fixed-B system at that B (|mu| ~ 0.88)
    n = 7000.0
    root = max(orbits_at(PeriodMap(fmu, FINE, "fixedPoint"), n), key=lambda o: o.B)
    p = dict(FINE, amplitudeMode=1, B=root.B)
    pm = PeriodMap(fmu, p, "fixedB")
    orb = shoot(pm, root.x[:2], n)
    assert orb is not None and orb.amplitude > pm.d and orb.stable and not root.stable
    assert abs(orb.amplitude - root.B) <= 1e-8 * root.B  # A(B) = B on it
    start = {"tipDisplacement": 1.01 * orb.x[0], "tipVelocity": 0.99 * orb.x[1]}
    r = _period_end_states(fmu, dict(p, **start), n, 300)
    w = omega(pm.p, n)
    assert abs(r["tipDisplacement"][-1] - orb.x[0]) <= 1e-8 * orb.amplitude
    assert abs(r["tipVelocity"][-1] - orb.x[1]) <= 1e-8 * orb.amplitude * w


# ---- every root of A(B) = B, against the exact piecewise-linear reference ----
def _exact_orbit(params, n, B, x0):
    """(q0, q0') and max |q| of the fixed-B periodic orbit near x0 with the exact stepper: Newton
    with central differences; (None, nan) if it does not converge."""
    w = omega(params, n)
    T, d = 2 * math.pi / w, params["d"]
    st = PiecewiseStepper(params, n, B)

    def P(x):
        q, v, _, m = st.advance(0.0, x[0], x[1], st.initial_g(x[0]), T)
        return np.array([q, v]), m

    x = np.array(x0, dtype=float)
    for _ in range(40):
        Px, m = P(x)
        sc = np.array([max(abs(x[0]), d), max(abs(x[0]), d) * w])
        if np.max(np.abs(Px - x) / sc) < 1e-12:
            return x, m
        J = np.empty((2, 2))
        for j in range(2):
            e = np.zeros(2)
            e[j] = 1e-7 * sc[j]
            J[:, j] = (P(x + e)[0] - P(x - e)[0]) / (2 * e[j])
        x = x + np.linalg.solve(J - np.eye(2), -(Px - x))
    return None, math.nan


def _reference_roots(params, n, n_grid=160):
    """Roots of g(B) = A(B) - B, A(B) = max |q| of the fixed-B periodic orbit with contact, from
    the exact stepper: Newton (central differences) on its period map from the harmonic guess."""
    d = params["d"]

    def orbit(B, x0):
        return _exact_orbit(params, n, B, x0)

    def g(B, x0):
        x, m = orbit(B, x0)
        return (m - B if x is not None and m > d else math.nan), x

    from harness.analysis.periodic.search import linear_bound

    grid = np.geomspace(d * (1 + 1e-6), 1.5 * linear_bound(params, n), n_grid)
    vals, xs, prev = [], [], None
    for B in grid:
        guess = prev if prev is not None else linear_orbit(params, n, B)
        gv, x = g(B, guess)
        if math.isnan(gv):
            gv, x = g(B, linear_orbit(params, n, B))
        vals.append(gv)
        xs.append(x)
        prev = x
    roots = []
    for i in range(len(grid) - 1):
        a, b = vals[i], vals[i + 1]
        if np.isfinite(a) and np.isfinite(b) and a * b < 0:
            x0 = xs[i]
            roots.append(brentq(lambda B: g(B, x0)[0], grid[i], grid[i + 1], xtol=1e-14, rtol=1e-12))
    return roots


# 8500 and 9000 rpm: two roots in a window of B a few per cent wide below the fold at 9431 rpm,
# between the points of the search's B scan (found on the branch traced around the speed)
CASES = [
    ({}, 6250.0),
    ({}, 7000.0),
    ({}, 8000.0),
    ({}, 8500.0),
    ({}, 9000.0),
    ({"d": 2e-5}, 7000.0),
    ({"gamma": math.pi / 5}, 7000.0),
    ({"kn": 1e6}, 6000.0),
]


@pytest.mark.parametrize("over,n", CASES, ids=[f"{o or 'base'}-{n:g}" for o, n in CASES])
def test_every_contact_root_of_the_fixed_point_is_found(fmu, over, n):
    pm = PeriodMap(fmu, dict(FINE, **over), "fixedPoint")
    orbits = orbits_at(pm, n)
    found = [o.B for o in orbits if o.B > pm.d * (1 + 1e-6)]
    ref_params = dict(pm.p, amplitudeMode=1)
    ref = _reference_roots(ref_params, n)
    assert ref, "the reference must find a contact root here (else the case tests nothing)"
    for B in ref:
        assert any(abs(f - B) <= 1e-5 * B for f in found), f"root B = {B:.9e} m missed; found {found}"
    # and each root found is one of the exact model: the exact fixed-B orbit from the FMU's state
    # at that B has max |q| = B (roots on a second fixed-B orbit family are not in the scan above)
    for o in orbits:
        if o.B > pm.d * (1 + 1e-6):
            x, A = _exact_orbit(ref_params, n, o.B, o.x[:2])
            assert x is not None and abs(A - o.B) <= 1e-5 * o.B, f"B = {o.B:.9e} m: exact A(B) = {A:.9e} m"


# ---- started on a stable orbit, the FMU stays on it ----
@pytest.mark.parametrize("model,n", [("fixedPoint", 9000.0), ("fixedPoint", 7000.0), ("jenkins", 7000.0)])
def test_fmu_started_on_a_stable_orbit_stays_on_it(fmu, model, n):
    pm = PeriodMap(fmu, {}, model)
    stable = [o for o in orbits_at(pm, n) if o.stable]
    assert stable
    for o in stable:
        p = dict(o.start_values, amplitudeMode=2 if model != "jenkins" else 1)
        if model == "jenkins":
            p["frictionModel"] = 3
        r = _period_end_states(fmu, p, n, 60)
        w = omega(pm.p, n)
        dq = np.max(np.abs(r["tipDisplacement"] - o.x[0]))
        dv = np.max(np.abs(r["tipVelocity"] - o.x[1]))
        assert dq <= 1e-6 * o.amplitude and dv <= 1e-6 * o.amplitude * w, (o.amplitude, dq, dv)


# ---- gating off: the fixed point is the one-harmonic balance exactly (the orbit is harmonic) ----
@pytest.mark.parametrize("n", [6000.0, 8000.0])
def test_ungated_fixed_point_equals_harmonic_balance_with_tracked_stability(fmu, n):
    """Gating off and B fixed, the ODE is linear: the orbit has no higher harmonic, so its roots of
    A(B) = B are exactly the HB roots (harness.analysis.harmonic_balance, Illinois to 1e-14), all of
    them; and the tracked model's spectral radius at each equals the reference's period map
    (harness.reference.tracked, exact linear solution + brentq extrema, central differences)."""
    pm = PeriodMap(fmu, dict(FINE, gating=False), "fixedPoint")
    orbs = orbits_at(pm, n)
    hb = harmonic_balance(dict(gating=False), n)
    assert len(orbs) == len(hb) >= 2
    for o, h, radius in zip(orbs, hb, tracked_radii(dict(gating=False), hb)):
        assert abs(o.B - h.B) <= 1e-8 * h.B
        assert abs(np.max(np.abs(o.multipliers)) - radius) <= 1e-5


# ---- the multipliers of the tracked map are its growth rate in the FMU ----
@pytest.mark.parametrize("n", [7500.0, 7700.0])
def test_multiplier_modulus_equals_the_fmu_growth_rate_near_the_contact_orbit(fmu, n):
    """max |q| over a period is a kink at a half-wave symmetric orbit (equal positive and negative
    peaks), so the tracked map has no derivative there; the reported multipliers (central
    differences) must still be the rate at which a small perturbation grows or decays in the
    tracked FMU itself: |mu| ~ 1.015 at 7500 rpm (unstable), ~ 0.987 at 7700 rpm (stable), where
    one-sided differences give 1.08 and 1.04. Rate from the envelope of |q(kT) - q0| over 200
    periods, 1e-4 of the amplitude off the orbit: within 3e-3 of |mu|."""
    pm = PeriodMap(fmu, {}, "fixedPoint")
    o = max(orbits_at(pm, n), key=lambda o: o.amplitude)
    mu = float(np.max(np.abs(o.multipliers)))
    assert abs(mu - 1.0) > 0.01  # clear of the boundary, so the rate can tell stable from unstable
    p = dict(o.start_values, amplitudeMode=2, tipDisplacement=o.x[0] + 1e-4 * o.amplitude)
    dev = np.abs(_period_end_states(fmu, p, n, 301)["tipDisplacement"] - o.x[0])
    early, late = np.max(dev[50:100]), np.max(dev[250:300])
    rate = (late / early) ** (1.0 / 200.0)
    assert abs(rate - mu) <= 3e-3, (rate, mu)


def test_every_orbit_at_the_top_of_the_speed_range(fmu):
    """At 30000 rpm (the FMU's rotorSpeed maximum) the branch traced around the speed must not step
    beyond it (its speed difference goes backwards there); the one orbit is contact-free and equals
    the closed-form linear response (1e-6 at the default maxStep)."""
    pm = PeriodMap(fmu, {}, "fixedB")
    orbits = orbits_at(pm, 30000.0)
    assert len(orbits) == 1
    q0, v0 = linear_orbit(pm.p, 30000.0, None)
    assert abs(orbits[0].x[0] - q0) <= 1e-6 * orbits[0].amplitude
    assert abs(orbits[0].x[1] - v0) <= 1e-6 * orbits[0].amplitude * omega(pm.p, 30000.0)


@pytest.mark.parametrize(
    "model, n", [("fixedPoint", 7000.0), ("coulomb", 6000.0), ("jenkins", 6000.0), ("jenkins", 8000.0)]
)
def test_multipliers_from_sensitivities_equal_central_differences(fmu, model, n):
    """Every orbit found at n: the monodromy matrix from the FMU's sensitivities (the default) has
    the multipliers of the central-difference one (sensitivities off) within 1e-5: the two differ
    by the differences' truncation and the kink of max |q| at half-wave symmetric orbits (the
    sensitivities take the mean gradient of equal peaks, the central difference's limit). The
    differences run at 8 steps per period: at 4 the load interpolant leaves the two peaks ~1e-10
    apart, so a difference step of 1e-6 no longer straddles the kink."""
    from harness.analysis.periodic.period_map import ShootingSettings
    from harness.analysis.periodic.search import solutions_at
    from harness.analysis.periodic.shooting import orbit

    pm_s = PeriodMap(fmu, {}, model)
    pm_f = PeriodMap(fmu, {}, model, ShootingSettings(sensitivities=False, steps_per_period=8))
    sols = solutions_at(pm_f, n)
    assert len(sols) >= 2
    for sol in sols:
        a = orbit(pm_f, sol, n).multipliers
        b = shoot(pm_s, sol.x, n).multipliers
        assert np.allclose(np.sort(np.abs(a)), np.sort(np.abs(b)), rtol=0, atol=1e-5), (sol.amplitude, a, b)
