"""FMI 2.0 model exchange of build/ShroudedBlade.fmu (fmu_src/fmi/fmi2_me.c over
fmu_src/models/ShroudedBlade/model_me.c): fmpy validates the FMU, integrates it with its CVode and Euler
solvers, and the results equal the co-simulation FMU's; invalid model-exchange calls answer
fmi2Error (or fmi2Discard) with a message.

Measured (this file's scenarios, 0.05 s of free vibration from q0 = 1.5e-4 m at 5000 rpm, maximum
over the samples relative to the largest |value|): CVode at relative tolerance 1e-10 against the CS
FMU at maxStep = 2.5e-6 s differ by <= 6e-7 in tipDisplacement and tipVelocity (CVode's global
error: CS at 2.5e-6 s is within 3e-9 of CS at 2.5e-7 s, CVode at 1e-12 within 1.3e-8), the
energy, tracked amplitude and running maximum by <= 5e-7; the run-up (4000 -> 6000 rpm in 30 ms)
differs by 4e-4 in q and 7e-5 in the tracked amplitudes, from fmpy's inputs (ME: held between solver
steps and set at every root-finding evaluation, CS: held over each communication step). Euler
(step 2e-7 s, one period) is within 0.4 %.
"""

from __future__ import annotations

import ctypes
from ctypes import c_int

import numpy as np
import pytest
from fmpy import simulate_fmu
from fmpy.validation import validate_fmu

from tests.support.fmi2me import NX, NZ, EventInfo, Me, arr
from tests.support.fmi2raw import CO_SIMULATION, DISCARD, ERROR, MODEL_EXCHANGE, OK, VR, Instance

OUT = [
    "tipDisplacement",
    "tipVelocity",
    "dissipatedEnergy",
    "amplitude",
    "runningMaximum",
    "jenkinsForce",
    "contactState",
]
FREE = dict(tipDisplacement=1.5e-4, aeroLoad=100.0, rotorSpeed=5000.0)
# output interval incommensurate with the excitation period (4 ms at 5000 rpm, engine order 3): a
# period end on a sample point would be sampled before its event by one solver, after by the other
DT = 1.3e-4

SCENARIOS = {
    "macroslip DF, gated, tracked": dict(frictionModel=1),
    "Coulomb DF, gated, tracked": dict(frictionModel=2),
    "Jenkins element, tracked": dict(frictionModel=3),
    "macroslip DF, ungated, tracked": dict(frictionModel=1, gating=False),
    "Jenkins element, fixed amplitude": dict(frictionModel=3, amplitudeMode=1),
    "Coulomb DF, ungated, fixed amplitude": dict(frictionModel=2, gating=False, amplitudeMode=1),
}


def _rel(a: np.ndarray, b: np.ndarray) -> float:
    n = min(len(a), len(b))
    return float(np.max(np.abs(a[:n] - b[:n])) / max(np.max(np.abs(a[:n])), 1e-300))


def _cs(fmu_path, start, stop, dt=DT, **kw):
    return simulate_fmu(
        str(fmu_path),
        fmi_type="CoSimulation",
        stop_time=stop,
        output_interval=dt,
        start_values=dict(start, maxStep=2.5e-6, Fw0=0.0),
        output=OUT,
        **kw,
    )


def _me(fmu_path, start, stop, solver="CVode", dt=DT, **kw):
    return simulate_fmu(
        str(fmu_path),
        fmi_type="ModelExchange",
        solver=solver,
        stop_time=stop,
        output_interval=dt,
        start_values=dict(start, Fw0=0.0),
        output=OUT,
        record_events=False,
        **kw,
    )


def test_validate_fmu_clean(fmu_path) -> None:
    assert validate_fmu(str(fmu_path)) == []


