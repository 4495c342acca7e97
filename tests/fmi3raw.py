"""Raw ctypes binding of the FMI 3.0 co-simulation C API of build/fmi3/ShroudedBlade.fmu, in the
style of tests/fmi2raw.py: every call returns the raw fmi3Status (an int), pointers may be None
(NULL), arrays are numpy arrays, and each instance records every logMessage call as a
fmi2raw.LogRecord (FMI 3.0's callback has no instance name: the record carries the name the
instance was created with). fmpy's FMU3Slave raises on every non-OK status and cannot pass NULL,
so the invalid-input catalogue and the fuzz machine use this layer. The binary is the one packaged
in the FMU (extracted once per process) unless SB_FMU3_BINARY names another build of it."""
from __future__ import annotations

import ctypes
import os
import threading
import xml.etree.ElementTree as ET
from ctypes import CFUNCTYPE, c_char_p, c_double, c_int, c_size_t, c_uint32, c_void_p
from pathlib import Path
from typing import Sequence

import numpy as np

import fmi2raw as F

FMU3_FILE = F.REPO_ROOT / "build" / "fmi3" / "ShroudedBlade.fmu"
MODEL_DESCRIPTION3 = F.REPO_ROOT / "fmu_src" / "models" / "ShroudedBlade" / "modelDescription3.xml"
TOKEN = ET.parse(MODEL_DESCRIPTION3).getroot().get("instantiationToken")
VR3 = {v.get("name"): int(v.get("valueReference")) for v in ET.parse(MODEL_DESCRIPTION3).getroot()
       .find("ModelVariables")}
_P, _B = c_void_p, ctypes.c_bool  # fmi3Boolean is C's bool

LogMessage = CFUNCTYPE(None, c_void_p, c_int, c_char_p, c_char_p)

