"""The harmonic balance (harness.analysis.harmonic_balance) against the reference, and the reference
fixed point (harness.reference.fixedpoint).

HB roots are checked against the HB equation evaluated with the reference's Galerkin constants and
describing function by quadrature (not the closed forms the solver uses), relative residual <= 1e-9. Completeness is checked against
an independent dense linear scan. The slow-flow stability flag is checked against the eigenvalues of
a finite-difference Jacobian of the averaged equation 2 i w M A' = F_c - D(|A|) A, and the
tracked-amplitude stability (harness.reference.tracked) against simulations started on the periodic
solution. The fixed point
A(B) = B is checked against the linear closed form (no contact) and, for a contact case, against
the DOP853 simulation (slow).
"""

from __future__ import annotations

import math

import numpy as np
import pytest

from harness.analysis.harmonic_balance import harmonic_balance
from harness.model import contact as closed_form
from harness.reference.blade import galerkin
from harness.reference.contact import describing_function
from harness.reference.dynamics import simulate
from harness.reference.fixedpoint import fixed_point, naive_iteration, steady_amplitude
from harness.reference.tracked import tracked_radii

SPEEDS = np.linspace(3000, 10000, 36)
CASES = [{}, {"frictionModel": 2}, {"projection": 2}, {"gamma": math.pi / 7}, {"kn": 1e6}, {"formulation": 2}]


def _lin(p: dict, n: float) -> tuple[complex, float, float]:
    g = galerkin(p)
    Om = 2 * math.pi * n / 60
    w = 3 * Om
    return complex(g.K0(Om) - g.M * w * w, w * g.C0), 100.0 * g.loadGain, w


@pytest.mark.parametrize("params", CASES)
def test_roots_solve_hb_with_quadrature_df(params: dict) -> None:
    curve = harmonic_balance(params, SPEEDS)
    model, proj = int(params.get("frictionModel", 1)), int(params.get("projection", 1))
    n_contact = 0
    for n, sols in zip(SPEEDS, curve):
        D0, F, w = _lin(params, n)
        assert len(sols) % 2 == 1  # R(0) = -F < 0 and R -> +inf: an odd number of simple roots
        for s in sols:
            df = describing_function(params, s.B, w, model, proj)
            D = D0 + df.Keq + 1j * w * df.Ceq
            assert abs(s.B * abs(D) - F) <= 1e-9 * F
            assert s.phase == pytest.approx(-np.angle(D), abs=1e-9)
            assert s.B <= F / (w * galerkin(params).C0)
            n_contact += not s.open
    assert n_contact > 0


@pytest.mark.parametrize("params", CASES[:3])
def test_all_roots_found(params: dict) -> None:
    """Independent dense linear scan of R(B) over (d, 10 d] (+ the open branch) counts the same roots
    (the closed-form describing function: 20001 amplitudes are too many for the quadrature)."""
    d = 3e-5
    for n in (5000.0, 6000.0, 7000.0, 8000.0, 9000.0):
        D0, F, w = _lin(params, n)
        Bs = np.linspace(d * (1 + 1e-7), 10 * d, 20001)
        df = closed_form.describing_function(
            params, Bs, w, int(params.get("frictionModel", 1)), int(params.get("projection", 1))
        )
        R = Bs * np.abs(D0 + df.Keq + 1j * df.CeqOmega) - F
        count = int(np.count_nonzero(np.sign(R[1:]) != np.sign(R[:-1]))) + int(F / abs(D0) <= d)
        sols = [s for s in harmonic_balance(params, n) if s.open or s.B <= 10 * d]
        assert len(sols) == count


def test_vectorised_curve_equals_scalar_calls() -> None:
    curve = harmonic_balance({}, SPEEDS[::5])
    for n, sols in zip(SPEEDS[::5], curve):
        single = harmonic_balance({}, float(n))
        assert np.allclose([s.B for s in single], [s.B for s in sols], rtol=1e-13, atol=0)  # grids differ
        assert [s.stable for s in single] == [s.stable for s in sols]


def test_open_branch_is_the_linear_response() -> None:
    D0, F, _ = _lin({}, 3000.0)
    (s,) = harmonic_balance({}, 3000.0)
    assert s.open and s.stable and s.B == pytest.approx(F / abs(D0), rel=1e-14)


