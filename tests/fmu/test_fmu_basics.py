"""Basic packaging checks of build/ShroudedBlade.fmu: valid per fmpy, GUID of the XML compiled into
the binary, every FMI 2.0 function exported, and fmpy runs the default experiment (and a loaded
run with an input signal) with finite outputs.
"""

from __future__ import annotations

import ctypes
import math
import zipfile
from pathlib import Path

import numpy as np
import fmpy
from fmpy import read_model_description
from fmpy.validation import validate_fmu

FMI2_FUNCTIONS = """
fmi2GetTypesPlatform fmi2GetVersion fmi2SetDebugLogging fmi2Instantiate fmi2FreeInstance
fmi2SetupExperiment fmi2EnterInitializationMode fmi2ExitInitializationMode fmi2Terminate fmi2Reset
fmi2GetReal fmi2GetInteger fmi2GetBoolean fmi2GetString fmi2SetReal fmi2SetInteger fmi2SetBoolean
fmi2SetString fmi2GetFMUstate fmi2SetFMUstate fmi2FreeFMUstate fmi2SerializedFMUstateSize
fmi2SerializeFMUstate fmi2DeSerializeFMUstate fmi2GetDirectionalDerivative
fmi2EnterEventMode fmi2NewDiscreteStates fmi2EnterContinuousTimeMode fmi2CompletedIntegratorStep
fmi2SetTime fmi2SetContinuousStates fmi2GetDerivatives fmi2GetEventIndicators fmi2GetContinuousStates
fmi2GetNominalsOfContinuousStates
fmi2SetRealInputDerivatives fmi2GetRealOutputDerivatives fmi2DoStep fmi2CancelStep fmi2GetStatus
fmi2GetRealStatus fmi2GetIntegerStatus fmi2GetBooleanStatus fmi2GetStringStatus
""".split()


def test_validate_fmu(fmu_path: Path) -> None:
    assert validate_fmu(str(fmu_path)) == []


def test_guid_in_binary_equals_xml(fmu_path: Path) -> None:
    with zipfile.ZipFile(fmu_path) as zf:
        binary = zf.read("binaries/linux64/ShroudedBlade.so")
    guid = read_model_description(str(fmu_path)).guid
    assert guid.encode("ascii") in binary


def test_every_fmi2_function_exported(fmu_path: Path, tmp_path: Path) -> None:
    assert len(FMI2_FUNCTIONS) == 44
    with zipfile.ZipFile(fmu_path) as zf:
        zf.extract("binaries/linux64/ShroudedBlade.so", tmp_path)
    lib = ctypes.CDLL(str(tmp_path / "binaries/linux64/ShroudedBlade.so"))
    missing = [name for name in FMI2_FUNCTIONS if not hasattr(lib, name)]
    assert missing == []
    lib.fmi2GetVersion.restype = ctypes.c_char_p
    lib.fmi2GetTypesPlatform.restype = ctypes.c_char_p
    assert lib.fmi2GetVersion() == b"2.0"
    assert lib.fmi2GetTypesPlatform() == b"default"


def _assert_finite(result: np.ndarray) -> None:
    for name in result.dtype.names:
        assert np.all(np.isfinite(result[name].astype(float))), name


def test_default_experiment_runs(fmu_path: Path) -> None:
    result = fmpy.simulate_fmu(str(fmu_path))
    assert result.dtype.names[0] == "time"
    assert result["time"][-1] == 0.3  # DefaultExperiment stopTime
    _assert_finite(result)


def test_loaded_run_with_input(fmu_path: Path) -> None:
    """aeroLoad = 100 sin(3 Omega t) from an input table at 5000 rpm: outputs finite, contact reached."""
    omega = 3 * 2 * math.pi * 5000 / 60
    t = np.linspace(0.0, 0.05, 5001)
    signal = np.array(list(zip(t, 100 * np.sin(omega * t))), dtype=[("time", float), ("aeroLoad", float)])
    result = fmpy.simulate_fmu(
        str(fmu_path), stop_time=0.05, output_interval=1e-5, input=signal, start_values={"frictionModel": 3}
    )
    _assert_finite(result)
    assert np.max(np.abs(result["tipDisplacement"])) > 3e-5  # beyond the gap d
    assert set(np.unique(result["contactState"])) >= {0, 1, 2}  # open, stick and slip all seen
