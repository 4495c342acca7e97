"""Convergence order of the FMU's integrator (docs/model-notes.md s.6), without and with switching.

The same piecewise-polynomial input (aeroLoad = 100 sin(omega t) as value plus derivatives 1..8 at
communication points 2e-4 s apart, 5000 rpm) drives runs with maxStep = 4e-5 ... 2.5e-6 s (5 to 80
equal internal steps per communication step) and a reference run with maxStep = 2.5e-7 s, whose own
error is (2.5e-7/2.5e-6)^4 = 1e-4 of the finest run's. The error is max |q - q_ref| over the
communication grid of 0.03 s (contact starts after ~7 ms), relative to max |q_ref|. Classical RK4
with switching instants located on the cubic Hermite interpolant and the step redone up to them
keeps order 4; without location an impact model drops to order 1. Asserted: the least-squares
slope of log(error) over log(maxStep) >= 3.5, every halving gains at least 2^3, and the switching
cases really switch (events counted from the logEvents category). The range stops at 2.5e-6 s:
below it, rounding in the 1.2e5-step reference (~2e-11 relative) starts to show.
"""

from __future__ import annotations

import math
from pathlib import Path

import numpy as np
import pytest
from tests.support.fmi2raw import aero_derivatives
from fmpy import extract, read_model_description
from fmpy.fmi2 import FMU2Slave, fmi2CallbackFunctions, fmi2CallbackLoggerTYPE

VR_D, VR_B, VR_MAXSTEP = 11, 12, 13
VR_FRICTION, VR_AMPMODE, VR_GATING = 20, 23, 30
VR_AERO, VR_SPEED, VR_Q = 40, 41, 50

H_COMM = 2e-4
DURATION = 0.03
RPM = 5000.0
FW0 = 100.0
MAX_STEPS = [4e-5, 2e-5, 1e-5, 5e-6, 2.5e-6]
REFERENCE_STEP = 2.5e-7

CASES = {
    "no switching (d = 1 m)": dict(d=1.0, B=6e-5, friction=1, amplitudeMode=1, gating=True),
    "gating, d = 3e-5 m, fixed B = 6e-5 m": dict(d=3e-5, B=6e-5, friction=1, amplitudeMode=1, gating=True),
    "gating, tracked B (period and extremum events)": dict(d=3e-5, B=6e-5, friction=1, amplitudeMode=2, gating=True),
    "Jenkins element (frictionModel 3)": dict(d=3e-5, B=6e-5, friction=3, amplitudeMode=1, gating=True),
}


@pytest.fixture(scope="module")
def unzipped(fmu_path: Path, tmp_path_factory: pytest.TempPathFactory) -> tuple[str, str]:
    md = read_model_description(str(fmu_path))
    return md.guid, extract(str(fmu_path), unzipdir=str(tmp_path_factory.mktemp("convergence")))


def run(unzipped: tuple[str, str], case: dict, max_step: float, count_events: bool = False) -> tuple[np.ndarray, int]:
    """q on the communication grid, and the number of logged switching events (if counted)."""
    guid, directory = unzipped
    events = [0]

    def logger(env, name, status, category, message) -> None:  # noqa: ANN001 (ctypes callback)
        if category == b"logEvents" and b"period" not in message:
            events[0] += 1

    callbacks = fmi2CallbackFunctions()
    callbacks.logger = fmi2CallbackLoggerTYPE(logger)
    slave = FMU2Slave(guid=guid, unzipDirectory=directory, modelIdentifier="ShroudedBlade", instanceName="conv")
    slave.instantiate(callbacks=callbacks, loggingOn=False)
    try:
        if count_events:
            slave.setDebugLogging(True, ["logEvents"])
        slave.setupExperiment(startTime=0.0)
        slave.setReal([VR_D, VR_B, VR_MAXSTEP], [case["d"], case["B"], max_step])
        slave.setInteger([VR_FRICTION, VR_AMPMODE], [case["friction"], case["amplitudeMode"]])
        slave.setBoolean([VR_GATING], [case["gating"]])
        slave.enterInitializationMode()
        slave.setReal([VR_SPEED], [RPM])
        slave.exitInitializationMode()
        omega = 3 * 2 * math.pi * RPM / 60
        n = int(round(DURATION / H_COMM))
        orders = list(range(1, 9))
        q = np.zeros(n + 1)
        for k in range(n):
            tk = k * H_COMM
            load = aero_derivatives(tk, FW0, omega)  # value and derivatives 1..8 of FW0 sin(omega t)
            slave.setReal([VR_AERO], load[:1])
            slave.setRealInputDerivatives([VR_AERO] * 8, orders, load[1:])
            slave.doStep(tk, H_COMM)
            q[k + 1] = slave.getReal([VR_Q])[0]
        slave.terminate()
    finally:
        slave.freeInstance()
    return q, events[0]


@pytest.mark.parametrize("name", list(CASES))
def test_fourth_order(unzipped: tuple[str, str], name: str, record_property) -> None:  # noqa: ANN001
    case = CASES[name]
    ref, n_events = run(unzipped, case, REFERENCE_STEP, count_events=True)
    scale = float(np.max(np.abs(ref)))
    errors = np.array([np.max(np.abs(run(unzipped, case, h)[0] - ref)) / scale for h in MAX_STEPS])
    pairwise = np.log2(errors[:-1] / errors[1:])
    slope = float(np.polyfit(np.log(MAX_STEPS), np.log(errors), 1)[0])
    report = (
        f"{name}: {n_events} switching events; relative errors "
        + ", ".join(f"{h:.2e} s: {e:.2e}" for h, e in zip(MAX_STEPS, errors))
        + f"; pairwise orders {np.round(pairwise, 2).tolist()}; least-squares order {slope:.2f}"
    )
    print(report)
    record_property("convergence", report)
    if case["d"] < 1.0:
        assert n_events >= 10, report  # the switching case switches
    else:
        assert n_events == 0, report
    assert slope >= 3.5, report
    assert np.all(pairwise >= 3.0), report
    assert errors[-1] > 1e-12, report  # still above the rounding floor
