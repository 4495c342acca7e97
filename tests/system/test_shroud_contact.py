"""The ShroudContact FMU against the independent Python reference (harness/reference/shroud_contact.py).

Each motion is prescribed as u = q_A - q_B with both sides moving (an offset common to both sides
must not matter). Checks and tolerances:
- forces vs the reference at every communication point: the FMU sees the motion as the Taylor
  polynomial of order 8 the master sets at each point (error (omega h)^9 / 9! ~ 3e-9 relative for the
  third harmonic at h = 1e-4 s), the reference the exact motion: 1e-8 of the largest force;
  the ramps are exactly linear (values only: the FMU builds u from the velocities): 1e-11;
- the dissipated energy (closed form in C) vs the reference's quadrature of F_f times the slip rate
  w': 1e-8 of the final energy; describing functions: quadrature of C_eq u'^2, 1e-8 (the FMU
  integrates the square of the Taylor polynomial's slope);
- forceA = -forceB exactly, at every point of every run;
- the steady cycle of u = B cos(omega t) dissipates sin(gamma) times the closed-form cycle work of
  harness.reference.contact.jenkins_cycle_dissipation (1e-9 relative);
- contactState equals the reference's except where the master's new u lies a rounding-sized step
  behind the extrapolated one and the element just reversed (FMU stick, reference slip), and
  there |F_f| equals the friction limit to 1e-6.
"""

from __future__ import annotations

import math

import numpy as np
import pytest
from fmpy.validation import validate_fmu

from harness.fmu.binding import FmiError
from harness.fmu.slave import Unpacked, build_ring_fmus
from harness.reference.contact import jenkins_cycle_dissipation
from harness.reference.shroud_contact import JenkinsPair, Motion, df_pair

D = 3e-5  # default gap [m]
W = 2 * math.pi * 250  # [rad/s]
H = 1e-4  # communication step [s]
OUT = ["forceA", "forceB", "normalForce", "frictionForce", "dissipatedEnergy", "contactState"]


@pytest.fixture(scope="module")
def contact():
    _, sc = build_ring_fmus()
    with Unpacked(sc) as u:
        yield u


def harmonic_derivs(t: float, terms: list[tuple[float, float, float]], offset: float = 0.0) -> list[float]:
    """u^(k)(t), k = 0..9, of offset + sum A sin(w t + phi)."""
    return [
        sum(A * w**k * math.sin(w * t + ph + k * math.pi / 2) for A, w, ph in terms) + (offset if k == 0 else 0.0)
        for k in range(10)
    ]


def run_fmu(
    u: Unpacked, params: dict, t: np.ndarray, derivs, common=lambda t: 0.0, order: int = 8, speed: float = 5000.0
) -> np.ndarray:
    """Drive the FMU: q_A = u + c, q_B = c (c common to both sides); u and q_A' from derivs(t). The
    start state is at u(t_0) (inputs set before the end of initialization), as the reference's."""
    D0, c0 = derivs(t[0]), common(t[0])
    s = u.instance("c", params, inputs={"displacementA": D0[0] + c0, "velocityA": D0[1], "displacementB": c0})
    rows = []
    try:
        for k, tk in enumerate(t):
            D_ = derivs(tk)
            c = common(tk)
            s.set_inputs(
                {
                    "displacementA": D_[0] + c,
                    "velocityA": D_[1],
                    "displacementB": c,
                    "velocityB": 0.0,
                    "rotorSpeed": speed,
                },
                {"displacementA": D_[1 : order + 1]} if order else None,
            )
            rows.append(s.get(OUT))
            if k + 1 < len(t):
                s.step(float(tk), float(t[k + 1] - tk))
    finally:
        s.free()
    return np.array(rows)


def assert_opposite(r: np.ndarray) -> None:
    assert np.all(r[:, 0] == -r[:, 1]), "forceA != -forceB"


TWO_HARMONICS = [(2.2 * D, W, 0.0), (0.4 * D, 3 * W, 0.3)]  # stick, slip, open, reversals inside contact


