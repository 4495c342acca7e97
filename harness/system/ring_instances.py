"""The ring's instances (docs/model.md s.8): N BladeExternalContact blades, N ShroudContact contacts,
N Excitation instances (travelling wave: bladeIndex i of bladeCount N), initialised and freed
together, with the communication points both masters use (libcosim's integer nanoseconds)."""
from __future__ import annotations

import atexit
from contextlib import contextmanager
from pathlib import Path
from typing import Iterator

import numpy as np

from harness.fmu.build import EXCITATION_FMU, build
from harness.fmu.libcosim import ns_time_grid
from harness.fmu.slave import BLADE_EXTERNAL_FMU, SHROUD_CONTACT_FMU, Slave, Unpacked, build_ring_fmus


def check(ring) -> None:
    if ring.n < 2:
        raise ValueError(f"a ring needs n >= 2 blades, got {ring.n}")
    if ring.blade_each and len(ring.blade_each) != ring.n:
        raise ValueError(f"blade_each has {len(ring.blade_each)} entries for {ring.n} blades")


_built: set[str] = set()  # per process: CMake is asked once (0.3 s a call), not per ring
_unpacked: dict[str, Unpacked] = {}  # per process: each FMU extracted once (20 ms), removed at exit


def _build_once() -> tuple:
    if "ring" not in _built:
        build_ring_fmus()
        build(("excitation_fmu",))
        _built.add("ring")
    return BLADE_EXTERNAL_FMU, SHROUD_CONTACT_FMU


def _extracted(path) -> Unpacked:
    """The FMU extracted once per process (again if the file changed)."""
    key = f"{path}:{Path(path).stat().st_mtime_ns}"
    if key not in _unpacked:
        u = _unpacked[key] = Unpacked(path)
        atexit.register(u.close)
    return _unpacked[key]


@contextmanager
def open_ring(ring) -> Iterator[tuple[np.ndarray, list[Slave], list[Slave], list[Slave]]]:
    """(t_0..t_K, blades, contacts, excitations) of `ring` (a harness.system.ring.Ring), freed on exit."""
    check(ring)
    bx_path, sc_path = _build_once()
    N = ring.n
    BX, SC, EX = (_extracted(p) for p in (bx_path, sc_path, EXCITATION_FMU))
    made: list[Slave] = []
    try:
        blades = [BX.instance(f"blade{i}", {**ring.blade_params(i), "Fw0": 0.0}) for i in range(N)]  # load: Excitation FMU
        made += blades
        contacts = [SC.instance(f"contact{j}", {**dict(ring.contact), "engineOrder": ring.engine_order})
                    for j in range(N)]
        made += contacts
        excs = [EX.instance(f"exc{i}", {"Fw0": ring.fw0, "n0": ring.speed, "n1": ring.speed,
                                        "engineOrder": ring.engine_order, "bladeIndex": i, "bladeCount": N})
                for i in range(N)]
        made += excs
        yield ns_time_grid(0.0, ring.step, ring.n_steps), blades, contacts, excs
    finally:
        for fmu in made:
            fmu.free()
