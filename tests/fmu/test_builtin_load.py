"""The blade FMUs' built-in aerodynamic load Fw0 sin(psi + 2 pi engineOrder bladeIndex / bladeCount),
psi the excitation phase integrated with the state: exact at any communication step, in any master.

The comparison is the harness's own path with the FMU's Fw0 = 0 and the load fed through the
aeroLoad input with its exact Taylor derivatives (order 8) at a communication step of 1e-4 s
(accurate to ~1e-12 of the response at that step). The load fed there is written here (tests/support/loads.py,
Fw0 sin(omega t + lead)), or for the run-up the harness's Python AeroLoad (eq. 17, its phase the
integral of the speed): never the FMU's C load code. Tolerances are ~10x the measured differences
(stated per test); a phase error of 1e-4 rad in the built-in load moves the response by 3.7e-9 m
(fixed B) to 6.4e-5 m (tracked amplitude), far outside them.
"""

from __future__ import annotations

import math
import subprocess
import sys
from pathlib import Path

import numpy as np
import pytest
from fmpy import extract, read_model_description, simulate_fmu
from fmpy.fmi2 import FMU2Slave

from harness.fmu import build as _build
from harness.fmu.blade import BladeFMU
from harness.model.excitation import AeroLoad, LinearRamp
from tests.support.loads import Sine

FW0, EO, SPEED = 100.0, 3, 5000.0
OMEGA = EO * 2 * math.pi * SPEED / 60  # [rad/s]
# [m]: measured 1.06e-10 with the tracked amplitude (its own spread between 1e-4 and 1e-5 s steps in
# the harness is 2e-10), 6.0e-15 with B fixed, 7.1e-15 with the Jenkins element
RUN_UP_TOL = 6e-16  # [m]: measured 6.0e-17 (run-up, Jenkins element)
TOL = {"tracked amplitude": 1e-9, "fixed B": 5e-14, "Jenkins element": 5e-14}


def _harness(fmu: BladeFMU, params: dict, aero, speed, stop: float) -> np.ndarray:
    return fmu.run(params, stop, 1e-4, aero=aero, speed_rpm=speed, outputs=["tipDisplacement"])["tipDisplacement"][::10]


@pytest.mark.parametrize(
    "name, model",
    [("tracked amplitude", {}), ("fixed B", {"amplitudeMode": 1}), ("Jenkins element", {"frictionModel": 3})],
)
def test_fmpy_at_1e_3_s_equals_the_harness(fmu_path: Path, fmu: BladeFMU, name: str, model: dict) -> None:
    r = simulate_fmu(
        fmu_path, stop_time=0.3, output_interval=1e-3, start_values={"Fw0": FW0, **model}, output=["tipDisplacement"]
    )
    q = _harness(fmu, model, Sine(FW0, OMEGA), SPEED, 0.3)
    assert np.max(np.abs(r["tipDisplacement"] - q)) <= TOL[name]
    assert np.max(np.abs(q)) > 3e-5  # the shrouds are in contact: not a trivial comparison


def test_travelling_wave_lead(fmu_path: Path, fmu: BladeFMU) -> None:
    i, n = 2, 7
    lead = 2 * math.pi * EO * i / n
    r = simulate_fmu(
        fmu_path,
        stop_time=0.2,
        output_interval=1e-3,
        output=["tipDisplacement"],
        start_values={"Fw0": FW0, "bladeIndex": i, "bladeCount": n, "frictionModel": 3},
    )
    q = _harness(fmu, {"frictionModel": 3}, Sine(FW0, OMEGA, lead), SPEED, 0.2)
    assert np.max(np.abs(r["tipDisplacement"] - q)) <= 2e-14  # measured 2.0e-15


