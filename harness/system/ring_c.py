"""The ring of harness/system/ring.py with its communication loop in C (harness/native/ring_master.c):
the same instances (made, parameterised and initialised through fmpy), the same data flow (both
couplings) and extrapolation weights, but no Python between the FMI calls. `run`
returns what `ring.run` returns (the fmpy master stays the readable reference; tests/system/test_ring_c.py
holds the two together). `CRing` keeps a ring open between calls: `advance` runs it on by a number
of steps at a rotor speed (a speed sweep steps rotorSpeed between calls),
`set_step` changes the whole-ns communication step from the current point on (the extrapolation
history restarts, as at t_0), `exact_grid` puts the points from the current one on on an exact
grid t = t_base + j h (history restarted), `save`/`restore` keep and put back the whole state (FMU
states, the master's histories and grid, the load phase), `history`/`set_history` read and set the
master's histories alone (the ring's period map carries them in its state). `phase` is the blades'
load phase psi at the current point modulo 2 pi: they integrate psi' = EO 2 pi rpm / 60 from psi = 0
at t = 0 (the speed constant within a call), so it is tracked here from the speeds and the times.
"""

from __future__ import annotations

import ctypes as C
import math
from contextlib import ExitStack
from dataclasses import replace
from typing import Any

import numpy as np

from harness.fmu.build import build
from harness.fmu.slave import Slave
from harness.paths import BUILD_DIR
from harness.system.time_grid import to_ns
from harness.system.ring import Ring, RingDiverged, diverged_message, extrapolation_weights
from harness.system.ring_instances import open_ring

LIBRARY = BUILD_DIR / "libring_master.so"
MAX_ORDER = 4  # RING_MAX_ORDER
_FUNCTIONS = ("fmi2GetReal", "fmi2SetReal", "fmi2GetInteger", "fmi2SetRealInputDerivatives", "fmi2DoStep")
_FAILED = {
    1: "a bad setup",
    2: "an fmi2Get call",
    3: "an fmi2SetReal call",
    4: "fmi2SetRealInputDerivatives",
    5: "fmi2DoStep",
}
_DIVERGED = 6
_RECORDS = ("q", "v", "E", "W", "contactForce", "forceA", "forceB", "Ec", "state")


class _Api(C.Structure):
    _fields_ = [(f, C.c_void_p) for f in ("getReal", "setReal", "getInteger", "setRealInputDerivatives", "doStep")]


class _Setup(C.Structure):
    _fields_ = [
        ("n", C.c_int),
        ("first", C.c_int),
        ("last", C.c_int),
        ("finish", C.c_int),
        ("order", C.c_int),
        ("afterStep", C.c_int),
        ("timeDoSteps", C.c_int),
        ("recordEvery", C.c_int),
        ("stepNs", C.c_longlong),
        ("baseNs", C.c_longlong),
        ("baseK", C.c_int),
        ("rpm", C.c_double),
        ("qLimit", C.c_double),
        ("weights", C.POINTER(C.c_double)),
        ("blade", _Api),
        ("contact", _Api),
        ("blades", C.POINTER(C.c_void_p)),
        ("contacts", C.POINTER(C.c_void_p)),
        ("bladeOut", C.c_uint * 4),
        ("contactIn", C.c_uint * 5),
        ("contactOut", C.c_uint * 3),
        ("contactState", C.c_uint),
        ("bladeIn", C.c_uint * 2),
        ("exactStep", C.c_double),
        ("baseTime", C.c_double),
        ("readState", C.c_int),
    ]


class _Record(C.Structure):
    _fields_ = [(k, C.c_void_p) for k in _RECORDS]  # double * (an address: cheaper to set than a POINTER)


_lib: C.CDLL | None = None


def _library() -> C.CDLL:
    global _lib
    if _lib is None:
        build(("ring_master",))
        _lib = C.CDLL(str(LIBRARY))
        _lib.ringRun.argtypes = [
            C.POINTER(_Setup),
            C.POINTER(_Record),
            C.POINTER(C.c_double),
            C.POINTER(C.c_int),
            C.POINTER(C.c_int),
            C.POINTER(C.c_int),
            C.POINTER(C.c_double),
        ]
        _lib.ringRun.restype = C.c_int
    return _lib