@pytest.mark.parametrize("name", list(SCENARIOS))
def test_cvode_equals_cs(fmu_path, name) -> None:
    start = dict(FREE, **SCENARIOS[name])
    cs = _cs(fmu_path, start, 0.05)
    me = _me(fmu_path, start, 0.05, relative_tolerance=1e-10)
    for k in ("tipDisplacement", "tipVelocity"):
        assert _rel(cs[k], me[k]) < 2e-6, (k, _rel(cs[k], me[k]))
    for k in ("dissipatedEnergy", "amplitude", "runningMaximum", "jenkinsForce"):
        if np.any(cs[k] != 0.0):
            assert _rel(cs[k], me[k]) < 2e-6, (k, _rel(cs[k], me[k]))
        else:
            assert np.all(me[k][: len(cs)] == 0.0), k
    n = min(len(cs), len(me))
    assert np.sum(cs["contactState"][:n] != me["contactState"][:n]) <= 1
    if start.get("amplitudeMode", 2) == 2:  # the tracked amplitude moved at the period ends
        assert len(set(cs["amplitude"])) > 3 and len(set(me["amplitude"])) > 3


def test_cvode_run_up_equals_cs(fmu_path) -> None:
    """rotorSpeed 4000 -> 6000 rpm in 30 ms under a constant load (fmpy interpolates the table)."""
    t = np.linspace(0.0, 0.03, 31)
    signal = np.array(
        list(zip(t, np.full_like(t, 100.0), 4000.0 + 2000.0 * t / 0.03)),
        dtype=[("time", float), ("aeroLoad", float), ("rotorSpeed", float)],
    )
    start = dict(tipDisplacement=1.5e-4, frictionModel=1)
    cs = _cs(fmu_path, start, 0.03, dt=2e-5, input=signal)
    me = _me(fmu_path, start, 0.03, dt=2e-5, input=signal, relative_tolerance=1e-10)
    assert _rel(cs["tipDisplacement"], me["tipDisplacement"]) < 1e-3
    # the tracked amplitude, period by period (a period end near a sample point may fall on
    # either side of it)
    a_cs, a_me = np.unique(cs["amplitude"]), np.unique(me["amplitude"])
    assert len(a_cs) == len(a_me) > 3
    assert np.max(np.abs(a_cs - a_me) / a_cs) < 1e-3


@pytest.mark.parametrize("friction", [1, 3])
def test_euler_equals_cs(fmu_path, friction) -> None:
    """Forward Euler (first order): one excitation period with steps of 2e-7 s (fmpy's Euler steps
    from output point to output point)."""
    start = dict(FREE, frictionModel=friction)
    cs = _cs(fmu_path, start, 0.004, dt=1e-4)
    me = _me(fmu_path, start, 0.004, solver="Euler", dt=2e-7, step_size=2e-7)
    q = np.interp(cs["time"], me["time"], me["tipDisplacement"])
    err = _rel(cs["tipDisplacement"], q)
    assert 1e-5 < err < 1e-2  # first order: visibly different, but within its tolerance


# ---------------------------------------------------------------------------------------------
# the raw API: call sequence, arguments, consistency with the variables

_arr = arr


def _error(inst: Instance, status: int, *fragments: str, expected: int = ERROR) -> None:
    assert status == expected, (status, [str(r) for r in inst.log[-3:]])
    msg = inst.log[-1].message or ""
    assert all(f in msg for f in fragments), msg


def _started(lib, **params) -> Instance:
    inst = Instance(lib, name="me", fmu_type=MODEL_EXCHANGE)
    assert inst.ok
    assert inst.setup() == OK and inst.enter_init() == OK
    for k, v in params.items():
        assert inst.set_real([k], [v]) == OK
    assert inst.exit_init() == OK
    return inst