def _slow_flow_eigs(p: dict, n: float, B: float, phase: float) -> np.ndarray:
    """Eigenvalues of the FD Jacobian of 2 i w M A' = F_c - D(|A|) A at the HB solution, with
    q = Re(A e^{i w t}) and the load F sin(w t) = Re(-i F e^{i w t}) (independent of the solver)."""
    g = galerkin(p)
    D0, F, w = _lin(p, n)
    model, proj = int(p.get("frictionModel", 1)), int(p.get("projection", 1))

    def rhs(x: np.ndarray) -> np.ndarray:
        A = complex(x[0], x[1])
        df = describing_function(p, abs(A), w, model, proj)
        dA = (-1j * F - (D0 + df.Keq + 1j * w * df.Ceq) * A) / (2j * w * g.M)
        return np.array([dA.real, dA.imag])

    A0 = B * np.exp(1j * (phase - math.pi / 2))  # B sin(psi + phase) = Re(B e^{i(phase - pi/2)} e^{i psi})
    x0 = np.array([A0.real, A0.imag])
    assert np.max(np.abs(rhs(x0))) <= 1e-8 * B * w
    J = np.empty((2, 2))
    h = 1e-6 * B
    for j in range(2):
        e = np.zeros(2)
        e[j] = h
        J[:, j] = (rhs(x0 + e) - rhs(x0 - e)) / (2 * h)
    return np.linalg.eigvals(J)


@pytest.mark.parametrize("params", [{}, {"kn": 1e6}, {"gamma": math.pi / 7}, {"frictionModel": 2}])
def test_slow_flow_stability_flag(params: dict) -> None:
    checked = {True: 0, False: 0}
    for n in (6000.0, 7000.0, 8000.0, 9000.0, 5000.0):
        for s in harmonic_balance(params, n):
            if s.open:
                continue
            ev = _slow_flow_eigs(params, n, s.B, s.phase)
            if np.max(np.abs(ev.real)) < 1e-3 * np.max(np.abs(ev)):
                continue  # too close to a fold to judge by finite differences
            assert s.stable == bool(np.all(ev.real < 0)), (n, s)
            checked[s.stable] += 1
    assert checked[True] > 0


def _run_from_periodic_state(p: dict, n: float, s, rel: float, stop: float) -> np.ndarray:
    om = 3 * 2 * math.pi * n / 60
    q0, v0 = s.B * math.sin(s.phase), s.B * om * math.cos(s.phase)
    r = simulate(
        dict(p, B=s.B * (1 + rel)),
        stop,
        lambda t: 100 * math.sin(om * t),
        lambda t: n,
        np.linspace(0, stop, 11),
        initial=(q0, v0),
    )
    return r["amplitude"] / s.B - 1


def test_tracked_amplitude_stability_7000rpm() -> None:
    """7000 rpm, gating off: three roots. Started on the periodic solution with B 0.1% high, the
    tracked-amplitude run returns to the upper root (period-map radius ~0.85) and leaves the middle
    one (radius ~1.9) for the upper root. The slow-flow flag agrees with both here."""
    p = {"gating": False, "amplitudeMode": 2}
    low, mid, up = harmonic_balance(p, 7000.0)
    assert low.open and not mid.stable and up.stable
    r_low, r_mid, r_up = tracked_radii(p, (low, mid, up))
    assert r_up < 1 and not r_mid < 1 and r_low < 1
    dev = _run_from_periodic_state(p, 7000.0, up, 1e-3, 0.5)
    assert abs(dev[-1]) < 1e-8
    dev = _run_from_periodic_state(p, 7000.0, mid, 1e-3, 0.5)
    assert dev[-1] == pytest.approx(up.B / mid.B - 1, rel=1e-6)


def test_tracked_amplitude_can_be_unstable_where_slow_flow_is_stable() -> None:
    """5000 rpm, k_n = 1e7, gating off: the unique root is slow-flow stable, but K_eq(B) is so steep
    that the period-by-period update overshoots (radius ~1.5): the tracked run leaves it."""
    p = {"gating": False, "amplitudeMode": 2}
    (s,) = harmonic_balance(p, 5000.0)
    assert s.stable and not tracked_radii(p, [s])[0] < 1
    dev = _run_from_periodic_state(p, 5000.0, s, 1e-6, 0.1)
    assert np.max(np.abs(dev)) > 1e-4  # a 1e-6 perturbation grew > 100x in 25 periods


