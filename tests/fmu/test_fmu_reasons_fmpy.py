"""What an fmpy user sees when an FMU refuses something, with debug logging OFF (fmpy's default).

For every group of the invalid-input catalogue (tests/fmu/test_fmu_errors.py, tests/support/errors_me.py,
tests/support/errors_fmi3.py) one refusal is driven through fmpy's own classes (`simulate_fmu`,
`FMU2Slave`, `FMU2Model`, `FMU3Slave`) with fmpy's default logger, which prints the FMU's messages to
stdout. The test asserts that the FMU's reason (the variable, the value, the range or the rule) is
printed. The "NULL component" groups are the exception: without an instance the FMU has no logger
to talk to, so there the call must only return an error and print nothing. The other FMUs
(Excitation, BladeExternalContact, ShroudContact) share the logging layer; one refused parameter
each is checked the same way.
"""

from __future__ import annotations

import ctypes
import math
from pathlib import Path
from typing import Callable

import numpy as np
import pytest
from fmpy import extract, read_model_description, simulate_fmu
from fmpy.fmi2 import FMU2Model, FMU2Slave
from fmpy.fmi3 import FMU3Slave

from tests.support import errors_fmi3
from tests.support import errors_me
from tests.fmu import test_fmu_errors
from harness.fmu import build as _build


class Fmus:
    """The extracted FMI 2.0 and 3.0 ShroudedBlade FMUs and their value references."""

    def __init__(self, fmu2: Path, fmu3: Path, tmp: Path) -> None:
        self.fmu2, self.fmu3 = fmu2, fmu3
        self.md2, self.md3 = read_model_description(fmu2), read_model_description(fmu3)
        self.dir2 = extract(fmu2, unzipdir=tmp / "fmi2")
        self.dir3 = extract(fmu3, unzipdir=tmp / "fmi3")
        self.vr2 = {v.name: v.valueReference for v in self.md2.modelVariables}
        self.vr3 = {v.name: v.valueReference for v in self.md3.modelVariables}

    def slave(self, guid: str | None = None) -> FMU2Slave:
        return FMU2Slave(
            guid=guid or self.md2.guid,
            unzipDirectory=self.dir2,
            instanceName="sb",
            modelIdentifier=self.md2.coSimulation.modelIdentifier,
        )

    def model(self) -> FMU2Model:
        return FMU2Model(
            guid=self.md2.guid,
            unzipDirectory=self.dir2,
            instanceName="sb",
            modelIdentifier=self.md2.modelExchange.modelIdentifier,
        )

    def slave3(self, token: str | None = None) -> FMU3Slave:
        return FMU3Slave(
            guid=token or self.md3.guid,
            unzipDirectory=self.dir3,
            instanceName="sb3",
            modelIdentifier=self.md3.coSimulation.modelIdentifier,
        )


@pytest.fixture(scope="module")
def fmus(fmu_path: Path, fmu3_path: Path, tmp_path_factory: pytest.TempPathFactory) -> Fmus:
    return Fmus(fmu_path, fmu3_path, tmp_path_factory.mktemp("reasons"))


def _refused(call: Callable[[], object]) -> None:
    """fmpy raises on an Error/Discard status (the exception says only the status)."""
    with pytest.raises(Exception):
        call()


def _simulate(fmus: Fmus, **kw) -> None:
    _refused(lambda: simulate_fmu(fmus.fmu2, stop_time=1e-3, output_interval=1e-4, **kw))


def _cs_ready(fmus: Fmus) -> FMU2Slave:
    s = fmus.slave()
    s.instantiate(loggingOn=False)
    s.setupExperiment(startTime=0.0)
    s.enterInitializationMode()
    s.exitInitializationMode()
    return s


def _in_step_mode(fmus: Fmus, act: Callable[[FMU2Slave], object]) -> None:
    s = _cs_ready(fmus)
    try:
        _refused(lambda: act(s))
    finally:
        s.freeInstance()


def _in_instantiated(fmus: Fmus, act: Callable[[FMU2Slave], object]) -> None:
    s = fmus.slave()
    s.instantiate(loggingOn=False)
    try:
        _refused(lambda: act(s))
    finally:
        s.freeInstance()


def _me(fmus: Fmus, act: Callable[[FMU2Model], object], continuous: bool = True) -> None:
    m = fmus.model()
    m.instantiate(loggingOn=False)
    try:
        if continuous:
            m.setupExperiment(startTime=0.0)
            m.enterInitializationMode()
            m.exitInitializationMode()
            m.newDiscreteStates()
            m.enterContinuousTimeMode()
        _refused(lambda: act(m))
    finally:
        m.freeInstance()


