"""System example: the Excitation FMU driving a tuned and a mistuned blade, in fmpy and in libcosim.

Checks, each against something computed independently of the code under test:
- the excitation FMU's outputs equal harness.model.excitation's closed-form run-up (phase ~ 400 rad,
  so double rounding of the phase gives ~1e-13 relative; tolerance 1e-11 of F_w0);
- libcosim and the fmpy master loop give the same trajectories for every recorded variable (same
  Jacobi scheme, same t_k and h_k, so identical up to 1e-12 relative);
- each blade in the system equals a standalone run of the same FMU fed the same held inputs (1e-12);
- the parameters reached the instances: the natural frequency at t = 0 matches the Galerkin
  reference (harness.reference.galerkin, quadrature; 1e-8 relative) for both parameter sets;
- the excitation's travelling wave: blade i of N gets the load 2 pi EO i / N ahead (closed form,
  1e-11 of F_w0), and a blade index off the disk is refused with a message naming the range.
"""

from __future__ import annotations

import math

import numpy as np
import pytest

from harness.crosscheck import system_example as se
from harness.crosscheck.common import max_rel_diff
from harness.crosscheck.importers.fmpy import SlaveLoop
from harness.system.time_grid import ns_time_grid
from harness.crosscheck.plan import InputPlan
from harness.model.excitation import AeroLoad, LinearRamp
from harness.model.params import validate
from harness.reference import galerkin


SYSTEM = se.System(stop_time=0.05)


@pytest.fixture(scope="module")
def runs(fmu_path):
    exc = se.build_excitation_fmu()
    return fmu_path, se.run_binding(fmu_path, exc, SYSTEM), se.run_libcosim(fmu_path, exc, SYSTEM)


def test_excitation_matches_closed_form(runs):
    _, a, _ = runs
    e = SYSTEM.excitation
    ramp = LinearRamp(e["n0"], e["n1"], e["t0"], e["t1"])
    load = AeroLoad(100.0, 3, ramp)
    t = a["time"]
    assert np.max(np.abs(a["excitation.rotorSpeed"] - ramp(t))) <= 1e-9
    assert np.max(np.abs(a["excitation.aeroLoad"] - load(t))) <= 1e-11 * 100.0


def test_libcosim_equals_fmpy_master(runs):
    _, a, b = runs
    assert np.array_equal(a["time"], b["time"])
    d, worst = max_rel_diff(b, a)
    assert d <= 1e-12, f"{worst}: {d:.3e}"


def test_blades_in_the_system_equal_standalone_runs(runs):
    fmu, a, _ = runs
    t = ns_time_grid(0.0, SYSTEM.step, SYSTEM.n_steps)
    plan = InputPlan(
        t,
        {
            "aeroLoad": a["excitation.aeroLoad"][None, :].copy(),
            "rotorSpeed": a["excitation.rotorSpeed"][None, :].copy(),
        },
        0,
    )
    with SlaveLoop(fmu) as loop:
        for name, params in SYSTEM.blades.items():
            alone = loop.run(plan, params)
            cols = [n for n in alone.dtype.names if n != "time"]
            mine = np.empty(len(t), dtype=alone.dtype)
            mine["time"] = a["time"]
            for c in cols:
                mine[c] = a[f"{name}.{c}"]
            d, worst = max_rel_diff(mine, alone)
            assert d <= 1e-12, f"{name}.{worst}: {d:.3e}"


@pytest.mark.parametrize("name", sorted(SYSTEM.blades))
def test_parameters_reached_the_instances(runs, name):
    _, a, b = runs
    p = validate(dict(SYSTEM.blades[name]))
    g = galerkin(p)
    omega = 2 * math.pi * SYSTEM.excitation["n0"] / 60
    f = math.sqrt((g.K0static + g.K0omega2 * omega**2) / g.M) / (2 * math.pi)
    for res in (a, b):
        assert res[f"{name}.naturalFrequency"][0] == pytest.approx(f, rel=1e-8)


def test_mistuned_blade_responds_differently(runs):
    _, a, _ = runs
    ta = np.max(np.abs(a["tuned.tipDisplacement"]))
    tb = np.max(np.abs(a["mistuned.tipDisplacement"]))
    assert ta > 0 and tb > 0 and abs(ta - tb) > 1e-3 * ta


@pytest.mark.parametrize("index,count", [(0, 1), (3, 7), (35, 36)])
def test_excitation_travelling_wave_phase(index, count):
    """Blade `index` of `count` sees the engine-fixed load 2 pi EO index / count earlier: aeroLoad
    equals Fw0 sin(psi_e(t) + 2 pi EO index / count) from harness.model.excitation's phase (1e-11
    of F_w0); blade 0 of 1 is the single-blade load."""
    from fmpy import simulate_fmu

    from harness.model.excitation import Constant

    r = simulate_fmu(
        str(se.build_excitation_fmu()),
        stop_time=0.01,
        output_interval=1e-4,
        output=["aeroLoad"],
        start_values={"bladeIndex": index, "bladeCount": count, "n0": 6000.0, "n1": 6000.0},
    )
    load = AeroLoad(100.0, 3, Constant(6000.0))
    expected = 100.0 * np.sin(load.phase(r["time"]) + 2 * math.pi * 3 * index / count)
    assert np.max(np.abs(r["aeroLoad"] - expected)) <= 1e-11 * 100.0


def test_excitation_blade_off_the_disk_is_refused():
    from fmpy import simulate_fmu
    from fmpy.fmi1 import FMICallException

    messages = []

    def logger(env, name, status, category, message):  # noqa: ANN001
        messages.append(message.decode())

    with pytest.raises(FMICallException):
        simulate_fmu(
            str(se.build_excitation_fmu()),
            stop_time=0.01,
            output_interval=1e-4,
            logger=logger,
            debug_logging=True,
            start_values={"bladeIndex": 7, "bladeCount": 7},
        )
    assert any("bladeIndex = 7" in m and "[0, 6]" in m for m in messages), messages
