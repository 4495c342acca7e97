"""The ring's instances (docs/model.md s.8): N BladeExternalContact blades (the built-in load's
travelling wave: bladeIndex i of bladeCount N) and N ShroudContact contacts, initialised and freed
together, with the communication points both masters use (libcosim's integer nanoseconds)."""

from __future__ import annotations

from contextlib import contextmanager
from typing import Iterator

import numpy as np

from harness.system.time_grid import ns_time_grid
from harness.fmu.pool import worker_unpacked
from harness.fmu.slave import BLADE_EXTERNAL_FMU, SHROUD_CONTACT_FMU, Slave, build_ring_fmus


def check(ring) -> None:
    if ring.n < 2:
        raise ValueError(f"a ring needs n >= 2 blades, got {ring.n}")
    if ring.blade_each and len(ring.blade_each) != ring.n:
        raise ValueError(f"blade_each has {len(ring.blade_each)} entries for {ring.n} blades")


_built = False  # per process: CMake is asked once (0.3 s a call), not per ring


def _build_once() -> tuple:
    global _built
    if not _built:
        build_ring_fmus()
        _built = True
    return BLADE_EXTERNAL_FMU, SHROUD_CONTACT_FMU


@contextmanager
def open_ring(ring) -> Iterator[tuple[np.ndarray, list[Slave], list[Slave]]]:
    """(t_0..t_K, blades, contacts) of `ring` (a harness.system.ring.Ring), freed on exit; blades and
    contacts start with rotorSpeed = ring.speed."""
    check(ring)
    bx_path, sc_path = _build_once()
    N = ring.n
    BX, SC = worker_unpacked(bx_path), worker_unpacked(sc_path)
    speed = {"rotorSpeed": ring.speed}
    made: list[Slave] = []
    try:
        blades = [BX.instance(f"blade{i}", ring.blade_instance_params(i), inputs=speed) for i in range(N)]
        made += blades
        contacts = [
            SC.instance(f"contact{j}", {**dict(ring.contact), "engineOrder": ring.engine_order}, inputs=speed)
            for j in range(N)
        ]
        made += contacts
        yield ns_time_grid(0.0, ring.step, ring.n_steps), blades, contacts
    finally:
        for fmu in made:
            fmu.free()
