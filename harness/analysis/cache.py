"""The per-point result cache: one JSON file per computed point under a directory, keyed by a hash
of everything the point depends on (parameters, scenario, start state, code version), written
atomically, so that an interrupted study finds its finished points and continues; `fmu_identity`
gives the FMU file's hash for the keys."""

from __future__ import annotations

import hashlib
import json
from dataclasses import dataclass
from pathlib import Path
from typing import Any

import numpy as np

from harness.files.atomic import atomic_write_text
from harness.fmu.blade import fmu_path
from harness.paths import DEFAULT_CACHE_DIR


def _canonical(obj: Any) -> Any:
    """A JSON-able, deterministic form of `obj` (floats by repr, dict keys sorted)."""
    if isinstance(obj, dict):
        return {str(k): _canonical(v) for k, v in sorted(obj.items())}
    if isinstance(obj, (list, tuple)):
        return [_canonical(v) for v in obj]
    if isinstance(obj, (bool, np.bool_)):
        return bool(obj)
    if isinstance(obj, (int, np.integer)):
        return int(obj)
    if isinstance(obj, (float, np.floating)):
        return repr(float(obj))
    if isinstance(obj, bytes):
        return hashlib.sha256(obj).hexdigest()
    if obj is None or isinstance(obj, str):
        return obj
    raise TypeError(f"cannot hash {type(obj).__name__} into a cache key")


def point_key(**parts: Any) -> str:
    """Hex digest identifying one computed point (parameters, scenario, start state, code version)."""
    text = json.dumps(_canonical(parts), sort_keys=True, separators=(",", ":"))
    return hashlib.sha256(text.encode()).hexdigest()[:32]


@dataclass
class PointCache:
    """One JSON file per point, `<dir>/<key[:2]>/<key>.json`; `None` directory disables caching."""

    directory: Path | None = DEFAULT_CACHE_DIR
    hits: int = 0
    misses: int = 0

    def _path(self, key: str) -> Path:
        assert self.directory is not None
        return Path(self.directory) / key[:2] / f"{key}.json"

    def get(self, key: str) -> dict[str, Any] | None:
        if self.directory is None:
            self.misses += 1
            return None
        try:
            with open(self._path(key)) as fh:
                rec: dict[str, Any] = json.load(fh)
        except (FileNotFoundError, json.JSONDecodeError, UnicodeDecodeError):
            self.misses += 1
            return None
        self.hits += 1
        return rec

    def put(self, key: str, record: dict[str, Any]) -> None:
        if self.directory is None:
            return
        atomic_write_text(self._path(key), json.dumps(record, sort_keys=True))

    def count(self) -> int:
        if self.directory is None or not Path(self.directory).exists():
            return 0
        return sum(1 for _ in Path(self.directory).glob("*/*.json"))


_HASHES: dict[str, str] = {}


def fmu_identity(path: str | Path | None = None) -> tuple[str, str]:
    """(path, sha256 of the FMU file): the hash enters every cache key (a rebuilt FMU is new)."""
    if path is None:
        path = fmu_path(build=True)
    path = str(Path(path).resolve())
    st = Path(path).stat()
    tag = f"{path}:{st.st_mtime_ns}:{st.st_size}"
    if tag not in _HASHES:
        _HASHES[tag] = hashlib.sha256(Path(path).read_bytes()).hexdigest()
    return path, _HASHES[tag]
