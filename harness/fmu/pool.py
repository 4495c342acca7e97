"""The FMUs a worker (process or thread) opens once and reuses: one per worker and file, created on
first use (extract, load, instantiate: 10-20 ms) and closed at exit. Every run resets what it uses,
so tasks sharing a worker's FMU cannot see each other. Per thread, because an FMU instance is not
to be called from two threads at once."""

from __future__ import annotations

import atexit
import threading
from pathlib import Path
from typing import Any, Callable, TypeVar

from harness.fmu.blade import BladeFMU
from harness.fmu.slave import Unpacked

T = TypeVar("T")
_LOCAL = threading.local()


def _per_worker(key: str, make: Callable[[], T], close: Callable[[T], Any]) -> T:
    objects: dict[str, Any] = _LOCAL.__dict__.setdefault("objects", {})
    if key not in objects:
        objects[key] = make()
        atexit.register(close, objects[key])
    obj: T = objects[key]
    return obj


def worker_fmu(path: str | Path) -> BladeFMU:
    """This worker's BladeFMU of the FMU file `path`."""
    return _per_worker(f"blade:{path}", lambda: BladeFMU(path), BladeFMU.close)


def worker_unpacked(path: str | Path) -> Unpacked:
    """This worker's extraction of the FMU file `path` (the ring's FMUs: instances are made per
    ring from it); extracted again if the file changed."""
    key = f"unpacked:{path}:{Path(path).stat().st_mtime_ns}"
    return _per_worker(key, lambda: Unpacked(Path(path)), Unpacked.close)
