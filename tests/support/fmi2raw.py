"""Test helpers over the package's FMI binding (harness.fmu.binding) in raw mode, for the black-box
robustness tests: every call returns the raw fmi2Status (an int), pointers may be None (NULL), and
each instance records every logger call (instance name, status, category, formatted message).
The variadic FMI logger is formatted by a tiny C proxy (tests/c/sb_logproxy.c, compiled on first
use into build-sbtests/) exactly as a conforming importer would (vsnprintf), and the memory
callbacks count their calls; both are handed to the binding as the instance's
fmi2CallbackFunctions. The FMU binary is the one packaged in build/ShroudedBlade.fmu (extracted
once per process), unless the environment variable SB_FMU_BINARY names another build of it (the
AddressSanitizer build, see tests/fmu/test_fmu_sanitizers.py). Model-description facts come from
modelDescription.xml, never from the code under test.
"""

from __future__ import annotations

import atexit
import ctypes
import fcntl
import itertools
import math
import os
import re
import shutil
import subprocess
import tempfile
import threading
import xml.etree.ElementTree as ET
import zipfile
from ctypes import CFUNCTYPE, Structure, c_char_p, c_int, c_uint, c_void_p
from dataclasses import dataclass
from pathlib import Path
from typing import Any, MutableSequence, Sequence

import numpy as np

from harness.fmu.binding import fmi2
from harness.fmu.binding.fmi2 import (
    CO_SIMULATION,
    DO_STEP_STATUS,  # noqa: F401
    LAST_SUCCESSFUL_TIME,  # noqa: F401
    MODEL_EXCHANGE,  # noqa: F401
    PENDING_STATUS,  # noqa: F401
    TERMINATED,  # noqa: F401
)
from harness.fmu.binding.fmi2_signatures import MODEL_EXCHANGE as _ME_SIGNATURES
from harness.fmu.binding.library import Library
from harness.fmu.stepper import Derivatives, Stepper, Values
from harness.fmu.binding.log import LogRecord
from harness.fmu.binding.log import decode as _dec
from harness.fmu.binding.status import (
    DISCARD,  # noqa: F401
    ERROR,  # noqa: F401
    FATAL,  # noqa: F401
    OK,
    PENDING,  # noqa: F401
    STATUS_NAMES,  # noqa: F401
    VALID_STATUSES,  # noqa: F401
    WARNING,
)

REPO_ROOT = Path(__file__).resolve().parents[2]
MODEL_DESCRIPTION = REPO_ROOT / "fmu_src" / "models" / "ShroudedBlade" / "modelDescription.xml"
FMU_FILE = REPO_ROOT / "build" / "ShroudedBlade.fmu"
PROXY_SOURCE = REPO_ROOT / "tests" / "c" / "sb_logproxy.c"
TEST_BUILD_DIR = REPO_ROOT / "build-sbtests"

CS_FUNCTIONS = fmi2.REQUIRED_CS  # common + co-simulation: every co-simulation FMU exports them
ME_FUNCTIONS = tuple(_ME_SIGNATURES)  # a co-simulation-only FMU may export them (then they refuse)

PlainLogger = CFUNCTYPE(None, c_void_p, c_char_p, c_int, c_char_p, c_char_p)


class SbLogEnv(Structure):
    _fields_ = [("magic", c_uint), ("callback", PlainLogger), ("cookie", c_void_p)]


SB_LOG_MAGIC = 0x5B10C0DE


# ---------------------------------------------------------------------------------------------
# model description


@dataclass(frozen=True)
class Variable:
    name: str
    vr: int
    type: str  # Real, Integer, Boolean, String
    causality: str
    variability: str
    initial: str | None
    start: Any
    low: float | None
    high: float | None