def test_me_sequence_and_variables(lib) -> None:
    me = Me(lib)
    inst = _started(lib, tipDisplacement=1.5e-4)
    try:
        info = EventInfo()
        assert me.new_discrete(inst.c, ctypes.byref(info)) == OK and not info.newDiscreteStatesNeeded
        assert me.enter_ct(inst.c) == OK
        x, dx, z, nom = _arr(NX), _arr(NX), _arr(NZ), _arr(NX)
        assert me.get_x(inst.c, x, NX) == OK and x[0] == 1.5e-4 and x[2] == 0.0
        assert me.get_dx(inst.c, dx, NX) == OK and dx[0] == x[1]
        assert me.nominals(inst.c, nom, NX) == OK and all(v > 0.0 for v in nom)
        status, der = inst.get_real(
            [
                "der(tipDisplacement)",
                "der(tipVelocity)",
                "der(excitationPhase)",
                "der(dissipatedEnergy)",
                "der(sliderPosition)",
            ]
            + [f"der(modalDisplacement[{k}])" for k in range(2, 7)]
            + [f"der(modalVelocity[{k}])" for k in range(2, 7)]
        )
        assert status == OK and list(der) == list(dx)
        assert NX == 15 and not any(dx[5:])  # the modal states of modes 2..6 held at 0 (modes = 1)
        # 5000 rpm, engine order 3: omega = 2 pi 250 rad/s
        assert dx[2] == pytest.approx(2 * np.pi * 250.0, rel=1e-15)
        assert me.get_z(inst.c, z, NZ) == OK
        assert z[0] == pytest.approx(1.5e-4 - 3e-5)  # gate on at q0 > d: sigma q - d
        x[0] = 2e-5  # inside the gap: the gate's switching function is negative now
        assert me.set_x(inst.c, x, NX) == OK
        assert me.get_z(inst.c, z, NZ) == OK and z[0] < 0.0
        enter, term = c_int(1), c_int(1)
        assert me.completed(inst.c, 1, ctypes.byref(enter), ctypes.byref(term)) == OK
        assert enter.value == 0 and term.value == 0
        assert me.enter_event(inst.c) == OK
        status, keq = inst.get_real(["Keq"])
        assert status == OK and keq[0] > 0.0  # gate still on: the switch happens in event mode
        assert me.new_discrete(inst.c, ctypes.byref(info)) == OK  # a state set across the gate
        status, keq = inst.get_real(["Keq"])
        assert status == OK and keq[0] == 0.0  # gate off
        assert me.get_z(inst.c, z, NZ) == OK and z[0] > 0.0 and z[1] > 0.0  # d -+ q
        assert me.enter_ct(inst.c) == OK
        assert me.set_time(inst.c, 1e-3) == OK
        assert inst.terminate() == OK
    finally:
        inst.free()