@pytest.mark.parametrize(
    "params",
    [{}, {"gamma": math.pi / 7}, {"kdRatio": 0.8235, "mu": 0.5, "d": 2e-5}],
    ids=["default", "fullstick-angle", "mindlin"],
)
def test_jenkins_vs_reference_harmonics(contact, params):
    t = np.arange(241) * H
    f = lambda x: harmonic_derivs(x, TWO_HARMONICS, 0.1 * D)  # noqa: E731
    r = run_fmu(contact, params, t, f, common=lambda x: 1e-3 * math.sin(7 * x))
    assert_opposite(r)
    ref = JenkinsPair(params).evaluate(Motion(lambda x: f(x)[0], lambda x: f(x)[1]), t, H / 20)
    fmax = np.abs(ref["forceB"]).max()
    assert fmax > 10.0  # the contact did close
    for i, k in enumerate(OUT[:4]):
        assert np.abs(r[:, i] - ref[k]).max() <= 1e-8 * fmax, k
    E = ref["dissipatedEnergy"]
    if params.get("gamma") != math.pi / 7:
        assert E[-1] > 0.0
    assert np.abs(r[:, 4] - E).max() <= 1e-8 * max(E[-1], 1e-12)
    assert np.all(np.diff(r[:, 4]) >= -1e-18), "energy must not decrease"
    mism = r[:, 5] != ref["contactState"]
    assert set(zip(r[mism, 5], ref["contactState"][mism])) <= {(1.0, 2.0)}
    L = params.get("mu", 0.33) * np.abs(ref["normalForce"][mism])  # friction limit mu |F_n|
    assert np.all(np.abs(np.abs(r[mism, 3]) - L) <= 1e-6 * fmax)


def test_jenkins_ramps_velocity_path(contact):
    """Piecewise-linear u with kinks at communication points, given as values only: the FMU takes
    the displacement's slope from the velocity input."""
    knots = np.array([0.0, 40, 60, 100, 130, 200]) * H
    vals = np.array([0.0, 3 * D, 2.2 * D, -3 * D, -1.5 * D, 2.5 * D])
    t = np.arange(201) * H

    def u(x: float) -> float:
        return float(np.interp(x, knots, vals))

    def du(x: float) -> float:  # right derivative: the slope of the step starting at x
        i = min(np.searchsorted(knots, x, side="right") - 1, len(knots) - 2)
        return float((vals[i + 1] - vals[i]) / (knots[i + 1] - knots[i]))

    r = run_fmu(contact, {}, t, lambda x: [u(x), du(x)] + [0.0] * 8, order=0)
    assert_opposite(r)
    ref = JenkinsPair({}).evaluate(Motion(u, du), t, H / 10)
    fmax = np.abs(ref["forceB"]).max()
    for i, k in enumerate(OUT[:4]):
        assert np.abs(r[:, i] - ref[k]).max() <= 1e-11 * fmax, k
    assert np.abs(r[:, 4] - ref["dissipatedEnergy"]).max() <= 1e-10 * ref["dissipatedEnergy"][-1]
    assert np.array_equal(r[:, 5], ref["contactState"])
    assert {0.0, 1.0, 2.0} <= set(r[:, 5])  # open, stick and slip all seen


def test_cycle_dissipation_closed_form(contact):
    """u = B cos(omega t): after the first cycle every cycle dissipates sin(g) closed int F_f du."""
    B = 2.5 * D
    n_per = 80
    h = 2 * math.pi / W / n_per
    t = np.arange(4 * n_per + 1) * h
    r = run_fmu(contact, {}, t, lambda x: harmonic_derivs(x, [(B, W, math.pi / 2)]))
    per_cycle = np.diff(r[::n_per, 4])[1:]
    expect = math.sin(math.pi / 3) * jenkins_cycle_dissipation({}, B)
    assert expect > 0
    assert np.all(np.abs(per_cycle - expect) <= 1e-9 * expect), (per_cycle, expect)


@pytest.mark.parametrize("model", [1, 2])
@pytest.mark.parametrize("gating", [True, False])
def test_describing_function_vs_reference(contact, model, gating):
    t = np.arange(161) * H
    f = lambda x: harmonic_derivs(x, TWO_HARMONICS, 0.1 * D)  # noqa: E731
    params = {"frictionModel": model, "gating": gating, "B": 7e-5, "projection": 2 if model == 2 else 1}
    r = run_fmu(contact, params, t, f, speed=4000.0)
    assert_opposite(r)
    ref = df_pair(
        {},
        Motion(lambda x: f(x)[0], lambda x: f(x)[1]),
        t,
        3 * 2 * math.pi * 4000 / 60,
        model,
        7e-5,
        projection=params["projection"],
        gating=gating,
        dt_scan=H / 20,
    )
    fmax = np.abs(ref["forceB"]).max()
    for i, k in enumerate(OUT[:4]):
        assert np.abs(r[:, i] - ref[k]).max() <= 1e-8 * fmax, k
    # u'^2 of the order-8 Taylor polynomial: (3 omega h)^8 / 8! ~ 5e-7 of the third harmonic's share
    assert np.abs(r[:, 4] - ref["dissipatedEnergy"]).max() <= 1e-8 * ref["dissipatedEnergy"][-1]


