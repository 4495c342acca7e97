"""fmpy as the cross-check reference: `simulate_fmu` with an input table; and a master loop of our own.

`run_simulate_fmu` is fmpy's one-shot API with the held input table (inputs sampled at the left end
of each step: fmpy's co-simulation default without `set_input_derivatives`); it is the reference
every held-input importer is compared with. `run_slave_loop` is the hand-written master loop over
the project's FMI binding (harness.fmu.binding; fmpy extracts the FMU) that passes t_k = start + k h
and h exactly from the plan and, for a plan of order > 0, sets the input derivatives with
fmi2SetRealInputDerivatives after the values.
"""

from __future__ import annotations

import shutil
from pathlib import Path
from typing import Any, Mapping

import fmpy
import numpy as np
from fmpy import extract, read_model_description, simulate_fmu

from harness.crosscheck.common import Run, as_float_result, outputs, result_array, timed
from harness.fmu.slave import variables_by_name
from harness.crosscheck.plan import INPUTS, InputPlan, Scenario
from harness.fmu.binding import FmiError, fmi2

VERSION = fmpy.__version__
SLAVE_LOOP = "FMI binding loop"  # run_slave_loop's importer name in the reports (our own code: no version)


def _start_values(overrides: Mapping[str, Any]) -> dict[str, Any]:
    return {k: (bool(v) if isinstance(v, bool) else v) for k, v in overrides.items()}


def run_simulate_fmu(fmu: Path, scenario: Scenario, plan: InputPlan) -> Run:
    """fmpy.simulate_fmu with the held input table of `plan`, output every communication step."""
    names = [o.name for o in outputs(fmu)]
    table = plan.held().input_table()

    def go() -> np.ndarray:
        return simulate_fmu(
            str(fmu),
            fmi_type="CoSimulation",
            start_time=scenario.start_time,
            stop_time=float(plan.time[-1]),
            output_interval=scenario.step,
            start_values=_start_values(scenario.fmu_overrides()),
            input=table,
            output=names,
            validate=False,
        )

    res, wall = timed(go)
    return Run(
        "fmpy simulate_fmu",
        VERSION,
        "held",
        as_float_result(res, names),
        wall,
        note="input table on the communication grid, sampled at the step start",
    )


class SlaveLoop:
    """An extracted FMU instantiated once: run plans with reset in between (the FMI binding)."""

    def __init__(self, fmu: Path, instance_name: str = "blade"):
        self.fmu = Path(fmu)
        self.md = read_model_description(str(fmu))
        self.unzipdir = extract(str(fmu))
        self.vars = variables_by_name(fmu)
        self.outs = outputs(fmu)
        lib = fmi2.load(fmi2.binary_path(self.unzipdir, self.md.coSimulation.modelIdentifier))
        self.slave = fmi2.Fmi2Instance(lib, instance_name, self.md.guid, fmi2.resource_uri(self.unzipdir))
        self._fresh = True

    def close(self) -> None:
        try:
            self.slave.terminate()
        except FmiError:  # already terminated or failed: freeing is what matters
            pass
        self.slave.free_instance()
        self.slave.lib.close()
        shutil.rmtree(self.unzipdir, ignore_errors=True)

    def __enter__(self) -> "SlaveLoop":
        return self

    def __exit__(self, *exc: object) -> None:
        self.close()

    def set_values(self, values: Mapping[str, Any]) -> None:
        for name, value in values.items():
            vr, typ = self.vars[name]
            if typ == "Real":
                self.slave.set_real([vr], [float(value)])
            elif typ == "Integer":
                self.slave.set_integer([vr], [int(value)])
            elif typ == "Boolean":
                self.slave.set_boolean([vr], [bool(value)])
            else:
                raise ValueError(f"cannot set {name} of type {typ}")

    def set_inputs(self, plan: InputPlan, k: int, derivatives: bool) -> None:
        vrs = [self.vars[n][0] for n in INPUTS]
        self.slave.set_real(vrs, [float(plan.derivs[n][0, k]) for n in INPUTS])
        if derivatives and plan.order > 0:
            dvrs, orders, vals = [], [], []
            for j in range(1, plan.order + 1):
                for n, vr in zip(INPUTS, vrs):
                    dvrs.append(vr)
                    orders.append(j)
                    vals.append(float(plan.derivs[n][j, k]))
            self.slave.set_real_input_derivatives(dvrs, orders, vals)

    def sample(self) -> list[float]:
        reals = [o.vr for o in self.outs if o.type == "Real"]
        ints = [o.vr for o in self.outs if o.type == "Integer"]
        rv = dict(zip(reals, self.slave.get_real(reals))) if reals else {}
        iv = dict(zip(ints, self.slave.get_integer(ints))) if ints else {}
        return [float(rv[o.vr]) if o.type == "Real" else float(iv[o.vr]) for o in self.outs]

    def run(self, plan: InputPlan, start_values: Mapping[str, Any] | None = None) -> np.ndarray:
        """Initialize (reset first if used before), then step along the plan; returns time + outputs."""
        if not self._fresh:
            self.slave.reset()
        self._fresh = False
        t0, t_end = float(plan.time[0]), float(plan.time[-1])
        self.slave.setup_experiment(t0, t_end)
        self.slave.enter_initialization_mode()
        self.set_values(start_values or {})
        self.set_inputs(plan, 0, derivatives=False)
        self.slave.exit_initialization_mode()
        rows = np.empty((len(plan.time), len(self.outs)))
        rows[0] = self.sample()
        t, h = plan.time, plan.h()
        for k in range(plan.n_steps):
            self.set_inputs(plan, k, derivatives=True)
            self.slave.do_step(float(t[k]), float(h[k]))
            rows[k + 1] = self.sample()
        return result_array(plan.time, {o.name: rows[:, i] for i, o in enumerate(self.outs)})


def run_slave_loop(fmu: Path, scenario: Scenario, plan: InputPlan) -> Run:
    """Our master loop along `plan` (held values, or values + derivatives up to plan.order)."""
    inputs = "held" if plan.order == 0 else f"taylor{plan.order}"
    overrides = scenario.fmu_overrides()

    def go() -> np.ndarray:
        with SlaveLoop(fmu) as loop:
            return loop.run(plan, overrides)

    res, wall = timed(go)
    return Run(SLAVE_LOOP, "-", inputs, res, wall, note="t_k and h_k from the plan")
