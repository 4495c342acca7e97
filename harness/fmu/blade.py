"""Locate/build the ShroudedBlade FMU and drive it fast: a context-managed wrapper over the project's
FMI binding (harness.fmu.binding; fmpy reads the model description and extracts the FMU).

`BladeFMU` extracts the FMU once, instantiates it once, and for every `run()` calls fmi2Reset,
sets the (validated) parameters, initializes and steps over a fixed communication grid. The step
loop is built for sweeps with millions of doSteps: input values and all input derivatives for the
whole grid are computed with numpy before the loop (`step_inputs`: the load's Taylor expansion at
each step start, or its Chebyshev interpolant over the step, accurate at 2 steps per period); per
step it makes only raw ctypes calls with prebuilt arrays: fmi2SetReal (both inputs; only before the
first step with `carry_values`), one fmi2SetRealInputDerivatives (all orders of both inputs),
fmi2DoStep, and fmi2GetReal into a preallocated array on sampled steps. An FMU status
Discard/Error becomes `FMUError` carrying the FMU's log messages, the time reached and the partial
result. The instance is always terminated and freed, and the extracted directory removed.
"""

from __future__ import annotations

import collections
import ctypes
import math
import shutil
import sys
from pathlib import Path
from typing import Any, Callable, Mapping, Sequence, TypeVar

import numpy as np
from fmpy import extract, read_model_description

from harness.fmu import build as _build
from harness.fmu.binding import FmiError, LogRecord, fmi2
from harness.fmu.stepper import STATUS, Stepper, Values
from harness.model.excitation import MAX_ORDER, AeroLoad, ExcitationError, Piecewise, Signal, as_speed
from harness.model.params import ParameterError, fmu_parameters, input_range, validate, value_reference
from harness.paths import IN_CHECKOUT, REPO_ROOT

Result = TypeVar("Result")  # what a guarded FMI call returns

VR_AERO, VR_SPEED = value_reference("aeroLoad"), value_reference("rotorSpeed")  # modelDescription.xml
SPEED_RANGE = input_range("rotorSpeed")  # rotorSpeed min/max [rpm], from modelDescription.xml
_ERROR_CATEGORIES = ["logStatusWarning", "logStatusDiscard", "logStatusError", "logStatusFatal"]


class FMUNotFoundError(FileNotFoundError):
    """No FMU file where expected; the message says how to build or point to one."""


class FMUError(RuntimeError):
    """The FMU returned Discard/Error/Fatal. Carries `time` (last communication point reached),
    `partial` (results up to it), `messages` (the FMU's log) and `status`."""

    def __init__(
        self,
        message: str,
        *,
        time: float = math.nan,
        partial: np.ndarray | None = None,
        messages: Sequence[str] = (),
        status: int = 3,
        function: str = "",
    ):
        super().__init__(message)
        self.time, self.partial, self.messages = time, partial, list(messages)
        self.status, self.function = status, function


class FMUState(bytes):
    """A serialized FMU state (the bytes of fmi2SerializeFMUstate) that remembers its time."""

    time: float | None = None
    params: dict[str, Any] | None = None


def fmu_path(build: bool = True) -> Path:
    """build/ShroudedBlade.fmu, built (if out of date) when `build` and the C sources are present;
    installed: the package's own (harness/fmus/ShroudedBlade.fmu)."""
    sources = list((REPO_ROOT / "fmu_src").rglob("*.c")) if IN_CHECKOUT else []
    if build and sources and shutil.which("cmake"):
        try:
            return _build.build(("fmu",))
        except _build.BuildError as exc:
            first = str(exc).splitlines()[0] if str(exc) else "cmake failed"
            raise FMUNotFoundError(
                f"building {_build.FMU_PATH} failed ({first}): run `make fmu` to see the compiler output"
            ) from exc
    if not _build.FMU_PATH.is_file():
        how = "build it with `make fmu`" if IN_CHECKOUT else "reinstall the harness with `pip install`"
        raise FMUNotFoundError(
            f"{_build.FMU_PATH} not found: {how} (needs cmake and a C compiler) or pass the path of an FMU"
        )
    return _build.FMU_PATH


