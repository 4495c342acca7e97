"""Stateful fuzzing of the FMU's FMI 2.0 co-simulation API with hypothesis (RuleBasedStateMachine).

Each example is one sequence of random FMI calls on one instance: every co-simulation function,
with random, boundary and garbage arguments (NaN, inf, huge, negative, unknown and wrongly typed
value references, wrong communication points, calls in the wrong state, corrupt, truncated or
resealed state blobs, random log categories). The machine keeps a model of what the standard
says the instance is in (instantiated, initialization mode, step complete, step failed,
terminated, error), of the inputs and derivatives the FMU accepted, of the saved FMU states and of
the enabled log categories, and checks after every call:
- no crash, and every status is a valid fmi2Status;
- Real outputs are finite whenever fmi2GetReal returned fmi2OK;
- fmi2DoStep is refused outside "step complete" (after an fmi2Error or fmi2Discard of a step, an
  fmi2Error of fmi2ExitInitializationMode, before initialization, after fmi2Terminate), and for a
  wrong communication point, h <= 0 or t + h == t; a valid step with valid inputs is never an fmi2Error;
- every non-OK status that is an fmi2Warning or worse is explained in the log whatever the debug
  settings; the debug categories (logEvents, logCalls) reach the logger only when enabled
  (fmi2SetDebugLogging(fmi2True, subset): only those, per FMI 2.0 section 2.1.5;
  fmi2SetDebugLogging(fmi2False, 0 categories) or loggingOn = fmi2False at instantiation: none),
  always with our instance name and a known category;
- valid parameters, inputs and derivatives are accepted; a changed state blob is refused unless
  its checksum was recomputed (then its content is validated or it is safe to use).
The same file runs the machines of the FMI 2.0 model-exchange interface (tests/support/fuzz_me.py) and of
the FMI 3.0 co-simulation FMU (tests/support/fuzz_fmi3.py), SB_FUZZ_EXAMPLES sequences each.
Default: SB_FUZZ_EXAMPLES sequences (default 300, deterministic). The `slow` test runs
SB_FUZZ_SLOW_EXAMPLES (default 10000, random, in chunks of 500 because hypothesis keeps per-run
bookkeeping). SB_FUZZ_VERBOSE=1 prints how often each call returned each status. A failure
prints the shrunk call sequence. The same test runs against the AddressSanitizer build in
tests/fmu/test_fmu_sanitizers.py: a child pytest with LD_PRELOAD=libasan, ASAN_OPTIONS=detect_leaks=0
and SB_FMU_BINARY pointing to build-asan/ShroudedBlade.so.
"""

from __future__ import annotations

import math
import os

import numpy as np
import pytest
from hypothesis import HealthCheck, seed, settings
from hypothesis import strategies as st
from hypothesis.stateful import Bundle, RuleBasedStateMachine, consumes, initialize, rule

from tests.support import fmi2raw as F
from tests.support.fmi2raw import DISCARD, ERROR, OK, VALID_STATUSES, WARNING, Fmi2Library, Instance

# the categories of the status messages, which are not filtered by the debug settings
STATUS_CATEGORIES = ("logStatusWarning", "logStatusDiscard", "logStatusError", "logStatusFatal")
from tests.support.fuzz_fmi3 import Fmi3Machine
from tests.support.fuzz_me import MeMachine

FUZZ_EXAMPLES = int(os.environ.get("SB_FUZZ_EXAMPLES", "300"))
FUZZ_SLOW_EXAMPLES = int(os.environ.get("SB_FUZZ_SLOW_EXAMPLES", "10000"))
STEPS_PER_SEQUENCE = 40

INSTANTIATED, INIT, STEP, FAILED, TERMINATED, ERRORED, UNKNOWN = (
    "instantiated",
    "initializationMode",
    "stepComplete",
    "stepFailed",
    "terminated",
    "error",
    "unknown (restored from a resealed blob)",
)
SPEED_MAX = 30000.0
OUTPUT_VRS = [F.VR[n] for n in F.REAL_OUTPUTS]
INT_VRS = [F.VR[n] for n in F.INT_PARAMS + F.INT_OUTPUTS]
BOOL_VRS = [F.VR[n] for n in F.BOOL_PARAMS]

