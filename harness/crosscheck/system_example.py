"""System-level example: an excitation FMU driving two blade FMU instances, in our master loop and in libcosim.

The project's small `Excitation` FMU (fmu_src/models/Excitation: rotor speed n(t), constant or a
linear run-up, and the phase-continuous load f_w = Fw0 sin(3 * int 2 pi n/60)) is connected to two
instances of ShroudedBlade with different parameters: `tuned` (paper Table 1) and `mistuned` (a
heavier shroud, m0 = 0.03 kg, and a wider gap, d = 4e-5 m). Connections: excitation.aeroLoad ->
each blade's aeroLoad, excitation.rotorSpeed -> each blade's rotorSpeed. Both masters use the same
fixed-step Jacobi scheme (outputs at t_k are the inputs for [t_k, t_{k+1}], inputs held): a
hand-written loop over the project's FMI binding (harness.fmu.slave), and libcosim (libcosimpy) with `connect_real_variables`;
both pass libcosim's integer-nanosecond communication points. The excitation FMU is built by the
project's CMake build with the blade (build/Excitation.fmu, `build_excitation_fmu`). `python -m
harness crosscheck` runs both masters (its system section) and reports the largest relative
difference.
"""

from __future__ import annotations

from contextlib import ExitStack
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any, Mapping

import numpy as np

from harness.crosscheck.common import max_rel_diff, outputs, result_array
from harness.fmu.build import EXCITATION_FMU, build
from harness.fmu.libcosim import last_error, samples
from harness.system.time_grid import NS_PER_S, ns_time_grid, to_ns
from harness.fmu.slave import Slave, Unpacked, variables_by_name
from harness.optional import require

EXC = "excitation"


@dataclass(frozen=True)
class System:
    """Parameters of the example: excitation (Fw0, n0, n1, t0, t1, engineOrder) and the blades."""

    excitation: Mapping[str, Any] = field(default_factory=lambda: {"n0": 4000.0, "n1": 6000.0, "t0": 0.0, "t1": 0.3})
    blades: Mapping[str, Mapping[str, Any]] = field(
        default_factory=lambda: {"tuned": {}, "mistuned": {"m0": 0.03, "d": 4e-5}}
    )
    stop_time: float = 0.3  # [s]
    step: float = 1e-4  # [s]

    @property
    def n_steps(self) -> int:
        return round(self.stop_time / self.step)


def build_excitation_fmu(out: Path = EXCITATION_FMU) -> Path:
    """build/Excitation.fmu, built by CMake with the blade FMU (target excitation_fmu, linked with
    libm), from fmu_src/fmi + fmu_src/models/Excitation; CMake rebuilds it when a source changed."""
    build(("excitation_fmu",))
    return out


def _result_names(blade_fmu: Path, system: System) -> list[tuple[str, str, str]]:
    """(instance, variable, column name) of everything recorded: excitation outputs, blade outputs."""
    cols = [(EXC, "aeroLoad", f"{EXC}.aeroLoad"), (EXC, "rotorSpeed", f"{EXC}.rotorSpeed")]
    for b in system.blades:
        cols += [(b, o.name, f"{b}.{o.name}") for o in outputs(blade_fmu)]
    return cols


def run_binding(blade_fmu: Path, exc_fmu: Path, system: System) -> np.ndarray:
    """The system in a hand-written master loop over the FMI binding (Jacobi, held inputs,
    libcosim's time grid)."""
    t = ns_time_grid(0.0, system.step, system.n_steps)
    cols = _result_names(blade_fmu, system)
    slaves: dict[str, Slave] = {}
    with ExitStack() as stack:
        exc, blade = (stack.enter_context(Unpacked(f)) for f in (exc_fmu, blade_fmu))
        slaves[EXC] = exc.instance(EXC, initialize=False, stop_time=float(t[-1]))
        stack.callback(slaves[EXC].free)
        for b in system.blades:
            slaves[b] = blade.instance(b, initialize=False, stop_time=float(t[-1]))
            stack.callback(slaves[b].free)
        params = {EXC: dict(system.excitation), **{b: dict(p) for b, p in system.blades.items()}}
        for name, s in slaves.items():
            s.s.enter_initialization_mode()
            s.set_params(params[name])

        def transfer() -> None:
            u = dict(zip(("aeroLoad", "rotorSpeed"), slaves[EXC].get(["aeroLoad", "rotorSpeed"])))
            for b in system.blades:
                slaves[b].set_params(u)

        transfer()  # initial inputs from the excitation's initial outputs
        for s in slaves.values():
            s.s.exit_initialization_mode()
        rows = np.empty((len(t), len(cols)))
        rows[0] = [slaves[i].get([v])[0] for i, v, _ in cols]
        for k in range(system.n_steps):
            transfer()
            for s in slaves.values():
                s.step(float(t[k]), float(t[k + 1] - t[k]))
            rows[k + 1] = [slaves[i].get([v])[0] for i, v, _ in cols]
    return result_array(t, {c: rows[:, j] for j, (_, _, c) in enumerate(cols)})