def test_validate_fmu_clean():
    for p in build_ring_fmus():
        assert validate_fmu(str(p)) == [], p


@pytest.mark.parametrize(
    "name,value,words",
    [
        ("gamma", 2.0, ["gamma", "2", "(0, 1.5708"]),
        ("kn", -1.0, ["kn", "-1"]),
        ("d", float("nan"), ["d", "nan"]),
        ("frictionModel", 4, ["frictionModel", "4", "[1, 3]"]),
    ],
)
def test_invalid_parameters_give_error_with_message(contact, name, value, words):
    s = contact.instance("bad", initialize=False)
    try:
        with pytest.raises(FmiError) as e:
            s.set_params({name: value})
        assert e.value.status == 3  # fmi2Error
        text = " ".join(s.messages)
        for w in words:
            assert w in text, (w, text)
    finally:
        s.free()


def test_rotor_speed_input_out_of_range(contact):
    s = contact.instance("bad", {"frictionModel": 1})
    try:
        with pytest.raises(FmiError) as e:
            s.set_inputs({"rotorSpeed": -5.0})
        assert e.value.status == 3
        assert any("rotorSpeed" in m and "-5" in m for m in s.messages), s.messages
    finally:
        s.free()


def test_state_round_trip(contact):
    """An FMU state taken mid-run continues bit-identically."""
    s = contact.instance("st", {})
    try:
        f = lambda x: harmonic_derivs(x, TWO_HARMONICS, 0.1 * D)  # noqa: E731
        for k in range(50):
            D_ = f(k * H)
            s.set_inputs({"displacementA": D_[0], "velocityA": D_[1]}, {"displacementA": D_[1:9]})
            s.step(k * H, H)
        st = s.s.get_fmu_state()
        runs = []
        for _ in range(2):
            s.s.set_fmu_state(st)
            out = []
            for k in range(50, 90):
                D_ = f(k * H)
                s.set_inputs({"displacementA": D_[0], "velocityA": D_[1]}, {"displacementA": D_[1:9]})
                out.append(s.get(OUT))
                s.step(k * H, H)
            runs.append(out)
        s.s.free_fmu_state(st)
        assert runs[0] == runs[1]
    finally:
        s.free()


def test_inputs_carried_on_without_a_new_set(contact):
    """A master that sets values only and reads before setting again (libcosim) sees the state at
    the step's end: u moved along the velocities, no back-and-forth path (no extra dissipation)."""
    s = contact.instance("c", {})
    try:
        s.set_inputs({"displacementA": 2.5 * D, "velocityA": 0.02, "displacementB": -0.5 * D, "velocityB": -0.01})
        e = []
        for k in range(20):
            s.step(k * H, H)
            u, E = s.get(["relativeDisplacement", "dissipatedEnergy"])
            e.append(E)
            assert abs(u - (3 * D + 0.03 * (k + 1) * H)) <= 1e-15
        assert all(np.diff(e) >= 0.0) and e[-1] > 0.0  # slipping forward all the time
        # the same motion set explicitly at every point: the same forces and energy
        s2 = contact.instance("c2", {})
        try:
            for k in range(20):
                s2.set_inputs(
                    {
                        "displacementA": 2.5 * D + 0.02 * k * H,
                        "velocityA": 0.02,
                        "displacementB": -0.5 * D - 0.01 * k * H,
                        "velocityB": -0.01,
                    }
                )
                s2.step(k * H, H)
            s2.set_inputs(
                {
                    "displacementA": 2.5 * D + 0.02 * 20 * H,
                    "velocityA": 0.02,
                    "displacementB": -0.5 * D - 0.01 * 20 * H,
                    "velocityB": -0.01,
                }
            )
            a, b = s.get(["forceB", "dissipatedEnergy"]), s2.get(["forceB", "dissipatedEnergy"])
            assert np.allclose(a, b, rtol=1e-12, atol=0.0), (a, b)
        finally:
            s2.free()
    finally:
        s.free()


