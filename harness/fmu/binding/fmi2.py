"""One FMI 2.0 instance (co-simulation or model exchange) over a Library with the FMI 2.0 table.

Checked mode (default): a call returning Discard, Error, Fatal or Pending raises FmiError naming
the function, the status and the instance's last logged message. Raw mode (raw=True, the
robustness tests): nothing raises; every method returns the status (getters return their values
and leave the status in `status`, which every call updates). Hot loops call the Library's raw
functions with `c` directly (`lib.fmi2DoStep(inst.c, t, h, 1)`).

Callbacks: by default a per-instance Python logger that records every call in `log` (the FMI 2.0
logger is variadic and ctypes cannot format it: the binding takes the message as the FMU passed
it, with '%%' read as '%' -- our FMUs format their messages themselves and escape '%', the rest
of the printf syntax is not interpreted) and the C library's calloc/free as memory callbacks
(FMI 2.0 requires them). A caller may pass its own fmi2CallbackFunctions instead (callbacks=...,
None for a NULL pointer), e.g. a C logger that formats with vsnprintf."""

from __future__ import annotations

import ctypes
import math
from ctypes import CFUNCTYPE, Structure, c_char_p, c_double, c_int, c_size_t, c_uint, c_void_p
from pathlib import Path
from typing import Any, Callable, MutableSequence, Sequence

import numpy as np

from harness.fmu.binding.fmi2_signatures import CO_SIMULATION as _CS
from harness.fmu.binding.fmi2_signatures import COMMON as _COMMON
from harness.fmu.binding.fmi2_signatures import SIGNATURES
from harness.fmu.binding.instance import Instance
from harness.fmu.binding.library import Library
from harness.fmu.binding.log import LogHook, LogRecord, decode
from harness.fmu.binding.status import ERROR, FmiError, failed

MODEL_EXCHANGE, CO_SIMULATION = 0, 1  # fmi2Type
DO_STEP_STATUS, PENDING_STATUS, LAST_SUCCESSFUL_TIME, TERMINATED = 0, 1, 2, 3  # fmi2StatusKind
REQUIRED_CS = tuple(list(_COMMON) + list(_CS))  # what a co-simulation FMU must export

Logger = CFUNCTYPE(None, c_void_p, c_char_p, c_int, c_char_p, c_char_p)  # variadic tail not read


class CallbackFunctions(Structure):
    """fmi2CallbackFunctions with plain pointers, so any member can be NULL."""

    _fields_ = [
        ("logger", c_void_p),
        ("allocateMemory", c_void_p),
        ("freeMemory", c_void_p),
        ("stepFinished", c_void_p),
        ("componentEnvironment", c_void_p),
    ]


class EventInfo(Structure):
    """fmi2EventInfo (fmi2NewDiscreteStates)."""

    _fields_ = [
        ("newDiscreteStatesNeeded", c_int),
        ("terminateSimulation", c_int),
        ("nominalsOfContinuousStatesChanged", c_int),
        ("valuesOfContinuousStatesChanged", c_int),
        ("nextEventTimeDefined", c_int),
        ("nextEventTime", c_double),
    ]


_LIBC = ctypes.CDLL(None)
CALLOC = ctypes.cast(_LIBC.calloc, c_void_p).value
FREE = ctypes.cast(_LIBC.free, c_void_p).value
DEFAULT = object()  # callbacks=DEFAULT: the binding's own logger and memory callbacks


def load(binary: str | Path) -> Library:
    """An FMI 2.0 binary with the FMI 2.0 prototypes set."""
    return Library(binary, SIGNATURES, REQUIRED_CS)


def binary_path(unzip_dir: str | Path, model_identifier: str) -> Path:
    """The Linux x86-64 binary of an unzipped FMI 2.0 FMU (FMI 2.0 s.2.4, binaries/linux64)."""
    return Path(unzip_dir) / "binaries" / "linux64" / f"{model_identifier}.so"


def resource_uri(unzip_dir: str | Path) -> str:
    """The fmuResourceLocation of an unzipped FMU: the file URI of its resources/ folder."""
    return Path(unzip_dir, "resources").resolve().as_uri()


def _u32(vrs: Any) -> np.ndarray:
    return np.ascontiguousarray(vrs, dtype=np.uint32)


# Scalar access builds ctypes arrays: for the few values a master moves per call they cost a
# fraction of numpy's `.ctypes.data` (the ring master makes several such calls per FMU and step).
_SENTINEL = {c_double: math.nan, c_int: -987654}  # what a raw-mode getter leaves where the FMU wrote nothing