# where the harness's own FMU comes from, in both settings
OWN_FMU = "installed: inside the package, `pip install` again if it is missing; checkout: `make fmu`"


def _missing_file_message(path: Path) -> str:
    """What to do about an FMU path that is not a file: a directory is named as one (with the FMU
    inside it, if there is one), a missing file as missing."""
    if path.is_dir():
        inside = sorted(path.glob("*.fmu"))
        hint = f"did you mean {inside[0]}?" if inside else "it holds no .fmu file"
        return f"FMU path {path} is a directory, not an FMU file: pass the .fmu file itself ({hint})"
    return f"FMU file {path} not found: check the path, or leave the path out to use the harness's own FMU ({OWN_FMU})"


INPUT_FITS = ("taylor", "chebyshev")


def input_error(omega_h: float, order: int, fit: str = "taylor") -> float:
    """Bound of the relative error of a sine input over one communication step of phase length
    omega_h [rad] represented by a polynomial of degree `order`: Taylor at the step start
    (omega h)^(K+1)/(K+1)!, Chebyshev interpolation 2 (omega h / 4)^(K+1)/(K+1)!."""
    if fit not in INPUT_FITS:
        raise ParameterError(f"input_fit = {fit!r}: choose from {', '.join(INPUT_FITS)}")
    x = omega_h / 4.0 if fit == "chebyshev" else omega_h
    return (2.0 if fit == "chebyshev" else 1.0) * x ** (order + 1) / math.factorial(order + 1)


_CHEB: dict[int, tuple[np.ndarray, np.ndarray]] = {}


def _cheb(order: int) -> tuple[np.ndarray, np.ndarray]:
    """Chebyshev nodes s_i of [0, 1] and the inverse Vandermonde matrix mapping the values at them
    to the monomial coefficients of the interpolant in s (condition number 7e5 at degree 8)."""
    if order not in _CHEB:
        i = np.arange(order + 1)
        s = 0.5 * (1.0 - np.cos((2 * i + 1) * math.pi / (2 * (order + 1))))
        _CHEB[order] = (s, np.linalg.inv(s[:, None] ** np.arange(order + 1)[None, :]))
    return _CHEB[order]


def step_inputs(signal: Signal, grid: np.ndarray, order: int, fit: str = "taylor") -> np.ndarray:
    """Value and derivatives 1..order the master sets at the start of each step of `grid`, shape
    (order + 1, len(grid) - 1). "taylor": the signal's derivatives at the step start. "chebyshev":
    the derivatives at the step start of the degree-`order` polynomial interpolating the signal at
    the Chebyshev nodes of the step (the FMU evaluates exactly that polynomial over the step; its
    value at the step start differs from the signal by the interpolation error)."""
    if fit not in INPUT_FITS:
        raise ParameterError(f"input_fit = {fit!r}: choose from {', '.join(INPUT_FITS)}")
    if fit == "taylor" or order == 0:
        return np.asarray(signal.derivatives(grid[:-1], order), dtype=float)
    s, Vinv = _cheb(order)
    t0, h = grid[:-1], np.diff(grid)
    tt = t0[:, None] + h[:, None] * s[None, :]
    F = np.asarray(signal(tt.ravel()), dtype=float).reshape(tt.shape)  # (N, order + 1): signals take 1-D t
    c = F @ Vinv.T  # c_j: coefficient of s^j, s = (t - t0) / h
    j = np.arange(order + 1)
    fact = np.array([math.factorial(int(k)) for k in j], dtype=float)
    out: np.ndarray = (c * fact[None, :] / h[:, None] ** j[None, :]).T
    return out


