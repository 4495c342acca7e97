"""Result tables as CSV, written atomically (temporary file + rename: an interrupted run never
leaves a truncated table): `write_csv` / `read_csv` for the studies' structured arrays (floats at
harness.digits' significant digits of their column), `write_result_csv` for a simulation result
(time + FMU outputs) in fmpy's format, each column named with its unit from the model description."""

from __future__ import annotations

import os
import tempfile
from pathlib import Path
from typing import Any, Mapping

import numpy as np
from fmpy.util import write_csv as fmpy_write_csv

from harness import digits
from harness.files.atomic import atomic_write_text
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
    named: np.dtype[Any] = np.dtype(
        {
            "names": [with_unit(n, unit(n)) for n in names],
            "formats": [fields[n][0] for n in names],
            "offsets": [fields[n][1] for n in names],
            "itemsize": result.dtype.itemsize,
        }
    )
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
        fmpy_write_csv(str(tmp), with_units(result, variables))
        os.replace(tmp, target)
    finally:
        tmp.unlink(missing_ok=True)


def write_csv(path: Path | str, table: np.ndarray, header_comment: str = "") -> None:
    """Write a structured array as CSV (quoted header; floats with harness.digits.SIGNIFICANT
    significant digits of their column's largest magnitude), atomically."""
    names = table.dtype.names or ()
    lines = []
    if header_comment:
        lines += [f"# {ln}" for ln in header_comment.splitlines()]
    lines.append(",".join(f'"{n}"' for n in names))
    floats = {n: digits.column(table[n]) for n in names if np.issubdtype(table.dtype[n], np.floating)}
    for i, row in enumerate(table):
        cells = []
        for n in names:
            v = row[n]
            if isinstance(v, (bytes, np.bytes_)):
                v = v.decode()
            if n in floats:
                cells.append(floats[n][i])
            elif isinstance(v, (bool, np.bool_)):
                cells.append("1" if v else "0")
            else:
                cells.append(str(v))
        lines.append(",".join(cells))
    atomic_write_text(path, "\n".join(lines) + "\n")


def read_csv(path: Path | str) -> np.ndarray:
    """Read a CSV written by `write_csv` back into a structured array (numbers as float)."""
    with open(path) as fh:
        rows = [ln for ln in fh if not ln.startswith("#")]
    names = [n.strip().strip('"') for n in rows[0].strip().split(",")]
    cols: list[list[str]] = [[] for _ in names]
    for ln in rows[1:]:
        for i, cell in enumerate(ln.strip().split(",")):
            cols[i].append(cell)
    arrays = []
    for c in cols:
        try:
            arrays.append(np.array([float(x) for x in c]))
        except ValueError:
            arrays.append(np.array(c))
    dtype = [(n, a.dtype) for n, a in zip(names, arrays)]
    out = np.zeros(len(rows) - 1, dtype=dtype)
    for n, a in zip(names, arrays):
        out[n] = a
    return out
