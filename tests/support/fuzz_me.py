"""The stateful fuzz machine of the FMI 2.0 model-exchange interface (run by tests/fmu/test_fmu_fuzz.py):
random sequences of every model-exchange call (fmi2SetTime, fmi2SetContinuousStates,
fmi2GetDerivatives, fmi2GetEventIndicators, fmi2GetContinuousStates,
fmi2GetNominalsOfContinuousStates, fmi2EnterEventMode, fmi2NewDiscreteStates,
fmi2EnterContinuousTimeMode, fmi2CompletedIntegratorStep) and the common ones on one
model-exchange instance, with garbage arguments (NaN, inf, huge states, wrong sizes) and calls in
the wrong state, plus a small explicit-Euler master with event handling so that most sequences
really integrate. The machine keeps what the FMI 2.0 state table (s.3.2.3) says the instance is in
and checks after every call: a valid status; a call outside its states is fmi2Error; fmi2OK
derivatives, event indicators and Real outputs are finite; non-finite states are refused
(fmi2Discard) and leave the states unchanged; contactState, a discrete variable, does not change
in continuous-time mode; the logger is used with our name and known categories only."""

from __future__ import annotations

import ctypes
import math

import numpy as np
from hypothesis import strategies as st
from hypothesis.stateful import Bundle, RuleBasedStateMachine, consumes, initialize, rule

from tests.support import fmi2raw as F
from tests.support.fmi2me import NX, NZ, EventInfo, Me, arr
from tests.support.fmi2raw import DISCARD, ERROR, OK, VALID_STATUSES, WARNING, Fmi2Library, Instance

INSTANTIATED, INIT, EVENT, CT, TERMINATED, ERRORED = (
    "instantiated",
    "initializationMode",
    "eventMode",
    "continuousTimeMode",
    "terminated",
    "error",
)
GETTER_STATES = {INIT, EVENT, CT, TERMINATED, ERRORED}
garbage = st.sampled_from([math.nan, math.inf, -math.inf, 1e300, -1e300, 5e-324, -0.0, 0.0, 1e-3])
OUTPUT_VRS = [F.VR[n] for n in F.REAL_OUTPUTS]
GOOD_PARAMS = {
    "frictionModel": st.integers(1, 3),
    "amplitudeMode": st.integers(1, 2),
    "gating": st.integers(0, 1),
    "kn": st.sampled_from([1e6, 1e7]),
    "d": st.floats(0.0, 6e-5),
    "B": st.floats(1e-6, 2e-4),
    "tipDisplacement": st.floats(-2e-4, 2e-4),
    "tipVelocity": st.floats(-0.5, 0.5),
    "gamma": st.floats(0.2, 1.4),
    "engineOrder": st.integers(1, 6),
}