class _InputTable:
    """The inputs of a whole run, computed before the loop: per step the values (aeroLoad,
    rotorSpeed) and their derivatives 1..order, contiguous, with the address of each step's slice
    (8 (2K + 2) bytes per step) and the value references the FMI calls take."""

    def __init__(
        self,
        grid: np.ndarray,
        aero: Signal,
        speed: Signal,
        order: int,
        fit: str,
        check: Callable[[np.ndarray, np.ndarray, np.ndarray], None],
    ) -> None:
        aero_in = step_inputs(aero, grid, order, fit)  # (order + 1, steps)
        speed_in = np.asarray(speed.derivatives(grid, order), dtype=float)  # (order + 1, grid points)
        check(grid, aero_in, speed_in)
        speed_in = speed_in[:, :-1]
        self.values = np.ascontiguousarray(np.stack([aero_in[0], speed_in[0]], axis=1))
        self.derivs = np.ascontiguousarray(np.concatenate([aero_in[1:].T, speed_in[1:].T], axis=1))
        self.first = (float(aero(grid[0])), float(speed_in[0, 0]))  # the start values of the inputs
        steps = np.arange(len(grid) - 1)
        self.value_addr = (self.values.ctypes.data + 16 * steps).tolist()
        self.deriv_addr = (self.derivs.ctypes.data + 16 * order * steps).tolist()
        self.n_derivatives = 2 * order
        self._vr_in = (ctypes.c_uint * 2)(VR_AERO, VR_SPEED)
        self._vr_der = (ctypes.c_uint * (2 * order + 1))(*([VR_AERO] * order + [VR_SPEED] * order))
        self._order = (ctypes.c_int * (2 * order + 1))(*(list(range(1, order + 1)) * 2))
        self.a_vr_in, self.a_vr_der = ctypes.addressof(self._vr_in), ctypes.addressof(self._vr_der)
        self.a_order = ctypes.addressof(self._order)


class _Recorder:
    """The sampled outputs of a run: preallocated rows (the start, every `sample_every`-th step,
    the end), the address each sampled step writes to, and the structured result of the rows
    filled so far (also the partial result an FMUError carries)."""

    def __init__(self, fmu: "BladeFMU", grid: np.ndarray, real: list[str], ints: list[str], sample_every: int):
        self.fmu, self.real, self.ints, self.sample_every = fmu, real, ints, sample_every
        n = len(grid) - 1
        sampled = np.zeros(n + 1, dtype=bool)
        sampled[::sample_every] = True
        sampled[0] = sampled[n] = True
        self.times = grid[sampled]
        self.out_real = np.zeros((len(self.times), max(len(real), 1)))
        self.out_int = np.zeros((len(self.times), max(len(ints), 1)), dtype=np.int32)
        row_real, row_int = 8 * self.out_real.shape[1], 4 * self.out_int.shape[1]  # bytes per row
        row_after = np.cumsum(sampled[1:])  # the row written after step k (if sampled)
        self.rows_before = np.concatenate([[1], 1 + row_after]).tolist()  # rows filled before step k
        self.real_addr = (
            np.where(sampled[1:], self.out_real.ctypes.data + row_real * row_after, 0).tolist() if real else [0] * n
        )
        self.int_addr = (
            np.where(sampled[1:], self.out_int.ctypes.data + row_int * row_after, 0).tolist() if ints else [0] * n
        )
        self._vr_real = (ctypes.c_uint * max(len(real), 1))(*[fmu.variables[v].valueReference for v in real])
        self._vr_int = (ctypes.c_uint * max(len(ints), 1))(*[fmu.variables[v].valueReference for v in ints])
        self.a_vr_real, self.a_vr_int = ctypes.addressof(self._vr_real), ctypes.addressof(self._vr_int)

    def sample_start(self) -> None:
        """Row 0: the outputs at the start of the run."""
        fmi, t = self.fmu.stepper, float(self.times[0])
        st_real = fmi.getReal(fmi.c, self.a_vr_real, len(self.real), self.out_real.ctypes.data) if self.real else 0
        st_int = fmi.getInteger(fmi.c, self.a_vr_int, len(self.ints), self.out_int.ctypes.data) if self.ints else 0
        if (st_real | st_int) > 1:
            raise self.fmu.failure("fmi2GetReal/fmi2GetInteger", max(st_real, st_int), t, self.result(0))

    def result(self, rows: int) -> np.ndarray:
        dt = np.dtype([("time", float)] + [(v, float) for v in self.real] + [(v, np.int32) for v in self.ints])
        res = np.zeros(rows, dtype=dt)
        res["time"] = self.times[:rows]
        for j, v in enumerate(self.real):
            res[v] = self.out_real[:rows, j]
        for j, v in enumerate(self.ints):
            res[v] = self.out_int[:rows, j]
        return res