# --- strategies ---------------------------------------------------------------------------------
garbage_float = st.sampled_from(
    [math.nan, math.inf, -math.inf, 1e308, -1e308, 5e-324, -0.0, 0.0, -1.0, 1e-300, 2**53 + 1.0]
)
any_float = st.one_of(garbage_float, st.floats(allow_nan=True, allow_infinity=True, width=64))
some_vr = st.one_of(
    st.sampled_from(F.ALL_VRS), st.sampled_from([0, 14, 42, 63, 999, 2**32 - 1]), st.integers(0, 2**32 - 1)
)
int_value = st.one_of(st.integers(-3, 110), st.sampled_from([-(2**31), 2**31 - 1]))

# sensible parameter values (most sequences should reach stepping) and garbage
GOOD_PARAMS = {
    "EI": st.floats(200.0, 500.0),
    "rho": st.floats(5000.0, 9000.0),
    "A": st.floats(2e-4, 6e-4),
    "l": st.floats(0.1, 0.2),
    "c": st.floats(0.0, 60.0),
    "m0": st.floats(0.0, 0.1),
    "kn": st.sampled_from([1e5, 1e6, 1e7, 3e7]),
    "kdRatio": st.floats(0.3, 1.0),
    "mu": st.floats(0.0, 0.6),
    "gamma": st.floats(0.2, 1.4),
    "d": st.floats(0.0, 8e-5),
    "B": st.floats(1e-6, 2e-4),
    "maxStep": st.sampled_from([1e-3, 1e-4, 1e-5, 3e-6]),
    "frictionModel": st.integers(1, 3),
    "formulation": st.integers(1, 2),
    "projection": st.integers(1, 2),
    "amplitudeMode": st.integers(1, 2),
    "engineOrder": st.integers(1, 6),
    "gating": st.integers(0, 1),
}


def speed_strategy() -> st.SearchStrategy[float]:
    return st.one_of(st.floats(0.0, SPEED_MAX), st.sampled_from([0.0, SPEED_MAX]), garbage_float)


