"""A small name-based wrapper over the project's FMI binding (harness.fmu.binding) for the
bladed-disk FMUs (ShroudContact, BladeExternalContact, Excitation): extract once (fmpy), load the
binary once, instantiate, set parameters by name, set inputs with their time derivatives
(fmi2SetRealInputDerivatives), step, read outputs. Used by the ring master
(harness/system/ring.py) and the tests of the new FMUs; `Slave.s` is the binding's instance
(checked mode: a refused call raises FmiError)."""

from __future__ import annotations

import shutil
from pathlib import Path
from typing import Any, Mapping, Sequence

from fmpy import extract, read_model_description

from harness.fmu.binding import FmiError, LogRecord, fmi2
from harness.fmu.build import build
from harness.paths import BUILD_DIR

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
    """An FMU extracted and its binary loaded once; `instance()` makes slaves from it; `close()`
    removes the directory (the binary stays loaded: instances of it may outlive this object)."""

    def __init__(self, path: Path):
        self.path = Path(path)
        self.md = read_model_description(str(self.path))
        self.dir = extract(str(self.path))
        self.vars = {v.name: v for v in self.md.modelVariables}
        self.lib = fmi2.load(fmi2.binary_path(self.dir, self.md.coSimulation.modelIdentifier))

    def instance(
        self,
        name: str,
        params: Mapping[str, Any] | None = None,
        start_time: float = 0.0,
        initialize: bool = True,
        inputs: Mapping[str, float] | None = None,
        stop_time: float | None = None,
    ) -> "Slave":
        """inputs: values set before the end of initialization (the start state follows them)."""
        return Slave(self, name, params or {}, start_time, initialize, inputs or {}, stop_time)

    def close(self) -> None:
        shutil.rmtree(self.dir, ignore_errors=True)

    def __enter__(self) -> "Unpacked":
        return self

    def __exit__(self, *exc: Any) -> None:
        self.close()


class Slave:
    """One instance; with `initialize`, parameters are set and initialization is ended. The FMU's
    status messages (logStatus* categories) are collected in `messages` through the binding's
    per-instance logger."""

    def __init__(
        self,
        u: Unpacked,
        name: str,
        params: Mapping[str, Any],
        start_time: float,
        initialize: bool,
        inputs: Mapping[str, float],
        stop_time: float | None = None,
    ):
        self.u = u
        self.messages: list[str] = []
        self.s = fmi2.Fmi2Instance(
            u.lib, name, u.md.guid, fmi2.resource_uri(u.dir), logging_on=True, log_limit=100, on_log=self._on_log
        )
        self.s.set_debug_logging(False, [])
        self.s.set_debug_logging(True, ["logStatusWarning", "logStatusDiscard", "logStatusError", "logStatusFatal"])
        self.s.setup_experiment(start_time, stop_time)
        if initialize:
            self.set_params(params)
            if inputs:
                self.set_inputs(inputs)
            self.s.enter_initialization_mode()
            self.s.exit_initialization_mode()

    def _on_log(self, rec: LogRecord) -> None:
        self.messages.append(rec.message or "")

    def vr(self, name: str) -> int:
        return int(self.u.vars[name].valueReference)

    def set_params(self, params: Mapping[str, Any]) -> None:
        for k, v in params.items():
            var = self.u.vars[k]
            if var.type == "Real":
                self.s.set_real([var.valueReference], [float(v)])
            elif var.type == "Integer":
                self.s.set_integer([var.valueReference], [int(v)])
            else:
                self.s.set_boolean([var.valueReference], [bool(v)])

    def set_inputs(self, values: Mapping[str, float], derivatives: Mapping[str, Sequence[float]] | None = None) -> None:
        """Values, then derivatives of orders 1..len (one fmi2SetRealInputDerivatives call; the
        call for all of them)."""
        names = list(values)
        self.s.set_real([self.vr(n) for n in names], [float(values[n]) for n in names])
        if not derivatives:
            return
        vrs, orders, vals = [], [], []
        for n, ds in derivatives.items():
            for k, x in enumerate(ds, start=1):
                vrs.append(self.vr(n))
                orders.append(k)
                vals.append(float(x))
        if vrs:
            self.s.set_real_input_derivatives(vrs, orders, vals)

    def get(self, names: Sequence[str]) -> list[float]:
        out = []
        for n in names:
            var = self.u.vars[n]
            if var.type == "Real":
                out.append(float(self.s.get_real([var.valueReference])[0]))
            else:
                out.append(float(self.s.get_integer([var.valueReference])[0]))
        return out

    def step(self, t: float, h: float) -> None:
        self.s.do_step(t, h)

    def free(self) -> None:
        """Terminates (where the state allows it) and frees the instance."""
        try:
            self.s.terminate()
        except FmiError:
            pass  # not initialized, or after an error: fmi2FreeInstance is still allowed
        self.s.free_instance()


__all__ = ["BLADE_EXTERNAL_FMU", "SHROUD_CONTACT_FMU", "Slave", "Unpacked", "build_ring_fmus"]
