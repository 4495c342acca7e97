"""One FMI 3.0 co-simulation instance over a Library with the FMI 3.0 table; checked and raw mode
as in fmi2.py. FMI 3.0's logMessage callback is not variadic and has no instance name: the records
carry the name the instance was created with ('' for none)."""

from __future__ import annotations

import ctypes
from ctypes import CFUNCTYPE, c_bool, c_char_p, c_double, c_int, c_size_t, c_void_p
from dataclasses import dataclass
from pathlib import Path
from typing import Any, Callable, Sequence

import numpy as np

from harness.fmu.binding.fmi3_signatures import CO_SIMULATION as _CS
from harness.fmu.binding.fmi3_signatures import SIGNATURES
from harness.fmu.binding.instance import Instance
from harness.fmu.binding.library import Library
from harness.fmu.binding.log import LogHook, LogRecord, decode
from harness.fmu.binding.status import ERROR, FmiError, failed

LogMessage = CFUNCTYPE(None, c_void_p, c_int, c_char_p, c_char_p)
REQUIRED_CS = (
    "fmi3GetVersion",
    "fmi3SetDebugLogging",
    "fmi3InstantiateCoSimulation",
    "fmi3FreeInstance",
    "fmi3EnterInitializationMode",
    "fmi3ExitInitializationMode",
    "fmi3Terminate",
    "fmi3Reset",
    "fmi3GetFloat64",
    "fmi3SetFloat64",
    *_CS,
)
DEFAULT = object()  # logger=DEFAULT: the binding's recording logger


def load(binary: str | Path) -> Library:
    """An FMI 3.0 binary with the FMI 3.0 prototypes set."""
    return Library(binary, SIGNATURES, REQUIRED_CS)


def binary_path(unzip_dir: str | Path, model_identifier: str) -> Path:
    """The Linux x86-64 binary of an unzipped FMI 3.0 FMU (FMI 3.0 s.2.5.1, binaries/x86_64-linux)."""
    return Path(unzip_dir) / "binaries" / "x86_64-linux" / f"{model_identifier}.so"


@dataclass(frozen=True)
class StepResult:
    """The out-arguments of fmi3DoStep."""

    event_handling_needed: bool
    terminate_simulation: bool
    early_return: bool
    last_successful_time: float


_DTYPES = {
    "Float64": np.float64,
    "Float32": np.float32,
    "Int32": np.int32,
    "Int64": np.int64,
    "UInt32": np.uint32,
    "UInt64": np.uint64,
    "Int8": np.int8,
    "UInt8": np.uint8,
    "Int16": np.int16,
    "UInt16": np.uint16,
    "Boolean": np.bool_,
}