def _load_md() -> tuple[str, dict[str, Variable], list[str]]:
    root = ET.parse(MODEL_DESCRIPTION).getroot()
    variables: dict[str, Variable] = {}
    for sv in root.iter("ScalarVariable"):
        (typ,) = list(sv)
        start: Any = typ.get("start")
        if start is not None:
            start = {"Real": float, "Integer": int, "Boolean": lambda s: s == "true", "String": str}[typ.tag](start)
        lo, hi = typ.get("min"), typ.get("max")
        variables[sv.get("name")] = Variable(
            sv.get("name"),
            int(sv.get("valueReference")),
            typ.tag,
            sv.get("causality", "local"),
            sv.get("variability", "continuous"),
            sv.get("initial"),
            start,
            None if lo is None else float(lo),
            None if hi is None else float(hi),
        )
    cats = [c.get("name") for c in root.iter("Category")]
    return root.get("guid"), variables, cats


GUID, VARIABLES, LOG_CATEGORIES = _load_md()
VR = {v.name: v.vr for v in VARIABLES.values()}
REAL_OUTPUTS = [v.name for v in VARIABLES.values() if v.causality == "output" and v.type == "Real"]
INT_OUTPUTS = [v.name for v in VARIABLES.values() if v.causality == "output" and v.type == "Integer"]
REAL_PARAMS = [v.name for v in VARIABLES.values() if v.causality == "parameter" and v.type == "Real"]
INT_PARAMS = [v.name for v in VARIABLES.values() if v.causality == "parameter" and v.type == "Integer"]
BOOL_PARAMS = [v.name for v in VARIABLES.values() if v.causality == "parameter" and v.type == "Boolean"]
INPUTS = [v.name for v in VARIABLES.values() if v.causality == "input"]
ALL_VRS = sorted({v.vr for v in VARIABLES.values()})


# ---------------------------------------------------------------------------------------------
# locating / building the binaries


def _locked(path: Path):
    path.parent.mkdir(parents=True, exist_ok=True)
    f = open(path, "w")
    fcntl.flock(f, fcntl.LOCK_EX)
    return f


def proxy_library() -> Path:
    """build-sbtests/libsb_logproxy.so, compiled from tests/c/sb_logproxy.c when out of date."""
    out = TEST_BUILD_DIR / "libsb_logproxy.so"
    with _locked(TEST_BUILD_DIR / ".proxy.lock"):
        if not out.exists() or out.stat().st_mtime < PROXY_SOURCE.stat().st_mtime:
            tmp = out.with_suffix(f".{os.getpid()}.tmp")
            subprocess.run(
                [
                    "cc",
                    "-std=c99",
                    "-O2",
                    "-g",
                    "-fPIC",
                    "-shared",
                    "-Wall",
                    "-Wextra",
                    "-Werror",
                    "-o",
                    str(tmp),
                    str(PROXY_SOURCE),
                ],
                check=True,
            )
            os.replace(tmp, out)
    return out


_extract_lock = threading.Lock()
_extracted: dict[str, Path] = {}


def extract_fmu(fmu: Path = FMU_FILE) -> Path:
    """Unzip the FMU once per process into a temporary directory (with a space in its name, so
    every test also exercises resource URIs with spaces); returns the unzip directory."""
    key = str(fmu)  # once per process: other engineers may rebuild the file meanwhile
    with _extract_lock:
        if key not in _extracted:
            d = Path(tempfile.mkdtemp(prefix="sb fmu "))
            with zipfile.ZipFile(fmu) as z:
                z.extractall(d)
            (d / "resources").mkdir(exist_ok=True)
            _extracted[key] = d
        return _extracted[key]


_spare: list[Path] = []


def _spare_resources() -> Path:
    with _extract_lock:
        if not _spare:
            _spare.append(Path(tempfile.mkdtemp(prefix="sb resources ")))
        return _spare[0]


@atexit.register
def _remove_temporary_dirs() -> None:
    """The unzipped FMUs and spare resource folders of this process go with it."""
    for d in list(_extracted.values()) + _spare:
        shutil.rmtree(d, ignore_errors=True)


def fmu_binary() -> Path:
    """The FMU shared library under test: $SB_FMU_BINARY or the one inside build/ShroudedBlade.fmu."""
    env = os.environ.get("SB_FMU_BINARY")
    if env:
        return Path(env)
    return extract_fmu() / "binaries" / "linux64" / "ShroudedBlade.so"


