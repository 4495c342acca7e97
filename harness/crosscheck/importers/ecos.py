"""Ecos (Ecos-platform) as an importer, through ecospy (PyPI; its libecosc.so needs Debian's libtbb12).

Ecos' fixed-step algorithm passes the same step size h to every fmi2DoStep and accumulates the
communication point (t_{k+1} = t_k + h in double precision), so its t_k drifts from k h by a few
ulps; `accumulated_time_grid` reproduces that grid for the comparison. Ecos does not set input
derivatives: inputs are held. Values set with `set_real("blade::aeroLoad", ...)` are applied when the
next step starts; parameters and the inputs at t_0 go in as a parameter set applied in
initialization mode; outputs are read after every step with `get_real`/`get_integer`.
"""

from __future__ import annotations

from importlib.metadata import version as dist_version
from pathlib import Path

import numpy as np

from harness.crosscheck.common import Run, outputs, result_array, timed
from harness.crosscheck.plan import INPUTS, InputPlan, Scenario
from harness.fmu.slave import variables_by_name
from harness.optional import require

INSTANCE = "blade"


def version() -> str:
    require("ecospy")
    # optional dependency (extra `crosscheck`): imported only when this runs
    from ecospy import EcosLib

    return f"{EcosLib.version()!r}".lstrip("v") + f" (ecospy {dist_version('ecospy')})"


def accumulated_time_grid(start: float, step: float, n_steps: int) -> np.ndarray:
    """Ecos' communication points: t_0 = start, t_{k+1} = t_k + step in double precision."""
    t = np.empty(n_steps + 1)
    acc = float(start)
    for k in range(n_steps + 1):
        t[k] = acc
        acc = acc + step
    return t


def run(fmu: Path, scenario: Scenario, plan: InputPlan) -> Run:
    """One Ecos simulation of `plan` with held inputs."""
    require("ecospy")
    # optional dependency (extra `crosscheck`): imported only when this runs
    from ecospy import EcosSimulation, EcosSimulationStructure

    vars_ = variables_by_name(fmu)
    outs = outputs(fmu)
    ident = {name: f"{INSTANCE}::{name}" for name in vars_}

    def go() -> tuple[np.ndarray, np.ndarray]:
        structure = EcosSimulationStructure()
        structure.add_model(INSTANCE, str(Path(fmu).resolve()))
        init: dict[str, object] = {}
        for name, value in scenario.fmu_overrides().items():
            typ = vars_[name][1]
            init[ident[name]] = float(value) if typ == "Real" else (bool(value) if typ == "Boolean" else int(value))
        for name in INPUTS:
            init[ident[name]] = float(plan.values(name)[0])
        structure.add_parameter_set("initial", init)
        sim = EcosSimulation(structure=structure, step_size=scenario.step)
        try:
            if not sim.init(scenario.start_time, "initial"):
                raise RuntimeError("ecos: simulation init failed")
            rows = np.empty((plan.n_steps + 1, len(outs)))
            times = np.empty(plan.n_steps + 1)
            getters = [
                (sim.get_real if o.type in ("Real", "Float64") else sim.get_integer, ident[o.name]) for o in outs
            ]  # FMI 2.0 or 3.0 type names
            rows[0] = [g(i) for g, i in getters]
            times[0] = sim.get_time()
            values = np.column_stack([plan.values(n) for n in INPUTS])
            for k in range(plan.n_steps):
                for name, v in zip(INPUTS, values[k]):
                    sim.set_real(ident[name], float(v))
                times[k + 1] = sim.step()
                rows[k + 1] = [g(i) for g, i in getters]
            sim.terminate()
        finally:
            sim.free()
            structure.free()
        return rows, times

    (rows, times), wall = timed(go)
    return Run(
        "Ecos (ecospy)",
        version(),
        "held",
        result_array(times, {o.name: rows[:, i] for i, o in enumerate(outs)}),
        wall,
        note="accumulated time t += h; inputs held (set_real before each step)",
    )
