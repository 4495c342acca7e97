"""libcosim (Open Simulation Platform) as an importer, through libcosimpy (PyPI).

libcosim keeps time as integer nanoseconds: the step 1e-4 s is exactly 100000 ns, the communication
point passed to fmi2DoStep is double(k * 100000 ns) / 1e9 and the step size is the difference of two
such doubles (libcosim's `to_double_duration`), so neither accumulates. libcosim does not call
fmi2SetRealInputDerivatives: inputs are held over a step. They are set through an override
manipulator before every step (libcosim applies it when the step commences) and as initial values
before initialization; outputs come from a time-series observer (step 0 = after initialization).
"""

from __future__ import annotations

import ctypes
from pathlib import Path

import numpy as np

from harness.crosscheck.common import Run, outputs, result_array, timed
from harness.crosscheck.plan import INPUTS, InputPlan, Scenario
from harness.fmu.libcosim import last_error, samples
from harness.system.time_grid import NS_PER_S, to_ns
from harness.fmu.slave import variables_by_name
from harness.optional import require


class _Version(ctypes.Structure):
    _fields_ = [("major", ctypes.c_int), ("minor", ctypes.c_int), ("patch", ctypes.c_int)]


def version() -> str:
    """libcosim (C++) version as reported by libcosimc, plus the libcosimpy wrapper version."""
    require("libcosimpy")
    # optional dependency (extra `crosscheck`): imported only when this runs
    from libcosimpy import __about__
    from libcosimpy._internal import libcosimc

    lib = libcosimc()
    fn = lib.cosim_libcosim_version
    fn.restype = _Version
    v = fn()
    return f"{v.major}.{v.minor}.{v.patch} (libcosimpy {__about__.__version__})"


def run(fmu: Path, scenario: Scenario, plan: InputPlan) -> Run:
    """One libcosim execution of `plan` (held inputs: plan.order is ignored beyond the values)."""
    require("libcosimpy")
    # optional dependency (extra `crosscheck`): imported only when this runs
    from libcosimpy.CosimExecution import CosimExecution
    from libcosimpy.CosimLogging import CosimLogLevel, log_output_level
    from libcosimpy.CosimManipulator import CosimManipulator
    from libcosimpy.CosimObserver import CosimObserver
    from libcosimpy.CosimEnums import CosimVariableType
    from libcosimpy.CosimSlave import CosimLocalSlave

    if scenario.start_time != 0.0:
        raise ValueError("libcosimpy's CosimExecution.from_step_size always starts at t = 0")
    vars_ = variables_by_name(fmu)
    outs = outputs(fmu)
    in_vrs = [vars_[n][0] for n in INPUTS]

    log_output_level(CosimLogLevel.ERROR)  # libcosim logs every FMI call at debug level by default

    def go() -> tuple[np.ndarray, np.ndarray]:
        execution = CosimExecution.from_step_size(step_size=to_ns(scenario.step))
        local = CosimLocalSlave(fmu_path=str(fmu), instance_name="blade")
        idx = execution.add_local_slave(local_slave=local)
        if idx < 0:
            raise RuntimeError(f"libcosim could not load {fmu}: {last_error()}")
        for name, value in scenario.fmu_overrides().items():
            vr, typ = vars_[name]
            ok = {
                "Real": lambda: execution.real_initial_value(idx, vr, float(value)),
                "Integer": lambda: execution.integer_initial_value(idx, vr, int(value)),
                "Boolean": lambda: execution.boolean_initial_value(idx, vr, bool(value)),
            }[typ]()
            if not ok:
                raise RuntimeError(f"libcosim refused the initial value {name} = {value}: {last_error()}")
        for vr, name in zip(in_vrs, INPUTS):
            if not execution.real_initial_value(idx, vr, float(plan.values(name)[0])):
                raise RuntimeError(f"libcosim refused the initial input {name}: {last_error()}")
        manipulator = CosimManipulator.create_override()
        observer = CosimObserver.create_time_series(buffer_size=plan.n_steps + 16)
        execution.add_manipulator(manipulator=manipulator)
        execution.add_observer(observer=observer)
        for o in outs:
            kind = CosimVariableType.REAL if o.type == "Real" else CosimVariableType.INTEGER
            if not observer.start_time_series(idx, o.vr, kind):
                raise RuntimeError(f"libcosim cannot observe {o.name}: {last_error()}")
        values = np.column_stack([plan.values(n) for n in INPUTS])
        for k in range(plan.n_steps):
            # the first step also initializes the slave (with the initial values above)
            manipulator.slave_real_values(idx, in_vrs, [float(x) for x in values[k]])
            if not execution.step():
                raise RuntimeError(f"libcosim step {k} failed: {last_error()}")
        rows = np.empty((plan.n_steps + 1, len(outs)))
        times = None
        for i, o in enumerate(outs):
            t_ns, steps, vals = samples(observer, idx, o.vr, o.type, plan.n_steps + 1)
            if list(steps) != list(range(plan.n_steps + 1)):
                raise RuntimeError(f"libcosim observer returned steps {steps[:3]}..{steps[-3:]} for {o.name}")
            rows[:, i] = vals
            times = t_ns
        return rows, np.asarray(times, dtype=np.int64)

    (rows, t_ns), wall = timed(go)
    t = t_ns / NS_PER_S  # libcosim's own communication points, as it converts them for fmi2DoStep
    return Run(
        "libcosim (libcosimpy)",
        version(),
        "held",
        result_array(t, {o.name: rows[:, i] for i, o in enumerate(outs)}),
        wall,
        note="integer-ns time; inputs held (override manipulator)",
    )
