"""The FMI 2.0 model-exchange rows of the invalid-input catalogue (tests/fmu/test_fmu_errors.py): every
model-exchange entry point (fmi2SetTime, fmi2SetContinuousStates, fmi2GetDerivatives,
fmi2GetEventIndicators, fmi2GetContinuousStates, fmi2GetNominalsOfContinuousStates,
fmi2EnterEventMode, fmi2NewDiscreteStates, fmi2EnterContinuousTimeMode,
fmi2CompletedIntegratorStep) in the wrong state, with wrong sizes, NULL pointers, NaN and bad
values, and the co-simulation functions on a model-exchange instance. Each row drives a fresh
model-exchange instance into its state (FMI 2.0 s.3.2.3) and makes the one call; what is expected
comes from the standard's state table and docs/model-notes.md, never from the FMU."""

from __future__ import annotations

import ctypes
import math
from typing import Callable

from tests.support.catalogue import Case, Outcome
from tests.support.fmi2me import NX, NZ, EventInfo, Me, arr
from tests.support.fmi2raw import MODEL_EXCHANGE, OK, VARIABLES, Fmi2Library, Instance

STATES = ("instantiated", "initializationMode", "eventMode", "continuousTimeMode", "terminated")
_ME: dict[int, Me] = {}


def me_of(lib: Fmi2Library) -> Me:
    if id(lib) not in _ME:
        _ME[id(lib)] = Me(lib)
    return _ME[id(lib)]


def me_instance(lib: Fmi2Library, state: str, params: dict | None = None) -> Instance:
    """A model-exchange instance driven into `state` with valid calls (asserted OK)."""
    me = me_of(lib)
    c = Instance(lib, name="me", fmu_type=MODEL_EXCHANGE)
    assert c.ok
    steps: list[Callable[[], int]] = []
    if state != "instantiated":
        steps += [c.setup, c.enter_init]
        if params:
            steps.append(lambda: c.set_params(params))
    if state in ("eventMode", "continuousTimeMode", "terminated"):
        steps += [c.exit_init, lambda: me.new_discrete(c.c, ctypes.byref(EventInfo()))]
    if state in ("continuousTimeMode", "terminated"):
        steps.append(lambda: me.enter_ct(c.c))
    if state == "terminated":
        steps.append(c.terminate)
    for f in steps:
        assert f() == OK, c.log_text()
    c.clear_log()
    return c


def _case(
    kind: str,
    label: str,
    state: str,
    call: str,
    fn: Callable[[Instance, Me], int],
    expect: str = "refuse",
    params: dict | None = None,
    **kw,
) -> Case:
    def run(lib: Fmi2Library) -> Outcome:
        with me_instance(lib, state, params) as c:
            return Outcome(fn(c, me_of(lib)), call, list(c.log))

    return Case(kind, f"{label} (in {state})", run, expect, **kw)


def _flags() -> tuple:
    return ctypes.byref(ctypes.c_int()), ctypes.byref(ctypes.c_int())


