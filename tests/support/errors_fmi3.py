"""The FMI 3.0 co-simulation rows of the invalid-input catalogue (tests/fmu/test_fmu_errors.py): the
entry points of build/fmi3/ShroudedBlade.fmu (fmi3InstantiateCoSimulation and the other
instantiation functions, fmi3Set/GetFloat64/Int32/Boolean, fmi3DoStep, the FMU state functions)
with bad arguments, unknown and undeclared value references, NaN and out-of-range values, wrong
communication points and calls in the wrong state, as the FMI 2.0 rows do for fmi2*. Driven through
tests/support/fmi3raw.py; the expectations come from the FMI 3.0 standard (s.4.3 state machine, s.2.3),
modelDescription3.xml and docs/model-notes.md."""

from __future__ import annotations

import ctypes
import math
from typing import Callable

from tests.support import fmi2raw as F
from tests.support.catalogue import NULL_INSTANCE, Case, Outcome, _sequence
from tests.support.fmi3raw import TOKEN, VR3, Fmi3Library, Instance3

K = "FMI 3.0 "  # group prefix


def _outcome(st: int, call: str, c: Instance3 | None) -> Outcome:
    return Outcome(st, call, list(c.log) if c else [], face="fmi3")


def ready(state: str = "Step Mode", params: dict | None = None) -> Instance3:
    """A fresh FMI 3.0 instance driven into `state` with valid calls (asserted OK)."""
    c = Instance3(Fmi3Library.get())
    assert c.ok, c.log
    steps: list[Callable[[], int]] = []
    if state != "Instantiated":
        steps.append(c.enter_init)
        if params:
            steps.append(lambda: c.set_params(params))
    if state in ("Step Mode", "Terminated"):
        steps.append(c.exit_init)
    if state == "Terminated":
        steps.append(c.terminate)
    for f in steps:
        assert f() == F.OK, c.log
    c.clear_log()
    return c


def _case(
    kind: str,
    label: str,
    call: str,
    fn: Callable[[Instance3], int],
    state: str = "Step Mode",
    expect: str = "refuse",
    params: dict | None = None,
    **kw,
) -> Case:
    def run(lib) -> Outcome:  # noqa: ANN001 (the FMI 2.0 library of the catalogue: unused)
        with ready(state, params) as c:
            return _outcome(fn(c), call, c)

    return Case(K + kind, f"{label} (in {state})", run, expect, **kw)


def instantiate_cases() -> list[Case]:
    def inst(label: str, expect: str = "refuse", needle: str | None = None, **kw) -> Case:
        def run(lib) -> Outcome:  # noqa: ANN001
            c = Instance3(Fmi3Library.get(), **kw)
            try:
                if not c.ok:
                    return _outcome(NULL_INSTANCE, "fmi3InstantiateCoSimulation", c)
                out = _sequence(
                    c,
                    [
                        ("fmi3EnterInitializationMode", c.enter_init),
                        ("fmi3ExitInitializationMode", c.exit_init),
                        ("fmi3DoStep x5", lambda: max(c.do_step(i * 1e-4, 1e-4) for i in range(5))),
                    ],
                )
                out.face = "fmi3"
                out.call = "instantiate + initialize + 5 steps" if out.status == F.OK else out.call
                return out
            finally:
                c.free()

        return Case(K + "instantiate", label, run, expect, needle=needle)

    def other(fn: str, call: Callable[[ctypes.CDLL], int]) -> Case:
        def run(lib) -> Outcome:  # noqa: ANN001
            log: list = []
            return Outcome(NULL_INSTANCE if not call(Fmi3Library.get().dll) else F.OK, fn, log, face="fmi3")

        return Case(K + "instantiate", f"{fn} (a co-simulation FMU)", run)

    L3 = ctypes.CFUNCTYPE(None, ctypes.c_void_p, ctypes.c_int, ctypes.c_char_p, ctypes.c_char_p)
    silent = L3(lambda *a: None)
    return [
        inst("wrong instantiationToken", token="{00000000-0000-0000-0000-000000000000}", needle="instantiationToken"),
        inst("instantiationToken = NULL", token=None),
        inst("instanceName = '' (empty)", name=""),
        inst("instanceName = NULL", name=None),
        inst("eventModeUsed = true (hasEventMode false)", event_mode_used=True, needle="eventModeUsed"),
        inst("requiredIntermediateVariables given", required=[50], needle="requiredIntermediateVariables"),
        inst("logMessage = NULL", expect="accept", logger=False),
        inst("loggingOn = false", expect="accept", logging_on=False),
        other(
            "fmi3InstantiateModelExchange",
            lambda dll: dll.fmi3InstantiateModelExchange(
                b"x", TOKEN.encode(), None, False, True, None, ctypes.cast(silent, ctypes.c_void_p)
            ),
        ),
    ]


