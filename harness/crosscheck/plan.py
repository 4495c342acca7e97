"""Cross-check scenarios and the input plan every importer is fed, step by step.

A `Scenario` (rotor speed profile, aerodynamic load, parameters, stop time, communication step) is
turned into an `InputPlan`: the communication points t_k = start + k h (computed from the integer
k, never accumulated) and, at each t_k, the input values and their time derivatives up to order 8
from `harness.model.excitation` (exact, right-sided). Every importer sets exactly these numbers before
the step [t_k, t_{k+1}], so the only freedom left to a tool is how it passes time and step size to
fmi2DoStep; that is what the cross-check measures. Order 0 (held inputs) is what importers without
fmi2SetRealInputDerivatives can do; `input_table()` is the same held sequence as an fmpy input table.
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any, Mapping

import numpy as np

from harness.model import params as _params
from harness.model.excitation import AeroLoad, Constant, LinearRamp, Piecewise

INPUTS = ("aeroLoad", "rotorSpeed")  # the FMU's Real inputs


@dataclass(frozen=True)
class Scenario:
    """One cross-check experiment. speed: constant [rpm] or (n0, n1) for a linear run-up over the run."""

    name: str
    description: str
    speed: float | tuple[float, float]
    stop_time: float = 0.3  # [s]
    step: float = 1e-4  # communication step [s]
    start_time: float = 0.0  # [s]
    params: Mapping[str, Any] = field(default_factory=dict)  # overrides of the FMU/harness defaults
    # True: the FMU's built-in load carries F_w0 (its parameter Fw0) and the master feeds aeroLoad = 0;
    # False: the master feeds aeroLoad = F_w0 sin(EO Omega t) and sets the FMU's Fw0 = 0
    builtin_load: bool = False

    def validated_params(self) -> dict[str, Any]:
        return _params.validate(dict(self.params), source=f"crosscheck scenario {self.name!r}")

    def fmu_overrides(self) -> dict[str, Any]:
        """Only the FMU parameters that differ from the modelDescription start values (set on the FMU)."""
        p = self.validated_params()
        d = _params.defaults()
        fmu = _params.fmu_parameters(p, external_load=not self.builtin_load)
        return {k: v for k, v in fmu.items() if k not in d or v != d[k]}

    def speed_signal(self) -> Piecewise:
        if isinstance(self.speed, tuple):
            n0, n1 = self.speed
            return LinearRamp(n0, n1, self.start_time, self.stop_time)
        return Constant(float(self.speed))

    def aero_signal(self) -> AeroLoad:
        p = self.validated_params()
        return AeroLoad(0.0 if self.builtin_load else p["Fw0"], p["engineOrder"], self.speed_signal())

    def n_steps(self) -> int:
        n = round((self.stop_time - self.start_time) / self.step)
        if n < 1 or not math.isclose(self.start_time + n * self.step, self.stop_time, rel_tol=1e-12, abs_tol=1e-15):
            raise ValueError(
                f"scenario {self.name!r}: (stop - start) = {self.stop_time - self.start_time} s is "
                f"not a whole number of steps of {self.step} s"
            )
        return n

    def shortened(self, stop_time: float) -> "Scenario":
        """The same scenario over a shorter time (tests); a run-up keeps its ramp rate."""
        speed = self.speed
        if isinstance(speed, tuple):
            n0, n1 = speed
            frac = (stop_time - self.start_time) / (self.stop_time - self.start_time)
            speed = (n0, n0 + (n1 - n0) * frac)
        return Scenario(
            self.name,
            self.description,
            speed,
            stop_time,
            self.step,
            self.start_time,
            dict(self.params),
            self.builtin_load,
        )


#: The issue's scenarios: 5000 rpm with F_w0 = 100 N/m, f = F_w0 sin(3 Omega t), 0.3 s, h = 1e-4 s;
#: and a run-up 4000 -> 6000 rpm through the same time, with the time-domain contact element
#: (frictionModel 3) so that the second run exercises the other contact code path and its events.
SCENARIOS: dict[str, Scenario] = {
    "steady": Scenario("steady", "5000 rpm, Fw0 = 100 N/m, macroslip DF, tracked amplitude", 5000.0),
    "runup": Scenario(
        "runup",
        "run-up 4000 -> 6000 rpm, Fw0 = 100 N/m, time-domain macroslip element",
        (4000.0, 6000.0),
        params={"frictionModel": 3},
    ),
}


@dataclass(frozen=True)
class InputPlan:
    """Communication points and, per input, value + derivatives at each point (row j = order j)."""

    time: np.ndarray  # (N+1,) t_k [s]
    derivs: dict[str, np.ndarray]  # name -> (order+1, N+1)
    order: int
    step_sizes: np.ndarray | None = None  # (N,) h_k passed to fmi2DoStep; None: t_{k+1} - t_k

    def h(self) -> np.ndarray:
        """The step sizes h_k passed with fmi2DoStep(t_k, h_k)."""
        return np.diff(self.time) if self.step_sizes is None else self.step_sizes

    @property
    def n_steps(self) -> int:
        return len(self.time) - 1

    def values(self, name: str) -> np.ndarray:
        return self.derivs[name][0]

    def held(self) -> "InputPlan":
        """The same plan with only the values (order 0)."""
        return InputPlan(self.time, {k: v[:1].copy() for k, v in self.derivs.items()}, 0, self.step_sizes)

    def with_time(self, time: np.ndarray, step_sizes: np.ndarray | None = None) -> "InputPlan":
        """The same input numbers on another grid of communication points and step sizes (a tool's
        own: e.g. Ecos passes an accumulated t_k with a constant h, which is not t_{k+1} - t_k)."""
        time = np.asarray(time, dtype=float)
        if time.shape != self.time.shape:
            raise ValueError(f"grid of {len(time)} points for a plan of {len(self.time)}")
        h = None if step_sizes is None else np.broadcast_to(np.asarray(step_sizes, float), (len(time) - 1,)).copy()
        return InputPlan(time, self.derivs, self.order, h)

    def input_table(self) -> np.ndarray:
        """fmpy-style structured input array (time first) with the held values at each t_k."""
        dtype = [("time", np.float64)] + [(n, np.float64) for n in INPUTS]
        table = np.empty(len(self.time), dtype=dtype)
        table["time"] = self.time
        for n in INPUTS:
            table[n] = self.values(n)
        return table

    def column_names(self) -> list[str]:
        """CSV columns: values first, then `name@j` derivative columns (j = 1..order)."""
        cols = list(INPUTS)
        for j in range(1, self.order + 1):
            cols += [f"{n}@{j}" for n in INPUTS]
        return cols

    def write_csv(self, path: Path) -> Path:
        """The plan as CSV for drivers in other languages (numbers in shortest exact repr)."""
        cols = self.column_names()
        data = [self.time]
        for c in cols:
            name, _, j = c.partition("@")
            data.append(self.derivs[name][int(j) if j else 0])
        with open(path, "w", encoding="ascii") as f:
            f.write(
                "# ShroudedBlade cross-check input plan (harness/crosscheck/plan.py); row k: inputs for "
                "the step [t_k, t_{k+1}]\n"
            )
            f.write(",".join(["time"] + cols) + "\n")
            for row in np.column_stack(data):
                f.write(",".join(repr(float(x)) for x in row) + "\n")
        return path


def make_plan(scenario: Scenario, order: int = 0) -> InputPlan:
    """Input plan of `scenario` with derivatives up to `order` (0 = held inputs)."""
    n = scenario.n_steps()
    time = scenario.start_time + np.arange(n + 1) * scenario.step
    signals = {"aeroLoad": scenario.aero_signal(), "rotorSpeed": scenario.speed_signal()}
    derivs = {name: np.asarray(sig.derivatives(time, order), dtype=float) for name, sig in signals.items()}
    return InputPlan(time, derivs, order)
