"""The ring of harness/system/ring.py with its communication loop in C (harness/native/ring_master.c):
the same instances (made, parameterised and initialised through fmpy), the same data flow (both
couplings, "feedthrough" and "libcosim") and extrapolation weights, but no Python between the FMI
calls. Returns what `ring.run` returns (the
fmpy master stays the readable reference; tests/test_ring_c.py holds the two together).
"""
from __future__ import annotations

import ctypes as C

import numpy as np

from harness.fmu.build import BUILD_DIR, build
from harness.system.ring import Ring, extrapolation_weights
from harness.system.ring_instances import open_ring

LIBRARY = BUILD_DIR / "libring_master.so"
MAX_ORDER = 4  # RING_MAX_ORDER
_FUNCTIONS = ("fmi2GetReal", "fmi2SetReal", "fmi2GetInteger", "fmi2SetRealInputDerivatives", "fmi2DoStep")
_FAILED = {1: "a bad setup", 2: "an fmi2Get call", 3: "an fmi2SetReal call", 4: "fmi2SetRealInputDerivatives",
           5: "fmi2DoStep"}
_RECORDS = ("q", "v", "E", "W", "contactForce", "forceA", "forceB", "Ec", "state")


class _Api(C.Structure):
    _fields_ = [(f, C.c_void_p) for f in ("getReal", "setReal", "getInteger", "setRealInputDerivatives", "doStep")]


class _Setup(C.Structure):
    _fields_ = [("n", C.c_int), ("steps", C.c_int), ("order", C.c_int), ("afterStep", C.c_int),
                ("timeDoSteps", C.c_int), ("recordEvery", C.c_int), ("time", C.POINTER(C.c_double)),
                ("weights", C.POINTER(C.c_double)), ("blade", _Api), ("contact", _Api), ("excitation", _Api),
                ("blades", C.POINTER(C.c_void_p)), ("contacts", C.POINTER(C.c_void_p)),
                ("excitations", C.POINTER(C.c_void_p)), ("bladeOut", C.c_uint * 4), ("excitationOut", C.c_uint * 2),
                ("contactIn", C.c_uint * 5), ("contactOut", C.c_uint * 3), ("contactState", C.c_uint),
                ("bladeIn", C.c_uint * 3)]


class _Record(C.Structure):
    _fields_ = [(k, C.POINTER(C.c_double)) for k in _RECORDS]


_lib: C.CDLL | None = None


def _library() -> C.CDLL:
    global _lib
    if _lib is None:
        build(("ring_master",))
        _lib = C.CDLL(str(LIBRARY))
        _lib.ringRun.argtypes = [C.POINTER(_Setup), C.POINTER(_Record), C.POINTER(C.c_double), C.POINTER(C.c_int),
                                 C.POINTER(C.c_int), C.POINTER(C.c_double)]
        _lib.ringRun.restype = C.c_int
    return _lib


def _api(slave) -> _Api:
    dll = slave.s.lib.dll
    return _Api(*(C.cast(getattr(dll, f), C.c_void_p) for f in _FUNCTIONS))


def _ptr(a: np.ndarray) -> C.POINTER(C.c_double):
    return a.ctypes.data_as(C.POINTER(C.c_double))


def weights(p: int, h: float) -> np.ndarray:
    """W[q, m, j]: ring.py's extrapolation weights of order q <= p, zero-padded to (p+1)^3."""
    W = np.zeros((p + 1, p + 1, p + 1))
    for q in range(p + 1):
        W[q, : q + 1, : q + 1] = extrapolation_weights(q, h)
    return W


def run(ring: Ring, time_dosteps: bool = False, record_every: int = 1) -> dict[str, np.ndarray]:
    """As harness.system.ring.run(ring) (without record_inputs), the loop in C; with time_dosteps,
    res["inside_doStep"] is the time spent inside fmi2DoStep of all FMUs [s]; record_every = m keeps
    the communication points t_0, t_m, t_2m, ... (m must divide the number of steps)."""
    N, K, p = ring.n, ring.n_steps, ring.order
    if record_every < 1 or K % record_every:
        raise ValueError(f"record_every {record_every}: must be >= 1 and divide the {K} steps")
    if not 0 <= p <= MAX_ORDER:
        raise ValueError(f"extrapolation order {p} outside [0, {MAX_ORDER}] (the C loop's limit)")
    lib = _library()
    with open_ring(ring) as (tk, blades, contacts, excs):
        res = {k: np.zeros((K // record_every + 1, N)) for k in _RECORDS}
        res["time"] = tk[::record_every]
        b0, c0, e0 = blades[0], contacts[0], excs[0]
        W = np.ascontiguousarray(weights(p, ring.step))
        handles = [(C.c_void_p * N)(*(x.s.c for x in group)) for group in (blades, contacts, excs)]
        s = _Setup(n=N, steps=K, order=p, afterStep=int(ring.coupling == "libcosim"), timeDoSteps=int(time_dosteps),
                   recordEvery=record_every, time=_ptr(tk), weights=_ptr(W), blade=_api(b0), contact=_api(c0),
                   excitation=_api(e0), blades=handles[0], contacts=handles[1], excitations=handles[2])
        s.bladeOut[:] = [b0.vr(n) for n in ("tipDisplacement", "tipVelocity", "dissipatedEnergy", "contactWork")]
        s.excitationOut[:] = [e0.vr("aeroLoad"), e0.vr("rotorSpeed")]
        s.contactIn[:] = [c0.vr(n) for n in ("displacementA", "velocityA", "displacementB", "velocityB", "rotorSpeed")]
        s.contactOut[:] = [c0.vr(n) for n in ("forceA", "forceB", "dissipatedEnergy")]
        s.contactState = c0.vr("contactState")
        s.bladeIn[:] = [b0.vr(n) for n in ("aeroLoad", "rotorSpeed", "contactForce")]
        rec = _Record(*(_ptr(res[k]) for k in _RECORDS))
        work = np.zeros(3 * (p + 1) * N + 3 * p * N + 20 * N)
        step, fmu, inside = C.c_int(0), C.c_int(-1), C.c_double(0.0)
        rc = lib.ringRun(C.byref(s), C.byref(rec), _ptr(work), C.byref(step), C.byref(fmu), C.byref(inside))
        if rc != 0:
            who = [*blades, *contacts, *excs][fmu.value] if fmu.value >= 0 else None
            name = who.s.name if who else "the setup"
            said = "; ".join(who.messages) if who and who.messages else "no message"
            raise RuntimeError(f"ring (C loop): {_FAILED.get(rc, rc)} failed for {name} at t = "
                               f"{tk[min(step.value, K)]:.9g} s (step {step.value}): {said}")
    if time_dosteps:
        res["inside_doStep"] = np.array(inside.value)
    return res
