"""What a cached ring result was computed with: the ring's FMUs, the C loop's library and the Python
sources of the ring engine (harness/system, its ring_orbits, and the periodic-orbit solvers of
harness/analysis/periodic it borrows). A cache keyed on the FMUs alone kept records computed by an
older period map or continuation after either changed; with this digest any edit there computes
them again (a conservative key: a comment change also does)."""

from __future__ import annotations

import hashlib
from pathlib import Path

from harness.fmu.slave import build_ring_fmus

_HERE = Path(__file__).resolve().parent
_SOURCES = (_HERE, _HERE / "ring_orbits", _HERE.parent / "analysis" / "periodic")


def ring_engine_digest() -> str:
    """sha256 over the ring FMUs' bytes, the C loop's shared library and the engine's .py files
    (sorted by name, each with its path relative to harness/)."""
    from harness.system.ring_c import LIBRARY, _library

    _library()  # builds the C loop if it is missing
    h = hashlib.sha256()
    for p in (*build_ring_fmus(), LIBRARY):
        h.update(Path(p).read_bytes())
    root = _HERE.parent
    for folder in _SOURCES:
        for src in sorted(folder.glob("*.py")):
            h.update(str(src.relative_to(root)).encode())
            h.update(src.read_bytes())
    return h.hexdigest()