def run_libcosim(blade_fmu: Path, exc_fmu: Path, system: System) -> np.ndarray:
    """The same system in libcosim: three local slaves, four real connections, fixed step."""
    require("libcosimpy")
    # optional dependency (extra `crosscheck`): imported only when this runs
    from libcosimpy.CosimEnums import CosimVariableType
    from libcosimpy.CosimExecution import CosimExecution
    from libcosimpy.CosimLogging import CosimLogLevel, log_output_level
    from libcosimpy.CosimObserver import CosimObserver
    from libcosimpy.CosimSlave import CosimLocalSlave

    log_output_level(CosimLogLevel.ERROR)
    cols = _result_names(blade_fmu, system)
    fmus = {EXC: exc_fmu, **{b: blade_fmu for b in system.blades}}
    params = {EXC: dict(system.excitation), **{b: dict(p) for b, p in system.blades.items()}}
    execution = CosimExecution.from_step_size(step_size=to_ns(system.step))
    locals_, idx, vars_ = {}, {}, {}
    for name, path in fmus.items():
        locals_[name] = CosimLocalSlave(fmu_path=str(path), instance_name=name)
        idx[name] = execution.add_local_slave(local_slave=locals_[name])
        if idx[name] < 0:
            raise RuntimeError(f"libcosim could not load {path}: {last_error()}")
        vars_[name] = variables_by_name(path)
        for var, v in params[name].items():
            vr, typ = vars_[name][var]
            ok = {
                "Real": lambda: execution.real_initial_value(idx[name], vr, float(v)),
                "Integer": lambda: execution.integer_initial_value(idx[name], vr, int(v)),
                "Boolean": lambda: execution.boolean_initial_value(idx[name], vr, bool(v)),
            }[typ]()
            if not ok:
                raise RuntimeError(f"libcosim refused {name}.{var} = {v}: {last_error()}")
    for b in system.blades:
        for var in ("aeroLoad", "rotorSpeed"):
            rc = execution.connect_real_variables(idx[EXC], vars_[EXC][var][0], idx[b], vars_[b][var][0])
            if rc != 0:
                raise RuntimeError(f"libcosim: cannot connect {EXC}.{var} -> {b}.{var}: {last_error()}")
    observer = CosimObserver.create_time_series(buffer_size=system.n_steps + 16)
    execution.add_observer(observer=observer)
    for inst, var, _ in cols:
        vr, typ = vars_[inst][var]
        kind = CosimVariableType.REAL if typ == "Real" else CosimVariableType.INTEGER
        if not observer.start_time_series(idx[inst], vr, kind):
            raise RuntimeError(f"libcosim cannot observe {inst}.{var}: {last_error()}")
    if not execution.step(system.n_steps):
        raise RuntimeError(f"libcosim failed: {last_error()}")
    n = system.n_steps + 1
    data, times = {}, None
    for inst, var, c in cols:
        vr, typ = vars_[inst][var]
        t_ns, steps, vals = samples(observer, idx[inst], vr, typ, n)
        if list(steps) != list(range(n)):
            raise RuntimeError(f"libcosim observer returned unexpected steps for {c}")
        data[c], times = vals, t_ns
    return result_array(np.asarray(times, dtype=np.int64) / NS_PER_S, data)


def compare(a: np.ndarray, b: np.ndarray) -> tuple[float, str]:
    return max_rel_diff(a, b)