class FmuMachine(RuleBasedStateMachine):
    """One instance, a random sequence of FMI calls, the model of what must happen."""

    sequences = 0
    calls = 0
    steps_ok = 0
    outcomes: dict[tuple[str, int], int] = {}  # (function, status) -> count, for the summary
    states = Bundle("states")
    blobs = Bundle("blobs")

    def __init__(self) -> None:
        super().__init__()
        type(self).sequences += 1
        self.lib = Fmi2Library.get()
        self.c: Instance | None = None
        self.generation = 0  # FMU state handles die with their instance

    # --- helpers --------------------------------------------------------------------------------
    def call(self, fn, *args):  # noqa: ANN001, ANN202
        """Runs one FMI call; checks the status and the log records it produced."""
        type(self).calls += 1
        n0 = len(self.c.log)
        res = fn(*args)
        status = res[0] if isinstance(res, tuple) else res
        key = (fn.__name__, status)
        type(self).outcomes[key] = type(self).outcomes.get(key, 0) + 1
        assert status in VALID_STATUSES, f"{fn.__name__}: invalid status {status}"
        new = self.c.log[n0:]
        for r in new:
            assert r.instance == self.name, f"logger got instance name {r.instance!r}"
            assert r.category in F.LOG_CATEGORIES, f"unknown category {r.category!r}"
            assert r.status in VALID_STATUSES
            assert r.message is not None
            assert self.category_enabled(r.category), (
                f"{fn.__name__}: logged in disabled category {r.category} (enabled: {self.enabled}): {r.message}"
            )
        if status in (WARNING, ERROR) and self.c.c:  # a refusal or warning is always explained
            assert any(r.status == status for r in new), f"{fn.__name__} -> {status} with no message"
        self.last_log = [str(r) for r in new if r.category != "logCalls"][-10:]
        del self.c.log[:]  # keep memory flat in long sequences
        return res

    def category_enabled(self, cat: str) -> bool:
        if cat in STATUS_CATEGORIES:  # warnings and errors always reach the importer
            return True
        if self.enabled == "all":
            return True
        return cat in self.enabled or "logAll" in self.enabled

    def poly(self, i: int, h: float) -> float:
        """Input i at the end of a step of size h (the Taylor polynomial of model-notes s.1)."""
        return sum(self.inputs[i][j] * h**j / math.factorial(j) for j in range(9))

    @property
    def known(self) -> bool:
        return self.phase != UNKNOWN

    # --- lifecycle ------------------------------------------------------------------------------
    @initialize(logging=st.booleans(), name=st.sampled_from(["fuzz", "f z %s", "x" * 300]))
    def create(self, logging: bool, name: str) -> None:
        self.name = name
        self.c = Instance(self.lib, name=name, logging_on=logging)
        assert self.c.ok
        self.enabled: str | set = "all" if logging else set()
        self.last_log: list[str] = []
        self.reset_model()

    def reset_model(self) -> None:
        self.phase = INSTANTIATED
        self.t = 0.0
        self.start = 0.0
        self.stop: float | None = None
        self.inputs = [[0.0] * 9, [5000.0] + [0.0] * 8]  # value, derivatives 1..8 (start values)
        self.inputs_known = True
        self.max_step = 1e-5
        self.touched = False  # a random fmi2Set* of a parameter/start value was accepted

    def teardown(self) -> None:
        if self.c is not None:
            self.c.free()
            self.c = None

    @rule()
    def free_and_reinstantiate(self) -> None:
        self.c.free()
        self.generation += 1
        self.c = Instance(self.lib, name=self.name, logging_on=True)
        assert self.c.ok
        self.enabled = "all"
        self.reset_model()

    @rule(
        on=st.booleans(),
        cats=st.lists(st.sampled_from(F.LOG_CATEGORIES), max_size=4),
        garbage=st.sampled_from([None, None, None, None, "logNoSuch", ""]),
    )
    def set_debug_logging(self, on: bool, cats: list[str], garbage: str | None) -> None:
        # loggingOn = fmi2False is sent with an empty list only: "otherwise it is switched off"
        # (FMI 2.0 s.2.1.5) is read by some as "the listed categories are switched off"
        if not on:
            cats = []
        names = cats + ([garbage] if garbage is not None else [])
        old = self.enabled
        new = set() if not on else ("all" if not cats else set(cats))
        if garbage is None:  # the call's own messages may use the old or the new setting
            self.enabled = "all" if "all" in (old, new) else old | new
        s = self.call(self.c.set_debug_logging, on, names)
        self.enabled = old
        if garbage is not None:
            assert s == ERROR
            return
        assert s == OK
        self.enabled = new

    @rule(
        start=st.one_of(st.just(0.0), st.floats(-10.0, 10.0), garbage_float),
        stop=st.one_of(st.none(), st.floats(-1.0, 1.0), garbage_float),
        tol=st.one_of(st.none(), any_float),
    )
    def setup_experiment(self, start: float, stop: float | None, tol: float | None) -> None:
        s = self.call(self.c.setup, start, stop, tol)
        if not self.known:
            return
        if self.phase != INSTANTIATED:
            assert s == ERROR
        elif s in (OK, WARNING):
            self.start = self.t = start
            self.stop = stop

    @rule()
    def enter_init(self) -> None:
        s = self.call(self.c.enter_init)
        if not self.known:
            return
        if self.phase != INSTANTIATED:
            assert s == ERROR
        elif s in (OK, WARNING):
            self.phase = INIT

    @rule()
    def exit_init(self) -> None:
        s = self.call(self.c.exit_init)
        if not self.known:
            return
        if self.phase != INIT:
            assert s == ERROR
        elif s in (OK, WARNING):
            self.phase = STEP
            self.t = self.start
        else:
            assert s == ERROR
            self.phase = ERRORED

    @rule()
    def terminate(self) -> None:
        s = self.call(self.c.terminate)
        if not self.known:
            return
        if self.phase not in (STEP, FAILED):
            assert s == ERROR
        elif s in (OK, WARNING):
            self.phase = TERMINATED

    @rule()
    def reset(self) -> None:
        assert self.call(self.c.reset) == OK
        self.reset_model()

    # --- variables ------------------------------------------------------------------------------
    @rule(data=st.data())
    def set_good_parameter(self, data: st.DataObject) -> None:
        name = data.draw(st.sampled_from(sorted(GOOD_PARAMS)))
        value = data.draw(GOOD_PARAMS[name])
        s = self.call(self.c.set_params, {name: value})
        if not self.known:
            return
        if self.phase in (INSTANTIATED, INIT):
            assert s == OK, f"valid {name} = {value!r} refused: {self.last_log}"
            if name == "maxStep":
                self.max_step = value
        else:
            assert s == ERROR  # fixed parameters: only before initialization ends

    @rule(vrs=st.lists(some_vr, min_size=1, max_size=4), values=st.data())
    def set_real(self, vrs: list[int], values: st.DataObject) -> None:
        x = values.draw(st.lists(any_float, min_size=len(vrs), max_size=len(vrs)))
        s = self.call(self.c.set_real, vrs, x)
        if s == OK:
            self.touched = self.touched or any(v not in (40, 41) for v in vrs)
            for v, val in zip(vrs, x):
                assert v in F.ALL_VRS, f"unknown vr {v} accepted"
                var = next(u for u in F.VARIABLES.values() if u.vr == v)
                # FMI 2.0 s.4.2.4: before the end of initialization also the start values of
                # initial="exact" variables (here: tipDisplacement, tipVelocity, dissipatedEnergy,
                # jenkinsForce, runningMaximum)
                startable = var.causality == "parameter" or var.initial == "exact"
                assert var.type == "Real" and (startable or var.causality == "input"), (
                    f"fmi2SetReal of {var.name} ({var.causality} {var.type}) accepted"
                )
                assert math.isfinite(val), f"{var.name} = {val} accepted"
                if startable:
                    assert not self.known or self.phase in (INSTANTIATED, INIT), f"{var.name} set in {self.phase}"
                if v == F.VR["maxStep"]:
                    self.max_step = val
                if var.causality == "input":
                    if v == F.VR["rotorSpeed"]:
                        assert 0.0 <= val <= SPEED_MAX
                    self.inputs[v - F.VR["aeroLoad"]] = [val] + [0.0] * 8
        if self.known and self.phase in (FAILED, TERMINATED, ERRORED):
            assert s == ERROR

    @rule(speed=speed_strategy(), load=st.one_of(st.floats(-1e3, 1e3), garbage_float))
    def set_inputs(self, speed: float, load: float) -> None:
        s = self.call(self.c.set_real, ["aeroLoad", "rotorSpeed"], [load, speed])
        valid = math.isfinite(load) and math.isfinite(speed) and 0.0 <= speed <= SPEED_MAX
        if s == OK:
            assert valid, f"aeroLoad {load!r}, rotorSpeed {speed!r} accepted"
            self.inputs = [[load] + [0.0] * 8, [speed] + [0.0] * 8]
            self.inputs_known = True
        elif self.known and self.phase in (INSTANTIATED, INIT, STEP):
            assert not valid, f"valid inputs refused ({s}): {self.last_log}"

    @rule(vrs=st.lists(st.one_of(st.sampled_from([40, 41]), some_vr), min_size=1, max_size=9), data=st.data())
    def set_input_derivatives(self, vrs: list[int], data: st.DataObject) -> None:
        orders = data.draw(
            st.lists(st.one_of(st.integers(1, 8), st.integers(-2, 12)), min_size=len(vrs), max_size=len(vrs))
        )
        values = data.draw(st.lists(st.one_of(st.floats(-1e6, 1e6), any_float), min_size=len(vrs), max_size=len(vrs)))
        s = self.call(self.c.set_input_derivatives, vrs, orders, values)
        if s == OK:
            for v, o, x in zip(vrs, orders, values):
                assert v in (40, 41) and 1 <= o <= 8 and math.isfinite(x), (v, o, x)
                self.inputs[v - 40][o] = x

    @rule(vrs=st.lists(st.one_of(st.sampled_from(OUTPUT_VRS), some_vr), min_size=1, max_size=12))
    def get_real(self, vrs: list[int]) -> None:
        s, x = self.call(self.c.get_real, vrs)
        if s == OK:
            for v, val in zip(vrs, x):
                if v in OUTPUT_VRS:
                    assert math.isfinite(val), f"output vr {v} = {val} with fmi2OK"

    @rule(
        kind=st.sampled_from(["int", "bool"]),
        data=st.data(),
        values=st.lists(int_value, min_size=4, max_size=4),
        setter=st.booleans(),
    )
    def integer_and_boolean(self, kind: str, data: st.DataObject, values: list[int], setter: bool) -> None:
        typed = INT_VRS if kind == "int" else BOOL_VRS
        vrs = data.draw(
            st.lists(st.one_of(st.sampled_from(typed), st.sampled_from(typed), some_vr), min_size=1, max_size=4)
        )
        if setter:
            fn = self.c.set_integer if kind == "int" else self.c.set_boolean
            s = self.call(fn, vrs, values[: len(vrs)])
            self.touched = self.touched or s == OK
            if self.known and self.phase not in (INSTANTIATED, INIT):
                assert s == ERROR  # no tunable Integer/Boolean variables
        else:
            fn = self.c.get_integer if kind == "int" else self.c.get_boolean
            self.call(fn, vrs)

    @rule(vrs=st.lists(some_vr, max_size=2), setter=st.booleans())
    def strings(self, vrs: list[int], setter: bool) -> None:
        if setter:
            s = self.call(self.c.set_string, vrs, ["x"] * len(vrs))
        else:
            s, _ = self.call(self.c.get_string, vrs)
        if vrs:
            assert s == ERROR  # there are no String variables

    # --- the common path, weighted up (two rules each) so that most sequences really step -----
    def _initialize_run(self, params: dict) -> None:
        if self.phase != INSTANTIATED:
            return
        worst = max(
            self.call(self.c.setup, 0.0, None, None),
            self.call(self.c.set_params, params),
            self.call(self.c.enter_init),
            self.call(self.c.exit_init),
        )
        if not self.touched:
            assert worst in (OK, WARNING), f"valid parameters {params} refused: {self.last_log}"
        if worst in (OK, WARNING):
            self.phase, self.start, self.t, self.stop = STEP, 0.0, 0.0, None
            self.max_step = params.get("maxStep", self.max_step)
        else:
            self.phase = UNKNOWN

    @rule(params=st.fixed_dictionaries({}, optional=GOOD_PARAMS))
    def initialize_run(self, params: dict) -> None:
        self._initialize_run(params)

    @rule(params=st.fixed_dictionaries({}, optional=GOOD_PARAMS))
    def initialize_run_too(self, params: dict) -> None:
        self._initialize_run(params)

    def _run_steps(self, n: int, h: float, Fw0: float, speed: float, order: int) -> None:
        if self.phase != STEP:
            return
        eo = 3
        omega = eo * 2 * math.pi * speed / 60.0
        for _ in range(n):
            d = F.aero_derivatives(self.t, Fw0, omega, order)
            s1 = self.call(self.c.set_real, ["aeroLoad", "rotorSpeed"], [d[0], speed])
            s2 = (
                self.call(self.c.set_input_derivatives, ["aeroLoad"] * order, list(range(1, order + 1)), d[1:])
                if order
                else OK
            )
            assert s1 == OK and s2 == OK, self.last_log
            self.inputs = [d + [0.0] * (9 - len(d)), [speed] + [0.0] * 8]
            self.inputs_known = True
            self.do_step(0.0, h)
            if self.phase != STEP:
                break

    @rule(
        n=st.integers(1, 25),
        h=st.sampled_from([1e-4, 5e-4, 1e-3]),
        Fw0=st.sampled_from([0.0, 100.0, 1000.0, 1e5]),
        speed=st.floats(0.0, SPEED_MAX),
        order=st.integers(0, 8),
    )
    def run_steps(self, n: int, h: float, Fw0: float, speed: float, order: int) -> None:
        self._run_steps(n, h, Fw0, speed, order)

    @rule(
        n=st.integers(1, 25),
        h=st.sampled_from([1e-4, 2e-4]),
        Fw0=st.sampled_from([100.0, 300.0]),
        speed=st.sampled_from([3000.0, 5000.0, 7000.0]),
        order=st.sampled_from([0, 8]),
    )
    def run_steps_too(self, n: int, h: float, Fw0: float, speed: float, order: int) -> None:
        self._run_steps(n, h, Fw0, speed, order)

    # --- stepping -------------------------------------------------------------------------------
    @rule(
        dt=st.one_of(st.just(0.0), st.just(0.0), st.floats(-1e-3, 1e-3), garbage_float),
        h=st.one_of(
            st.sampled_from([1e-4, 1e-4, 5e-5, 5e-4, 1e-3, 2e-3]),
            st.floats(1e-6, 2e-3),
            st.sampled_from([0.0, -1e-4, math.nan, math.inf, 1e6, 1e300]),
            garbage_float,
        ),
    )
    def do_step(self, dt: float, h: float) -> None:
        t = self.t + dt
        s = self.call(self.c.do_step, t, h)
        if self.known:
            self.check_step(t, h, s)
        if s in (OK, WARNING):
            self.phase = STEP
            self.t = t + h
            self.inputs_known = False  # the FMU's extrapolation between steps is its own business
            type(self).steps_ok += 1
            st_, y = self.call(self.c.get_real, OUTPUT_VRS)
            assert st_ == OK and np.all(np.isfinite(y)), f"outputs after an OK step: {y}"
        elif s == DISCARD:
            self.phase = FAILED if self.known and self.phase == STEP else self.phase
        elif self.known and self.phase == STEP:
            self.phase = ERRORED

    def check_step(self, t: float, h: float, s: int) -> None:
        if self.phase != STEP:
            assert s == ERROR, f"fmi2DoStep in {self.phase} returned {s}"
            return
        tol = 1e-9 * max(1.0, abs(self.t))
        if (
            not (math.isfinite(t) and abs(t - self.t) <= tol) or not (h > 0.0) or not math.isfinite(h) or t + h == t
        ):  # below the time resolution at t: time would not advance
            assert s in (ERROR, DISCARD), f"bad step t={t!r} (now {self.t!r}) h={h!r}: {s}"
        elif self.stop is not None and math.isfinite(self.stop) and t + h > self.stop + 1e-9 * max(1.0, abs(self.stop)):
            assert s in (ERROR, DISCARD), f"step past the stop time {self.stop!r} accepted: {s}"
        elif h / self.max_step > 1e7:
            assert s == ERROR, f"a step of {h / self.max_step:.3g} internal steps: {s}"
        elif self.inputs_known and h <= 2e-3:
            end_speed = self.poly(1, h)
            margin = 1e-6 * SPEED_MAX
            if margin < end_speed < SPEED_MAX - margin and math.isfinite(self.poly(0, h)):
                assert s != ERROR, f"a valid step (t={t!r}, h={h!r}) gave fmi2Error: {self.last_log}"

    @rule(
        kind=st.sampled_from([0, 1, 2, 2, 3, 99, -1]),
        fn=st.sampled_from(["real", "real", "int", "bool", "string", "status", "cancel"]),
    )
    def status_query(self, kind: int, fn: str) -> None:
        if fn == "cancel":  # no asynchronous steps: always refused
            assert self.call(self.c.cancel_step) == ERROR
            return
        f = {
            "real": self.c.get_real_status,
            "int": self.c.get_integer_status,
            "bool": self.c.get_boolean_status,
            "string": self.c.get_string_status,
            "status": self.c.get_status,
        }[fn]
        s, v = self.call(f, kind)
        if fn == "real" and kind == F.LAST_SUCCESSFUL_TIME and s == OK and self.phase in (STEP, FAILED):
            assert abs(v - self.t) <= 1e-12 * max(1.0, abs(self.t)), (v, self.t)

    # --- FMU states -----------------------------------------------------------------------------
    @rule(target=states)
    def get_state(self):  # noqa: ANN201
        s, h = self.call(self.c.get_state)
        assert s == OK and h, f"fmi2GetFMUstate in {self.phase}: {s}"
        return (self.generation, h, self.snapshot())

    def snapshot(self) -> dict:
        return {
            "phase": self.phase,
            "t": self.t,
            "start": self.start,
            "stop": self.stop,
            "inputs": [list(x) for x in self.inputs],
            "inputs_known": self.inputs_known,
            "max_step": self.max_step,
            "touched": self.touched,
        }

    def restore(self, snap: dict) -> None:
        self.phase, self.t, self.start, self.stop = snap["phase"], snap["t"], snap["start"], snap["stop"]
        self.inputs = [list(x) for x in snap["inputs"]]
        self.inputs_known = snap["inputs_known"]
        self.max_step = snap["max_step"]
        self.touched = snap["touched"]

    @rule(state=states)
    def set_state(self, state) -> None:  # noqa: ANN001
        gen, h, snap = state
        if gen != self.generation:
            return
        assert self.call(self.c.set_state, h) == OK
        self.restore(snap)

    @rule(state=consumes(states))
    def free_state(self, state) -> None:  # noqa: ANN001
        gen, h, _ = state
        if gen == self.generation:
            assert self.call(self.c.free_state, h) == OK

    @rule(target=blobs, state=states)
    def serialize(self, state):  # noqa: ANN001, ANN201
        gen, h, snap = state
        if gen != self.generation:
            return (b"", snap)
        s, blob = self.call(self.c.serialize, h)
        assert s == OK and len(blob) > 0
        return (blob, snap)

    @rule(blob=blobs, how=st.sampled_from(["as is", "as is", "flip", "truncate", "extend", "reseal"]), data=st.data())
    def deserialize_and_set(self, blob, how: str, data: st.DataObject) -> None:  # noqa: ANN001
        raw, snap = blob
        if not raw:
            return
        if how == "flip":
            i = data.draw(st.integers(0, len(raw) - 1))
            raw = raw[:i] + bytes([raw[i] ^ data.draw(st.integers(1, 255))]) + raw[i + 1 :]
        elif how == "truncate":
            raw = raw[: data.draw(st.integers(0, len(raw) - 1))]
        elif how == "extend":
            raw = raw + data.draw(st.binary(min_size=1, max_size=16))
        elif how == "reseal":  # a legal checksum over changed content: the FMU must check content
            i = data.draw(st.integers(32, len(raw) - 9))
            b = bytearray(raw)
            b[i] ^= data.draw(st.integers(1, 255))
            raw = F.reseal(bytes(b))
        s, h = self.call(self.c.deserialize, raw)
        if how in ("flip", "truncate", "extend"):
            assert s == ERROR, f"a {how} blob was accepted"
        elif how == "as is":
            assert s == OK
        if s == OK:
            assert self.call(self.c.set_state, h) == OK
            if how == "as is":
                self.restore(snap)
                # a blob does not hold the state machine, only whether initialization had ended
                # (fmu_src/fmi/state_blob.c): it comes back stepping or instantiated; after an
                # error either can hold, so from then on only validity is checked
                self.phase = {
                    INSTANTIATED: INSTANTIATED,
                    INIT: INSTANTIATED,
                    STEP: STEP,
                    FAILED: STEP,
                    TERMINATED: STEP,
                }.get(self.phase, UNKNOWN)
            else:  # legal but unknown content: from now on only validity is checked
                self.phase = UNKNOWN
                st_, t = self.c.get_real_status(F.LAST_SUCCESSFUL_TIME)
                st2, ms = self.c.get_real(["maxStep"])
                del self.c.log[:]
                self.t = t if st_ == OK else self.t
                self.max_step = ms[0] if st2 == OK else self.max_step
                self.inputs_known = False
            assert self.call(self.c.free_state, h) == OK


