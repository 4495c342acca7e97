"""Test helpers over the package's FMI 3.0 binding (harness.fmu.binding.fmi3) in raw mode, for
build/fmi3/ShroudedBlade.fmu, in the style of tests/support/fmi2raw.py: every call returns the raw
fmi3Status (an int), getters (status, values), pointers may be None (NULL), arrays are numpy
arrays, and each instance records every logMessage call as a LogRecord (FMI 3.0's callback has no
instance name: the record carries the name the instance was created with). The invalid-input
catalogue and the fuzz machine use this layer. The binary is the one packaged in the FMU
(extracted once per process) unless SB_FMU3_BINARY names another build of it."""

from __future__ import annotations

import os
import threading
import xml.etree.ElementTree as ET
from pathlib import Path
from typing import Any, Sequence

import numpy as np

from tests.support import fmi2raw as F
from harness.fmu.binding import fmi3
from harness.fmu.binding.fmi3_signatures import SIGNATURES
from harness.fmu.binding.library import Library

FMU3_FILE = F.REPO_ROOT / "build" / "fmi3" / "ShroudedBlade.fmu"
MODEL_DESCRIPTION3 = F.REPO_ROOT / "fmu_src" / "models" / "ShroudedBlade" / "modelDescription3.xml"
TOKEN = ET.parse(MODEL_DESCRIPTION3).getroot().get("instantiationToken")
VR3 = {
    v.get("name"): int(v.get("valueReference")) for v in ET.parse(MODEL_DESCRIPTION3).getroot().find("ModelVariables")
}

_built: list[bool] = []


def fmu3_binary() -> Path:
    env = os.environ.get("SB_FMU3_BINARY")
    if env:
        return Path(env)
    if not _built:  # once per process: the FMU as the sources are now (a no-op when up to date)
        from harness.fmu import build as _build

        _build.build(("fmu3",))
        _built.append(True)
    return fmi3.binary_path(F.extract_fmu(FMU3_FILE), "ShroudedBlade")


class Fmi3Library(Library):
    """The binary with the binding's FMI 3.0 prototypes; one per binary per process (`get`)."""

    _cache: dict[str, "Fmi3Library"] = {}
    _lock = threading.Lock()

    @classmethod
    def get(cls) -> "Fmi3Library":
        with cls._lock:
            key = str(fmu3_binary())
            if key not in cls._cache:
                cls._cache[key] = cls(Path(key))
            return cls._cache[key]

    def __init__(self, binary: Path) -> None:
        super().__init__(binary, SIGNATURES, fmi3.REQUIRED_CS)


def _vrs(vrs: Sequence[str | int]) -> np.ndarray:
    return np.array([VR3[v] if isinstance(v, str) else v for v in vrs], dtype=np.uint32)


class Instance3:
    """One fmi3Instance (co-simulation) with a recording logger. Every method returns the raw status."""

    def __init__(
        self,
        lib: Fmi3Library | None = None,
        name: str | None = "sb3",
        token: str | None = TOKEN,
        logging_on: bool = True,
        event_mode_used: bool = False,
        logger: bool = True,
        required: Sequence[int] = (),
    ) -> None:
        self.lib = lib or Fmi3Library.get()
        self.name = name
        self.f = fmi3.Fmi3Instance(
            self.lib,
            name,
            token,
            None,
            logging_on=logging_on,
            event_mode_used=event_mode_used,
            required=required,
            raw=True,
            logger=fmi3.DEFAULT if logger else None,
        )
        self.log = self.f.log

    @property
    def c(self) -> int | None:
        return self.f.c

    @property
    def ok(self) -> bool:
        return self.f.ok

    def free(self) -> None:
        self.f.free_instance()

    def __enter__(self) -> "Instance3":
        return self

    def __exit__(self, *exc: Any) -> None:
        self.free()

    def clear_log(self) -> None:
        del self.log[:]

    def _got(self, values: Any) -> tuple[int, Any]:
        return self.f.status, values

    # --- lifecycle
    def enter_init(self, start: float = 0.0, stop: float | None = None) -> int:
        return self.f.enter_initialization_mode(start, stop)

    def exit_init(self) -> int:
        return self.f.exit_initialization_mode()

    def initialize(self, params: dict | None = None) -> int:
        """Enter/exit initialization with the start values; the built-in load off unless `params` sets Fw0
        (the tests feed aeroLoad themselves)."""
        worst = self.enter_init()
        worst = max(worst, self.set_params({"Fw0": 0.0, **(params or {})}))
        return max(worst, self.exit_init())

    def terminate(self) -> int:
        return self.f.terminate()

    def reset(self) -> int:
        return self.f.reset()

    def set_debug_logging(self, on: bool, categories: Sequence[str | None] = ()) -> int:
        return self.f.set_debug_logging(on, categories)

    # --- variables (names or value references)
    def get_float64(self, vrs, n_values: int | None = None) -> tuple[int, np.ndarray]:  # noqa: ANN001
        return self._got(self.f.get("Float64", _vrs(vrs), n_values))

    def get_int32(self, vrs) -> tuple[int, np.ndarray]:  # noqa: ANN001
        return self._got(self.f.get("Int32", _vrs(vrs)))

    def get_boolean(self, vrs) -> tuple[int, np.ndarray]:  # noqa: ANN001
        return self._got(self.f.get("Boolean", _vrs(vrs)))

    def get_int64(self, vrs) -> tuple[int, np.ndarray]:  # noqa: ANN001
        return self._got(self.f.get("Int64", _vrs(vrs)))

    def set_float64(self, vrs, values) -> int:  # noqa: ANN001
        return self.f.set("Float64", _vrs(vrs), values)

    def set_int32(self, vrs, values) -> int:  # noqa: ANN001
        return self.f.set("Int32", _vrs(vrs), values)

    def set_boolean(self, vrs, values) -> int:  # noqa: ANN001
        return self.f.set("Boolean", _vrs(vrs), values)

    def set_params(self, params: dict) -> int:
        """Parameters and start values by name, each through the setter of its FMI 3.0 type."""
        worst = F.OK
        for k, val in params.items():
            t = F.VARIABLES[k].type
            fn = {"Real": self.set_float64, "Integer": self.set_int32, "Boolean": self.set_boolean}[t]
            worst = max(worst, fn([k], [val]))
        return worst

    # --- stepping
    def do_step(self, t: float, h: float) -> int:
        self.f.do_step(t, h)
        return self.f.status

    # --- FMU states
    def get_state(self) -> tuple[int, int | None]:
        return self._got(self.f.get_fmu_state())

    def set_state(self, handle: int | None) -> int:
        return self.f.set_fmu_state(handle)

    def free_state(self, handle: int | None) -> int:
        return self.f.free_fmu_state(handle)

    def serialize(self, handle: int | None) -> tuple[int, bytes]:
        return self._got(self.f.serialize_fmu_state(handle))

    def deserialize(self, blob: bytes, size: int | None = None) -> tuple[int, int | None]:
        return self._got(self.f.deserialize_fmu_state(blob, size))


__all__ = ["Fmi3Library", "Instance3", "TOKEN", "VR3"]
