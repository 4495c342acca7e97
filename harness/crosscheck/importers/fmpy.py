"""fmpy as the cross-check reference: `simulate_fmu` with an input table, and an FMU2Slave loop.

`run_simulate_fmu` is fmpy's one-shot API with the held input table (inputs sampled at the left end
of each step: fmpy's co-simulation default without `set_input_derivatives`); it is the reference
every held-input importer is compared with. `run_slave_loop` is the hand-written master loop over
`FMU2Slave` that passes t_k = start + k h and h exactly from the plan and, for a plan of order > 0,
sets the input derivatives with fmi2SetRealInputDerivatives after the values.
"""
from __future__ import annotations

import ctypes
import shutil
from pathlib import Path
from typing import Any, Mapping

import fmpy
import numpy as np
from fmpy import extract, read_model_description, simulate_fmu
from fmpy.fmi2 import FMU2Slave

from harness.crosscheck.common import Run, as_float_result, outputs, result_array, timed
from harness.fmu.slave import variables_by_name
from harness.crosscheck.plan import INPUTS, InputPlan, Scenario

VERSION = fmpy.__version__


def _start_values(overrides: Mapping[str, Any]) -> dict[str, Any]:
    return {k: (bool(v) if isinstance(v, bool) else v) for k, v in overrides.items()}


def run_simulate_fmu(fmu: Path, scenario: Scenario, plan: InputPlan) -> Run:
    """fmpy.simulate_fmu with the held input table of `plan`, output every communication step."""
    names = [o.name for o in outputs(fmu)]
    table = plan.held().input_table()

    def go() -> np.ndarray:
        return simulate_fmu(str(fmu), fmi_type="CoSimulation", start_time=scenario.start_time,
                            stop_time=float(plan.time[-1]), output_interval=scenario.step,
                            start_values=_start_values(scenario.fmu_overrides()), input=table,
                            output=names, validate=False)

    res, wall = timed(go)
    return Run("fmpy simulate_fmu", VERSION, "held", as_float_result(res, names), wall,
               note="input table on the communication grid, sampled at the step start")


class SlaveLoop:
    """An extracted FMU instantiated once: run plans with reset in between (fmpy FMU2Slave)."""

    def __init__(self, fmu: Path, instance_name: str = "blade"):
        self.fmu = Path(fmu)
        self.md = read_model_description(str(fmu))
        self.unzipdir = extract(str(fmu))
        self.vars = variables_by_name(fmu)
        self.outs = outputs(fmu)
        self.slave = FMU2Slave(guid=self.md.guid, unzipDirectory=self.unzipdir,
                               modelIdentifier=self.md.coSimulation.modelIdentifier, instanceName=instance_name)
        self.slave.instantiate()
        self._fresh = True

    def close(self) -> None:
        try:
            self.slave.terminate()
        except Exception:  # already terminated or failed: freeing is what matters
            pass
        self.slave.freeInstance()
        shutil.rmtree(self.unzipdir, ignore_errors=True)

    def __enter__(self) -> "SlaveLoop":
        return self

    def __exit__(self, *exc: object) -> None:
        self.close()

    def set_values(self, values: Mapping[str, Any]) -> None:
        for name, value in values.items():
            vr, typ = self.vars[name]
            if typ == "Real":
                self.slave.setReal([vr], [float(value)])
            elif typ == "Integer":
                self.slave.setInteger([vr], [int(value)])
            elif typ == "Boolean":
                self.slave.setBoolean([vr], [bool(value)])
            else:
                raise ValueError(f"cannot set {name} of type {typ}")

    def set_inputs(self, plan: InputPlan, k: int, derivatives: bool) -> None:
        vrs = [self.vars[n][0] for n in INPUTS]
        self.slave.setReal(vrs, [float(plan.derivs[n][0, k]) for n in INPUTS])
        if derivatives and plan.order > 0:
            dvrs, orders, vals = [], [], []
            for j in range(1, plan.order + 1):
                for n, vr in zip(INPUTS, vrs):
                    dvrs.append(vr)
                    orders.append(j)
                    vals.append(float(plan.derivs[n][j, k]))
            n = len(dvrs)
            self.slave.fmi2SetRealInputDerivatives(self.slave.component, (ctypes.c_uint * n)(*dvrs), n,
                                                   (ctypes.c_int * n)(*orders), (ctypes.c_double * n)(*vals))

    def sample(self) -> list[float]:
        reals = [o.vr for o in self.outs if o.type == "Real"]
        ints = [o.vr for o in self.outs if o.type == "Integer"]
        rv = dict(zip(reals, self.slave.getReal(reals))) if reals else {}
        iv = dict(zip(ints, self.slave.getInteger(ints))) if ints else {}
        return [float(rv[o.vr]) if o.type == "Real" else float(iv[o.vr]) for o in self.outs]

    def run(self, plan: InputPlan, start_values: Mapping[str, Any] | None = None) -> np.ndarray:
        """Initialize (reset first if used before), then step along the plan; returns time + outputs."""
        if not self._fresh:
            self.slave.reset()
        self._fresh = False
        t0, t_end = float(plan.time[0]), float(plan.time[-1])
        self.slave.setupExperiment(startTime=t0, stopTime=t_end)
        self.slave.enterInitializationMode()
        self.set_values(start_values or {})
        self.set_inputs(plan, 0, derivatives=False)
        self.slave.exitInitializationMode()
        rows = np.empty((len(plan.time), len(self.outs)))
        rows[0] = self.sample()
        t, h = plan.time, plan.h()
        for k in range(plan.n_steps):
            self.set_inputs(plan, k, derivatives=True)
            self.slave.doStep(currentCommunicationPoint=float(t[k]), communicationStepSize=float(h[k]))
            rows[k + 1] = self.sample()
        return result_array(plan.time, {o.name: rows[:, i] for i, o in enumerate(self.outs)})


def run_slave_loop(fmu: Path, scenario: Scenario, plan: InputPlan) -> Run:
    """FMU2Slave master loop along `plan` (held values, or values + derivatives up to plan.order)."""
    inputs = "held" if plan.order == 0 else f"taylor{plan.order}"
    overrides = scenario.fmu_overrides()

    def go() -> np.ndarray:
        with SlaveLoop(fmu) as loop:
            return loop.run(plan, overrides)

    res, wall = timed(go)
    return Run("fmpy FMU2Slave loop", VERSION, inputs, res, wall,
               note="t_k and h_k from the plan")