SIGNATURES = {  # name: (restype, argtypes), FMI 3.0 s.2.3 and s.4.2
    "fmi3GetVersion": (c_char_p, []),
    "fmi3SetDebugLogging": (c_int, [_P, _B, c_size_t, _P]),
    "fmi3InstantiateCoSimulation": (_P, [c_char_p, c_char_p, c_char_p, _B, _B, _B, _B, _P, c_size_t, _P, _P, _P]),
    "fmi3InstantiateModelExchange": (_P, [c_char_p, c_char_p, c_char_p, _B, _B, _P, _P]),
    "fmi3FreeInstance": (None, [_P]),
    "fmi3EnterInitializationMode": (c_int, [_P, _B, c_double, c_double, _B, c_double]),
    "fmi3ExitInitializationMode": (c_int, [_P]),
    "fmi3EnterEventMode": (c_int, [_P]),
    "fmi3EnterStepMode": (c_int, [_P]),
    "fmi3Terminate": (c_int, [_P]),
    "fmi3Reset": (c_int, [_P]),
    "fmi3GetFloat64": (c_int, [_P, _P, c_size_t, _P, c_size_t]),
    "fmi3GetInt32": (c_int, [_P, _P, c_size_t, _P, c_size_t]),
    "fmi3GetBoolean": (c_int, [_P, _P, c_size_t, _P, c_size_t]),
    "fmi3GetInt64": (c_int, [_P, _P, c_size_t, _P, c_size_t]),
    "fmi3SetFloat64": (c_int, [_P, _P, c_size_t, _P, c_size_t]),
    "fmi3SetInt32": (c_int, [_P, _P, c_size_t, _P, c_size_t]),
    "fmi3SetBoolean": (c_int, [_P, _P, c_size_t, _P, c_size_t]),
    "fmi3GetFMUState": (c_int, [_P, _P]),
    "fmi3SetFMUState": (c_int, [_P, _P]),
    "fmi3FreeFMUState": (c_int, [_P, _P]),
    "fmi3SerializedFMUStateSize": (c_int, [_P, _P, _P]),
    "fmi3SerializeFMUState": (c_int, [_P, _P, _P, c_size_t]),
    "fmi3DeserializeFMUState": (c_int, [_P, _P, c_size_t, _P]),
    "fmi3DoStep": (c_int, [_P, c_double, c_double, _B, _P, _P, _P, _P]),
    "fmi3SetTime": (c_int, [_P, c_double]),
    "fmi3GetContinuousStates": (c_int, [_P, _P, c_size_t]),
    "fmi3UpdateDiscreteStates": (c_int, [_P, _P, _P, _P, _P, _P, _P]),
    "fmi3GetOutputDerivatives": (c_int, [_P, _P, c_size_t, _P, _P, c_size_t]),
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
    return F.extract_fmu(FMU3_FILE) / "binaries" / "x86_64-linux" / "ShroudedBlade.so"


class Fmi3Library:
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
        self.path = binary
        self.dll = ctypes.CDLL(str(binary), mode=os.RTLD_NOW | os.RTLD_LOCAL)
        for name, (restype, argtypes) in SIGNATURES.items():
            f = getattr(self.dll, name)
            f.restype, f.argtypes = restype, argtypes

    def __getattr__(self, name: str):  # noqa: ANN204
        if name.startswith("fmi3"):
            return getattr(self.dll, name)
        raise AttributeError(name)


def _vrs(vrs: Sequence[str | int]) -> np.ndarray:
    return np.array([VR3[v] if isinstance(v, str) else v for v in vrs], dtype=np.uint32)


class Instance3:
    """One fmi3Instance (co-simulation) with a recording logger. Every method returns the raw status."""

    def __init__(self, lib: Fmi3Library | None = None, name: str | None = "sb3", token: str | None = TOKEN,
                 logging_on: bool = True, event_mode_used: bool = False, logger: bool = True,
                 required: Sequence[int] = ()) -> None:
        self.lib = lib or Fmi3Library.get()
        self.name = name
        self.log: list[F.LogRecord] = []
        self._cb = LogMessage(self._record)
        req = np.array(required, dtype=np.uint32)
        self._req = req
        self.c = self.lib.fmi3InstantiateCoSimulation(
            name.encode() if name is not None else None, token.encode() if token is not None else None,
            None, False, logging_on, event_mode_used, False, req.ctypes.data if len(req) else None, len(req),
            None, ctypes.cast(self._cb, c_void_p) if logger else None, None)

    def _record(self, env, status, category, message) -> None:  # noqa: ANN001
        # FMI 3.0's callback has no instance name: the one this instance was created with ('' for NULL)
        self.log.append(F.LogRecord(self.name or "", status, category.decode() if category else None,
                                    message.decode() if message else None))

    @property
    def ok(self) -> bool:
        return bool(self.c)

    def free(self) -> None:
        if self.c:
            self.lib.fmi3FreeInstance(self.c)
            self.c = None

    def __enter__(self) -> "Instance3":
        return self

    def __exit__(self, *exc) -> None:  # noqa: ANN002
        self.free()

    def clear_log(self) -> None:
        del self.log[:]

    # --- lifecycle
    def enter_init(self, start: float = 0.0, stop: float | None = None) -> int:
        return self.lib.fmi3EnterInitializationMode(self.c, False, 0.0, start, stop is not None,
                                                   0.0 if stop is None else stop)

    def exit_init(self) -> int:
        return self.lib.fmi3ExitInitializationMode(self.c)

    def initialize(self, params: dict | None = None) -> int:
        worst = self.enter_init()
        if params:
            worst = max(worst, self.set_params(params))
        return max(worst, self.exit_init())

    def terminate(self) -> int:
        return self.lib.fmi3Terminate(self.c)

    def reset(self) -> int:
        return self.lib.fmi3Reset(self.c)

    def set_debug_logging(self, on: bool, categories: Sequence[str | None] = ()) -> int:
        arr = (c_char_p * max(1, len(categories)))(*[c.encode() if c else None for c in categories])
        return self.lib.fmi3SetDebugLogging(self.c, on, len(categories), ctypes.addressof(arr))

    # --- variables
    def _get(self, fn: str, vrs, dtype, n_values: int | None = None) -> tuple[int, np.ndarray]:  # noqa: ANN001
        v = _vrs(vrs)
        out = np.zeros(len(v), dtype=dtype)
        st = getattr(self.lib, fn)(self.c, v.ctypes.data, len(v), out.ctypes.data,
                                   len(v) if n_values is None else n_values)
        return st, out

    def _set(self, fn: str, vrs, values, dtype) -> int:  # noqa: ANN001
        v, x = _vrs(vrs), np.array(values, dtype=dtype)
        return getattr(self.lib, fn)(self.c, v.ctypes.data, len(v), x.ctypes.data, len(x))

    def get_float64(self, vrs, n_values: int | None = None) -> tuple[int, np.ndarray]:  # noqa: ANN001
        return self._get("fmi3GetFloat64", vrs, np.float64, n_values)

    def get_int32(self, vrs) -> tuple[int, np.ndarray]:  # noqa: ANN001
        return self._get("fmi3GetInt32", vrs, np.int32)

    def get_boolean(self, vrs) -> tuple[int, np.ndarray]:  # noqa: ANN001
        return self._get("fmi3GetBoolean", vrs, np.bool_)

    def get_int64(self, vrs) -> tuple[int, np.ndarray]:  # noqa: ANN001
        return self._get("fmi3GetInt64", vrs, np.int64)

    def set_float64(self, vrs, values) -> int:  # noqa: ANN001
        return self._set("fmi3SetFloat64", vrs, values, np.float64)

    def set_int32(self, vrs, values) -> int:  # noqa: ANN001
        return self._set("fmi3SetInt32", vrs, values, np.int32)

    def set_boolean(self, vrs, values) -> int:  # noqa: ANN001
        return self._set("fmi3SetBoolean", vrs, values, np.bool_)

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
        flags = [ctypes.c_bool(), ctypes.c_bool(), ctypes.c_bool()]
        self.last = c_double()
        return self.lib.fmi3DoStep(self.c, t, h, True, *[ctypes.addressof(f) for f in flags],
                                   ctypes.addressof(self.last))

    # --- FMU states
    def get_state(self) -> tuple[int, int | None]:
        h = c_void_p()
        st = self.lib.fmi3GetFMUState(self.c, ctypes.addressof(h))
        return st, h.value

    def set_state(self, handle: int | None) -> int:
        return self.lib.fmi3SetFMUState(self.c, handle)

    def free_state(self, handle: int | None) -> int:
        h = c_void_p(handle)
        return self.lib.fmi3FreeFMUState(self.c, ctypes.addressof(h))

    def serialize(self, handle: int | None) -> tuple[int, bytes]:
        size = c_size_t()
        st = self.lib.fmi3SerializedFMUStateSize(self.c, handle, ctypes.addressof(size))
        if st != F.OK:
            return st, b""
        buf = ctypes.create_string_buffer(size.value)
        st = self.lib.fmi3SerializeFMUState(self.c, handle, ctypes.addressof(buf), size.value)
        return st, buf.raw

    def deserialize(self, blob: bytes, size: int | None = None) -> tuple[int, int | None]:
        h = c_void_p()
        buf = ctypes.create_string_buffer(blob, len(blob)) if blob else None
        st = self.lib.fmi3DeserializeFMUState(self.c, ctypes.addressof(buf) if buf is not None else None,
                                              len(blob) if size is None else size, ctypes.addressof(h))
        return st, h.value


__all__ = ["Fmi3Library", "Instance3", "TOKEN", "VR3", "c_uint32"]
