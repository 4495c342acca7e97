"""The communication points every ring master shares, in libcosim's integer nanoseconds.

libcosim keeps time as integer nanoseconds: the communication point passed to fmi2DoStep is
double(start_ns + k * step_ns) / 1e9, so neither the time nor the step accumulates rounding. The
fmpy master and the C loop step on the same points, so that all masters see the same inputs.
"""

from __future__ import annotations

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