def _enc(s: str | bytes | None) -> bytes | None:
    return s.encode() if isinstance(s, str) else s


class Fmi2Instance(Instance):
    """An fmi2Component (see Instance for the log, status and the two modes)."""

    FREE = "fmi2FreeInstance"

    def __init__(
        self,
        lib: Library,
        name: str | bytes | None,
        guid: str | bytes | None,
        resource_uri: str | bytes | None,
        kind: int = CO_SIMULATION,
        *,
        visible: bool = False,
        logging_on: bool = False,
        raw: bool = False,
        callbacks: Any = DEFAULT,
        log: MutableSequence[LogRecord] | None = None,
        log_limit: int | None = None,
        on_log: LogHook | None = None,
        on_call: Callable[[str, int], None] | None = None,
    ):
        super().__init__(lib, raw, log, log_limit, on_log, on_call)
        self.name = decode(name) if isinstance(name, bytes) else name
        if callbacks is DEFAULT:
            self._logger = Logger(self._record)
            callbacks = CallbackFunctions(ctypes.cast(self._logger, c_void_p).value, CALLOC, FREE, None, None)
        self.callbacks = callbacks  # kept alive until after fmi2FreeInstance
        self._name_buf = _enc(name)
        self.c = lib.fmi2Instantiate(
            self._name_buf,
            kind,
            _enc(guid),
            _enc(resource_uri),
            None if callbacks is None else ctypes.addressof(callbacks),
            int(visible),
            int(logging_on),
        )
        if not self.c and not raw:
            raise FmiError("fmi2Instantiate", ERROR, self.last_message())

    def _record(
        self, env: Any, instance: bytes | None, status: int, category: bytes | None, message: bytes | None
    ) -> None:
        text = decode(message)
        self._append(
            LogRecord(
                decode(instance), int(status), decode(category), None if text is None else text.replace("%%", "%")
            )
        )

    # --- lifecycle
    def set_debug_logging(self, on: bool, categories: Sequence[str | None] | None = (), n: int | None = None) -> int:
        """categories None: a NULL array (with n, default 0, as its length)."""
        if categories is None:
            return self.check("fmi2SetDebugLogging", self.lib.fmi2SetDebugLogging(self.c, int(on), n or 0, None))
        bufs = (c_char_p * max(1, len(categories)))(*[None if s is None else s.encode() for s in categories])
        return self.check(
            "fmi2SetDebugLogging",
            self.lib.fmi2SetDebugLogging(self.c, int(on), len(categories) if n is None else n, ctypes.addressof(bufs)),
        )

    def setup_experiment(self, start: float = 0.0, stop: float | None = None, tolerance: float | None = None) -> int:
        return self.check(
            "fmi2SetupExperiment",
            self.lib.fmi2SetupExperiment(
                self.c,
                int(tolerance is not None),
                0.0 if tolerance is None else tolerance,
                start,
                int(stop is not None),
                0.0 if stop is None else stop,
            ),
        )

    def enter_initialization_mode(self) -> int:
        return self.check("fmi2EnterInitializationMode", self.lib.fmi2EnterInitializationMode(self.c))

    def exit_initialization_mode(self) -> int:
        return self.check("fmi2ExitInitializationMode", self.lib.fmi2ExitInitializationMode(self.c))

    def terminate(self) -> int:
        return self.check("fmi2Terminate", self.lib.fmi2Terminate(self.c))

    def reset(self) -> int:
        return self.check("fmi2Reset", self.lib.fmi2Reset(self.c))

    # --- variables (value references: a sequence or array of ints)
    def _get(self, function: str, vrs: Any, ctype: Any, dtype: Any) -> np.ndarray:
        n = len(vrs)
        out = (ctype * n)(*([_SENTINEL[ctype]] * n)) if self.raw else (ctype * n)()
        self.check(function, getattr(self.lib, function)(self.c, (c_uint * n)(*vrs), n, out))
        return np.frombuffer(out, dtype=dtype) if n else np.zeros(0, dtype=dtype)

    def _set(self, function: str, vrs: Any, values: Any) -> int:
        n = len(vrs)
        return self.check(function, getattr(self.lib, function)(self.c, (c_uint * n)(*vrs), n, values))

    def get_real(self, vrs: Any) -> np.ndarray:
        return self._get("fmi2GetReal", vrs, c_double, np.float64)

    def get_integer(self, vrs: Any) -> np.ndarray:
        return self._get("fmi2GetInteger", vrs, c_int, np.int32)

    def get_boolean(self, vrs: Any) -> np.ndarray:
        """fmi2Boolean values as ints (0/1; another value is the FMU's, shown as it is)."""
        return self._get("fmi2GetBoolean", vrs, c_int, np.int32)

    def get_string(self, vrs: Any) -> list[str | None]:
        v = _u32(vrs)
        arr = (c_char_p * max(1, len(v)))()
        self.check("fmi2GetString", self.lib.fmi2GetString(self.c, v.ctypes.data, len(v), ctypes.addressof(arr)))
        return [decode(arr[i]) for i in range(len(v))]

    def set_real(self, vrs: Any, values: Any) -> int:
        """values: as many numbers as vrs (a shorter list is passed zero-padded: the FMU reads len(vrs))."""
        return self._set("fmi2SetReal", vrs, (c_double * max(len(vrs), len(values)))(*values))

    def set_integer(self, vrs: Any, values: Any) -> int:
        x = np.ascontiguousarray(values, dtype=np.int32)  # numpy's conversion (floats truncate); alive during the call
        return self._set("fmi2SetInteger", vrs, x.ctypes.data)

    def set_boolean(self, vrs: Any, values: Any) -> int:
        """values: ints or bools (any int is passed on as it is: fmi2Boolean is a C int)."""
        x = np.ascontiguousarray(values, dtype=np.int32)
        return self._set("fmi2SetBoolean", vrs, x.ctypes.data)

    def set_string(self, vrs: Any, values: Sequence[str | None]) -> int:
        v = _u32(vrs)
        arr = (c_char_p * max(1, len(values)))(*[None if s is None else s.encode() for s in values])
        return self.check("fmi2SetString", self.lib.fmi2SetString(self.c, v.ctypes.data, len(v), ctypes.addressof(arr)))

    def set_real_input_derivatives(self, vrs: Any, orders: Any, values: Any) -> int:
        n = len(vrs)
        return self.check(
            "fmi2SetRealInputDerivatives",
            self.lib.fmi2SetRealInputDerivatives(
                self.c,
                (c_uint * n)(*vrs),
                n,
                (c_int * max(n, len(orders)))(*orders),
                (c_double * max(n, len(values)))(*values),
            ),
        )

    def get_real_output_derivatives(self, vrs: Any, orders: Any) -> np.ndarray:
        v, o = _u32(vrs), np.ascontiguousarray(orders, dtype=np.int32)
        out = np.full(len(v), math.nan)
        self.check(
            "fmi2GetRealOutputDerivatives",
            self.lib.fmi2GetRealOutputDerivatives(self.c, v.ctypes.data, len(v), o.ctypes.data, out.ctypes.data),
        )
        return out

    def get_directional_derivative(self, unknowns: Any, knowns: Any, seed: Any) -> np.ndarray:
        u, k = _u32(unknowns), _u32(knowns)
        s = np.ascontiguousarray(seed, dtype=np.float64)
        out = np.full(len(u), math.nan)
        self.check(
            "fmi2GetDirectionalDerivative",
            self.lib.fmi2GetDirectionalDerivative(
                self.c, u.ctypes.data, len(u), k.ctypes.data, len(k), s.ctypes.data, out.ctypes.data
            ),
        )
        return out

    # --- co-simulation
    def do_step(self, t: float, h: float, no_prior: bool = True) -> int:
        return self.check("fmi2DoStep", self.lib.fmi2DoStep(self.c, t, h, int(no_prior)))

    def cancel_step(self) -> int:
        return self.check("fmi2CancelStep", self.lib.fmi2CancelStep(self.c))

    def _status_of(self, function: str, kind: int, value: Any) -> Any:
        self.check(function, getattr(self.lib, function)(self.c, kind, ctypes.addressof(value)))
        return value.value

    def get_status(self, kind: int) -> int:
        return self._status_of("fmi2GetStatus", kind, c_int(-1))

    def get_real_status(self, kind: int) -> float:
        return self._status_of("fmi2GetRealStatus", kind, c_double(math.nan))

    def get_integer_status(self, kind: int) -> int:
        return self._status_of("fmi2GetIntegerStatus", kind, c_int(-1))

    def get_boolean_status(self, kind: int) -> int:
        return self._status_of("fmi2GetBooleanStatus", kind, c_int(-1))

    def get_string_status(self, kind: int) -> str | None:
        return decode(self._status_of("fmi2GetStringStatus", kind, c_char_p()))

    # --- FMU states (handles are addresses; None is NULL)
    def get_fmu_state(self, handle: int | None = None) -> int | None:
        """A new state (handle None) or an update of `handle`."""
        return self._status_of_handle("fmi2GetFMUstate", handle)

    def _status_of_handle(self, function: str, handle: int | None) -> int | None:
        s = c_void_p(handle)
        self.check(function, getattr(self.lib, function)(self.c, ctypes.addressof(s)))
        return s.value

    def set_fmu_state(self, handle: int | None) -> int:
        return self.check("fmi2SetFMUstate", self.lib.fmi2SetFMUstate(self.c, handle))

    def free_fmu_state(self, handle: int | None) -> int:
        s = c_void_p(handle)
        return self.check("fmi2FreeFMUstate", self.lib.fmi2FreeFMUstate(self.c, ctypes.addressof(s)))

    def serialized_fmu_state_size(self, handle: int | None) -> int:
        n = c_size_t(0)
        self.check(
            "fmi2SerializedFMUstateSize", self.lib.fmi2SerializedFMUstateSize(self.c, handle, ctypes.addressof(n))
        )
        return n.value

    def serialize_fmu_state(self, handle: int | None) -> bytes:
        """The serialized state (b'' when the size query fails in raw mode)."""
        n = self.serialized_fmu_state_size(handle)
        if failed(self.status):
            return b""
        buf = ctypes.create_string_buffer(n)
        self.check("fmi2SerializeFMUstate", self.lib.fmi2SerializeFMUstate(self.c, handle, ctypes.addressof(buf), n))
        return buf.raw[:n]

    def deserialize_fmu_state(
        self, blob: bytes | None, size: int | None = None, handle: int | None = None
    ) -> int | None:
        """blob None: a NULL buffer (with size, default 0); size defaults to len(blob)."""
        s = c_void_p(handle)
        if blob is None:
            st = self.lib.fmi2DeSerializeFMUstate(self.c, None, size or 0, ctypes.addressof(s))
        else:
            buf = ctypes.create_string_buffer(bytes(blob), max(1, len(blob)))
            st = self.lib.fmi2DeSerializeFMUstate(
                self.c, ctypes.addressof(buf), len(blob) if size is None else size, ctypes.addressof(s)
            )
        self.check("fmi2DeSerializeFMUstate", st)
        return s.value

    # --- model exchange (FMI 2.0 s.3.2)
    def enter_event_mode(self) -> int:
        return self.check("fmi2EnterEventMode", self.lib.fmi2EnterEventMode(self.c))

    def enter_continuous_time_mode(self) -> int:
        return self.check("fmi2EnterContinuousTimeMode", self.lib.fmi2EnterContinuousTimeMode(self.c))

    def new_discrete_states(self) -> EventInfo:
        info = EventInfo()
        self.check("fmi2NewDiscreteStates", self.lib.fmi2NewDiscreteStates(self.c, ctypes.addressof(info)))
        return info

    def completed_integrator_step(self, no_prior: bool = True) -> tuple[bool, bool]:
        """(enterEventMode, terminateSimulation)."""
        enter, stop = c_int(0), c_int(0)
        self.check(
            "fmi2CompletedIntegratorStep",
            self.lib.fmi2CompletedIntegratorStep(
                self.c, int(no_prior), ctypes.addressof(enter), ctypes.addressof(stop)
            ),
        )
        return bool(enter.value), bool(stop.value)

    def set_time(self, t: float) -> int:
        return self.check("fmi2SetTime", self.lib.fmi2SetTime(self.c, t))

    def set_continuous_states(self, x: Any) -> int:
        a = np.ascontiguousarray(x, dtype=np.float64)
        return self.check("fmi2SetContinuousStates", self.lib.fmi2SetContinuousStates(self.c, a.ctypes.data, len(a)))

    def _vector(self, function: str, n: int) -> np.ndarray:
        out = np.full(n, math.nan)
        self.check(function, getattr(self.lib, function)(self.c, out.ctypes.data, n))
        return out

    def get_continuous_states(self, n: int) -> np.ndarray:
        return self._vector("fmi2GetContinuousStates", n)

    def get_derivatives(self, n: int) -> np.ndarray:
        return self._vector("fmi2GetDerivatives", n)

    def get_event_indicators(self, n: int) -> np.ndarray:
        return self._vector("fmi2GetEventIndicators", n)

    def get_nominals_of_continuous_states(self, n: int) -> np.ndarray:
        return self._vector("fmi2GetNominalsOfContinuousStates", n)
