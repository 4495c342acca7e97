"""The stateful fuzz machine of the FMI 3.0 co-simulation interface (run by tests/fmu/test_fmu_fuzz.py):
random sequences of fmi3EnterInitializationMode/ExitInitializationMode, fmi3Set/GetFloat64, Int32,
Boolean (known, undeclared, unknown and mistyped value references, NaN, infinities, out-of-range
values, nValues != nValueReferences), fmi3DoStep (wrong communication points, h <= 0, NaN, huge
steps), fmi3Terminate, fmi3Reset and the FMU state functions (corrupt blobs) on one instance of
build/fmi3/ShroudedBlade.fmu through tests/support/fmi3raw.py. The machine keeps the FMI 3.0 state (s.4.3:
Instantiated, Initialization Mode, Step Mode, Terminated, after an fmi3Error) and checks after
every call: a valid status; calls outside their states and bad value references are fmi3Error; a
valid step is not an fmi3Error; fmi3OK outputs are finite; the logger gets known categories only."""

from __future__ import annotations

import ctypes
import math

import numpy as np
from hypothesis import strategies as st
from hypothesis.stateful import Bundle, RuleBasedStateMachine, consumes, initialize, rule

from tests.support import fmi2raw as F
from tests.support.fmi2raw import DISCARD, ERROR, OK, VALID_STATUSES, WARNING
from tests.support.fmi3raw import VR3, Fmi3Library, Instance3

INSTANTIATED, INIT, STEP, TERMINATED, ERRORED = (
    "Instantiated",
    "Initialization Mode",
    "Step Mode",
    "Terminated",
    "error",
)
garbage = st.sampled_from([math.nan, math.inf, -math.inf, 1e308, -1e308, 5e-324, -0.0, 0.0, -1.0])
REAL_OUT = [VR3[n] for n in F.REAL_OUTPUTS]
UNDECLARED = sorted(v.vr for v in F.VARIABLES.values() if v.name not in VR3)
some_vr = st.one_of(
    st.sampled_from(sorted(VR3.values())), st.sampled_from(UNDECLARED + [999, 2**32 - 1]), st.integers(0, 200)
)


