"""Files written atomically: readers see either the old file or the complete new one (a temporary
file beside the target, then `os.replace`), so an interrupted run never leaves a truncated result."""

from __future__ import annotations

import os
import tempfile
from pathlib import Path

from harness.outputs import write_error


def atomic_write_bytes(path: Path | str, data: bytes) -> None:
    """Write `data` to `path` so that readers see either the old file or the complete new one."""
    path = Path(path)
    try:
        path.parent.mkdir(parents=True, exist_ok=True)
        fd, tmp = tempfile.mkstemp(prefix=f".{path.name}.", suffix=".tmp", dir=path.parent)
    except OSError as exc:  # name the user's path, not a temporary one
        raise write_error(path, exc) from None
    try:
        with os.fdopen(fd, "wb") as fh:
            fh.write(data)
            fh.flush()
            os.fsync(fh.fileno())
        os.chmod(tmp, 0o644)  # mkstemp creates 0600; results are meant to be read by others
        os.replace(tmp, path)
    except BaseException:
        try:
            os.unlink(tmp)
        except FileNotFoundError:
            pass
        raise


def atomic_write_text(path: Path | str, text: str) -> None:
    """`text` as UTF-8, atomically (atomic_write_bytes)."""
    atomic_write_bytes(path, text.encode("utf-8"))