@pytest.mark.parametrize("seed", range(12))
def test_random_motions_and_parameters(contact, seed):
    """Seeded random two-harmonic motions (up to 900 Hz, offsets either side, start in or out of
    contact) and contact parameters (both regimes k_d tan g >< mu k_n): forces and energy equal the
    reference within 1e-7 (Taylor truncation (omega h)^9 / 9! <= 2e-8 at 900 Hz, h = 1e-4 s)."""
    rng = np.random.default_rng(seed)
    t = np.arange(161) * H
    terms = [
        (rng.uniform(0.5, 3) * D, 2 * math.pi * rng.uniform(100, 400), rng.uniform(0, 6.3)),
        (rng.uniform(0, 1) * D, 2 * math.pi * rng.uniform(300, 900), rng.uniform(0, 6.3)),
    ]
    off = rng.uniform(-1, 1) * D
    params = {
        "gamma": rng.uniform(0.3, 1.3),
        "mu": rng.uniform(0.05, 0.8),
        "kdRatio": rng.uniform(0.3, 1.0),
        "d": rng.uniform(0.5, 2) * D,
    }
    f = lambda x: harmonic_derivs(x, terms, off)  # noqa: E731
    r = run_fmu(contact, params, t, f)
    assert_opposite(r)
    ref = JenkinsPair(params).evaluate(Motion(lambda x: f(x)[0], lambda x: f(x)[1]), t, H / 20)
    fmax = max(np.abs(ref["forceB"]).max(), 1e-9)
    for i, k in enumerate(OUT[:4]):
        assert np.abs(r[:, i] - ref[k]).max() <= 1e-7 * fmax, k
    E = ref["dissipatedEnergy"]
    assert np.abs(r[:, 4] - E).max() <= 1e-7 * max(E[-1], 1e-15)


START_MOTION = [(2.2 * D, W, math.pi / 2), (0.4 * D, 3 * W, 0.3)]  # u(0) = 2.3 d + 0.4 d sin 0.3: closed


@pytest.mark.parametrize("share", [0.6, -0.95])
def test_start_friction_force_vs_reference(contact, share):
    """frictionForce's start value F0 (a fraction of the cone at u(0)): the FMU against the reference
    started with F_f = F0 in stick (its state is F_f itself, not the slider); same tolerances as the
    harmonic runs above."""
    t = np.arange(241) * H
    f = lambda x: harmonic_derivs(x, START_MOTION, 0.1 * D)  # noqa: E731
    u0 = f(0.0)[0]
    F0 = share * 0.33 * 1e7 * math.cos(math.pi / 3) * (abs(u0) - D)
    r = run_fmu(contact, {"frictionForce": F0}, t, f)
    assert abs(r[0, 3] - F0) <= 1e-12 * abs(F0)  # the start state holds F0
    ref = JenkinsPair({}, F0=F0).evaluate(Motion(lambda x: f(x)[0], lambda x: f(x)[1]), t, H / 20)
    fmax = np.abs(ref["forceB"]).max()
    for i, k in enumerate(OUT[:4]):
        assert np.abs(r[:, i] - ref[k]).max() <= 1e-8 * fmax, k
    assert np.abs(r[:, 4] - ref["dissipatedEnergy"]).max() <= 1e-8 * max(ref["dissipatedEnergy"][-1], 1e-12)
    # and the unloaded start differs (the start value is used)
    r0 = run_fmu(contact, {}, t[:2], f)
    assert abs(r0[0, 3]) == 0.0


@pytest.mark.parametrize(
    "params,u0,words",
    [
        ({"frictionModel": 1, "frictionForce": 5.0}, 3 * D, ["frictionForce = 5", "frictionModel", "[0, 0]"]),
        ({"frictionForce": 5.0}, 0.5 * D, ["frictionForce = 5", "open", "[0, 0]"]),
        ({"frictionForce": -200.0}, 2 * D, ["frictionForce = -200", "cone", "[-49.5", "49.5"]),
    ],
)
def test_start_friction_force_refused(contact, params, u0, words):
    """A start value that does not fit the start state is an error at the end of initialization,
    naming the value and the accepted range (cone: 0.33 * 1e7 * cos(60 deg) * (2 d - d) = 49.5 N)."""
    with pytest.raises(FmiError) as e:
        s = contact.instance("bad", params, inputs={"displacementA": u0, "displacementB": 0.0})
        s.free()
    text = str(e.value)
    for w in words:
        assert w in text, (w, text)
