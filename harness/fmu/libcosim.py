"""libcosim's C API where libcosimpy does not reach, shared by every libcosim master (the ring, the
SSP runner, the cross-check importer): observer samples from step 0 on, the last error. Its
integer-nanosecond time is harness.system.time_grid."""

from __future__ import annotations

import ctypes


def samples(observer, idx: int, vr: int, typ: str, n: int) -> tuple[list[int], list[int], list[float]]:
    """All n samples of one variable from step 0 (initialization) on: (time [ns], step, value).

    Called through libcosimc directly: libcosimpy's helper drops samples whose step number is 0.
    """
    from libcosimpy._internal import libcosimc  # optional dependency (extra `crosscheck`): only when libcosim runs

    ctype = ctypes.c_double if typ == "Real" else ctypes.c_int
    fn = getattr(
        libcosimc(),
        "cosim_observer_slave_get_real_samples" if typ == "Real" else "cosim_observer_slave_get_integer_samples",
    )
    fn.restype = ctypes.c_int64
    vals = (ctype * n)()
    steps = (ctypes.c_int64 * n)()
    times = (ctypes.c_int64 * n)()
    got = fn(
        observer.ptr(),
        ctypes.c_int(idx),
        ctypes.c_uint32(vr),
        ctypes.c_int64(0),
        ctypes.c_size_t(n),
        vals,
        steps,
        times,
    )
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