class MeMachine(RuleBasedStateMachine):
    sequences = 0
    calls = 0
    integrated = 0  # accepted explicit-Euler steps
    events = 0  # event iterations after an indicator changed sign
    states = Bundle("me_states")

    def __init__(self) -> None:
        super().__init__()
        type(self).sequences += 1
        self.lib = Fmi2Library.get()
        self.me = Me(self.lib)
        self.c: Instance | None = None
        self.generation = 0

    def call(self, fn, *args):  # noqa: ANN001, ANN202
        type(self).calls += 1
        res = fn(*args)
        status = res[0] if isinstance(res, tuple) else res
        assert status in VALID_STATUSES, f"invalid status {status}"
        for r in self.c.log:
            assert r.instance == "mefuzz" and r.category in F.LOG_CATEGORIES and r.message is not None, r
        self.last_log = [str(r) for r in self.c.log if r.category != "logCalls"][-6:]
        del self.c.log[:]
        return res

    def expect(self, status: int, allowed: set[str]) -> None:
        if self.phase not in allowed:
            assert status == ERROR, f"accepted in {self.phase}: {status}"

    @initialize(params=st.fixed_dictionaries({}, optional=GOOD_PARAMS))
    def create(self, params: dict) -> None:
        self.c = Instance(self.lib, name="mefuzz", fmu_type=F.MODEL_EXCHANGE)
        assert self.c.ok
        self.params = params
        self.phase = INSTANTIATED
        self.held: int | None = None  # contactState seen in continuous-time mode since the last event

    def teardown(self) -> None:
        if self.c is not None:
            self.c.free()
            self.c = None

    # --- lifecycle -------------------------------------------------------------------------
    @rule()
    def start(self) -> None:
        """The common path: setup, parameters, initialization, event iteration, continuous time."""
        if self.phase != INSTANTIATED:
            return
        for f in (self.c.setup, self.c.enter_init, lambda: self.c.set_params(self.params), self.c.exit_init):
            s = self.call(f)
            assert s in (OK, WARNING), f"valid start refused: {self.last_log}"
        self.phase = EVENT
        self.new_discrete()
        self.enter_ct()

    @rule()
    def setup_and_enter_init(self) -> None:
        s1 = self.call(self.c.setup)
        s2 = self.call(self.c.enter_init)
        self.expect(s1, {INSTANTIATED})
        if self.phase == INSTANTIATED:
            assert s1 == OK and s2 == OK
            self.phase = INIT

    @rule()
    def exit_init(self) -> None:
        s = self.call(self.c.exit_init)
        self.expect(s, {INIT})
        if self.phase == INIT:
            self.phase = EVENT if s in (OK, WARNING) else ERRORED

    @rule()
    def terminate(self) -> None:
        s = self.call(self.c.terminate)
        self.expect(s, {EVENT, CT})
        if s == OK:
            self.phase = TERMINATED

    @rule()
    def reset(self) -> None:
        assert self.call(self.c.reset) == OK
        self.phase, self.held = INSTANTIATED, None

    # --- model exchange ----------------------------------------------------------------------
    @rule()
    def enter_event(self) -> None:
        s = self.call(self.me.enter_event, self.c.c)
        self.expect(s, {EVENT, CT})
        if s == OK:
            self.phase = EVENT

    @rule()
    def new_discrete(self) -> None:
        info = EventInfo()
        s = self.call(self.me.new_discrete, self.c.c, ctypes.byref(info))
        self.expect(s, {EVENT})
        if self.phase == EVENT:
            assert s in (OK, WARNING, ERROR), s
            assert s != OK or not info.newDiscreteStatesNeeded  # the iteration runs in one call
            self.held = None
            if s == ERROR:
                self.phase = ERRORED

    @rule()
    def enter_ct(self) -> None:
        s = self.call(self.me.enter_ct, self.c.c)
        self.expect(s, {EVENT})
        if s == OK:
            self.phase = CT

    @rule(t=st.one_of(st.floats(-1.0, 1.0), garbage))
    def set_time(self, t: float) -> None:
        s = self.call(self.me.set_time, self.c.c, t)
        self.expect(s, {EVENT, CT})
        if not math.isfinite(t):
            assert s == ERROR

    @rule(
        i=st.integers(0, NX - 1),
        v=st.one_of(st.floats(-1e-3, 1e-3), garbage),
        n=st.sampled_from([NX] * 4 + [0, NX - 1, NX + 1]),
    )
    def set_states(self, i: int, v: float, n: int) -> None:
        x = arr(NX + 1)
        got = self.call(self.me.get_x, self.c.c, x, NX)
        x[i] = v
        s = self.call(self.me.set_x, self.c.c, x, n)
        self.expect(s, {CT})
        if self.phase == CT:
            if n != NX:
                assert s == ERROR
            elif not math.isfinite(v):
                assert s == DISCARD
                after = arr(NX)
                assert self.call(self.me.get_x, self.c.c, after, NX) == OK and after[i] != v
            else:
                assert s == OK and got == OK

    @rule(
        which=st.sampled_from(["x", "dx", "z", "nominal"]),
        n_off=st.sampled_from([0] * 6 + [-1, 1]),
        null=st.sampled_from([False] * 6 + [True]),
    )
    def getter(self, which: str, n_off: int, null: bool) -> None:
        n = (NZ if which == "z" else NX) + n_off
        buf = arr(max(n, 1) + 1)
        fn = {"x": self.me.get_x, "dx": self.me.get_dx, "z": self.me.get_z, "nominal": self.me.nominals}[which]
        s = self.call(fn, self.c.c, None if null else buf, n)
        self.expect(s, GETTER_STATES | ({INSTANTIATED} if which == "nominal" else set()))
        if n_off or null:
            assert s == ERROR
        if s == OK:
            assert all(math.isfinite(buf[k]) for k in range(n)), f"{which} not finite with fmi2OK: {list(buf)}"
            if which == "nominal":
                assert all(buf[k] > 0.0 for k in range(n))

    @rule()
    def completed(self) -> None:
        enter, term = ctypes.c_int(7), ctypes.c_int(7)
        s = self.call(self.me.completed, self.c.c, 1, ctypes.byref(enter), ctypes.byref(term))
        self.expect(s, {CT})
        if s == OK:
            assert enter.value in (0, 1) and term.value in (0, 1)

    @rule()
    def do_step_refused(self) -> None:
        assert self.call(self.me.do_step, self.c.c, 0.0, 1e-4, 1) == ERROR

    @rule(speed=st.one_of(st.floats(0.0, 30000.0), garbage), load=st.one_of(st.floats(-1e3, 1e3), garbage))
    def set_inputs(self, speed: float, load: float) -> None:
        s = self.call(self.c.set_real, ["aeroLoad", "rotorSpeed"], [load, speed])
        valid = math.isfinite(load) and math.isfinite(speed) and 0.0 <= speed <= 30000.0
        if s == OK:
            assert valid
        elif self.phase in (INSTANTIATED, INIT, EVENT, CT):
            assert not valid, f"valid inputs refused: {self.last_log}"

    @rule(vrs=st.lists(st.sampled_from(OUTPUT_VRS + [70, 71, 80, 81, 84]), min_size=1, max_size=6))
    def get_real(self, vrs: list[int]) -> None:
        s, y = self.call(self.c.get_real, vrs)
        if s == OK:
            assert np.all(np.isfinite(y)), y
        s, cs = self.call(self.c.get_integer, ["contactState"])
        if self.phase == CT and s == OK:  # discrete: constant between events
            if self.held is None:
                self.held = int(cs[0])
            assert int(cs[0]) == self.held, f"contactState {self.held} -> {cs[0]} in continuous-time mode"

    @rule(n=st.integers(1, 40), h=st.sampled_from([1e-6, 5e-6, 2e-5]))
    def integrate(self, n: int, h: float) -> None:
        """Explicit Euler with event handling at indicator sign changes (a minimal importer)."""
        if self.phase != CT:
            return
        t = 0.0
        x, dx, z0, z1 = arr(NX), arr(NX), arr(NZ), arr(NZ)
        if self.call(self.me.get_z, self.c.c, z0, NZ) != OK:
            return
        for _ in range(n):
            if self.call(self.me.get_x, self.c.c, x, NX) != OK or self.call(self.me.get_dx, self.c.c, dx, NX) != OK:
                return
            t += h
            for k in range(NX):
                x[k] += h * dx[k]
            if self.call(self.me.set_time, self.c.c, t) != OK or self.call(self.me.set_x, self.c.c, x, NX) != OK:
                return
            if self.call(self.me.get_z, self.c.c, z1, NZ) != OK:
                return
            type(self).integrated += 1
            self.get_real([OUTPUT_VRS[0]])
            if any((a > 0) != (b > 0) for a, b in zip(z0, z1)):
                type(self).events += 1
                assert self.call(self.me.enter_event, self.c.c) == OK
                self.phase = EVENT
                self.new_discrete()
                if self.phase != EVENT:
                    return
                self.enter_ct()
                self.call(self.me.get_z, self.c.c, z1, NZ)
            z0, z1 = z1, z0

    # --- FMU states ----------------------------------------------------------------------------
    @rule(target=states)
    def get_state(self):  # noqa: ANN201
        s, h = self.call(self.c.get_state)
        assert s == OK and h
        return (self.generation, h, self.phase)

    @rule(state=states)
    def set_state(self, state) -> None:  # noqa: ANN001
        gen, h, phase = state
        if gen == self.generation:
            assert self.call(self.c.set_state, h) == OK
            self.phase, self.held = phase, None

    @rule(state=consumes(states), how=st.sampled_from(["as is", "truncate", "flip"]))
    def serialize_round_trip(self, state, how: str) -> None:  # noqa: ANN001
        gen, h, phase = state
        if gen != self.generation:
            return
        s, blob = self.call(self.c.serialize, h)
        assert s == OK
        if how == "truncate":
            blob = blob[:-3]
        elif how == "flip":
            blob = blob[:40] + bytes([blob[40] ^ 0x5A]) + blob[41:]
        s, h2 = self.call(self.c.deserialize, blob)
        assert (s == OK) == (how == "as is"), (how, s)
        if s == OK:
            assert self.call(self.c.set_state, h2) == OK
            # a blob holds whether initialization had ended: a running instance comes back in
            # continuous-time mode, an earlier one instantiated (fmu_src/fmi/fmi2_cs.c)
            self.phase = CT if phase in (EVENT, CT, TERMINATED, ERRORED) else INSTANTIATED
            self.held = None
            assert self.call(self.c.free_state, h2) == OK
        assert self.call(self.c.free_state, h) == OK
