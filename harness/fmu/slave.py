"""A small name-based wrapper over fmpy's FMU2Slave for the bladed-disk FMUs (ShroudContact,
BladeExternalContact, Excitation): extract once, instantiate, set parameters by name, set inputs
with their time derivatives (fmi2SetRealInputDerivatives), step, read outputs. Used by the ring
master (harness/system/ring.py) and the tests of the new FMUs."""
from __future__ import annotations

import shutil
from pathlib import Path
from typing import Any, Mapping, Sequence

from fmpy import calloc, extract, free, read_model_description
from fmpy.fmi1 import FMICallException
from fmpy.fmi2 import (FMU2Slave, fmi2CallbackAllocateMemoryTYPE, fmi2CallbackFreeMemoryTYPE, fmi2CallbackFunctions,
                       fmi2CallbackLoggerTYPE, fmi2Integer, fmi2Real, fmi2ValueReference)

from harness.fmu.build import BUILD_DIR, build

BLADE_EXTERNAL_FMU = BUILD_DIR / "BladeExternalContact.fmu"
SHROUD_CONTACT_FMU = BUILD_DIR / "ShroudContact.fmu"


def variables_by_name(fmu: Path) -> dict[str, tuple[int, str]]:
    """name -> (value reference, type) for every variable of the FMU's model description."""
    md = read_model_description(str(fmu))
    return {v.name: (v.valueReference, v.type) for v in md.modelVariables}


def build_ring_fmus() -> tuple[Path, Path]:
    """build/BladeExternalContact.fmu and build/ShroudContact.fmu (CMake targets)."""
    build(("blade_external_fmu", "shroud_contact_fmu"))
    return BLADE_EXTERNAL_FMU, SHROUD_CONTACT_FMU


class Unpacked:
    """An FMU extracted once; `instance()` makes slaves from it; `close()` removes the directory."""

    def __init__(self, path: Path):
        self.path = Path(path)
        self.md = read_model_description(str(self.path))
        self.dir = extract(str(self.path))
        self.vars = {v.name: v for v in self.md.modelVariables}

    def instance(self, name: str, params: Mapping[str, Any] | None = None, start_time: float = 0.0,
                 initialize: bool = True, inputs: Mapping[str, float] | None = None) -> "Slave":
        """inputs: values set before the end of initialization (the start state follows them)."""
        return Slave(self, name, params or {}, start_time, initialize, inputs or {})

    def close(self) -> None:
        shutil.rmtree(self.dir, ignore_errors=True)

    def __enter__(self) -> "Unpacked":
        return self

    def __exit__(self, *exc: Any) -> None:
        self.close()


class Slave:
    """One instance; with `initialize`, parameters are set and initialization is ended. The FMU's
    status messages (logStatus* categories) are collected in `messages` through a per-instance
    logger callback (no fmpy logger proxy: it is process-global)."""

    def __init__(self, u: Unpacked, name: str, params: Mapping[str, Any], start_time: float, initialize: bool,
                 inputs: Mapping[str, float]):
        self.u = u
        self.messages: list[str] = []
        self.s = FMU2Slave(guid=u.md.guid, unzipDirectory=u.dir, modelIdentifier=u.md.coSimulation.modelIdentifier,
                           instanceName=name)
        cb = fmi2CallbackFunctions()
        cb.logger = fmi2CallbackLoggerTYPE(self._on_log)
        cb.allocateMemory = fmi2CallbackAllocateMemoryTYPE(calloc)
        cb.freeMemory = fmi2CallbackFreeMemoryTYPE(free)
        self._callbacks = cb  # kept alive until after fmi2FreeInstance
        self.s.instantiate(callbacks=cb, loggingOn=True)
        self.s.setDebugLogging(False, [])
        self.s.setDebugLogging(True, ["logStatusWarning", "logStatusDiscard", "logStatusError", "logStatusFatal"])
        self.s.setupExperiment(startTime=start_time)
        if initialize:
            self.set_params(params)
            if inputs:
                self.set_inputs(inputs)
            self.s.enterInitializationMode()
            self.s.exitInitializationMode()

    def _on_log(self, env: Any, instance: Any, status: int, category: bytes, message: bytes) -> None:
        self.messages.append((message or b"").decode(errors="replace").replace("%%", "%"))

    def vr(self, name: str) -> int:
        return self.u.vars[name].valueReference

    def set_params(self, params: Mapping[str, Any]) -> None:
        for k, v in params.items():
            var = self.u.vars[k]
            if var.type == "Real":
                self.s.setReal([var.valueReference], [float(v)])
            elif var.type == "Integer":
                self.s.setInteger([var.valueReference], [int(v)])
            else:
                self.s.setBoolean([var.valueReference], [bool(v)])

    def set_inputs(self, values: Mapping[str, float], derivatives: Mapping[str, Sequence[float]] | None = None) -> None:
        """Values, then derivatives of orders 1..len (one fmi2SetRealInputDerivatives call; the
        fmpy wrapper is bypassed: its buffer sizes are fixed, README fmpy note)."""
        names = list(values)
        self.s.setReal([self.vr(n) for n in names], [float(values[n]) for n in names])
        if not derivatives:
            return
        vrs, orders, vals = [], [], []
        for n, ds in derivatives.items():
            for k, x in enumerate(ds, start=1):
                vrs.append(self.vr(n))
                orders.append(k)
                vals.append(float(x))
        if vrs:
            m = len(vrs)
            self.s.fmi2SetRealInputDerivatives(self.s.component, (fmi2ValueReference * m)(*vrs), m,
                                              (fmi2Integer * m)(*orders), (fmi2Real * m)(*vals))

    def get(self, names: Sequence[str]) -> list[float]:
        out = []
        for n in names:
            var = self.u.vars[n]
            if var.type == "Real":
                out.append(self.s.getReal([var.valueReference])[0])
            else:
                out.append(float(self.s.getInteger([var.valueReference])[0]))
        return out

    def step(self, t: float, h: float) -> None:
        self.s.doStep(currentCommunicationPoint=t, communicationStepSize=h)

    def free(self) -> None:
        """Terminates (where the state allows it) and frees the instance."""
        try:
            self.s.terminate()
        except FMICallException:
            pass  # not initialized, or after an error: fmi2FreeInstance is still allowed
        self.s.freeInstance()


__all__ = ["BLADE_EXTERNAL_FMU", "SHROUD_CONTACT_FMU", "Slave", "Unpacked", "build_ring_fmus"]
