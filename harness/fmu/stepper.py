"""The one FMI 2.0 co-simulation call path of the harness: an FMU instantiated once, then per run
reset -> set (parameters, start values) -> initialize (the inputs at the start) -> steps -> read.

`Stepper` holds an instance of the project's binding (harness.fmu.binding.fmi2.Fmi2Instance) and its
raw ctypes entry points; `Values` and `Derivatives` are the arguments of one call (value references,
values, derivative orders) as ctypes arrays built once and refilled in place. Nothing is checked
here: every call returns the FMU's status as an int (> 1: Discard, Error or Fatal) with the name of
the call, and the caller raises its own error (BladeFMU's runs, harness.fmu.blade; the period map's
evaluations, harness.analysis.periodic.period_map). With `trace`, every call is printed to stderr
with its values (`simulate --fmi-logging`).
"""

from __future__ import annotations

import ctypes
import sys
from typing import Any, Callable, Sequence

from harness.fmu.binding import fmi2

STATUS = ("OK", "Warning", "Discard", "Error", "Fatal", "Pending")
_D, _U, _I = ctypes.c_double, ctypes.c_uint, ctypes.c_int


class Values:
    """The value references and values of one fmi2Set*/fmi2Get* call (`ctype`: c_double for Real,
    c_int for Integer and Boolean); `value` is refilled in place between calls."""

    def __init__(self, vrs: Sequence[int], values: Sequence[Any] = (), ctype: Any = _D) -> None:
        self.n = len(vrs)
        self.vr = (_U * max(self.n, 1))(*vrs)
        self.value = (ctype * max(self.n, 1))(*values)
        self.a_vr, self.a_value = ctypes.addressof(self.vr), ctypes.addressof(self.value)


class Derivatives:
    """The value references and derivative orders of one fmi2SetRealInputDerivatives call; the
    values come per step as the address of n doubles."""

    def __init__(self, vrs: Sequence[int], orders: Sequence[int]) -> None:
        self.n = len(vrs)
        self.vr = (_U * max(self.n, 1))(*vrs)
        self.order = (_I * max(self.n, 1))(*orders)
        self.a_vr, self.a_order = ctypes.addressof(self.vr), ctypes.addressof(self.order)


def status_name(status: int) -> str:
    return STATUS[status] if 0 <= status < len(STATUS) else str(status)


class Stepper:
    """The raw FMI calls of one instantiated co-simulation FMU, in the order of a run."""

    def __init__(self, instance: fmi2.Fmi2Instance, trace: bool = False) -> None:
        lib = instance.lib
        self.c = instance.c
        self.reset = lib.fmi2Reset
        self.setupExperiment = lib.fmi2SetupExperiment
        self.enterInitializationMode = lib.fmi2EnterInitializationMode
        self.exitInitializationMode = lib.fmi2ExitInitializationMode
        self.setReal, self.setInteger, self.setBoolean = lib.fmi2SetReal, lib.fmi2SetInteger, lib.fmi2SetBoolean
        self.getReal, self.getInteger = lib.fmi2GetReal, lib.fmi2GetInteger
        self.setDer, self.doStep = lib.fmi2SetRealInputDerivatives, lib.fmi2DoStep
        if trace:
            for name in (
                "reset",
                "setupExperiment",
                "enterInitializationMode",
                "exitInitializationMode",
                "setReal",
                "setInteger",
                "setBoolean",
                "getReal",
                "getInteger",
                "setDer",
                "doStep",
            ):
                setattr(self, name, _traced(name, getattr(self, name)))

    def start(
        self, reals: Values, ints: Values, bools: Values, inputs: Values, start_time: float = 0.0, reset: bool = True
    ) -> tuple[int, str]:
        """fmi2Reset (with `reset`), the parameters and start values (Real, Integer, Boolean),
        fmi2SetupExperiment at `start_time`, fmi2EnterInitializationMode, the inputs' start values,
        fmi2ExitInitializationMode. Returns (status, call): the first status > fmi2Warning and its
        call (nothing after it is called), else (the worst status, "")."""
        c = self.c
        calls = [
            (self.setReal, (c, reals.a_vr, reals.n, reals.a_value), "fmi2SetReal (parameters, start values)"),
            (self.setInteger, (c, ints.a_vr, ints.n, ints.a_value), "fmi2SetInteger (parameters)"),
            (self.setBoolean, (c, bools.a_vr, bools.n, bools.a_value), "fmi2SetBoolean (parameters)"),
            (self.setupExperiment, (c, 0, 0.0, start_time, 0, 0.0), "fmi2SetupExperiment"),
            (self.enterInitializationMode, (c,), "fmi2EnterInitializationMode"),
            (self.setReal, (c, inputs.a_vr, inputs.n, inputs.a_value), "fmi2SetReal (inputs)"),
            (self.exitInitializationMode, (c,), "fmi2ExitInitializationMode"),
        ]
        if reset:
            calls.insert(0, (self.reset, (c,), "fmi2Reset"))
        worst = 0
        for f, args, name in calls:
            st = f(*args)
            if st > 1:
                return st, name
            worst = max(worst, st)
        return worst, ""

    def derivative_steps(self, steps: Sequence[tuple[float, float, int]], der: Derivatives) -> tuple[int, int, str]:
        """Communication steps (t_k, h_k, address of the n derivative values of step k) with the
        input values carried by the FMU from the previous step (set at initialization): per step
        fmi2SetRealInputDerivatives and fmi2DoStep. Returns (status, k, call) of the first status
        > fmi2Warning, else (0, len(steps), "")."""
        c, setDer, doStep = self.c, self.setDer, self.doStep
        a_vr, a_order, n = der.a_vr, der.a_order, der.n
        for k, (t, h, a) in enumerate(steps):
            st = setDer(c, a_vr, n, a_order, a)
            if st > 1:
                return st, k, "fmi2SetRealInputDerivatives"
            st = doStep(c, t, h, 1)
            if st > 1:
                return st, k, "fmi2DoStep"
        return 0, len(steps), ""

    def read(self, reals: Values, n: int | None = None) -> int:
        """fmi2GetReal of the first `n` (default all) of `reals` into reals.value."""
        return int(self.getReal(self.c, reals.a_vr, reals.n if n is None else n, reals.a_value))


def _traced(name: str, f: Callable[..., int]) -> Callable[..., int]:
    """`f` printing each call with its values to stderr (value references, orders, values)."""
    label = "fmi2" + {"setDer": "SetRealInputDerivatives"}.get(name, name[0].upper() + name[1:])

    def arr(ctype: Any, addr: int, n: int) -> list[Any]:
        return list((ctype * n).from_address(addr)) if n and addr else []

    def call(*args: Any) -> int:
        st = f(*args)
        if name == "doStep":
            shown = f"t={args[1]:.17g}, h={args[2]:.17g}"
        elif name == "setDer":
            n = args[2]
            shown = (
                f"vr={arr(_U, args[1], n)}, order={arr(_I, args[3], n)}, "
                f"value={[float(f'{v:.6g}') for v in arr(_D, args[4], n)]}"
            )
        elif name in ("setReal", "getReal", "setInteger", "getInteger", "setBoolean"):
            n = args[2]
            vals = arr(_D if name.endswith("Real") else _I, args[3], n)
            shown = f"vr={arr(_U, args[1], n)}, value={vals}"
        else:
            shown = ""
        print(f"{label}({shown}) -> {status_name(st)}", file=sys.stderr)
        return st

    return call