def order_cases() -> list[Case]:
    step = lambda c: c.do_step(0.0, 1e-4)  # noqa: E731
    k = "call order"
    cases = [
        _case(k, "fmi3DoStep", "fmi3DoStep", step, s, needle="Illegal call sequence")
        for s in ("Instantiated", "Initialization Mode", "Terminated")
    ]
    cases += [
        _case(k, "fmi3ExitInitializationMode", "fmi3ExitInitializationMode", lambda c: c.exit_init(), "Instantiated"),
        _case(
            k,
            "fmi3EnterInitializationMode twice",
            "fmi3EnterInitializationMode",
            lambda c: c.enter_init(),
            "Initialization Mode",
        ),
        _case(k, "fmi3EnterInitializationMode", "fmi3EnterInitializationMode", lambda c: c.enter_init()),
        _case(k, "fmi3GetFloat64 of an output", "fmi3GetFloat64", lambda c: c.get_float64([50])[0], "Instantiated"),
        _case(k, "fmi3Terminate", "fmi3Terminate", lambda c: c.terminate(), "Instantiated"),
        _case(k, "fmi3Terminate twice", "fmi3Terminate", lambda c: c.terminate(), "Terminated"),
        _case(
            k,
            "set fixed Float64 parameter EI = 300",
            "fmi3SetFloat64",
            lambda c: c.set_float64(["EI"], [300.0]),
            name="EI",
        ),
        _case(
            k,
            "set fixed Int32 parameter frictionModel = 2",
            "fmi3SetInt32",
            lambda c: c.set_int32(["frictionModel"], [2]),
            name="frictionModel",
        ),
        _case(
            k,
            "set fixed Boolean parameter gating = false",
            "fmi3SetBoolean",
            lambda c: c.set_boolean(["gating"], [False]),
            name="gating",
        ),
        _case(k, "set input aeroLoad", "fmi3SetFloat64", lambda c: c.set_float64(["aeroLoad"], [1.0]), "Terminated"),
        _case(
            k,
            "fmi3EnterEventMode (hasEventMode false)",
            "fmi3EnterEventMode",
            lambda c: c.lib.fmi3EnterEventMode(c.c),
            needle="not supported",
        ),
        _case(k, "fmi3EnterStepMode (no event mode)", "fmi3EnterStepMode", lambda c: c.lib.fmi3EnterStepMode(c.c)),
        _case(k, "fmi3SetTime (model exchange)", "fmi3SetTime", lambda c: c.lib.fmi3SetTime(c.c, 0.0)),
        _case(
            k,
            "fmi3GetContinuousStates (model exchange)",
            "fmi3GetContinuousStates",
            lambda c: c.lib.fmi3GetContinuousStates(c.c, None, 0),
        ),
        _case(
            k,
            "fmi3UpdateDiscreteStates (no event mode)",
            "fmi3UpdateDiscreteStates",
            lambda c: c.lib.fmi3UpdateDiscreteStates(c.c, *([None] * 6)),
        ),
        _case(
            k,
            "fmi3GetOutputDerivatives (maxOutputDerivativeOrder 0)",
            "fmi3GetOutputDerivatives",
            lambda c: c.lib.fmi3GetOutputDerivatives(
                c.c, (ctypes.c_uint32 * 1)(50), 1, (ctypes.c_int32 * 1)(1), (ctypes.c_double * 1)(), 1
            ),
        ),
    ]

    def after_error(c: Instance3) -> int:
        assert c.do_step(0.5, 1e-4) == F.ERROR  # a wrong communication point
        c.clear_log()
        return c.do_step(0.0, 1e-4)

    cases.append(_case(k, "valid fmi3DoStep after a refused fmi3DoStep (error state)", "fmi3DoStep", after_error))
    return cases


def value_cases() -> list[Case]:
    """Parameters, start values and inputs: refused with a message naming variable, value, range."""
    cases = []

    def param(name: str, value: float, state: str = "Initialization Mode") -> Case:
        var = F.VARIABLES[name]
        setter = {"Real": "set_float64", "Integer": "set_int32"}[var.type]
        return _case(
            "value",
            f"{name} = {value!r}",
            f"fmi3Set{'Float64' if var.type == 'Real' else 'Int32'}",
            lambda c: getattr(c, setter)([name], [value]),
            state,
            name=name,
            value=float(value),
            low=var.low,
            high=var.high,
        )

    for name in F.REAL_PARAMS:
        cases.append(param(name, math.nan))
    cases += [param("EI", -1.0), param("maxStep", 1.0), param("gamma", 2.0), param("d", -1e-3)]
    cases += [param("frictionModel", v) for v in (0, 4)] + [param("engineOrder", 101)]
    cases += [param("rotorSpeed", v, "Step Mode") for v in (math.nan, -1.0, 30001.0, math.inf)]
    cases += [param("aeroLoad", v, "Step Mode") for v in (math.nan, -math.inf)]
    cases += [param("tipDisplacement", v) for v in (math.nan, math.inf)]
    return cases