def order_cases() -> list[Case]:
    """Each model-exchange function in the states where FMI 2.0 s.3.2.3 forbids it (refuse) and in
    the ones where the standard allows them and the FMU accepts them (accept)."""
    calls: dict[str, tuple[Callable[[Instance, Me], int], set[str]]] = {
        # name: (the call, states where it is allowed)
        "fmi2SetTime": (lambda c, m: m.set_time(c.c, 0.0), {"eventMode", "continuousTimeMode"}),
        "fmi2SetContinuousStates": (lambda c, m: m.set_x(c.c, arr(NX), NX), {"continuousTimeMode"}),
        "fmi2GetDerivatives": (
            lambda c, m: m.get_dx(c.c, arr(NX), NX),
            {"initializationMode", "eventMode", "continuousTimeMode", "terminated"},
        ),
        "fmi2GetEventIndicators": (
            lambda c, m: m.get_z(c.c, arr(NZ), NZ),
            {"initializationMode", "eventMode", "continuousTimeMode", "terminated"},
        ),
        "fmi2GetContinuousStates": (
            lambda c, m: m.get_x(c.c, arr(NX), NX),
            {"initializationMode", "eventMode", "continuousTimeMode", "terminated"},
        ),
        "fmi2GetNominalsOfContinuousStates": (lambda c, m: m.nominals(c.c, arr(NX), NX), set(STATES)),
        "fmi2EnterEventMode": (lambda c, m: m.enter_event(c.c), {"eventMode", "continuousTimeMode"}),
        "fmi2NewDiscreteStates": (lambda c, m: m.new_discrete(c.c, ctypes.byref(EventInfo())), {"eventMode"}),
        "fmi2EnterContinuousTimeMode": (lambda c, m: m.enter_ct(c.c), {"eventMode"}),
        "fmi2CompletedIntegratorStep": (lambda c, m: m.completed(c.c, 1, *_flags()), {"continuousTimeMode"}),
    }
    cases = []
    for name, (fn, allowed) in calls.items():
        for state in STATES:
            cases.append(
                _case(
                    "ME call order",
                    name,
                    state,
                    name,
                    fn,
                    "accept" if state in allowed else "refuse",
                    needle=None if state in allowed else "Illegal call sequence",
                )
            )
    # the common and co-simulation functions on a model-exchange instance
    cases += [
        _case(
            "ME call order",
            "fmi2DoStep on a model-exchange instance",
            "eventMode",
            "fmi2DoStep",
            lambda c, m: m.do_step(c.c, 0.0, 1e-4, 1),
            needle="fmuType = fmi2ModelExchange",
        ),
        _case(
            "ME call order",
            "fmi2SetRealInputDerivatives on a model-exchange instance",
            "eventMode",
            "fmi2SetRealInputDerivatives",
            lambda c, m: c.set_input_derivatives(["aeroLoad"], [1], [1.0]),
            needle="model exchange",
        ),
        _case(
            "ME call order",
            "fmi2GetRealStatus on a model-exchange instance",
            "continuousTimeMode",
            "fmi2GetRealStatus",
            lambda c, m: c.get_real_status(2)[0],
            needle="model exchange",
        ),
        _case(
            "ME call order",
            "set fixed Real parameter kn = 1e6",
            "eventMode",
            "fmi2SetReal",
            lambda c, m: c.set_real(["kn"], [1e6]),
            name="kn",
        ),
        _case(
            "ME call order",
            "set fixed Integer parameter frictionModel = 2",
            "continuousTimeMode",
            "fmi2SetInteger",
            lambda c, m: c.set_integer(["frictionModel"], [2]),
            name="frictionModel",
        ),
        _case(
            "ME call order",
            "set the state's start value tipDisplacement = 1e-5",
            "continuousTimeMode",
            "fmi2SetReal",
            lambda c, m: c.set_real(["tipDisplacement"], [1e-5]),
            name="tipDisplacement",
        ),
        _case(
            "ME call order",
            "fmi2GetReal of der(tipVelocity)",
            "initializationMode",
            "fmi2GetReal",
            lambda c, m: c.get_real(["der(tipVelocity)"])[0],
            "accept",
        ),
        _case(
            "ME call order",
            "set input rotorSpeed = 6000",
            "continuousTimeMode",
            "fmi2SetReal",
            lambda c, m: c.set_real(["rotorSpeed"], [6000.0]),
            "accept",
        ),
        _case("ME call order", "fmi2Terminate", "initializationMode", "fmi2Terminate", lambda c, m: c.terminate()),
        _case(
            "ME call order",
            "fmi2Terminate",
            "continuousTimeMode",
            "fmi2Terminate",
            lambda c, m: c.terminate(),
            "accept",
        ),
    ]
    return cases


def argument_cases() -> list[Case]:
    """Wrong array sizes and NULL pointers (the sizes come from modelDescription.xml)."""
    k = "ME arguments"
    ct = "continuousTimeMode"
    cases = []
    for name, attr, n in (
        ("fmi2GetContinuousStates", "get_x", NX),
        ("fmi2SetContinuousStates", "set_x", NX),
        ("fmi2GetDerivatives", "get_dx", NX),
        ("fmi2GetEventIndicators", "get_z", NZ),
        ("fmi2GetNominalsOfContinuousStates", "nominals", NX),
    ):
        what = "ni" if attr == "get_z" else "nx"
        for bad in (0, n - 1, n + 1, 2**63):
            cases.append(
                _case(
                    k,
                    f"{name} {what} = {bad}",
                    ct,
                    name,
                    lambda c, m, a=attr, b=bad, n=n: getattr(m, a)(c.c, arr(n + 1), b),
                    needle=f"{what} = {bad}",
                )
            )
        cases.append(
            _case(
                k, f"{name} NULL array", ct, name, lambda c, m, a=attr, n=n: getattr(m, a)(c.c, None, n), needle="NULL"
            )
        )
    cases += [
        _case(
            k,
            "fmi2NewDiscreteStates eventInfo = NULL",
            "eventMode",
            "fmi2NewDiscreteStates",
            lambda c, m: m.new_discrete(c.c, None),
            needle="NULL",
        ),
        _case(
            k,
            "fmi2CompletedIntegratorStep enterEventMode = NULL",
            ct,
            "fmi2CompletedIntegratorStep",
            lambda c, m: m.completed(c.c, 1, None, _flags()[1]),
            needle="NULL",
        ),
        _case(
            k,
            "fmi2CompletedIntegratorStep terminateSimulation = NULL",
            ct,
            "fmi2CompletedIntegratorStep",
            lambda c, m: m.completed(c.c, 1, _flags()[0], None),
            needle="NULL",
        ),
    ]
    return cases


