"""Shared pieces of the cross-check drivers: the run record, output lists, result arrays, metrics.

Every importer driver (`crosscheck_fmpy`, `crosscheck_libcosim`, `crosscheck_ecos`,
`crosscheck_fmi4j`) returns a `Run`: a float64 structured array with `time` first and one column
per FMU output (modelDescription order, integers as floats), sampled after initialization and after
every communication step, plus the tool's name and version and the wall time. `max_rel_diff`
compares two runs column by column, each normalised by the reference column's largest magnitude.
"""

from __future__ import annotations

import time as _time
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any, Callable

import numpy as np
from fmpy import read_model_description

MODEL_NAME = "ShroudedBlade"


@dataclass(frozen=True)
class OutputVar:
    name: str
    vr: int
    type: str  # "Real" or "Integer"


def outputs(fmu: Path) -> list[OutputVar]:
    """The FMU's outputs in modelDescription order."""
    md = read_model_description(str(fmu))
    return [OutputVar(v.name, v.valueReference, v.type) for v in md.modelVariables if v.causality == "output"]


def result_array(time: np.ndarray, columns: dict[str, np.ndarray]) -> np.ndarray:
    """Structured float64 array: `time` first, then `columns` in the given order."""
    dtype = [("time", np.float64)] + [(n, np.float64) for n in columns]
    out = np.empty(len(time), dtype=dtype)
    out["time"] = time
    for n, v in columns.items():
        out[n] = np.asarray(v, dtype=np.float64)
    return out


def as_float_result(arr: np.ndarray, names: list[str]) -> np.ndarray:
    """A tool's structured result reduced to `time` + `names`, as float64."""
    return result_array(np.asarray(arr["time"], dtype=float), {n: arr[n] for n in names})


@dataclass
class Run:
    """One importer run of one scenario."""

    importer: str  # e.g. "fmpy simulate_fmu"
    version: str
    inputs: str  # "held" or "taylor<order>"
    result: np.ndarray | None = None
    wall_time: float = float("nan")  # [s] instantiate .. terminate as measured around the tool's calls
    note: str = ""
    error: str = ""  # non-empty: the run failed, with the command/message
    extra: dict[str, Any] = field(default_factory=dict)

    @property
    def ok(self) -> bool:
        return not self.error and self.result is not None


def timed(fn: Callable[[], np.ndarray]) -> tuple[np.ndarray, float]:
    t0 = _time.perf_counter()
    res = fn()
    return res, _time.perf_counter() - t0


def rel_diffs(result: np.ndarray, reference: np.ndarray) -> dict[str, float]:
    """Per output: max_t |y - y_ref| / max_t |y_ref| (0 if both are identically 0, inf if only y_ref is).

    Rows are matched one to one; a different number of rows or communication points that differ by
    more than 1e-12 relative are reported as an error (inf under the key "time").
    """
    out: dict[str, float] = {}
    if len(result) != len(reference):
        return {"time": float("inf")}
    t, tr = result["time"], reference["time"]
    if np.any(np.abs(t - tr) > 1e-12 * np.maximum(1.0, np.abs(tr))):
        return {"time": float("inf")}
    for name in reference.dtype.names[1:]:
        if name not in result.dtype.names:
            continue
        y, yr = np.asarray(result[name], float), np.asarray(reference[name], float)
        err = float(np.max(np.abs(y - yr)))
        scale = float(np.max(np.abs(yr)))
        if not (np.all(np.isfinite(y)) and np.all(np.isfinite(yr))):
            out[name] = float("inf")
        elif scale == 0.0:
            out[name] = 0.0 if err == 0.0 else float("inf")
        else:
            out[name] = err / scale
    return out


def max_rel_diff(result: np.ndarray, reference: np.ndarray) -> tuple[float, str]:
    """Largest of `rel_diffs` and the variable where it occurs."""
    d = rel_diffs(result, reference)
    if not d:
        return float("nan"), ""
    name = max(d, key=lambda k: d[k])
    return d[name], name