class BladeFMU:
    """The ShroudedBlade FMU, extracted and instantiated once; use as a context manager.

    log=True: enable all FMU log categories and echo messages to stderr (errors and warnings are
    always captured). fmi_logging=True: print every FMI call of the step loop to stderr (slow).
    """

    def __init__(self, path: str | Path | None = None, log: bool = False, fmi_logging: bool = False):
        self.path = Path(path) if path is not None else fmu_path(build=True)
        if not self.path.is_file():
            raise FMUNotFoundError(_missing_file_message(self.path))
        self.log, self.fmi_logging = log, fmi_logging
        self.messages: collections.deque[str] = collections.deque(maxlen=1000)
        self._run_messages: collections.deque[str] = collections.deque(maxlen=200)
        try:
            self.md = read_model_description(str(self.path))
        except Exception as exc:  # not a zip, no or bad modelDescription.xml
            raise FMUNotFoundError(
                f"{self.path} is not a readable FMU ({exc}): pass a .fmu file, or leave the path"
                f" out to use the harness's own FMU ({OWN_FMU})"
            ) from None
        self.variables = {v.name: v for v in self.md.modelVariables}
        self.output_names = [v.name for v in self.md.modelVariables if v.causality == "output"]
        self._unzip: str | None = extract(str(self.path))
        self._slave: fmi2.Fmi2Instance | None = None
        self._phase = "closed"  # instantiated | stepping | failed | closed
        self._time = math.nan
        self._params: dict[str, Any] | None = None
        self._held: bytes | None = None  # the serialized state the FMU is in (None: unknown/moved)
        try:
            self._instantiate()
        except BaseException:
            self.close()
            raise

    # ---- lifecycle ----
    def _instantiate(self) -> None:
        unzip = self._unzip
        assert unzip is not None  # extracted in __init__, removed only by close()
        lib = fmi2.load(fmi2.binary_path(unzip, self.md.coSimulation.modelIdentifier))
        # the binding's per-instance logger: several instances in one process keep their messages apart
        self._slave = fmi2.Fmi2Instance(
            lib,
            "blade",
            self.md.guid,
            fmi2.resource_uri(unzip),
            logging_on=True,
            log_limit=200,
            on_log=self._on_log,
            on_call=None,
        )
        self._phase = "instantiated"
        if not self.log:  # loggingOn enabled every category: keep only the status ones
            self._slave.set_debug_logging(False, [])
            self._slave.set_debug_logging(True, _ERROR_CATEGORIES)
        self._stepper = Stepper(self._slave, trace=self.fmi_logging)

    def _on_log(self, rec: LogRecord) -> None:
        status = rec.status
        text = f"[{STATUS[status] if 0 <= status < 6 else status}] {rec.category or ''}: {rec.message or ''}"
        self.messages.append(text)
        self._run_messages.append(text)
        if self.log:
            print(text, file=sys.stderr)

    def close(self) -> None:
        """Terminate (if initialized), free the instance, unload the library, remove the extract."""
        try:
            if self._slave is not None and self._phase != "closed":
                if self._phase == "stepping":
                    try:
                        self._slave.terminate()
                    except FmiError:
                        pass
                if self._phase != "fatal":
                    self._slave.free_instance()
                    self._slave.lib.close()
                else:
                    self._slave.abandon()  # no call is allowed after Fatal
        finally:
            self._slave, self._phase = None, "closed"
            if self._unzip is not None:
                shutil.rmtree(self._unzip, ignore_errors=True)
                self._unzip = None

    def __enter__(self) -> "BladeFMU":
        return self

    def __exit__(self, *exc: object) -> None:
        self.close()

    def __del__(self) -> None:
        try:
            self.close()
        except Exception:
            pass

    # ---- errors ----
    def _fail(self, what: str, status: int, t: float, partial: np.ndarray | None) -> FMUError:
        self._phase = "fatal" if status >= 4 else "failed"
        msgs = list(self._run_messages)
        detail = ("; FMU log: " + " | ".join(msgs[-5:])) if msgs else " (the FMU logged nothing)"
        return FMUError(
            f"{what} returned {STATUS[status] if 0 <= status < 6 else status} at t = {t:.9g} s{detail}",
            time=t,
            partial=partial,
            messages=msgs,
            status=status,
            function=what,
        )

    def _guard(self, what: str, t: float, fn: Callable[..., Result], *args: Any) -> Result:
        try:
            return fn(*args)
        except FmiError as exc:
            raise self._fail(what, exc.status, t, None) from None

    # ---- parameters and setup ----
    def _set_parameters(self, p: Mapping[str, Any], start: float, u0: tuple[float, float]) -> None:
        """reset (unless just instantiated) -> parameters -> initialization with the inputs u0."""
        by_type: dict[str, tuple[list[int], list[Any]]] = {"Real": ([], []), "Integer": ([], []), "Boolean": ([], [])}
        for name, value in fmu_parameters(p).items():
            v = self.variables[name]
            by_type[v.type][0].append(v.valueReference)
            by_type[v.type][1].append(value)
        reals = Values(by_type["Real"][0], [float(x) for x in by_type["Real"][1]])
        ints = Values(by_type["Integer"][0], [int(x) for x in by_type["Integer"][1]], ctypes.c_int)
        bools = Values(by_type["Boolean"][0], [int(x) for x in by_type["Boolean"][1]], ctypes.c_int)
        st, call = self._stepper.start(
            reals, ints, bools, Values([VR_AERO, VR_SPEED], u0), start, reset=self._phase != "instantiated"
        )
        if st > 1:
            raise self._fail(call, st, start, None)
        self._phase = "stepping"

    @staticmethod
    def _grid(start: float, stop: float, step: float) -> np.ndarray:
        for name, v in (("start_time", start), ("stop_time", stop), ("step", step)):
            if not math.isfinite(v):
                raise ParameterError(f"{name} = {v!r} is not a finite number")
        if not step > 0:
            raise ParameterError(f"communication step = {step!r} s must be > 0")
        if not stop > start:
            raise ParameterError(f"stop time {stop!r} s must be after the start time {start!r} s")
        n = (stop - start) / step
        N = int(round(n))
        if N < 1 or abs(n - N) > 1e-9 * max(1.0, n):
            N = int(math.ceil(n))  # the last step is shorter (canHandleVariableCommunicationStepSize)
        grid = start + step * np.arange(N + 1, dtype=float)
        grid[-1] = stop
        return grid

    def _select(self, outputs: Sequence[str] | None) -> tuple[list[str], list[str]]:
        names = list(self.output_names if outputs is None else outputs)
        unknown = [n for n in names if n not in self.variables or self.variables[n].type not in ("Real", "Integer")]
        if unknown:
            raise ParameterError(f"unknown output(s) {unknown}; available: {', '.join(self.output_names)}")
        real = [n for n in names if self.variables[n].type == "Real"]
        ints = [n for n in names if self.variables[n].type == "Integer"]
        return real, ints

    # ---- the run ----
    def run(
        self,
        params: Mapping[str, Any] | None,
        stop_time: float,
        step: float,
        *,
        aero: Signal | None = None,
        speed_rpm: float | Piecewise = 5000.0,
        outputs: Sequence[str] | None = None,
        derivative_order: int = MAX_ORDER,
        start_time: float | None = None,
        reset: bool = True,
        sample_every: int = 1,
        input_fit: str = "taylor",
        carry_values: bool = False,
    ) -> np.ndarray:
        """Simulate from start_time (default 0, or the current FMU time when reset=False) to
        stop_time with communication step `step`; returns a structured array ('time' + outputs)
        sampled every `sample_every` steps (plus the start and the end). speed_rpm: the rotor
        speed [rpm], a number or a speed profile (harness.model.excitation: Constant, LinearRamp,
        Stepped).

        input_fit: how the aero load's value and derivatives per step are chosen (`step_inputs`):
        "taylor" (its exact derivatives at the step start: what `excitation.fmu_view` reproduces) or
        "chebyshev" (the derivatives of its interpolant at the Chebyshev nodes of the step: far
        smaller error for large steps, e.g. 6e-7 instead of 8e-2 of the amplitude at 2 steps per
        period of a sine).
        carry_values: set the input values (fmi2SetReal) only before the first step of this call;
        later steps set the derivatives only and the FMU carries each value over from its
        polynomial of the previous step (docs/model-notes.md s.7): one FMI call less per step.
        Only for inputs without breakpoints inside the grid (else ParameterError): the carried
        value then differs from the signal by at most the fit error at the step end.

        The inputs of the whole grid are precomputed: 8 (2K + 2) bytes per step (144 B at K = 8),
        so split runs of many millions of steps into chunks (reset=False continues)."""
        if self._phase == "closed":
            raise RuntimeError("BladeFMU is closed")
        self._held = None  # whatever happens below, the FMU moves (or fails)
        p, start = self._run_start(params, reset, start_time)
        if not (isinstance(sample_every, (int, np.integer)) and sample_every >= 1):
            raise ParameterError(f"sample_every = {sample_every!r} must be an integer >= 1")
        order = int(derivative_order)
        if not 0 <= order <= MAX_ORDER:
            raise ParameterError(f"derivative_order = {derivative_order!r} outside [0, {MAX_ORDER}]")
        grid = self._grid(start, float(stop_time), float(step))
        real, ints = self._select(outputs)
        speed_sig = as_speed(speed_rpm)
        aero_sig = aero if aero is not None else AeroLoad(p["Fw0"], p["engineOrder"], speed_sig)
        if carry_values:
            inner = [
                b
                for sig in (aero_sig, speed_sig)
                for b in np.atleast_1d(getattr(sig, "breakpoints", []))
                if grid[0] < b < grid[-1]
            ]
            if inner or order == 0:
                raise ParameterError(
                    "carry_values needs inputs without breakpoints inside the run and "
                    "derivative_order >= 1" + (f" (breakpoint at t = {inner[0]:.9g} s)" if inner else "")
                )
        inputs = _InputTable(grid, aero_sig, speed_sig, order, input_fit, self._check_inputs)

        self._run_messages.clear()
        if reset:
            self._params = None
            self._set_parameters(p, start, inputs.first)
            self._params = p
            self._time = start
        rec = _Recorder(self, grid, real, ints, sample_every)
        rec.sample_start()
        self._step_loop(grid, inputs, rec, carry_values)
        self._time = float(grid[-1])
        return rec.result(rec.rows_before[-1])

    def _run_start(
        self, params: Mapping[str, Any] | None, reset: bool, start_time: float | None
    ) -> tuple[dict[str, Any], float]:
        """(validated parameters, start time) of a run: fresh ones with a reset, else the running
        FMU's (parameters cannot change without a reset; the start must be the FMU's time)."""
        if reset:
            return validate(params or {}, source="BladeFMU.run"), 0.0 if start_time is None else float(start_time)
        if self._phase != "stepping":
            raise RuntimeError(
                "reset=False needs an FMU in stepping mode (run once with reset=True or"
                " set_state first; after an FMU error, reset)"
            )
        p = dict(self._params or validate({}))
        if params is not None and validate(params, source="BladeFMU.run") != p:
            raise ParameterError("parameters cannot change without a reset (they are fixed during a run)")
        if start_time is None:
            if not math.isfinite(self._time):
                raise ParameterError("the FMU time is unknown after set_state: pass start_time")
            return p, self._time
        start = float(start_time)
        if math.isfinite(self._time) and abs(start - self._time) > 1e-9 * max(1.0, abs(start)):
            raise ParameterError(f"start_time {start} differs from the FMU time {self._time}")
        return p, start

    def _step_loop(self, grid: np.ndarray, inputs: "_InputTable", rec: "_Recorder", carry_values: bool) -> None:
        """The communication steps (the hot path: per-step addresses are precomputed, the loop
        makes only the raw FMI calls). Per step: the input values (only before the first step when
        carried), their derivatives, fmi2DoStep, and the outputs where the step is sampled."""
        fmi = self._stepper
        c, setReal, setDer, doStep, getReal, getInt = (
            fmi.c,
            fmi.setReal,
            fmi.setDer,
            fmi.doStep,
            fmi.getReal,
            fmi.getInteger,
        )
        n_der, a_vr_der, a_order = inputs.n_derivatives, inputs.a_vr_der, inputs.a_order
        a_vr_in = inputs.a_vr_in
        n_real, n_int, a_vr_real, a_vr_int = len(rec.real), len(rec.ints), rec.a_vr_real, rec.a_vr_int
        t_start, h = grid[:-1].tolist(), np.diff(grid).tolist()
        if not n_der:

            def setDer(*_: object) -> int:  # noqa: N802 (held inputs: no derivatives to set)
                return 0

        def fail(k: int, what: str, status: int, t: float) -> FMUError:
            return self._fail(what, status, t, rec.result(rec.rows_before[k]))

        def fail_step(k: int, status: int) -> FMUError:
            self._time = t_start[k]
            return fail(k, "fmi2DoStep", status, t_start[k])

        inputs_call, outputs_call = "fmi2SetReal/fmi2SetRealInputDerivatives (inputs)", "fmi2GetReal/fmi2GetInteger"
        # the sweeps' case: values carried, every step sampled, real outputs only: three FMI
        # calls per step after the first, nothing else in the loop
        lean = carry_values and n_der and n_real and not n_int and rec.sample_every == 1
        steps = zip(t_start, h, inputs.value_addr, inputs.deriv_addr, rec.real_addr, rec.int_addr)
        for k, (tk, hk, a_val, a_der, a_real, a_int) in enumerate(steps):
            st_val = setReal(c, a_vr_in, 2, a_val) if (k == 0 or not carry_values) else 0
            st_der = setDer(c, a_vr_der, n_der, a_order, a_der)
            if (st_val | st_der) > 1:  # statuses are 0..4: the OR exceeds 1 iff one of them does
                raise fail(k, inputs_call, max(st_val, st_der), tk)
            st = doStep(c, tk, hk, 1)
            if st > 1:
                raise fail_step(k, st)
            if a_real or a_int:
                st_real = getReal(c, a_vr_real, n_real, a_real) if a_real else 0
                st_int = getInt(c, a_vr_int, n_int, a_int) if a_int else 0
                if (st_real | st_int) > 1:
                    raise fail(k, outputs_call, max(st_real, st_int), tk + hk)
            if lean:
                break
        if lean:
            for k, tk, hk, a_der, a_real in zip(
                range(1, len(t_start)), t_start[1:], h[1:], inputs.deriv_addr[1:], rec.real_addr[1:]
            ):
                st = setDer(c, a_vr_der, n_der, a_order, a_der)
                if st > 1:
                    raise fail(k, inputs_call, st, tk)
                st = doStep(c, tk, hk, 1)
                if st > 1:
                    raise fail_step(k, st)
                st = getReal(c, a_vr_real, n_real, a_real)
                if st > 1:
                    raise fail(k, outputs_call, st, tk + hk)

    def _check_inputs(self, grid: np.ndarray, ua: np.ndarray, us: np.ndarray) -> None:
        if not np.all(np.isfinite(ua)):
            k = int(np.argwhere(~np.isfinite(ua))[0, 1])
            raise ExcitationError(f"aeroLoad (or a derivative) is not finite at t = {grid[k]:.9g} s")
        if not np.all(np.isfinite(us)):
            k = int(np.argwhere(~np.isfinite(us))[0, 1])
            raise ExcitationError(f"rotorSpeed (or a derivative) is not finite at t = {grid[k]:.9g} s")
        lo, hi = SPEED_RANGE
        bad = np.nonzero((us[0] < lo) | (us[0] > hi))[0]
        if len(bad):
            k = int(bad[0])
            raise ExcitationError(
                f"rotorSpeed = {us[0, k]:g} rpm at t = {grid[k]:.9g} s is outside [{lo:g}, {hi:g}] rpm"
            )

    # ---- the stepper, for drivers with their own hot loop (harness.analysis.periodic) ----
    @property
    def stepper(self) -> Stepper:
        """This instance's Stepper (harness.fmu.stepper), the calls run() makes."""
        return self._stepper

    def prepared(self) -> Stepper:
        """The Stepper for a driver that makes its own calls (reset -> set -> initialize -> steps
        -> read, without run()'s per-call setup). The wrapper forgets which state the FMU is in: a
        later run() resets it, a later get_state() reads whatever the driver's calls left."""
        if self._phase in ("closed", "fatal"):
            raise RuntimeError(f"BladeFMU is {self._phase}")
        self._phase, self._held, self._params, self._time = "stepping", None, None, math.nan
        return self._stepper

    def failure(self, what: str, status: int, t: float, partial: np.ndarray | None = None) -> FMUError:
        """The FMUError for a stepper call that returned `status` (> fmi2Warning) at time t, with the
        FMU's log messages (and the results up to t); marks the wrapper failed (the next run() resets)."""
        return self._fail(what, status, t, partial)

    # ---- FMU state ----
    def get_state(self) -> FMUState:
        """The current FMU state, serialized (fmi2SerializeFMUstate), with its time attached."""
        if self._phase not in ("stepping", "instantiated"):
            raise RuntimeError(f"cannot get the FMU state in phase {self._phase}")
        s = self._slave
        assert s is not None  # instantiated or stepping
        st = self._guard("fmi2GetFMUstate", self._time, s.get_fmu_state)
        try:
            raw = self._guard("fmi2SerializeFMUstate", self._time, s.serialize_fmu_state, st)
        finally:
            s.free_fmu_state(st)
        out = FMUState(raw)
        out.time, out.params = self._time, dict(self._params) if self._params else None
        self._held = bytes(raw)
        return out

    def holds(self, state: bytes) -> bool:
        """True if the FMU is in exactly this serialized state: it was taken (get_state) or
        restored (set_state) and nothing has run since. A driver continuing a chain of runs then
        needs no set_state."""
        return self._held is not None and self._phase == "stepping" and self._held == bytes(state)

    def set_state(self, state: bytes) -> None:
        """Restore a serialized state (from this or another instance/process); continue with
        run(..., reset=False)."""
        if self._phase in ("closed", "fatal"):
            raise RuntimeError(f"cannot set the FMU state in phase {self._phase}")
        s = self._slave
        assert s is not None  # not closed
        if self._phase == "failed":
            self._guard("fmi2Reset", self._time, s.reset)
            self._phase = "instantiated"
        st = self._guard("fmi2DeSerializeFMUstate", self._time, s.deserialize_fmu_state, bytes(state))
        try:
            self._guard("fmi2SetFMUstate", self._time, s.set_fmu_state, st)
        finally:
            s.free_fmu_state(st)
        self._phase = "stepping"
        self._held = bytes(state)
        t = getattr(state, "time", None)
        self._time = float(t) if t is not None else math.nan
        sp = getattr(state, "params", None)
        self._params = validate(sp, source="FMUState.params") if sp is not None else None
