"""A simulation result (time + FMU outputs) as a CSV file in fmpy's format, each column named with
its unit from the model description, written atomically (temporary file + rename, so an interrupted
run never leaves a truncated CSV)."""
from __future__ import annotations

import os
import tempfile
from pathlib import Path
from typing import Any, Mapping

import numpy as np
from fmpy.util import write_csv

from harness.outputs import with_unit, write_error


def with_units(result: np.ndarray, variables: Mapping[str, Any]) -> np.ndarray:
    """`result` (time + FMU outputs) with each column named with its unit from the model description
    (`variables`: name -> fmpy ModelVariable): `time_s`, `tipDisplacement_m`, ..., as every command's
    CSV and JSON names its quantities."""
    def unit(name: str) -> str | None:
        if name == "time":
            return "s"
        v = variables.get(name)
        return None if v is None else (v.unit or (v.declaredType.unit if v.declaredType else None))
    names = result.dtype.names or ()
    fields: Mapping[str, Any] = result.dtype.fields or {}
    named: np.dtype[Any] = np.dtype({"names": [with_unit(n, unit(n)) for n in names],
                                     "formats": [fields[n][0] for n in names],
                                     "offsets": [fields[n][1] for n in names],
                                     "itemsize": result.dtype.itemsize})
    out: np.ndarray = result.view(named).copy()  # a new dtype: the caller's array keeps its names
    return out


def _temporary_beside(target: Path, suffix: str) -> Path:
    """An empty temporary file in target's directory (created if needed), with the permissions of
    an ordinary new file (mkstemp makes 0600)."""
    try:
        target.parent.mkdir(parents=True, exist_ok=True)
        fd, tmp = tempfile.mkstemp(prefix=f".{target.name}.", suffix=suffix, dir=target.parent)
    except OSError as exc:  # name the user's path, not a temporary one
        raise write_error(target, exc) from None
    os.close(fd)
    umask = os.umask(0)
    os.umask(umask)
    os.chmod(tmp, 0o666 & ~umask)
    return Path(tmp)


def write_result_csv(path: str | os.PathLike[str], result: np.ndarray, variables: Mapping[str, Any]) -> None:
    """`result` with units in its column names (`with_units`) as CSV (fmpy.util.write_csv), atomically."""
    target = Path(path)
    tmp = _temporary_beside(target, ".csv")
    try:
        write_csv(str(tmp), with_units(result, variables))
        os.replace(tmp, target)
    finally:
        tmp.unlink(missing_ok=True)
