"""The BladeExternalContact FMU: the blade of ShroudedBlade with the contact force as an input.

- contactForce = 0 (never set, or set to 0 every step): bit-identical to ShroudedBlade with the
  contact open (d = 1 m) and no amplitude events (amplitudeMode 1), same communication points and
  inputs: the same RK4 over the same dynamics (FrictionNone);
- a constant contactForce F0 (no aero load): the steady deflection equals F0 / K0(Omega) of the
  independent Galerkin reference (harness.reference.galerkin; 1e-9 relative after 40 decay times);
- energy balance with a time-varying force and no aero load at constant speed: the work of the
  contact force (output contactWork, integrated by the FMU) equals M q'^2/2 + K0 q^2/2 + viscous
  dissipation, with M, K0 of the reference (RK4 at maxStep 1e-6: 1e-9 of the work's scale);
- input derivatives of contactForce are used: a ramp given as value + slope equals the same ramp
  set at 10x finer communication points to 1e-9 (held: first order, 1e-3 off);
- an invalid parameter gives fmi2Error with a message naming it.
"""

from __future__ import annotations

import math

import numpy as np
import pytest

from harness.fmu.binding import FmiError
from harness.fmu.build import FMU_PATH, build
from harness.fmu.slave import Unpacked, build_ring_fmus
from harness.reference import galerkin

H = 1e-4
OUT = ["tipDisplacement", "tipVelocity", "dissipatedEnergy"]

NO_BUILTIN_LOAD = {"Fw0": 0.0}  # these tests drive aeroLoad themselves: the built-in load is off


@pytest.fixture(scope="module")
def fmus():
    bx, _ = build_ring_fmus()
    build(("fmu",))
    with Unpacked(bx) as b, Unpacked(FMU_PATH) as sb:
        yield b, sb


def drive(s, n: int, h: float, force=None, force_slope=None, speed: float = 5000.0, fw0: float = 100.0):
    rows = []
    for k in range(n):
        t = k * h
        s.set_inputs({"aeroLoad": fw0 * math.sin(2 * math.pi * 250 * t), "rotorSpeed": speed})
        if force is not None:
            s.set_inputs(
                {"contactForce": force(t)}, {"contactForce": [force_slope(t)]} if force_slope is not None else None
            )
        s.step(t, h)
        rows.append(s.get(OUT + (["contactWork"] if "contactWork" in s.u.vars else [])))
    return np.array(rows)


@pytest.mark.parametrize("set_zero", [False, True])
@pytest.mark.parametrize("formulation", [1, 2])
def test_zero_force_equals_open_blade_bit_for_bit(fmus, set_zero, formulation):
    bx, sb = fmus
    a = sb.instance(
        "sb", {**NO_BUILTIN_LOAD, "d": 1.0, "amplitudeMode": 1, "formulation": formulation, "maxStep": 3e-5}
    )
    b = bx.instance("bx", {**NO_BUILTIN_LOAD, "formulation": formulation, "maxStep": 3e-5})
    try:
        ra = drive(a, 1500, H)
        rb = drive(b, 1500, H, force=(lambda t: 0.0) if set_zero else None)
    finally:
        a.free()
        b.free()
    assert np.abs(ra[:, 0]).max() > 1e-4  # it moved
    assert np.array_equal(ra, rb[:, :3])
    assert np.all(rb[:, 3] == 0.0)


def test_constant_force_static_deflection(fmus):
    bx, _ = fmus
    F0, n = 25.0, 5000.0
    g = galerkin({})
    K0 = g.K0(2 * math.pi * n / 60)
    tau = 2 * g.M / g.C0  # amplitude decay time [s]
    s = bx.instance("bx", NO_BUILTIN_LOAD)
    try:
        r = drive(s, int(40 * tau / 1e-3), 1e-3, force=lambda t: F0, speed=n, fw0=0.0)
    finally:
        s.free()
    assert abs(r[-1, 0] - F0 / K0) <= 1e-9 * F0 / K0


def test_contact_work_energy_balance(fmus):
    bx, _ = fmus
    n = 3000.0
    g = galerkin({})
    K0 = g.K0(2 * math.pi * n / 60)
    f = lambda t: 40.0 * math.sin(2 * math.pi * 180 * t) + 15.0 * math.cos(2 * math.pi * 410 * t)  # noqa: E731
    df = lambda t: (
        40.0 * 2 * math.pi * 180 * math.cos(2 * math.pi * 180 * t)
        - 15.0 * 2 * math.pi * 410 * math.sin(2 * math.pi * 410 * t)
    )  # noqa: E731
    s = bx.instance("bx", {**NO_BUILTIN_LOAD, "maxStep": 1e-6})
    try:
        r = drive(s, 600, H, force=f, force_slope=df, speed=n, fw0=0.0)
    finally:
        s.free()
    q, v, E, W = r.T
    stored = 0.5 * g.M * v**2 + 0.5 * K0 * q**2
    scale = np.abs(W).max() + E.max()
    assert E[-1] > 0 and scale > 0
    assert np.abs(W - (stored + E)).max() <= 1e-9 * scale


def test_force_derivative_is_used(fmus):
    bx, _ = fmus
    slope = 2e4  # [N/s]
    runs = {}
    for name, h, use in (("slope", 1e-3, True), ("held", 1e-3, False), ("fine", 1e-4, True)):
        s = bx.instance("bx", {**NO_BUILTIN_LOAD, "maxStep": 1e-5})
        try:
            r = drive(
                s,
                round(0.02 / h),
                h,
                force=lambda t: slope * t,
                force_slope=(lambda t: slope) if use else None,
                fw0=0.0,
            )
        finally:
            s.free()
        runs[name] = r[-1, 0]
    ref = runs["fine"]
    assert abs(runs["slope"] - ref) <= 1e-9 * abs(ref)
    assert abs(runs["held"] - ref) >= 1e-3 * abs(ref)


def test_invalid_parameter_message(fmus):
    bx, _ = fmus
    s = bx.instance("bad", initialize=False)
    try:
        with pytest.raises(FmiError) as e:
            s.set_params({"maxStep": 1.0})
        assert e.value.status == 3
        assert any("maxStep" in m and "1e-08" in m for m in s.messages), s.messages
    finally:
        s.free()


def test_second_force_input_adds(fmus):
    """contactForce2 (a ring's other contact, for masters that cannot add) adds to contactForce:
    F split as 30 % + 70 % equals F in contactForce alone to rounding (1e-13 of max |q|)."""
    bx, _ = fmus
    f = lambda t: 40.0 * math.sin(2 * math.pi * 180 * t)  # noqa: E731
    out = []
    for split in (False, True):
        s = bx.instance("bx", NO_BUILTIN_LOAD)
        try:
            rows = []
            for k in range(300):
                t = k * H
                s.set_inputs(
                    {
                        "aeroLoad": 0.0,
                        "rotorSpeed": 5000.0,
                        "contactForce": 0.3 * f(t) if split else f(t),
                        "contactForce2": 0.7 * f(t) if split else 0.0,
                    }
                )
                s.step(t, H)
                rows.append(s.get(["tipDisplacement", "contactWork"]))
        finally:
            s.free()
        out.append(np.array(rows))
    scale = np.abs(out[0]).max(axis=0)
    assert scale[0] > 1e-6
    assert np.all(np.abs(out[0] - out[1]) <= 1e-13 * scale)
