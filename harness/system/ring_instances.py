"""The ring's instances (docs/model.md s.8): N BladeExternalContact blades (the built-in load's
travelling wave: bladeIndex i of bladeCount N), N ShroudContact contacts (and, with load
"excitation", N Excitation instances making the load instead), initialised and freed together,
with the communication points both masters use (libcosim's integer nanoseconds)."""

from __future__ import annotations

from contextlib import contextmanager
from typing import Iterator

import numpy as np

from harness.fmu.build import EXCITATION_FMU, build
from harness.system.time_grid import ns_time_grid
from harness.fmu.pool import worker_unpacked
from harness.fmu.slave import BLADE_EXTERNAL_FMU, SHROUD_CONTACT_FMU, Slave, build_ring_fmus


def check(ring) -> None:
    if ring.n < 2:
        raise ValueError(f"a ring needs n >= 2 blades, got {ring.n}")
    if ring.blade_each and len(ring.blade_each) != ring.n:
        raise ValueError(f"blade_each has {len(ring.blade_each)} entries for {ring.n} blades")


_built: set[str] = set()  # per process: CMake is asked once (0.3 s a call), not per ring


def _build_once(excitation: bool) -> tuple:
    if "ring" not in _built:
        build_ring_fmus()
        _built.add("ring")
    if excitation and "excitation" not in _built:
        build(("excitation_fmu",))
        _built.add("excitation")
    return BLADE_EXTERNAL_FMU, SHROUD_CONTACT_FMU


@contextmanager
def open_ring(ring) -> Iterator[tuple[np.ndarray, list[Slave], list[Slave], list[Slave]]]:
    """(t_0..t_K, blades, contacts, excitations) of `ring` (a harness.system.ring.Ring), freed on
    exit; excitations is empty with the built-in load, whose blades and contacts start with
    rotorSpeed = ring.speed (the former ring: the inputs' start value, set before the first step)."""
    check(ring)
    excited = ring.load == "excitation"
    bx_path, sc_path = _build_once(excited)
    N = ring.n
    BX, SC = worker_unpacked(bx_path), worker_unpacked(sc_path)
    speed = {} if excited else {"rotorSpeed": ring.speed}
    made: list[Slave] = []
    try:
        blades = [BX.instance(f"blade{i}", ring.blade_instance_params(i), inputs=speed) for i in range(N)]
        made += blades
        contacts = [
            SC.instance(f"contact{j}", {**dict(ring.contact), "engineOrder": ring.engine_order}, inputs=speed)
            for j in range(N)
        ]
        made += contacts
        excs = []
        if excited:
            EX = worker_unpacked(EXCITATION_FMU)
            excs = [
                EX.instance(
                    f"exc{i}",
                    {
                        "Fw0": ring.fw0,
                        "n0": ring.speed,
                        "n1": ring.speed,
                        "engineOrder": ring.engine_order,
                        "bladeIndex": i,
                        "bladeCount": N,
                    },
                )
                for i in range(N)
            ]
        made += excs
        yield ns_time_grid(0.0, ring.step, ring.n_steps), blades, contacts, excs
    finally:
        for fmu in made:
            fmu.free()
