"""Output paths a command writes to: checked before any work, and errors that name the user's path.

Kept outside the layers (like harness.paths) so that the CLI and the atomic writers of every layer
share it. `check_file` / `check_dir` probe a path by creating (and removing) a temporary file where
the output will go, so that a path under an existing file, in a read-only or virtual file system
(/proc) or in an unwritable directory is refused at once with `OutputPathError` naming that path,
not after the computation with a traceback naming a temporary file.
"""

from __future__ import annotations

import errno
import os
import tempfile
from pathlib import Path


class OutputPathError(OSError):
    """An output path cannot be written; the message names the path as the user gave it and why."""


def _reason(exc: OSError) -> str:
    if isinstance(exc, (FileExistsError, NotADirectoryError)) or exc.errno in (errno.EEXIST, errno.ENOTDIR):
        return "a part of it is an existing file, not a directory"
    return exc.strerror or type(exc).__name__


def _probe(directory: Path, shown: str, option: str) -> None:
    """Create `directory` (and parents) and a temporary file in it, then remove the file."""
    try:
        directory.mkdir(parents=True, exist_ok=True)
        fd, tmp = tempfile.mkstemp(prefix=".write-test.", dir=directory)
        os.close(fd)
        os.unlink(tmp)
    except OSError as exc:
        raise OutputPathError(f"{option} {shown}: cannot write there ({_reason(exc)})") from None


def check_file(path: str | os.PathLike[str], option: str = "output file") -> Path:
    """Refuse a file path that cannot be written (exists as a directory, under a file, unwritable)."""
    p = Path(path)
    if p.is_dir():
        raise OutputPathError(f"{option} {path}: cannot write there (it is a directory)")
    _probe(p.parent, str(path), option)
    return p


def check_dir(path: str | os.PathLike[str], option: str = "output directory") -> Path:
    """Refuse a directory path where no file can be written (is a file, under a file, unwritable)."""
    p = Path(path)
    if p.exists() and not p.is_dir():
        raise OutputPathError(f"{option} {path}: cannot write there (it is an existing file, not a directory)")
    _probe(p, str(path), option)
    return p


def with_unit(name: str, unit: str | None) -> str:
    """A CSV column or JSON key that says its unit: `tipDisplacement_m`, `tipVelocity_m_s`, `time_s`
    ('/' becomes '_', '.' is dropped: `c_Ns_m2`); a dimensionless quantity keeps its name."""
    if not unit or unit in ("1", "-"):
        return name
    return f"{name}_{unit.replace('/', '_').replace('.', '')}"


def write_error(target: str | os.PathLike[str], exc: OSError) -> OutputPathError:
    """The error to raise when writing `target` failed with `exc` (which may name a temporary file)."""
    return OutputPathError(f"cannot write {target} ({_reason(exc)})")