CHUNK = 500  # hypothesis keeps per-run bookkeeping (~0.25 MB per sequence): long runs go in chunks


def _run(examples: int, randomize: bool = False) -> None:
    """Runs `examples` sequences (in chunks of CHUNK); reproducible (chunk k uses seed k, so the
    chunks differ) unless randomize or SB_FUZZ_RANDOM is set (a failure prints the shrunk call
    sequence either way)."""
    FmuMachine.sequences = FmuMachine.calls = FmuMachine.steps_ok = 0
    FmuMachine.outcomes = {}
    randomize = randomize or os.environ.get("SB_FUZZ_RANDOM") is not None
    left, chunk = examples, 0
    while left > 0:
        n = min(CHUNK, left)
        test = (FmuMachine if randomize else seed(chunk)(FmuMachine)).TestCase
        chunk += 1
        test.settings = settings(
            max_examples=n,
            stateful_step_count=STEPS_PER_SEQUENCE,
            deadline=None,
            suppress_health_check=list(HealthCheck),
            database=None,
        )
        test("runTest").runTest()
        left -= n
    print(
        f"\nfuzz: {FmuMachine.sequences} sequences, {FmuMachine.calls} FMI calls, {FmuMachine.steps_ok} accepted steps"
    )
    if os.environ.get("SB_FUZZ_VERBOSE"):
        for (fn, status), n in sorted(FmuMachine.outcomes.items()):
            print(f"  {fn:24s} {F.STATUS_NAMES.get(status, status):8s} {n}")
    assert FmuMachine.sequences >= examples // 2
    assert FmuMachine.steps_ok > 0