def resource_uri(binary: Path | None = None, form: str = "file:///") -> str:
    """The resources/ URI of the unzipped FMU, in the form `file:///` (RFC 8089) or `file:/`."""
    binary = (binary or fmu_binary()).resolve()
    root = binary.parent.parent.parent
    if binary.parent.parent.name == "binaries" and (root / "modelDescription.xml").exists():
        path = str(root / "resources")
    else:  # a bare build of the binary (e.g. the sanitizer build): any existing directory will do
        path = str(_spare_resources())
    if form == "file:///":
        return "file://" + path
    if form == "file:/":
        return "file:" + path
    if form == "percent":
        return "file://" + path.replace("%", "%25").replace(" ", "%20")
    raise ValueError(form)


# ---------------------------------------------------------------------------------------------
# the library: the package binding's FMI 2.0 library plus the test proxy's callbacks


_LOG_REGISTRY: dict[int, MutableSequence[LogRecord]] = {}
_LOG_REGISTRY_LOCK = threading.Lock()
_COOKIES = itertools.count(1)
_ORPHANS: list[LogRecord] = []


@PlainLogger
def _plain_logger(cookie, instance_name, status, category, message):  # noqa: ANN001
    with _LOG_REGISTRY_LOCK:
        target = _LOG_REGISTRY.get(cookie or 0)
    rec = LogRecord(_dec(instance_name), int(status), _dec(category), _dec(message))
    (target if target is not None else _ORPHANS).append(rec)


class Fmi2Library(Library):
    """The FMU binary with the binding's FMI 2.0 prototypes, and the test proxy (formatting logger,
    counting memory callbacks). One per binary per process (`get`)."""

    _cache: dict[str, "Fmi2Library"] = {}
    _cache_lock = threading.Lock()

    @classmethod
    def get(cls, binary: Path | None = None) -> "Fmi2Library":
        with cls._cache_lock:
            if binary is None and "default" in cls._cache:
                return cls._cache["default"]
            binary = Path(binary or fmu_binary())
            key = "default" if binary == fmu_binary() else str(binary.resolve())
            if key not in cls._cache:
                cls._cache[key] = cls(binary)
            return cls._cache[key]

    def __init__(self, binary: Path) -> None:
        super().__init__(binary, fmi2.SIGNATURES, fmi2.REQUIRED_CS)
        self.proxy = ctypes.CDLL(str(proxy_library()))
        for name in ("sbOrphanLogs", "sbNullEnvLogs", "sbAllocs", "sbFrees"):
            getattr(self.proxy, name).restype = ctypes.c_long
        self.logger_address = ctypes.cast(self.proxy.sbLogProxy, c_void_p).value
        self.calloc_address = ctypes.cast(self.proxy.sbCalloc, c_void_p).value
        self.free_address = ctypes.cast(self.proxy.sbFree, c_void_p).value
        self.me_exported = [n for n in ME_FUNCTIONS if self.has(n)]

    def orphan_logs(self) -> int:
        return int(self.proxy.sbOrphanLogs())

    def memory_callback_calls(self) -> int:
        return int(self.proxy.sbAllocs()) + int(self.proxy.sbFrees())


def vr_of(names_or_vrs: Sequence[str | int]) -> list[int]:
    return [VR[x] if isinstance(x, str) else int(x) for x in names_or_vrs]


# ---------------------------------------------------------------------------------------------
# one instance