def test_invalid_me_calls(lib) -> None:
    me = Me(lib)
    x = _arr(NX)
    inst = Instance(lib, name="me", fmu_type=MODEL_EXCHANGE)
    try:
        _error(inst, me.get_dx(inst.c, x, NX), "fmi2GetDerivatives: Illegal call sequence (state: instantiated)")
        assert me.nominals(inst.c, x, NX) == OK  # allowed before initialization (from the parameters)
        assert inst.setup() == OK and inst.enter_init() == OK and inst.exit_init() == OK  # -> eventMode
        _error(inst, me.do_step(inst.c, 0.0, 1e-4, 1), "fmi2DoStep: not available", "fmuType = fmi2ModelExchange")
        _error(inst, me.set_x(inst.c, x, NX), "fmi2SetContinuousStates: Illegal call sequence (state: eventMode)")
        _error(inst, me.completed(inst.c, 1, None, None), "Illegal call sequence (state: eventMode)")
        _error(inst, me.get_x(inst.c, x, 4), "fmi2GetContinuousStates: nx = 4, but this FMU has 15")
        _error(inst, me.get_z(inst.c, _arr(NZ), 5), f"fmi2GetEventIndicators: ni = 5, but this FMU has {NZ}")
        _error(inst, me.get_dx(inst.c, None, NX), "fmi2GetDerivatives: NULL array argument")
        _error(inst, me.new_discrete(inst.c, None), "fmi2NewDiscreteStates: fmi2eventInfo is NULL")
        _error(inst, me.set_time(inst.c, float("nan")), "fmi2SetTime: time = nan s is not a finite number")
        _error(inst, inst.set_real(["kn"], [1e6]), "parameter kn (vr 7) has variability fixed")
        _error(inst, inst.set_real(["der(tipVelocity)"], [1.0]), "der(tipVelocity) (vr 81) is a calculated variable")
        assert me.enter_ct(inst.c) == OK
        assert me.get_x(inst.c, x, NX) == OK
        bad = _arr(NX)
        bad[3] = float("inf")
        _error(inst, me.set_x(inst.c, bad, NX), "x[3] = inf is not finite", expected=DISCARD)
        after = _arr(NX)
        assert me.get_x(inst.c, after, NX) == OK and list(after) == list(x)  # unchanged
        _error(
            inst,
            me.new_discrete(inst.c, ctypes.byref(EventInfo())),
            "fmi2NewDiscreteStates: Illegal call sequence (state: continuousTimeMode)",
        )
        assert inst.set_real(["rotorSpeed"], [6000.0]) == OK  # inputs: also in continuous-time mode
    finally:
        inst.free()
    cs = Instance(lib, name="cs", fmu_type=CO_SIMULATION)
    try:
        assert cs.setup() == OK and cs.enter_init() == OK and cs.exit_init() == OK
        _error(cs, me.get_dx(cs.c, x, NX), "fmi2GetDerivatives: not available", "fmuType = fmi2CoSimulation")
        _error(cs, me.enter_event(cs.c), "fmi2EnterEventMode: not available")
    finally:
        cs.free()
    assert VR["der(sliderPosition)"] == 84


def test_me_fmu_state(lib) -> None:
    """FMU state copies of a model-exchange instance: the continuous and discrete state come back;
    an in-memory copy restores its mode, a deserialized one comes back in continuous-time mode."""
    me = Me(lib)
    inst = _started(lib, tipDisplacement=1.5e-4)
    try:
        info = EventInfo()
        st, in_event = inst.get_state()
        assert st == OK
        assert me.new_discrete(inst.c, ctypes.byref(info)) == OK and me.enter_ct(inst.c) == OK
        x0 = _arr(NX)
        assert me.get_x(inst.c, x0, NX) == OK
        st, h = inst.get_state()
        st2, blob = inst.serialize(h)
        assert st == OK and st2 == OK
        x1 = _arr(NX)
        x1[0], x1[1] = 2e-5, -1.0  # across the gate: the next event iteration switches it off
        assert me.set_time(inst.c, 1e-4) == OK and me.set_x(inst.c, x1, NX) == OK
        assert me.enter_event(inst.c) == OK and me.new_discrete(inst.c, ctypes.byref(info)) == OK
        assert inst.get_real(["Keq"])[1][0] == 0.0
        assert inst.set_state(h) == OK
        x = _arr(NX)
        assert me.get_x(inst.c, x, NX) == OK and list(x) == list(x0)
        assert inst.get_real(["Keq"])[1][0] > 0.0  # the gate is on again
        assert me.set_x(inst.c, x, NX) == OK  # continuous-time mode, as when the copy was taken
        st, h2 = inst.deserialize(blob)
        assert st == OK and inst.set_state(h2) == OK
        assert me.set_x(inst.c, x, NX) == OK  # a deserialized state: continuous-time mode
        assert inst.set_state(in_event) == OK  # event mode again
        assert me.new_discrete(inst.c, ctypes.byref(info)) == OK
        for handle in (in_event, h, h2):
            assert inst.free_state(handle) == OK
    finally:
        inst.free()


