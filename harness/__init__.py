"""ShroudedBlade harness: drive the shrouded-blade FMU with fmpy, find its periodic orbits, trace
their branches, run the bladed-disk ring, reproduce the paper.

The public API, thin over the package's own functions (`python -m harness` / `harness` is the
command line over the same):

    import harness
    orbits = harness.periodic_orbits(7000, d=4e-5)      # every periodic orbit at 7000 rpm
    res = harness.simulate(0.2, speed=7000, d=4e-5)     # one run: numpy record array
    branches = harness.branch((6000, 8000))             # orbit branches over a speed range
    ring = harness.run_ring(harness.Ring(n=6, stop_time=0.05))
    states = harness.ring_branches(harness.Ring(n=4), (5500, 7000))  # the ring's periodic steady states
    harness.fmu_path("ShroudedBlade")                   # the FMU file itself

Parameters are the FMU's (names, units, defaults and ranges of its modelDescription.xml) plus Fw0
[N/m]; a bad value raises `ParameterError` naming the value, the accepted range and the argument it
came from. Importing `harness` loads none of numpy, fmpy or the FMU: the names resolve on first use
from harness.api, where the functions live.
"""

from __future__ import annotations

import importlib
from typing import TYPE_CHECKING, Any

if TYPE_CHECKING:
    from harness.api import (
        RING_MASTERS,
        ParameterError,
        Ring,
        branch,
        fmu_path,
        periodic_orbits,  # noqa: F401
        ring_branches,
        run_ring,
        simulate,
    )

    __version__: str

__all__ = [
    "__version__",
    "fmu_path",
    "simulate",
    "periodic_orbits",
    "branch",
    "Ring",
    "run_ring",
    "ring_branches",
    "ParameterError",
    "RING_MASTERS",
]


def __getattr__(name: str) -> Any:
    """PEP 562: the public names come from harness.api when first asked for, so that `import harness`
    (which every `import harness.<module>` runs first) stays cheap; __version__ is harness.version's
    (a metadata lookup, without the API's imports)."""
    if name not in __all__:
        raise AttributeError(f"module 'harness' has no attribute {name!r}")
    if name == "__version__":
        return importlib.import_module("harness.version").version()
    return getattr(importlib.import_module("harness.api"), name)


def __dir__() -> list[str]:
    return sorted(set(globals()) | set(__all__))