def test_naive_iteration_classifies() -> None:
    class S:
        def __init__(self, a: float):
            self.A = a

    res = naive_iteration(lambda b: S(0.5 * b + 1.0), 5.0, 60)
    assert res["fixed"] == pytest.approx(2.0, rel=1e-5) and res["cycle"] is None
    res = naive_iteration(lambda b: S(2.0 / b), 0.5, 30)  # exact 2-cycle 0.5 <-> 4
    assert res["fixed"] is None and res["cycle"] == ((0.5, 0.5), (4.0, 4.0))
    res = naive_iteration(lambda b: S(2.0 - 0.5 * (b - 2.0)), 5.0, 12)  # converging alternation
    assert res["cycle"] is None


def test_fixed_point_without_contact_is_the_linear_amplitude() -> None:
    """3000 rpm: the linear response stays below the gap, A(B) = B_lin for every B."""
    D0, F, _ = _lin({}, 3000.0)
    res = fixed_point({}, 3000.0, n_scan=6, naive_iter=4)
    assert len(res.roots) == 1 and res.roots[0].open and res.roots[0].converged
    assert res.roots[0].B == pytest.approx(F / abs(D0), rel=1e-8)
    assert np.allclose(res.scan_A, F / abs(D0), rtol=1e-8) and res.scan_converged.all()
    assert res.naive["fixed"] == pytest.approx(F / abs(D0), rel=1e-8)


def test_steady_amplitude_against_simulation() -> None:
    """A(B) of the exact stepper with steady-state detection vs a 1.2 s DOP853 run (300 periods,
    contraction 0.953 per period: the transient is < 1e-6) sampled 4000 times in the last period
    (sampling error (pi/4000)^2/2 = 3e-7)."""
    n, B = 5000.0, 3.5e-5
    ss = steady_amplitude({"B": B}, n, B)
    assert ss.converged and ss.subharmonic == 1
    om = 3 * 2 * math.pi * n / 60
    T = 2 * math.pi / om
    stop = 300 * T
    te = np.linspace(stop - T, stop, 4001)
    r = simulate({"amplitudeMode": 1, "B": B}, stop, lambda t: 100 * math.sin(om * t), lambda t: n, te)
    assert np.max(np.abs(r["tipDisplacement"])) == pytest.approx(ss.A, rel=2e-6)


def test_subharmonic_steady_state_is_detected() -> None:
    """5000 rpm, B = 2e-4: the gated fixed-B response settles on a period-3T orbit."""
    ss = steady_amplitude({"B": 2e-4}, 5000.0, 2e-4)
    assert ss.converged and ss.subharmonic == 3


@pytest.mark.slow
def test_fixed_point_5000rpm_and_the_paper_two_cycle() -> None:
    """docs/model.md s.4: A(B) = B has a root near 0.035 mm at 5000 rpm with dA/dB < -1, so the naive
    procedure (0.2 s runs) falls into a 2-cycle ~0.03 mm <-> 0.4..0.8 mm."""
    res = fixed_point({}, 5000.0, n_scan=12, horizon=0.2)
    contact = [r for r in res.roots if not r.open]
    assert len(contact) == 1 and contact[0].converged
    root = contact[0]
    assert 3.3e-5 < root.B < 3.7e-5 and root.slope < -1
    assert steady_amplitude({"B": root.B}, 5000.0, root.B).A == pytest.approx(root.B, rel=1e-7)
    (lo, hi) = res.naive["cycle"]
    assert 2.5e-5 < lo[0] and lo[1] < 3.5e-5 and 4e-4 < hi[0] and hi[1] < 9e-4


@pytest.mark.slow
def test_fixed_point_root_against_simulation() -> None:
    """The root B* of A(B) = B: a 2 s DOP853 run with fixed B = B* settles at amplitude B*."""
    res = fixed_point({"kn": 1e5}, 5000.0, n_scan=10, naive_iter=2)
    (root,) = [r for r in res.roots if not r.open]
    om = 3 * 2 * math.pi * 5000.0 / 60
    T = 2 * math.pi / om
    stop = 500 * T
    te = np.linspace(stop - T, stop, 4001)
    r = simulate(
        {"kn": 1e5, "amplitudeMode": 1, "B": root.B}, stop, lambda t: 100 * math.sin(om * t), lambda t: 5000.0, te
    )
    assert np.max(np.abs(r["tipDisplacement"])) == pytest.approx(root.B, rel=1e-5)