def test_getters_in_initialization_mode(lib) -> None:
    """FMI 2.0 s.3.2.3: the states, their derivatives and the event indicators can be read in
    initialization mode (initial unknowns), like fmi2GetReal; they follow the start values set there."""
    me = Me(lib)
    inst = Instance(lib, name="me", fmu_type=MODEL_EXCHANGE)
    try:
        assert inst.setup() == OK and inst.enter_init() == OK
        assert inst.set_real(["tipDisplacement", "tipVelocity"], [1.5e-4, -0.25]) == OK
        x, dx, z = _arr(NX), _arr(NX), _arr(NZ)
        assert me.get_x(inst.c, x, NX) == OK, inst.log_text()
        assert (x[0], x[1]) == (1.5e-4, -0.25)
        assert me.get_dx(inst.c, dx, NX) == OK, inst.log_text()
        assert dx[0] == -0.25  # dq/dt = q'
        assert me.get_z(inst.c, z, NZ) == OK, inst.log_text()
        st, q = inst.get_real(["tipDisplacement"])
        assert st == OK and q[0] == 1.5e-4
        assert inst.exit_init() == OK
        assert me.get_x(inst.c, x, NX) == OK and (x[0], x[1]) == (1.5e-4, -0.25)
    finally:
        inst.free()


def _loop_angles(
    B: float,
    d: float = 3e-5,
    kn: float = 1e7,
    kd_ratio: float = 0.608695652173913,
    mu: float = 0.33,
    gamma: float = np.pi / 3,
) -> tuple[float, float, float]:
    """th1, th2, th3 of the macroslip loop (docs/model.md eq. 5, written here from the doc's
    versine forms): 1 - cos th1 = 2 b r/(a + b), 1 - cos th2 = r, 1 + cos th3 = (a - b) r/a."""
    a, b, r = kd_ratio * kn * np.sin(gamma), mu * kn * np.cos(gamma), (B - d) / B
    return (np.arccos(1 - 2 * b * r / (a + b)), np.arccos(1 - r), np.arccos((a - b) * r / a - 1))


def test_contact_state_changes_only_at_events(lib) -> None:
    """contactState is declared discrete: in model exchange the describing-function loop state
    (which follows the phase theta = atan2(-q'/omega, q)) changes at events only. A state moved
    in continuous-time mode from the stick interval [0, th1) into the slip interval [th1, th2)
    leaves contactState at stick, an event indicator changes sign, and the event switches it."""
    B, omega = 6e-5, 3 * 2 * np.pi * 5000 / 60
    th1, th2, _ = _loop_angles(B)
    R = B  # |q| = R cos(theta) > d on both sides

    def state(theta):
        return R * np.cos(theta), -omega * R * np.sin(theta)

    me = Me(lib)
    q0, v0 = state(th1 / 2)
    inst = Instance(lib, name="me", fmu_type=MODEL_EXCHANGE)
    try:
        assert inst.setup() == OK and inst.enter_init() == OK
        assert inst.set_integer(["frictionModel", "amplitudeMode"], [1, 1]) == OK
        assert inst.set_real(["tipDisplacement", "tipVelocity", "B"], [q0, v0, B]) == OK
        assert inst.exit_init() == OK
        info = EventInfo()
        assert me.new_discrete(inst.c, ctypes.byref(info)) == OK and me.enter_ct(inst.c) == OK
        assert inst.get_integer(["contactState"])[1][0] == 1  # stick
        x, z0, z1 = _arr(NX), _arr(NZ), _arr(NZ)
        assert me.get_x(inst.c, x, NX) == OK and me.get_z(inst.c, z0, NZ) == OK
        x[0], x[1] = state((th1 + th2) / 2)
        assert me.set_x(inst.c, x, NX) == OK and me.get_z(inst.c, z1, NZ) == OK
        assert any(a * b < 0 for a, b in zip(z0, z1)), "no event indicator saw the stick -> slip switch"
        assert inst.get_integer(["contactState"])[1][0] == 1  # held until the event
        assert me.enter_event(inst.c) == OK and me.new_discrete(inst.c, ctypes.byref(info)) == OK
        assert inst.get_integer(["contactState"])[1][0] == 2  # slip
    finally:
        inst.free()