def test_fuzz_fmi_sequences(lib: Fmi2Library) -> None:
    _run(FUZZ_EXAMPLES)


@pytest.mark.slow
def test_fuzz_fmi_sequences_long(lib: Fmi2Library) -> None:
    _run(FUZZ_SLOW_EXAMPLES)


def _run_machine(machine: type, examples: int, counters: tuple[str, ...]) -> None:
    """Runs `examples` sequences of another interface's machine (chunks, seeds as _run)."""
    machine.sequences = machine.calls = 0
    for name in counters:
        setattr(machine, name, 0)
    randomize = os.environ.get("SB_FUZZ_RANDOM") is not None
    left, chunk = examples, 0
    while left > 0:
        n = min(CHUNK, left)
        test = (machine if randomize else seed(chunk)(machine)).TestCase
        chunk += 1
        test.settings = settings(
            max_examples=n,
            stateful_step_count=STEPS_PER_SEQUENCE,
            deadline=None,
            suppress_health_check=list(HealthCheck),
            database=None,
        )
        test("runTest").runTest()
        left -= n
    print(
        f"\nfuzz {machine.__name__}: {machine.sequences} sequences, {machine.calls} FMI calls, "
        + ", ".join(f"{getattr(machine, c)} {c}" for c in counters)
    )
    assert machine.sequences >= examples // 2
    assert all(getattr(machine, c) > 0 for c in counters), "the sequences never reached the common path"


def test_fuzz_model_exchange(lib: Fmi2Library) -> None:
    _run_machine(MeMachine, FUZZ_EXAMPLES, ("integrated", "events"))


def test_fuzz_fmi3(lib: Fmi2Library) -> None:  # the FMI 3.0 binary: tests/support/fmi3raw.py (SB_FMU3_BINARY)
    _run_machine(Fmi3Machine, FUZZ_EXAMPLES, ("steps_ok",))


@pytest.mark.slow
def test_fuzz_model_exchange_and_fmi3_long(lib: Fmi2Library) -> None:
    _run_machine(MeMachine, FUZZ_SLOW_EXAMPLES // 4, ("integrated", "events"))
    _run_machine(Fmi3Machine, FUZZ_SLOW_EXAMPLES // 4, ("steps_ok",))