def _states_with(i: int, value: float) -> Callable[[Instance, Me], int]:
    def call(c: Instance, m: Me) -> int:
        x = arr(NX)
        assert m.get_x(c.c, x, NX) == OK
        x[i] = value
        return m.set_x(c.c, x, NX)

    return call


def value_cases() -> list[Case]:
    """NaN, infinities and out-of-range values through the model-exchange entry points."""
    k = "ME values"
    ct = "continuousTimeMode"
    cases = [
        _case(k, f"fmi2SetTime time = {t!r}", ct, "fmi2SetTime", lambda c, m, t=t: m.set_time(c.c, t), needle="time")
        for t in (math.nan, math.inf, -math.inf)
    ]
    for i in range(NX):
        for v in (math.nan, math.inf):
            cases.append(
                _case(
                    k,
                    f"fmi2SetContinuousStates x[{i}] = {v!r}",
                    ct,
                    "fmi2SetContinuousStates",
                    _states_with(i, v),
                    needle=f"x[{i}]",
                )
            )
    cases.append(
        _case(
            k,
            "fmi2SetContinuousStates x[0] = 1e300 (huge, finite)",
            ct,
            "fmi2SetContinuousStates",
            _states_with(0, 1e300),
            "either",
        )
    )

    def huge_rhs(c: Instance, m: Me) -> int:
        assert _states_with(1, 1e200)(c, m) == OK
        return m.get_dx(c.c, arr(NX), NX)

    # the dissipated power c q'^2 overflows: a solver must not get inf with fmi2OK
    cases.append(
        _case(
            k,
            "fmi2GetDerivatives at x[1] = q' = 1e200 m/s (the right-hand side overflows)",
            ct,
            "fmi2GetDerivatives",
            huge_rhs,
            needle="not finite",
        )
    )
    rs = VARIABLES["rotorSpeed"]
    for v in (math.nan, -1.0, 30001.0):
        cases.append(
            _case(
                k,
                f"rotorSpeed = {v!r}",
                ct,
                "fmi2SetReal",
                lambda c, m, v=v: c.set_real(["rotorSpeed"], [v]),
                name="rotorSpeed",
                value=v,
                low=rs.low,
                high=rs.high,
            )
        )
    cases.append(
        _case(
            k,
            "aeroLoad = inf",
            ct,
            "fmi2SetReal",
            lambda c, m: c.set_real(["aeroLoad"], [math.inf]),
            name="aeroLoad",
            value=math.inf,
        )
    )

    def no_speed(c: Instance, m: Me) -> int:
        assert c.set_real(["rotorSpeed"], [0.0]) == OK
        return m.get_dx(c.c, arr(NX), NX)

    # model-notes s.6: f_c = (f_c omega)/omega is undefined at omega = 0 under an acting DF contact
    cases.append(
        _case(
            k,
            "fmi2GetDerivatives at rotorSpeed = 0 with an ungated describing-function contact",
            ct,
            "fmi2GetDerivatives",
            no_speed,
            params={"gating": False, "tipDisplacement": 1.5e-4},
            needle="rotorSpeed = 0",
        )
    )
    return cases


def null_component_cases() -> list[Case]:
    """Every model-exchange function with a NULL fmi2Component: fmi2Error, nothing logged."""
    calls = {
        "fmi2SetTime": lambda m: m.set_time(None, 0.0),
        "fmi2SetContinuousStates": lambda m: m.set_x(None, arr(NX), NX),
        "fmi2GetDerivatives": lambda m: m.get_dx(None, arr(NX), NX),
        "fmi2GetEventIndicators": lambda m: m.get_z(None, arr(NZ), NZ),
        "fmi2GetContinuousStates": lambda m: m.get_x(None, arr(NX), NX),
        "fmi2GetNominalsOfContinuousStates": lambda m: m.nominals(None, arr(NX), NX),
        "fmi2EnterEventMode": lambda m: m.enter_event(None),
        "fmi2NewDiscreteStates": lambda m: m.new_discrete(None, ctypes.byref(EventInfo())),
        "fmi2EnterContinuousTimeMode": lambda m: m.enter_ct(None),
        "fmi2CompletedIntegratorStep": lambda m: m.completed(None, 1, *_flags()),
    }

    def make(name: str, fn: Callable[[Me], int]) -> Case:
        return Case("ME NULL component", name, lambda lib: Outcome(fn(me_of(lib)), name, []))

    return [make(n, f) for n, f in calls.items()]


def all_cases() -> list[Case]:
    return order_cases() + argument_cases() + value_cases() + null_component_cases()