def _api(slave: Slave) -> _Api:
    dll = slave.s.lib.dll
    return _Api(*(C.cast(getattr(dll, f), C.c_void_p) for f in _FUNCTIONS))


def _ptr(a: np.ndarray) -> C._Pointer[C.c_double]:
    return a.ctypes.data_as(C.POINTER(C.c_double))


def weights(p: int, h: float) -> np.ndarray:
    """W[q, m, j]: ring.py's extrapolation weights of order q <= p, zero-padded to (p+1)^3."""
    W = np.zeros((p + 1, p + 1, p + 1))
    for q in range(p + 1):
        W[q, : q + 1, : q + 1] = extrapolation_weights(q, h)
    return W


def _check_step(h: float) -> None:
    if not (isinstance(h, (int, float)) and math.isfinite(h) and h > 0.0):
        raise ValueError(f"exact step {h!r} s: must be a positive finite number")


class CRing:
    """An open ring driven by the C loop; use as a context manager (frees the instances). read_state
    False: the records' contact states stay 0 (one fmi2GetInteger less per contact and point, which
    makes the contact compute its outputs again)."""

    def __init__(self, ring: Ring, time_dosteps: bool = False, read_state: bool = True):
        if not 0 <= ring.order <= MAX_ORDER:
            raise ValueError(f"extrapolation order {ring.order} outside [0, {MAX_ORDER}] (the C loop's limit)")
        self.ring, self.k, self.rpm, self.phase = ring, 0, ring.speed, 0.0
        self._lib = _library()
        self._stack = ExitStack()
        tk, self.blades, self.contacts = self._stack.enter_context(open_ring(ring))
        N, p = ring.n, ring.order
        b0, c0 = self.blades[0], self.contacts[0]
        self._W = np.ascontiguousarray(weights(p, ring.step))
        self._handles = [(C.c_void_p * N)(*(x.s.c for x in g)) for g in (self.blades, self.contacts)]
        s = self.setup = _Setup(
            n=N,
            order=p,
            afterStep=int(ring.coupling == "libcosim"),
            timeDoSteps=int(time_dosteps),
            stepNs=to_ns(ring.step),
            qLimit=ring.q_limit,
            weights=_ptr(self._W),
            blade=_api(b0),
            contact=_api(c0),
            blades=self._handles[0],
            contacts=self._handles[1],
            readState=int(read_state),
        )
        s.bladeOut[:] = [b0.vr(n) for n in ("tipDisplacement", "tipVelocity", "dissipatedEnergy", "contactWork")]
        s.contactIn[:] = [c0.vr(n) for n in ("displacementA", "velocityA", "displacementB", "velocityB", "rotorSpeed")]
        s.contactOut[:] = [c0.vr(n) for n in ("forceA", "forceB", "dissipatedEnergy")]
        s.contactState = c0.vr("contactState")
        s.bladeIn[:] = [b0.vr(n) for n in ("rotorSpeed", "contactForce")]
        # the C loop's histories (of v, then of the contact force) and scratch; filled: their lengths
        self._work = np.zeros(2 * (p + 1) * N + 2 * p * N + 18 * N)
        self._work_ptr = _ptr(self._work)  # (the buffer is only ever written in place)
        self._filled = (C.c_int * 2)(0, 0)
        self._spare = np.zeros(0)  # where the C loop writes the records `advance` is not asked for
        self.inside = 0.0  # time inside fmi2DoStep so far [s] (with time_dosteps)

    def __enter__(self) -> "CRing":
        return self

    def __exit__(self, *exc: object) -> None:
        self._stack.close()

    def time(self, k: int) -> float:
        """t_k [s], as the C loop computes it (libcosim's integer nanoseconds, or the exact grid)."""
        s = self.setup
        if s.exactStep > 0.0:
            return float(s.baseTime + float(k - s.baseK) * s.exactStep)
        return float(s.baseNs + (k - s.baseK) * s.stepNs) / 1e9  # (`times` for many points)

    def times(self, k: np.ndarray) -> np.ndarray:
        """`time` of every point in k (integers), the same doubles."""
        s = self.setup
        if s.exactStep > 0.0:
            t: np.ndarray = s.baseTime + (k - s.baseK).astype(float) * s.exactStep
            return t
        ns: np.ndarray = (s.baseNs + (k - s.baseK).astype(np.int64) * s.stepNs).astype(float)
        return ns / 1e9

    def restart_exact(self, h: float) -> None:
        """Point k = 0 at t = 0 on the exact grid t_k = k h (h [s] any positive double: K steps make
        exactly K h), the extrapolation history restarted. The FMUs are the caller's: it resets and
        initialises them at t = 0 first (harness/system/ring_orbits/period_map.py)."""
        _check_step(h)
        self.k, self.phase, self.setup.baseNs = 0, 0.0, 0
        self.exact_grid(h, 0.0)
        self._work[:] = 0.0

    def exact_grid(self, h: float, base_time: float | None = None) -> None:
        """The points from the current one k on at t_j = base_time + (j - k) h (h [s] any positive
        double; base_time default the current point's time, so the run goes on without a jump), the
        extrapolation history restarted (lower orders for the next p steps, as at the start of a run)."""
        _check_step(h)
        s = self.setup
        t = self.time(self.k) if base_time is None else float(base_time)
        s.baseK, s.baseTime, s.exactStep = self.k, t, float(h)
        if self.ring.step != h:
            self.ring = replace(self.ring, step=h)
            self._W[:] = weights(self.ring.order, h)
        self._filled[:] = [0, 0]

    def history(self) -> tuple[np.ndarray, np.ndarray]:
        """Copies of the master's extrapolation history as it is now: the blades' tip velocities and
        the contact-force sums per blade, each (p + 1, N), row j the value j points back from the
        newest (the C loop's History buffers, newest first; rows beyond `filled` are stale)."""
        p1, N = self.ring.order + 1, self.ring.n
        w = self._work
        return w[: p1 * N].reshape(p1, N).copy(), w[p1 * N : 2 * p1 * N].reshape(p1, N).copy()

    def set_history(self, v: np.ndarray, f: np.ndarray) -> None:
        """The history before the next point: v and f (p, N), row j - 1 the value at t_{k-j} (j = 1..p):
        the next point pushes its own values in front and extrapolates at the full order p, as a run
        that had been going on would (the C loop's History: newest first, `filled` = p)."""
        p, N = self.ring.order, self.ring.n
        w = self._work
        for k, a in enumerate((v, f)):
            a = np.asarray(a, dtype=float)
            if a.shape != (p, N):
                raise ValueError(f"set_history: need ({p}, {N}) values (order p, blades N), got {a.shape}")
            w[k * (p + 1) * N : k * (p + 1) * N + p * N] = a.ravel()
            w[k * (p + 1) * N + p * N : (k + 1) * (p + 1) * N] = 0.0
        self._filled[:] = [p, p]

    def set_step(self, h: float) -> None:
        """Communication step h [s, whole ns] from the current point on; the input derivatives'
        history restarts (lower orders for the next p steps, as at the start of a run)."""
        ns = to_ns(h)
        s = self.setup
        if s.exactStep > 0.0:
            raise ValueError("set_step: this ring runs on the exact grid (restart_exact); restart it there instead")
        if ns == s.stepNs:
            return
        s.baseNs, s.baseK, s.stepNs = s.baseNs + (self.k - s.baseK) * s.stepNs, self.k, ns
        self.ring = replace(self.ring, step=h)
        self._W[:] = weights(self.ring.order, h)
        self._filled[:] = [0, 0]

    def advance(
        self,
        steps: int,
        rpm: float | None = None,
        record_every: int = 1,
        finish: bool = False,
        records: tuple[str, ...] = _RECORDS,
    ) -> dict[str, np.ndarray]:
        """Runs points k..k+steps-1 with their steps (and point k+steps, not stepped, with finish)
        at rotor speed rpm (default: the last one); returns the `records` (default all) of the kept
        points (every record_every-th from k) and their times; raises RingDiverged or RuntimeError."""
        if rpm is not None and rpm != self.rpm:
            self.rpm = float(rpm)
        if record_every < 1 or steps % record_every:
            raise ValueError(f"record_every {record_every}: must be >= 1 and divide the {steps} steps")
        unknown = sorted(set(records) - set(_RECORDS))
        if unknown or "q" not in records:
            raise ValueError(f"records {records!r}: need 'q' and names from {', '.join(_RECORDS)}")
        N, k0 = self.ring.n, self.k
        rows = steps // record_every + int(finish)
        res = {k: np.zeros((rows, N)) for k in records}
        if len(records) < len(_RECORDS) and self._spare.size < rows * N:
            self._spare = np.zeros(rows * N)
        s = self.setup
        s.first, s.last, s.finish, s.recordEvery, s.rpm = k0, k0 + steps, int(finish), record_every, self.rpm
        rec = _Record(*((res[k] if k in res else self._spare).ctypes.data for k in _RECORDS))
        step, fmu, inside = C.c_int(0), C.c_int(-1), C.c_double(0.0)
        rc = self._lib.ringRun(
            C.byref(s), C.byref(rec), self._work_ptr, self._filled, C.byref(step), C.byref(fmu), C.byref(inside)
        )
        self.inside += inside.value
        if rc == _DIVERGED:
            row = (step.value - k0) // record_every
            q = res["q"][row, fmu.value] if (step.value - k0) % record_every == 0 else float("nan")
            if not np.isfinite(q) or abs(q) <= self.ring.q_limit:  # not a kept row: read the blade
                q = self.blades[fmu.value].get(["tipDisplacement"])[0]
            raise RingDiverged(diverged_message(self.ring, step.value, self.time(step.value), fmu.value, q, "c"))
        if rc != 0:
            who = [*self.blades, *self.contacts][fmu.value] if fmu.value >= 0 else None
            name = who.s.name if who else "the setup"
            said = "; ".join(who.messages) if who and who.messages else "no message"
            raise RuntimeError(
                f"ring (C loop): {_FAILED.get(rc, rc)} failed for {name} at t = "
                f"{self.time(step.value):.9g} s (step {step.value}): {said}"
            )
        self.k = k0 + steps
        w = self.ring.engine_order * 2.0 * math.pi * self.rpm / 60.0
        self.phase = (self.phase + w * (self.time(self.k) - self.time(k0))) % (2.0 * math.pi)
        res["time"] = self.times(np.arange(k0, k0 + steps + int(finish), record_every)[:rows])
        return res

    def save(self) -> tuple[Any, ...]:
        """The whole state: every FMU's (fmi2GetFMUstate; freed with the ring) and the master's."""
        fmus = [x.s.get_fmu_state() for x in (*self.blades, *self.contacts)]
        for x, h in zip((*self.blades, *self.contacts), fmus):
            self._stack.callback(x.s.free_fmu_state, h)
        s = self.setup
        return (
            self.k,
            self.rpm,
            fmus,
            self._work.copy(),
            tuple(self._filled),
            (s.stepNs, s.baseNs, s.baseK, s.exactStep, s.baseTime),
            self.ring,
            self._W.copy(),
            self.phase,
        )

    def restore(self, state: tuple[Any, ...]) -> None:
        self.k, self.rpm, fmus, work, filled, grid, self.ring, W, self.phase = state
        for x, h in zip((*self.blades, *self.contacts), fmus):
            x.s.set_fmu_state(h)
        self._work[:] = work
        self._filled[:] = list(filled)
        s = self.setup
        s.stepNs, s.baseNs, s.baseK, s.exactStep, s.baseTime = grid
        self._W[:] = W


def run(ring: Ring, time_dosteps: bool = False, record_every: int = 1) -> dict[str, np.ndarray]:
    """As harness.system.ring.run(ring), the loop in C; with time_dosteps,
    res["inside_doStep"] is the time spent inside fmi2DoStep of all FMUs [s]; record_every = m keeps
    the communication points t_0, t_m, t_2m, ... (m must divide the number of steps)."""
    K = ring.n_steps
    if record_every < 1 or K % record_every:
        raise ValueError(f"record_every {record_every}: must be >= 1 and divide the {K} steps")
    with CRing(ring, time_dosteps=time_dosteps) as r:
        res = r.advance(K, record_every=record_every, finish=True)
        if time_dosteps:
            res["inside_doStep"] = np.array(r.inside)
    return res