class Fmi3Instance(Instance):
    """An fmi3Instance created with fmi3InstantiateCoSimulation. logger: DEFAULT (record in `log`),
    None (a NULL callback) or the address of a C callback."""

    FREE = "fmi3FreeInstance"

    def __init__(
        self,
        lib: Library,
        name: str | None,
        token: str | None,
        resource_path: str | None = None,
        *,
        visible: bool = False,
        logging_on: bool = False,
        event_mode_used: bool = False,
        early_return_allowed: bool = False,
        required: Sequence[int] = (),
        raw: bool = False,
        logger: Any = DEFAULT,
        log_limit: int | None = None,
        on_log: LogHook | None = None,
        on_call: Callable[[str, int], None] | None = None,
    ):
        super().__init__(lib, raw, None, log_limit, on_log, on_call)
        self.name = name
        if logger is DEFAULT:
            self._logger = LogMessage(self._record)
            logger = ctypes.cast(self._logger, c_void_p).value
        self._required = np.array(required, dtype=np.uint32)
        enc = lambda s: None if s is None else s.encode()
        self.c = lib.fmi3InstantiateCoSimulation(
            enc(name),
            enc(token),
            enc(resource_path),
            visible,
            logging_on,
            event_mode_used,
            early_return_allowed,
            self._required.ctypes.data if len(self._required) else None,
            len(self._required),
            None,
            logger,
            None,
        )
        if not self.c and not raw:
            raise FmiError("fmi3InstantiateCoSimulation", ERROR, self.last_message())

    def _record(self, env: Any, status: int, category: bytes | None, message: bytes | None) -> None:
        self._append(LogRecord(self.name or "", int(status), decode(category), decode(message)))

    # --- lifecycle
    def set_debug_logging(self, on: bool, categories: Sequence[str | None] = ()) -> int:
        arr = (c_char_p * max(1, len(categories)))(*[c.encode() if c else None for c in categories])
        return self.check(
            "fmi3SetDebugLogging", self.lib.fmi3SetDebugLogging(self.c, on, len(categories), ctypes.addressof(arr))
        )

    def enter_initialization_mode(
        self, start: float = 0.0, stop: float | None = None, tolerance: float | None = None
    ) -> int:
        return self.check(
            "fmi3EnterInitializationMode",
            self.lib.fmi3EnterInitializationMode(
                self.c,
                tolerance is not None,
                0.0 if tolerance is None else tolerance,
                start,
                stop is not None,
                0.0 if stop is None else stop,
            ),
        )

    def exit_initialization_mode(self) -> int:
        return self.check("fmi3ExitInitializationMode", self.lib.fmi3ExitInitializationMode(self.c))

    def enter_event_mode(self) -> int:
        return self.check("fmi3EnterEventMode", self.lib.fmi3EnterEventMode(self.c))

    def enter_step_mode(self) -> int:
        return self.check("fmi3EnterStepMode", self.lib.fmi3EnterStepMode(self.c))

    def terminate(self) -> int:
        return self.check("fmi3Terminate", self.lib.fmi3Terminate(self.c))

    def reset(self) -> int:
        return self.check("fmi3Reset", self.lib.fmi3Reset(self.c))

    # --- variables: get(type, vrs) / set(type, vrs, values), type one of Float64, Int32, Boolean, ...
    def get(self, typ: str, vrs: Any, n_values: int | None = None) -> np.ndarray:
        """n_values: the array length passed (default: one value per reference, scalars)."""
        v = np.ascontiguousarray(vrs, dtype=np.uint32)
        out = np.zeros(len(v), dtype=_DTYPES[typ])
        fn = f"fmi3Get{typ}"
        self.check(
            fn,
            getattr(self.lib, fn)(
                self.c, v.ctypes.data, len(v), out.ctypes.data, len(v) if n_values is None else n_values
            ),
        )
        return out

    def set(self, typ: str, vrs: Any, values: Any) -> int:
        v = np.ascontiguousarray(vrs, dtype=np.uint32)
        x = np.ascontiguousarray(values, dtype=_DTYPES[typ])
        fn = f"fmi3Set{typ}"
        return self.check(fn, getattr(self.lib, fn)(self.c, v.ctypes.data, len(v), x.ctypes.data, len(x)))

    def get_output_derivatives(self, vrs: Any, orders: Any) -> np.ndarray:
        v, o = np.ascontiguousarray(vrs, dtype=np.uint32), np.ascontiguousarray(orders, dtype=np.int32)
        out = np.zeros(len(v))
        self.check(
            "fmi3GetOutputDerivatives",
            self.lib.fmi3GetOutputDerivatives(self.c, v.ctypes.data, len(v), o.ctypes.data, out.ctypes.data, len(v)),
        )
        return out

    # --- stepping
    def do_step(self, t: float, h: float, no_prior: bool = True) -> StepResult:
        flags = [c_bool(), c_bool(), c_bool()]
        last = c_double()
        self.check(
            "fmi3DoStep",
            self.lib.fmi3DoStep(self.c, t, h, no_prior, *[ctypes.addressof(f) for f in flags], ctypes.addressof(last)),
        )
        return StepResult(flags[0].value, flags[1].value, flags[2].value, last.value)

    # --- FMU states (handles are addresses; None is NULL)
    def get_fmu_state(self, handle: int | None = None) -> int | None:
        h = c_void_p(handle)
        self.check("fmi3GetFMUState", self.lib.fmi3GetFMUState(self.c, ctypes.addressof(h)))
        return h.value

    def set_fmu_state(self, handle: int | None) -> int:
        return self.check("fmi3SetFMUState", self.lib.fmi3SetFMUState(self.c, handle))

    def free_fmu_state(self, handle: int | None) -> int:
        h = c_void_p(handle)
        return self.check("fmi3FreeFMUState", self.lib.fmi3FreeFMUState(self.c, ctypes.addressof(h)))

    def serialize_fmu_state(self, handle: int | None) -> bytes:
        """The serialized state (b'' when the size query fails in raw mode)."""
        size = c_size_t()
        self.check(
            "fmi3SerializedFMUStateSize", self.lib.fmi3SerializedFMUStateSize(self.c, handle, ctypes.addressof(size))
        )
        if failed(self.status):
            return b""
        buf = ctypes.create_string_buffer(size.value)
        self.check(
            "fmi3SerializeFMUState", self.lib.fmi3SerializeFMUState(self.c, handle, ctypes.addressof(buf), size.value)
        )
        return buf.raw

    def deserialize_fmu_state(self, blob: bytes, size: int | None = None) -> int | None:
        """An empty blob is passed as a NULL buffer; size defaults to len(blob)."""
        h = c_void_p()
        buf = ctypes.create_string_buffer(bytes(blob), len(blob)) if blob else None
        self.check(
            "fmi3DeserializeFMUState",
            self.lib.fmi3DeserializeFMUState(
                self.c,
                ctypes.addressof(buf) if buf is not None else None,
                len(blob) if size is None else size,
                ctypes.addressof(h),
            ),
        )
        return h.value