class Instance:
    """One fmi2Component of the package binding in raw mode, with the proxy's recording logger
    (`log`). Every method returns the raw fmi2Status; getters return (status, values)."""

    def __init__(
        self,
        lib: Fmi2Library | None = None,
        name: str | bytes | None = "sb",
        guid: str | bytes | None = GUID,
        fmu_type: int = CO_SIMULATION,
        resources: str | bytes | None = "default",
        logging_on: bool = True,
        visible: bool = False,
        logger: bool = True,
        memory: bool = True,
        callbacks: bool = True,
        environment: bool = True,
    ) -> None:
        self.lib = lib or Fmi2Library.get()
        self.log: list[LogRecord] = []
        self.cookie = next(_COOKIES)
        with _LOG_REGISTRY_LOCK:  # the proxy's records of this instance go to self.log
            _LOG_REGISTRY[self.cookie] = self.log
        self.env = SbLogEnv(SB_LOG_MAGIC, _plain_logger, self.cookie)
        self.callbacks = fmi2.CallbackFunctions(
            self.lib.logger_address if logger else None,
            self.lib.calloc_address if memory else None,
            self.lib.free_address if memory else None,
            None,
            ctypes.addressof(self.env) if environment else None,
        )
        if resources == "default":
            resources = resource_uri(self.lib.path)
        self.name = name
        self.f = fmi2.Fmi2Instance(
            self.lib,
            name,
            guid,
            resources,
            fmu_type,
            visible=visible,
            logging_on=logging_on,
            raw=True,
            callbacks=self.callbacks if callbacks else None,
            log=self.log,
        )

    # --- lifecycle -----------------------------------------------------------------------------
    @property
    def c(self) -> int | None:
        return self.f.c

    @property
    def ok(self) -> bool:
        return self.f.ok

    def free(self) -> None:
        self.f.free_instance()
        with _LOG_REGISTRY_LOCK:
            _LOG_REGISTRY.pop(self.cookie, None)

    def __enter__(self) -> "Instance":
        return self

    def __exit__(self, *exc: Any) -> None:
        self.free()

    def __del__(self) -> None:
        try:
            self.free()
        except Exception:
            pass

    def set_debug_logging(self, on: bool, categories: Sequence[str | None] | None = None, n: int | None = None) -> int:
        return self.f.set_debug_logging(on, categories, n)

    def setup(self, start: float = 0.0, stop: float | None = None, tolerance: float | None = None) -> int:
        return self.f.setup_experiment(start, stop, tolerance)

    def enter_init(self) -> int:
        return self.f.enter_initialization_mode()

    def exit_init(self) -> int:
        return self.f.exit_initialization_mode()

    def terminate(self) -> int:
        return self.f.terminate()

    def reset(self) -> int:
        return self.f.reset()

    # --- get/set (names or value references) ---------------------------------------------------
    def set_real(self, vrs: Sequence[str | int], values: Sequence[float]) -> int:
        return self.f.set_real(vr_of(vrs), values)

    def set_integer(self, vrs: Sequence[str | int], values: Sequence[int]) -> int:
        return self.f.set_integer(vr_of(vrs), values)

    def set_boolean(self, vrs: Sequence[str | int], values: Sequence[int]) -> int:
        return self.f.set_boolean(vr_of(vrs), values)

    def set_string(self, vrs: Sequence[str | int], values: Sequence[str | None]) -> int:
        return self.f.set_string(vr_of(vrs), values)

    def _got(self, values: Any) -> tuple[int, Any]:
        return self.f.status, values

    def get_real(self, vrs: Sequence[str | int]) -> tuple[int, np.ndarray]:
        return self._got(self.f.get_real(vr_of(vrs)))

    def get_integer(self, vrs: Sequence[str | int]) -> tuple[int, np.ndarray]:
        return self._got(self.f.get_integer(vr_of(vrs)))

    def get_boolean(self, vrs: Sequence[str | int]) -> tuple[int, np.ndarray]:
        return self._got(self.f.get_boolean(vr_of(vrs)))

    def get_string(self, vrs: Sequence[str | int]) -> tuple[int, list[str | None]]:
        return self._got(self.f.get_string(vr_of(vrs)))

    def set_input_derivatives(self, vrs: Sequence[str | int], orders: Sequence[int], values: Sequence[float]) -> int:
        return self.f.set_real_input_derivatives(vr_of(vrs), orders, values)

    def get_output_derivatives(self, vrs: Sequence[str | int], orders: Sequence[int]) -> tuple[int, np.ndarray]:
        return self._got(self.f.get_real_output_derivatives(vr_of(vrs), orders))

    # --- stepping ------------------------------------------------------------------------------
    def do_step(self, t: float, h: float, no_prior: bool = True) -> int:
        return self.f.do_step(t, h, no_prior)

    def cancel_step(self) -> int:
        return self.f.cancel_step()

    def get_status(self, kind: int) -> tuple[int, int]:
        return self._got(self.f.get_status(kind))

    def get_real_status(self, kind: int) -> tuple[int, float]:
        return self._got(self.f.get_real_status(kind))

    def get_integer_status(self, kind: int) -> tuple[int, int]:
        return self._got(self.f.get_integer_status(kind))

    def get_boolean_status(self, kind: int) -> tuple[int, int]:
        return self._got(self.f.get_boolean_status(kind))

    def get_string_status(self, kind: int) -> tuple[int, str | None]:
        return self._got(self.f.get_string_status(kind))

    # --- FMU state -----------------------------------------------------------------------------
    def get_state(self, handle: int | None = None) -> tuple[int, int | None]:
        """fmi2GetFMUstate: new handle (handle=None) or update an existing one."""
        return self._got(self.f.get_fmu_state(handle))

    def set_state(self, handle: int | None) -> int:
        return self.f.set_fmu_state(handle)

    def free_state(self, handle: int | None) -> int:
        return self.f.free_fmu_state(handle)

    def state_size(self, handle: int | None) -> tuple[int, int]:
        return self._got(self.f.serialized_fmu_state_size(handle))

    def serialize(self, handle: int | None) -> tuple[int, bytes]:
        return self._got(self.f.serialize_fmu_state(handle))

    def deserialize(
        self, blob: bytes | None, size: int | None = None, handle: int | None = None
    ) -> tuple[int, int | None]:
        return self._got(self.f.deserialize_fmu_state(blob, size, handle))

    # --- conveniences --------------------------------------------------------------------------
    def messages(self, min_status: int = OK) -> list[LogRecord]:
        return [r for r in self.log if r.status >= min_status]

    def log_text(self, calls: bool = False, last: int = 40) -> str:
        """The log for failure messages: without logCalls records unless `calls`, last lines."""
        recs = [r for r in self.log if calls or r.category != "logCalls"]
        return "\n".join(str(r) for r in recs[-last:])

    def clear_log(self) -> None:
        del self.log[:]

    def initialize(
        self,
        params: dict[str, Any] | None = None,
        start: float = 0.0,
        stop: float | None = None,
        inputs: dict[str, float] | None = None,
    ) -> int:
        """setup + start values + enter/exit initialization; returns the worst status. The tests
        feed aeroLoad themselves (run_steps), so the FMU's built-in load is off unless `params` sets Fw0."""
        worst = self.setup(start, stop)
        worst = max(worst, self.set_params({"Fw0": 0.0, **(params or {})}))
        worst = max(worst, self.enter_init())
        if inputs:
            worst = max(worst, self.set_real(list(inputs), list(inputs.values())))
        worst = max(worst, self.exit_init())
        return worst

    def set_params(self, params: dict[str, Any]) -> int:
        worst = OK
        for k, v in params.items():
            t = VARIABLES[k].type
            if t == "Real":
                worst = max(worst, self.set_real([k], [v]))
            elif t == "Integer":
                worst = max(worst, self.set_integer([k], [v]))
            else:
                worst = max(worst, self.set_boolean([k], [int(bool(v))]))
        return worst

    def outputs(self) -> tuple[int, np.ndarray]:
        """All Real outputs then all Integer outputs (as float64), one status."""
        st1, r = self.get_real(REAL_OUTPUTS)
        st2, i = self.get_integer(INT_OUTPUTS)
        return max(st1, st2), np.concatenate([r, i.astype(np.float64)])