def vr_cases() -> list[Case]:
    k = "value reference"
    undeclared = sorted(v.vr for v in F.VARIABLES.values() if v.name not in VR3)
    cases = [
        _case(
            k,
            f"fmi3GetFloat64 vr {vr} (not in modelDescription3.xml)",
            "fmi3GetFloat64",
            lambda c, vr=vr: c.get_float64([vr])[0],
            needle=f"unknown value reference {vr}",
        )
        for vr in undeclared + [999, 2**32 - 1]
    ]
    cases += [
        _case(
            k,
            f"fmi3SetFloat64 vr {vr}",
            "fmi3SetFloat64",
            lambda c, vr=vr: c.set_float64([vr], [1.0]),
            needle="unknown value reference",
        )
        for vr in (70, 999)
    ]
    cases += [
        _case(
            k,
            "fmi3SetFloat64 of time (vr 0)",
            "fmi3SetFloat64",
            lambda c: c.set_float64([0], [1.0]),
            needle="independent variable",
        ),
        _case(k, "fmi3GetInt32 of time (vr 0)", "fmi3GetInt32", lambda c: c.get_int32([0])[0], needle="time"),
        _case(
            k,
            "fmi3GetFloat64 of an Int32 (regime)",
            "fmi3GetFloat64",
            lambda c: c.get_float64(["regime"])[0],
            name="regime",
        ),
        _case(
            k,
            "fmi3GetInt32 of a Float64 (tipDisplacement)",
            "fmi3GetInt32",
            lambda c: c.get_int32(["tipDisplacement"])[0],
            name="tipDisplacement",
        ),
        _case(k, "fmi3GetBoolean of a Float64 (EI)", "fmi3GetBoolean", lambda c: c.get_boolean(["EI"])[0], name="EI"),
        _case(
            k,
            "fmi3GetInt64 (no Int64 variables)",
            "fmi3GetInt64",
            lambda c: c.get_int64(["frictionModel"])[0],
            name="frictionModel",
        ),
        _case(
            k,
            "fmi3SetFloat64 of an output (normalForce)",
            "fmi3SetFloat64",
            lambda c: c.set_float64(["normalForce"], [1.0]),
            name="normalForce",
        ),
        _case(
            k,
            "fmi3GetFloat64 nValues = 2 for one reference",
            "fmi3GetFloat64",
            lambda c: c.get_float64([50], n_values=2)[0],
            needle="nValues",
        ),
        _case(k, "good and bad vr in one fmi3GetFloat64", "fmi3GetFloat64", lambda c: c.get_float64([50, 999])[0]),
    ]
    return cases


def pointer_cases() -> list[Case]:
    k = "NULL pointer"
    one = ctypes.c_double()
    return [
        _case(
            k,
            "fmi3GetFloat64 values = NULL",
            "fmi3GetFloat64",
            lambda c: c.lib.fmi3GetFloat64(c.c, (ctypes.c_uint32 * 1)(50), 1, None, 1),
            needle="NULL",
        ),
        _case(
            k,
            "fmi3SetFloat64 valueReferences = NULL",
            "fmi3SetFloat64",
            lambda c: c.lib.fmi3SetFloat64(c.c, None, 1, ctypes.addressof(one), 1),
            needle="NULL",
        ),
        _case(
            k,
            "fmi3DoStep lastSuccessfulTime = NULL",
            "fmi3DoStep",
            lambda c: c.lib.fmi3DoStep(c.c, 0.0, 1e-4, True, *[ctypes.addressof(ctypes.c_bool())] * 3, None),
            needle="NULL",
        ),
        _case(
            k,
            "fmi3GetFMUState FMUState = NULL",
            "fmi3GetFMUState",
            lambda c: c.lib.fmi3GetFMUState(c.c, None),
            needle="NULL",
        ),
        _case(k, "fmi3SetFMUState FMUState = NULL", "fmi3SetFMUState", lambda c: c.set_state(None), needle="NULL"),
        _case(
            k,
            "fmi3SerializedFMUStateSize size = NULL",
            "fmi3SerializedFMUStateSize",
            lambda c: c.lib.fmi3SerializedFMUStateSize(c.c, c.get_state()[1], None),
            needle="NULL",
        ),
        _case(
            k,
            "fmi3DeserializeFMUState serializedState = NULL",
            "fmi3DeserializeFMUState",
            lambda c: c.deserialize(b"", 472)[0],
            needle="NULL",
        ),
    ]


