"""docs/examples/quickstart.py runs from a directory outside the checkout, and what it prints agrees
with the FMU driven here directly through fmpy's FMU2Slave (not through the harness): the same
1.5 s from rest at 7000 rpm, step 1e-4 s, the load Fw0 sin(EO 2 pi n t / 60) with its exact
derivatives of orders 1..8 set every step (the FMU interpolates its inputs)."""

from __future__ import annotations

import math
import re
import shutil
import subprocess
import sys
from pathlib import Path

import numpy as np
from fmpy import extract, read_model_description
from fmpy.fmi2 import FMU2Slave

import harness

REPO = Path(__file__).resolve().parents[2]
EXAMPLE = REPO / "docs" / "examples" / "quickstart.py"
SPEED, STOP, STEP, ORDER = 7000.0, 1.5, 1e-4, 8  # as in the example ([rpm], [s], [s], its default order)
PRINTED_RTOL = 1e-6  # the example prints 7 significant digits


def _direct_last_period_amplitude() -> float:
    """max |tipDisplacement| over the last excitation period, the FMU stepped by fmpy directly."""
    path = harness.fmu_path("ShroudedBlade")
    md = read_model_description(str(path))
    vr = {v.name: v.valueReference for v in md.modelVariables}
    start = {v.name: float(v.start) for v in md.modelVariables if v.name in ("engineOrder",)}
    fw0 = 100.0  # the harness's default load amplitude Fw0 [N/m] (docs/model.md s.1), fed through aeroLoad
    w = start["engineOrder"] * 2 * math.pi * SPEED / 60  # [rad/s]
    unzipdir = extract(str(path))
    fmu = FMU2Slave(
        guid=md.guid, unzipDirectory=unzipdir, modelIdentifier=md.coSimulation.modelIdentifier, instanceName="direct"
    )
    try:
        fmu.instantiate()
        fmu.setupExperiment(startTime=0.0)
        fmu.setReal([vr["Fw0"]], [0.0])  # the load is fed through aeroLoad below: the built-in one is off
        fmu.enterInitializationMode()
        fmu.setReal([vr["rotorSpeed"], vr["aeroLoad"]], [SPEED, 0.0])
        fmu.exitInitializationMode()
        n = round(STOP / STEP)
        q = np.empty(n + 1)
        q[0] = fmu.getReal([vr["tipDisplacement"]])[0]
        orders = list(range(1, ORDER + 1))
        for k in range(n):
            t = k * STEP
            fmu.setReal([vr["aeroLoad"]], [fw0 * math.sin(w * t)])
            # d^j/dt^j sin(w t) = w^j sin(w t + j pi / 2)
            fmu.setRealInputDerivatives(
                [vr["aeroLoad"]] * ORDER, orders, [fw0 * w**j * math.sin(w * t + j * math.pi / 2) for j in orders]
            )
            fmu.doStep(t, STEP)
            q[k + 1] = fmu.getReal([vr["tipDisplacement"]])[0]
        fmu.terminate()
        fmu.freeInstance()
    finally:
        shutil.rmtree(unzipdir, ignore_errors=True)
    time = np.arange(n + 1) * STEP
    return float(np.max(np.abs(q[time >= time[-1] - 2 * math.pi / w])))


def test_quickstart_agrees_with_fmpy_direct(tmp_path):
    proc = subprocess.run([sys.executable, str(EXAMPLE)], cwd=tmp_path, capture_output=True, text=True, timeout=600)
    assert proc.returncode == 0, proc.stderr
    orbits = [(float(a), label) for a, label in re.findall(r"orbit: max\|q\| = (\S+) m \((.+)\)", proc.stdout)]
    (simulated,) = [float(v) for v in re.findall(r"simulate: max\|q\| over the last period = (\S+) m", proc.stdout)]
    direct = _direct_last_period_amplitude()
    assert math.isclose(simulated, direct, rel_tol=PRINTED_RTOL), (simulated, direct)
    # the run from rest ends on the stable orbit: the transient left after 525 periods at the orbit's
    # |mu| = 0.987 per period is below 1e-3 of its start
    stable = [a for a, label in orbits if label == "stable"]
    assert len(stable) == 1 and math.isclose(stable[0], direct, rel_tol=1e-3), (orbits, direct)
    assert list(tmp_path.iterdir()) == []  # it writes nothing