# ---------------------------------------------------------------------------------------------
# a standard drive: sine aerodynamic load with its Taylor derivatives (docs/model-notes.md s.1)


def aero_derivatives(t: float, Fw0: float, omega: float, order: int = 8) -> list[float]:
    """Value and derivatives 1..order of Fw0 sin(omega t) (exact). Where the phase overflows (the fuzz
    drives times up to 1e308) the load is taken as 0: any finite drive will do there."""
    phase = omega * t
    if not math.isfinite(phase):
        return [0.0] * (order + 1)
    return [Fw0 * omega**j * math.sin(phase + j * math.pi / 2) for j in range(order + 1)]


def run_steps(
    inst: Instance,
    t0: float,
    h: float,
    n: int,
    Fw0: float = 100.0,
    speed: float = 5000.0,
    engine_order: int = 3,
    order: int = 8,
    speed_slope: float = 0.0,
) -> tuple[int, np.ndarray]:
    """n communication steps from t0 with inputs and derivatives set before each; returns the
    worst status and the (n, n_outputs) array of outputs after each step (stops at non-OK)."""
    omega = engine_order * 2 * math.pi * speed / 60.0
    fmi = Stepper(inst.f)  # the harness's call path (harness/fmu/stepper.py) on this raw instance
    c, inputs = fmi.c, Values(vr_of(["aeroLoad", "rotorSpeed"]))
    aero, aero_values = (
        Derivatives(vr_of(["aeroLoad"] * order), range(1, order + 1)),
        (ctypes.c_double * max(order, 1))(),
    )
    slope, slope_value = Derivatives(vr_of(["rotorSpeed"]), [1]), (ctypes.c_double * 1)(speed_slope)
    rows = []
    worst = OK
    for k in range(n):
        t = t0 + k * h
        d = aero_derivatives(t, Fw0, omega, order)
        inputs.value[0], inputs.value[1] = d[0], speed + speed_slope * (t - t0)
        st = fmi.setReal(c, inputs.a_vr, inputs.n, inputs.a_value)
        if order:
            aero_values[:order] = d[1:]
            st = max(st, fmi.setDer(c, aero.a_vr, aero.n, aero.a_order, ctypes.addressof(aero_values)))
            if speed_slope:
                st = max(st, fmi.setDer(c, slope.a_vr, slope.n, slope.a_order, ctypes.addressof(slope_value)))
        st = max(st, fmi.doStep(c, t, h, 1))
        worst = max(worst, st)
        if st not in (OK, WARNING):
            break
        so, out = inst.outputs()
        worst = max(worst, so)
        rows.append(out)
    return worst, np.array(rows).reshape(len(rows), len(REAL_OUTPUTS) + len(INT_OUTPUTS))