def _fmi3(fmus: Fmus, act: Callable[[FMU3Slave], object], mode: str = "step") -> None:
    s = fmus.slave3()
    s.instantiate(loggingOn=False)
    try:
        if mode in ("init", "step"):
            s.enterInitializationMode(startTime=0.0)
        if mode == "step":
            s.exitInitializationMode()
        _refused(lambda: act(s))
    finally:
        s.freeInstance()


def _derivative_out_of_range(s: FMU2Slave, vr: int) -> None:
    s.setReal([vr], [29999.0])
    s.setRealInputDerivatives([vr], [1], [1e7])
    s.doStep(currentCommunicationPoint=0.0, communicationStepSize=1e-3)


def _null_array(s: FMU2Slave, vr: int) -> None:
    value = (ctypes.c_double * 1)()
    s.fmi2GetReal(s.component, None, 1, value)


def _directional(s: FMU2Slave, fmus: Fmus) -> None:
    v = (ctypes.c_uint * 1)(fmus.vr2["tipDisplacement"])
    u = (ctypes.c_uint * 1)(fmus.vr2["aeroLoad"])
    seed, out = (ctypes.c_double * 1)(1.0), (ctypes.c_double * 1)()
    s.fmi2GetDirectionalDerivative(s.component, v, 1, u, 1, seed, out)


def _wrong_nx(m: FMU2Model) -> None:
    x = (ctypes.c_double * 4)()
    m.fmi2GetContinuousStates(m.component, x, 4)


def _null_array3(s: FMU3Slave, vr: int) -> None:
    v = (ctypes.c_uint * 1)(vr)
    s.fmi3GetFloat64(s.component, v, 1, None, 1)


def _instantiate(make: Callable[[], object]) -> None:
    _refused(lambda: make().instantiate(loggingOn=False))


# group -> (what drives it through fmpy, what the printed reason must contain)
SCENARIOS: dict[str, tuple[Callable[[Fmus], None], list[str]]] = {
    "parameter": (lambda f: _simulate(f, start_values={"gamma": 2.0}), ["gamma = 2", "(0, 1.5708)"]),
    "start value": (
        lambda f: _simulate(f, start_values={"runningMaximum": -1e-5}),
        ["runningMaximum = -1e-05", "[0, inf)"],
    ),
    "input": (
        lambda f: _in_step_mode(f, lambda s: s.setReal([f.vr2["rotorSpeed"]], [1e9])),
        ["rotorSpeed = 1e+09", "[0, 30000]"],
    ),
    "input derivative": (
        lambda f: _in_step_mode(f, lambda s: _derivative_out_of_range(s, f.vr2["rotorSpeed"])),
        ["rotorSpeed = 29999 rpm", "[0, 30000] rpm"],
    ),
    "instantiate": (
        lambda f: _instantiate(lambda: f.slave("{00000000-0000-0000-0000-000000000000}")),
        ["GUID {00000000-0000-0000-0000-000000000000} does not match"],
    ),
    "call order": (
        lambda f: _in_instantiated(f, lambda s: s.doStep(0.0, 1e-4)),
        ["fmi2DoStep: Illegal call sequence (state: instantiated)"],
    ),
    "experiment": (
        lambda f: _in_instantiated(f, lambda s: s.setupExperiment(startTime=2.0, stopTime=1.0)),
        ["stopTime = 1 s must be finite and >= startTime = 2 s"],
    ),
    "step": (
        lambda f: _in_step_mode(f, lambda s: s.doStep(0.0, -1e-4)),
        ["communicationStepSize = -0.0001 s must be > 0"],
    ),
    "huge step": (lambda f: _in_step_mode(f, lambda s: s.doStep(0.0, 1e3)), ["more than 10000000 are refused"]),
    "NULL pointer": (
        lambda f: _in_step_mode(f, lambda s: _null_array(s, f.vr2["tipDisplacement"])),
        ["fmi2GetReal: NULL array argument with nvr = 1"],
    ),
    "NULL component": (lambda f: _refused(lambda: f.slave().fmi2DoStep(None, 0.0, 1e-4, 1)), []),
    "state blob": (
        lambda f: _in_step_mode(f, lambda s: s.deSerializeFMUstate(b"\x00")),
        ["not a ShroudedBlade FMU state"],
    ),
    "unsupported": (
        lambda f: _in_step_mode(f, lambda s: _directional(s, f)),
        ["not supported (providesDirectionalDerivative = false)"],
    ),
    "value reference": (lambda f: _in_step_mode(f, lambda s: s.getReal([999])), ["unknown value reference 999"]),
    "ME arguments": (lambda f: _me(f, _wrong_nx), ["nx = 4, but this FMU has"]),
    "ME values": (lambda f: _me(f, lambda m: m.setTime(math.nan)), ["time = nan s is not a finite number"]),
    "ME call order": (
        lambda f: _me(f, lambda m: m.setTime(0.0), continuous=False),
        ["fmi2SetTime: Illegal call sequence (state: instantiated)"],
    ),
    "ME NULL component": (lambda f: _refused(lambda: f.model().fmi2SetTime(None, 0.0)), []),
    "FMI 3.0 value": (
        lambda f: _fmi3(f, lambda s: s.setFloat64([f.vr3["EI"]], [math.nan]), mode="init"),
        ["EI = nan N.m2 is not a finite number", "(0, inf)"],
    ),
    "FMI 3.0 value reference": (lambda f: _fmi3(f, lambda s: s.getFloat64([70])), ["unknown value reference 70"]),
    "FMI 3.0 call order": (
        lambda f: _fmi3(f, lambda s: s.doStep(0.0, 1e-4), mode="instantiated"),
        ["fmi3DoStep: Illegal call sequence (state: Instantiated)"],
    ),
    "FMI 3.0 instantiate": (
        lambda f: _instantiate(lambda: f.slave3("{00000000-0000-0000-0000-000000000000}")),
        ["instantiationToken {00000000-0000-0000-0000-000000000000} does not match"],
    ),
    "FMI 3.0 state blob": (
        lambda f: _fmi3(f, lambda s: s.deserializeFMUState(b"\x00" * 16)),
        ["fmi3DeserializeFMUState"],
    ),
    "FMI 3.0 step": (lambda f: _fmi3(f, lambda s: s.doStep(0.5, 1e-4)), ["does not match the FMU time 0 s"]),
    "FMI 3.0 NULL pointer": (
        lambda f: _fmi3(f, lambda s: _null_array3(s, f.vr3["tipDisplacement"])),
        ["fmi3GetFloat64: NULL array argument"],
    ),
    "FMI 3.0 NULL component": (
        lambda f: _refused(lambda: f.slave3().fmi3DoStep(None, 0.0, 1e-4, True, None, None, None, None)),
        [],
    ),
}
# accepted inputs: nothing to explain, and no error may be printed
VALID = {"valid boundary": {"gamma": 1.5707}, "valid run": {"frictionModel": 3}}


