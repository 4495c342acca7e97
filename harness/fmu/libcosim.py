"""libcosim's time and its C API, shared by every libcosim master (the ring, the SSP runner, the
cross-check importer): integer-nanosecond communication points, observer samples, the last error.

libcosim keeps time as integer nanoseconds: the communication point passed to fmi2DoStep is
double(k * step_ns) / 1e9, so neither the time nor the step accumulates rounding.
"""
from __future__ import annotations

import ctypes

import numpy as np

NS_PER_S = 1_000_000_000


def to_ns(seconds: float) -> int:
    """A step or time in whole nanoseconds; refuses values that are not (libcosim would round them)."""
    ns = round(seconds * NS_PER_S)
    if abs(ns / NS_PER_S - seconds) > 1e-15 * max(1.0, abs(seconds)):
        raise ValueError(f"{seconds} s is not a whole number of nanoseconds")
    return ns


def ns_time_grid(start: float, step: float, n_steps: int) -> np.ndarray:
    """The communication points libcosim passes to the FMU: double(start_ns + k step_ns) / 1e9."""
    s0, h = to_ns(start), to_ns(step)
    return np.array([(s0 + k * h) / NS_PER_S for k in range(n_steps + 1)])


def samples(observer, idx: int, vr: int, typ: str, n: int) -> tuple[list[int], list[int], list[float]]:
    """All n samples of one variable from step 0 (initialization) on: (time [ns], step, value).

    Called through libcosimc directly: libcosimpy's helper drops samples whose step number is 0.
    """
    from libcosimpy._internal import libcosimc  # optional dependency (extra `crosscheck`): only when libcosim runs

    ctype = ctypes.c_double if typ == "Real" else ctypes.c_int
    fn = getattr(libcosimc(), "cosim_observer_slave_get_real_samples" if typ == "Real"
                 else "cosim_observer_slave_get_integer_samples")
    fn.restype = ctypes.c_int64
    vals = (ctype * n)()
    steps = (ctypes.c_int64 * n)()
    times = (ctypes.c_int64 * n)()
    got = fn(observer.ptr(), ctypes.c_int(idx), ctypes.c_uint32(vr), ctypes.c_int64(0), ctypes.c_size_t(n),
             vals, steps, times)
    if got != n:
        raise RuntimeError(f"libcosim returned {got} samples of vr {vr}, expected {n}: {last_error()}")
    return list(times), list(steps), [float(v) for v in vals]


def last_error() -> str:
    """libcosim's message for the call that just failed."""
    from libcosimpy._internal import get_last_error_message  # optional dependency (extra `crosscheck`)

    try:
        return get_last_error_message()
    except Exception as exc:  # the message itself could not be fetched
        return f"(no message: {exc})"