# ---------------------------------------------------------------------------------------------
# the serialized-state format documented in fmu_src/fmi/state_blob.c (magic "SBLDSTAT", int32
# version at offset 8, int32 total size at 12, FNV-1a 64 of the GUID at 16, counts at 24, doubles
# from 32, then int32s, and an FNV-1a 64 checksum of everything before it in the last 8 bytes)

BLOB_MAGIC = b"SBLDSTAT"


def fnv1a(data: bytes) -> int:
    """FNV-1a 64, the checksum of the blob format."""
    h = 0xCBF29CE484222325
    for b in data:
        h = ((h ^ b) * 0x100000001B3) & 0xFFFFFFFFFFFFFFFF
    return h


def reseal(blob: bytes) -> bytes:
    """Recomputes the trailing checksum, so only the FMU's content checks can catch a change."""
    import struct

    return bytes(blob[:-8]) + struct.pack("<Q", fnv1a(bytes(blob[:-8])))


# ---------------------------------------------------------------------------------------------
# checking log messages


_TOKEN = re.compile(r"(?P<num>[-+]?(?:\d+\.?\d*|\.\d+)(?:[eE][-+]?\d+)?)|(?P<id>[A-Za-z_]\w*)")


def numbers_in(text: str) -> list[float]:
    """The numbers written in a message; digits inside identifiers (fmi2SetReal) do not count,
    inf/nan words do."""
    out = []
    for m in _TOKEN.finditer(text):
        if m.group("num") is not None:
            out.append(float(m.group("num")))
        elif m.group("id").lower() in ("inf", "infinity", "nan"):
            neg = m.start() > 0 and text[m.start() - 1] == "-"
            out.append(-float(m.group("id")) if neg else float(m.group("id")))
    return out


def _same(a: float, b: float) -> bool:
    if math.isnan(a) or math.isnan(b):
        return math.isnan(a) and math.isnan(b)
    if math.isinf(a) or math.isinf(b):
        return a == b
    # %g prints 6 significant digits: accept a relative difference of 1e-5.
    return abs(a - b) <= 1e-5 * max(abs(a), abs(b)) or abs(a - b) < 1e-300