def null_instance_cases() -> list[Case]:
    calls = {
        "fmi3EnterInitializationMode": lambda d: d.fmi3EnterInitializationMode(None, False, 0.0, 0.0, False, 0.0),
        "fmi3ExitInitializationMode": lambda d: d.fmi3ExitInitializationMode(None),
        "fmi3DoStep": lambda d: d.fmi3DoStep(None, 0.0, 1e-4, True, None, None, None, None),
        "fmi3GetFloat64": lambda d: d.fmi3GetFloat64(None, None, 0, None, 0),
        "fmi3SetInt32": lambda d: d.fmi3SetInt32(None, None, 0, None, 0),
        "fmi3GetFMUState": lambda d: d.fmi3GetFMUState(None, None),
        "fmi3Reset": lambda d: d.fmi3Reset(None),
        "fmi3Terminate": lambda d: d.fmi3Terminate(None),
    }

    def make(name: str, fn: Callable) -> Case:
        return Case(K + "NULL component", name, lambda lib: Outcome(fn(Fmi3Library.get().dll), name, [], face="fmi3"))

    return [make(n, f) for n, f in calls.items()]


def step_cases() -> list[Case]:
    k = "step"
    cases = [
        _case(k, f"fmi3DoStep t = {t!r}, h = {h!r}", "fmi3DoStep", lambda c, t=t, h=h: c.do_step(t, h))
        for t, h in (
            (0.5, 1e-4),
            (math.nan, 1e-4),
            (0.0, 0.0),
            (0.0, -1e-4),
            (0.0, math.nan),
            (0.0, math.inf),
            (0.0, 1e300),
        )
    ]

    def past_stop(c: Instance3) -> int:
        return c.do_step(0.0, 2e-3)

    cases.append(Case(K + k, "fmi3DoStep past the stop time 1e-3 s", lambda lib: _stop_run(past_stop)))
    return cases


def _stop_run(fn: Callable[[Instance3], int]) -> Outcome:
    with Instance3(Fmi3Library.get()) as c:
        assert c.enter_init(0.0, 1e-3) == F.OK and c.exit_init() == F.OK
        c.clear_log()
        return _outcome(fn(c), "fmi3DoStep", c)


def blob_cases() -> list[Case]:
    k = "state blob"

    def with_blob(mutate: Callable[[bytes], bytes], size: Callable[[bytes], int] | None = None):
        def call(c: Instance3) -> int:
            st, h = c.get_state()
            st2, blob = c.serialize(h)
            assert st == st2 == F.OK
            c.free_state(h)
            b = mutate(blob)
            st, h2 = c.deserialize(b, size(blob) if size else None)
            if st == F.OK:
                c.set_state(h2)
            return st

        return call

    flip = lambda b: b[:40] + bytes([b[40] ^ 0xFF]) + b[41:]  # noqa: E731
    return [
        _case(k, "truncated by one byte", "fmi3DeserializeFMUState", with_blob(lambda b: b[:-1])),
        _case(k, "a flipped byte", "fmi3DeserializeFMUState", with_blob(flip), needle="checksum"),
        _case(k, "size 0", "fmi3DeserializeFMUState", with_blob(lambda b: b, lambda b: 0)),
        _case(k, "an FMI 2.0 blob of the same state", "fmi3DeserializeFMUState", _fmi2_blob, expect="either"),
        _case(k, "serialize into a buffer one byte short", "fmi3SerializeFMUState", _short_buffer),
    ]


def _fmi2_blob(c: Instance3) -> int:
    """The blob format is the layer's, not the face's: an FMI 2.0 blob may load (either is legal)."""
    with F.Instance(F.Fmi2Library.get()) as c2:
        assert c2.initialize() == F.OK
        st, h = c2.get_state()
        st2, blob = c2.serialize(h)
        c2.free_state(h)
    st, h3 = c.deserialize(blob)
    if st == F.OK:
        c.free_state(h3)
    return st


def _short_buffer(c: Instance3) -> int:
    st, h = c.get_state()
    size = ctypes.c_size_t()
    assert c.lib.fmi3SerializedFMUStateSize(c.c, h, ctypes.addressof(size)) == F.OK
    buf = ctypes.create_string_buffer(size.value)
    return c.lib.fmi3SerializeFMUState(c.c, h, ctypes.addressof(buf), size.value - 1)


def all_cases() -> list[Case]:
    return (
        instantiate_cases()
        + order_cases()
        + value_cases()
        + vr_cases()
        + pointer_cases()
        + null_instance_cases()
        + step_cases()
        + blob_cases()
    )