def test_every_catalogue_group_has_an_fmpy_scenario() -> None:
    groups = (
        {c.kind for c in test_fmu_errors.CASES}
        | {c.kind for c in errors_me.all_cases()}
        | {c.kind for c in errors_fmi3.all_cases()}
    )
    assert groups == set(SCENARIOS) | set(VALID)


@pytest.mark.parametrize("group", sorted(SCENARIOS))
def test_fmpy_prints_the_reason_with_debug_logging_off(
    fmus: Fmus, group: str, capsys: pytest.CaptureFixture[str]
) -> None:
    drive, reasons = SCENARIOS[group]
    drive(fmus)
    printed = capsys.readouterr().out
    if not reasons:  # no instance, no logger: an error status and silence
        assert printed == ""
        return
    lines = [ln for ln in printed.splitlines() if ln.startswith(("[ERROR]", "[DISCARD]", "[FATAL]"))]
    assert lines, f"{group}: fmpy printed no reason: {printed!r}"
    assert any(all(r in ln for r in reasons) for ln in lines), f"{group}: {reasons} not in {lines}"


@pytest.mark.parametrize("group", sorted(VALID))
def test_valid_inputs_print_no_error(fmus: Fmus, group: str, capsys: pytest.CaptureFixture[str]) -> None:
    t = np.arange(0.0, 1e-3 + 1e-12, 1e-4)
    load = np.array(list(zip(t, 300.0 * np.sin(2 * np.pi * 250.0 * t))), dtype=[("time", float), ("aeroLoad", float)])
    simulate_fmu(fmus.fmu2, stop_time=1e-3, output_interval=1e-4, start_values=VALID[group], input=load)
    assert "[ERROR]" not in capsys.readouterr().out


@pytest.mark.parametrize(
    "fmu_name, target, start_values, reason",
    [
        ("Excitation", "excitation_fmu", {"bladeCount": 0}, "bladeCount = 0"),
        ("BladeExternalContact", "blade_external_fmu", {"EI": -1.0}, "EI = -1"),
        ("ShroudContact", "shroud_contact_fmu", {"gamma": 2.0}, "gamma = 2"),
    ],
)
def test_other_fmus_print_the_reason_with_debug_logging_off(
    fmu_name: str, target: str, start_values: dict, reason: str, capsys: pytest.CaptureFixture[str]
) -> None:
    _build.build((target,))
    path = _build.BUILD_DIR / f"{fmu_name}.fmu"
    _refused(lambda: simulate_fmu(path, stop_time=1e-3, output_interval=1e-4, start_values=start_values))
    printed = capsys.readouterr().out
    assert any(ln.startswith("[ERROR]") and reason in ln for ln in printed.splitlines()), printed