def message_names_value_and_range(
    text: str, name: str, value: float, low: float | None, high: float | None
) -> list[str]:
    """What a parameter/input error message lacks: [] when it names the variable, shows the
    rejected value and both finite bounds of the accepted range (pi/2 may be written 'pi/2')."""
    problems = []
    if not re.search(rf"(?<![A-Za-z0-9_]){re.escape(name)}(?![A-Za-z0-9_])", text):
        problems.append(f"name {name!r} missing")
    nums = numbers_in(text)
    needed = [value] + [b for b in (low, high) if b is not None and math.isfinite(b)]
    pool = list(nums)
    for want in needed:
        if (
            low is not None
            and high is not None
            and want == high
            and abs(want - math.pi / 2) < 1e-12
            and re.search(r"pi\s*/\s*2", text, re.IGNORECASE)
        ):
            continue
        hit = next((i for i, x in enumerate(pool) if _same(x, want)), None)
        if hit is None:
            problems.append(f"number {want!r} missing")
        else:
            pool.pop(hit)
    return problems


# ---------------------------------------------------------------------------------------------
# the sanitizer build (tests/c/CMakeLists.txt, option SB_SANITIZE)

ASAN_BUILD_DIR = REPO_ROOT / "build-asan"
SANITIZER_REPORT = re.compile(
    r"ERROR: AddressSanitizer|ERROR: LeakSanitizer|runtime error:|"
    r"SUMMARY: (Address|Undefined|Leak)Sanitizer"
)


def build_asan() -> tuple[Path, Path]:
    """Configures (once) and builds build-asan/: the FMU binaries (FMI 2.0; FMI 3.0 in
    build-asan/fmi3/, see ASAN_FMI3_BINARY) and tests/c/sb_importer, all with
    -fsanitize=address,undefined,float-cast-overflow -fno-sanitize-recover=all. Returns
    (FMI 2.0 FMU binary, importer)."""
    import sys

    d = ASAN_BUILD_DIR
    with _locked(d / ".build.lock"):
        if not (d / "CMakeCache.txt").exists():
            subprocess.run(
                [
                    "cmake",
                    "-S",
                    str(REPO_ROOT),
                    "-B",
                    str(d),
                    "-DSB_SANITIZE=ON",
                    "-DCMAKE_BUILD_TYPE=RelWithDebInfo",
                    f"-DPython3_EXECUTABLE={sys.executable}",
                ],
                check=True,
                capture_output=True,
                text=True,
            )
        proc = subprocess.run(
            ["cmake", "--build", str(d), "-j", "2", "--target", "ShroudedBlade", "ShroudedBlade3", "sb_importer"],
            capture_output=True,
            text=True,
        )
        if proc.returncode != 0:
            raise RuntimeError(f"sanitizer build failed:\n{proc.stdout[-4000:]}\n{proc.stderr[-4000:]}")
    return d / "ShroudedBlade.so", d / "tests" / "c" / "sb_importer"


ASAN_FMI3_BINARY = ASAN_BUILD_DIR / "fmi3" / "ShroudedBlade.so"


def sanitizer_env(python: bool) -> dict[str, str]:
    """Environment for a sanitized run. For a Python child, libasan is preloaded (the interpreter
    itself is not instrumented) and leak detection is off (the interpreter's own allocations at
    exit are not leaks of the FMU); the C importer runs with LeakSanitizer on."""
    env = os.environ.copy()
    # distinct exit codes: 99 = AddressSanitizer/LeakSanitizer, 98 = UndefinedBehaviorSanitizer
    env["UBSAN_OPTIONS"] = "print_stacktrace=1:halt_on_error=1:exitcode=98"
    if python:
        libasan = subprocess.run(
            ["cc", "-print-file-name=libasan.so"], capture_output=True, text=True, check=True
        ).stdout.strip()
        env["LD_PRELOAD"] = str(Path(libasan).resolve())
        env["ASAN_OPTIONS"] = "detect_leaks=0:halt_on_error=1:abort_on_error=0:exitcode=99"
    else:
        env.pop("LD_PRELOAD", None)
        env["ASAN_OPTIONS"] = (
            "detect_leaks=1:halt_on_error=1:abort_on_error=0:exitcode=99:"
            "detect_stack_use_after_return=1:strict_string_checks=1"
        )
    return env