class Fmi3Machine(RuleBasedStateMachine):
    sequences = 0
    calls = 0
    steps_ok = 0
    states = Bundle("fmi3_states")

    def __init__(self) -> None:
        super().__init__()
        type(self).sequences += 1
        self.c: Instance3 | None = None

    def call(self, fn, *args):  # noqa: ANN001, ANN202
        type(self).calls += 1
        res = fn(*args)
        status = res[0] if isinstance(res, tuple) else res
        assert status in VALID_STATUSES, f"invalid status {status}"
        for r in self.c.log:
            assert r.category in F.LOG_CATEGORIES and r.message, r
        self.last_log = [str(r) for r in self.c.log if r.category != "logCalls"][-6:]
        del self.c.log[:]
        return res

    def expect(self, status: int, allowed: set[str]) -> None:
        if self.phase not in allowed:
            assert status == ERROR, f"accepted in {self.phase}: {status}"

    @initialize(logging=st.booleans())
    def create(self, logging: bool) -> None:
        self.c = Instance3(Fmi3Library.get(), name="f3fuzz", logging_on=logging)
        assert self.c.ok
        self.phase, self.t, self.stop = INSTANTIATED, 0.0, None
        self.touched = False  # a parameter or start value was set: initialization may refuse it

    def teardown(self) -> None:
        if self.c is not None:
            self.c.free()
            self.c = None

    @rule(stop=st.one_of(st.none(), st.floats(1e-3, 1.0), garbage))
    def enter_init(self, stop: float | None) -> None:
        s = self.call(self.c.enter_init, 0.0, stop)
        self.expect(s, {INSTANTIATED})
        if s in (OK, WARNING):
            self.phase, self.stop = INIT, stop

    @rule()
    def exit_init(self) -> None:
        s = self.call(self.c.exit_init)
        self.expect(s, {INIT})
        if self.phase == INIT:
            self.phase, self.t = (STEP, 0.0) if s in (OK, WARNING) else (ERRORED, self.t)

    @rule()
    def terminate(self) -> None:
        s = self.call(self.c.terminate)
        self.expect(s, {STEP})
        if s == OK:
            self.phase = TERMINATED

    @rule()
    def reset(self) -> None:
        assert self.call(self.c.reset) == OK
        self.phase, self.t, self.stop = INSTANTIATED, 0.0, None
        self.touched = False

    @rule(
        vrs=st.lists(some_vr, min_size=1, max_size=4),
        data=st.data(),
        kind=st.sampled_from(["Float64", "Float64", "Int32", "Boolean"]),
        wrong_n=st.sampled_from([False] * 5 + [True]),
    )
    def set_values(self, vrs: list[int], data: st.DataObject, kind: str, wrong_n: bool) -> None:
        vals = data.draw(
            st.lists(
                st.one_of(st.floats(-1e4, 1e4), garbage) if kind == "Float64" else st.integers(-5, 110),
                min_size=len(vrs),
                max_size=len(vrs),
            )
        )
        v = np.array(vrs, dtype=np.uint32)
        x = np.array(vals, dtype={"Float64": np.float64, "Int32": np.int32, "Boolean": np.bool_}[kind])
        s = self.call(
            getattr(self.c.lib, f"fmi3Set{kind}"),
            self.c.c,
            v.ctypes.data,
            len(v),
            x.ctypes.data,
            len(v) + 1 if wrong_n else len(v),
        )
        if s == OK:
            assert not wrong_n and all(r in VR3.values() and r != 0 for r in vrs), (vrs, kind)
            assert self.phase in (INSTANTIATED, INIT, STEP)
            # e.g. jenkinsForce != 0 with frictionModel 1 is refused at exit (cross-field)
            self.touched = self.touched or any(r not in (VR3["aeroLoad"], VR3["rotorSpeed"]) for r in vrs)
        if wrong_n or any(r not in VR3.values() for r in vrs):
            assert s == ERROR

    @rule(speed=st.one_of(st.floats(0.0, 30000.0), garbage), load=st.one_of(st.floats(-1e3, 1e3), garbage))
    def set_inputs(self, speed: float, load: float) -> None:
        s = self.call(self.c.set_float64, ["aeroLoad", "rotorSpeed"], [load, speed])
        valid = math.isfinite(load) and math.isfinite(speed) and 0.0 <= speed <= 30000.0
        self.expect(s, {INSTANTIATED, INIT, STEP})
        if self.phase in (INSTANTIATED, INIT, STEP):
            assert (s == OK) == valid, (speed, load, s, self.last_log)

    @rule(vrs=st.lists(st.one_of(st.sampled_from(REAL_OUT + [0]), some_vr), min_size=1, max_size=8))
    def get_float64(self, vrs: list[int]) -> None:
        s, y = self.call(self.c.get_float64, vrs)
        self.expect(s, {INIT, STEP, TERMINATED, ERRORED})
        if any(r not in VR3.values() for r in vrs):
            assert s == ERROR
        if s == OK:
            assert np.all(np.isfinite(y[[r in REAL_OUT for r in vrs]])), y

    @rule(
        n=st.integers(1, 20),
        h=st.sampled_from([1e-4, 5e-4, 1e-3]),
        speed=st.floats(1000.0, 12000.0),
        load=st.sampled_from([0.0, 100.0, 1000.0]),
    )
    def run_steps(self, n: int, h: float, speed: float, load: float) -> None:
        if self.phase == INSTANTIATED:
            assert self.call(self.c.enter_init) in (OK, WARNING), self.last_log
            s = self.call(self.c.exit_init)
            if s == ERROR and self.touched:  # the parameters set do not fit together: terminal
                self.phase = ERRORED
                return
            assert s in (OK, WARNING), self.last_log
            self.phase, self.t, self.stop = STEP, 0.0, None
        for i in range(n):
            if self.phase != STEP:
                return
            assert (
                self.call(
                    self.c.set_float64, ["aeroLoad", "rotorSpeed"], [load * math.sin(2 * math.pi * 250 * self.t), speed]
                )
                == OK
            )
            self.do_step(0.0, h)

    @rule(
        dt=st.one_of(st.just(0.0), st.floats(-1e-3, 1e-3), garbage),
        h=st.one_of(st.sampled_from([1e-4, 1e-3]), st.floats(1e-6, 2e-3), garbage, st.sampled_from([1e6, 1e300])),
    )
    def do_step(self, dt: float, h: float) -> None:
        t = self.t + dt
        s = self.call(self.c.do_step, t, h)
        self.expect(s, {STEP})
        if self.phase != STEP:
            return
        tol = 1e-9 * max(1.0, abs(self.t))
        bad = not (math.isfinite(t) and abs(t - self.t) <= tol and h > 0.0 and math.isfinite(h)) or t + h == t
        past = (
            self.stop is not None and math.isfinite(self.stop) and t + h > self.stop + 1e-9 * max(1.0, abs(self.stop))
        )
        if bad or past:
            assert s in (ERROR, DISCARD), (t, h, s)
        elif h <= 2e-3:
            assert s != ERROR, f"a valid step gave fmi3Error: {self.last_log}"
        if s in (OK, WARNING):
            self.t = t + h
            type(self).steps_ok += 1
            s2, y = self.call(self.c.get_float64, REAL_OUT)
            assert s2 == OK and np.all(np.isfinite(y)), y
        elif s == ERROR:
            self.phase = ERRORED

    @rule(target=states)
    def get_state(self):  # noqa: ANN201
        s, h = self.call(self.c.get_state)
        assert s == OK and h
        return (h, self.phase, self.t, self.stop)

    @rule(state=states)
    def set_state(self, state) -> None:  # noqa: ANN001
        h, phase, t, stop = state
        assert self.call(self.c.set_state, h) == OK
        self.phase, self.t, self.stop = phase, t, stop

    @rule(state=consumes(states), how=st.sampled_from(["as is", "truncate", "flip", "short buffer"]))
    def serialize(self, state, how: str) -> None:  # noqa: ANN001
        h, phase, t, stop = state
        if how == "short buffer":
            size = ctypes.c_size_t()
            assert self.call(self.c.lib.fmi3SerializedFMUStateSize, self.c.c, h, ctypes.addressof(size)) == OK
            buf = ctypes.create_string_buffer(size.value)
            assert (
                self.call(self.c.lib.fmi3SerializeFMUState, self.c.c, h, ctypes.addressof(buf), size.value - 1) == ERROR
            )
        else:
            s, blob = self.call(self.c.serialize, h)
            assert s == OK
            blob = {"as is": blob, "truncate": blob[:-1], "flip": blob[:50] + bytes([blob[50] ^ 1]) + blob[51:]}[how]
            s, h2 = self.call(self.c.deserialize, blob)
            assert (s == OK) == (how == "as is")
            if s == OK:
                assert self.call(self.c.free_state, h2) == OK
        assert self.call(self.c.free_state, h) == OK