def test_run_up_with_the_speed_slope_as_input_derivative(fmu_path: Path, fmu: BladeFMU, tmp_path: Path) -> None:
    # 4000 -> 6000 rpm in 0.2 s: psi = EO int Omega dt is quadratic in t, integrated by the FMU
    ramp = LinearRamp(4000.0, 6000.0, 0.0, 0.2)
    slope = 2000.0 / 0.2
    md = read_model_description(fmu_path)
    vr = {v.name: v.valueReference for v in md.modelVariables}
    s = FMU2Slave(
        guid=md.guid,
        unzipDirectory=extract(fmu_path, tmp_path / "x"),
        instanceName="runup",
        modelIdentifier=md.coSimulation.modelIdentifier,
    )
    s.instantiate()
    s.setupExperiment(startTime=0.0)
    s.setReal([vr["Fw0"]], [FW0])
    s.setInteger([vr["frictionModel"]], [3])
    s.enterInitializationMode()
    s.exitInitializationMode()
    h, q = 1e-3, [s.getReal([vr["tipDisplacement"]])[0]]
    for k in range(200):
        t = k * h
        s.setReal([vr["rotorSpeed"]], [float(ramp(t))])
        s.setRealInputDerivatives([vr["rotorSpeed"]], [1], [slope])
        s.doStep(t, h)
        q.append(s.getReal([vr["tipDisplacement"]])[0])
    s.terminate()
    s.freeInstance()
    ref = _harness(fmu, {"frictionModel": 3}, AeroLoad(FW0, EO, ramp), ramp, 0.2)
    assert np.max(np.abs(np.array(q) - ref)) <= RUN_UP_TOL


def test_blade_external_contact_has_the_same_load(fmu: BladeFMU) -> None:
    # BladeExternalContact's built-in load (blade 1 of 4, no contact force) against ShroudedBlade with
    # the contact open (d = 1 m, fixed B) fed the load written here: measured 5.0e-15 m of a 4.2e-4 m
    # response, tolerance 5e-14
    _build.build(("fmu", "blade_external_fmu"))
    b = simulate_fmu(
        _build.BUILD_DIR / "BladeExternalContact.fmu",
        stop_time=0.1,
        output_interval=1e-3,
        output=["tipDisplacement"],
        start_values={"Fw0": FW0, "bladeIndex": 1, "bladeCount": 4},
    )
    q = _harness(fmu, {"d": 1.0, "amplitudeMode": 1}, Sine(FW0, OMEGA, 2 * math.pi * EO * 1 / 4), SPEED, 0.1)
    assert np.max(np.abs(b["tipDisplacement"] - q)) <= 5e-14
    assert np.max(np.abs(q)) > 1e-5


def test_fmpy_with_defaults_equals_harness_simulate(fmu_path: Path, tmp_path: Path) -> None:
    """`fmpy.simulate_fmu` with nothing but the FMU's defaults (built-in Fw0 = 100 N/m, rotorSpeed
    start 5000 rpm, 1e-3 s steps, no input) shows the paper's 5000 rpm response, and it is the run
    of `harness simulate` at the same settings (load fed through aeroLoad with derivatives, 1e-4 s)."""
    r = simulate_fmu(fmu_path, stop_time=0.3, output_interval=1e-3, output=["tipDisplacement"])
    out = tmp_path / "sim.csv"
    proc = subprocess.run(
        [
            sys.executable,
            "-m",
            "harness",
            "simulate",
            "--speed",
            "5000",
            "--stop-time",
            "0.3",
            "--output-interval",
            "1e-4",
            "--output-file",
            str(out),
        ],
        capture_output=True,
        text=True,
    )
    assert proc.returncode == 0, proc.stderr
    ours = np.genfromtxt(out, delimiter=",", names=True, deletechars="")
    q = ours["tipDisplacement_m"][::10]
    assert len(q) == len(r) and np.allclose(ours["time_s"][::10], r["time"], rtol=0, atol=1e-12)
    assert np.max(np.abs(q)) > 3e-5  # loaded beyond the gap: the shrouds are in contact, not at rest
    assert np.max(np.abs(r["tipDisplacement"] - q)) <= TOL["tracked amplitude"]  # the default model: measured 1.04e-10
