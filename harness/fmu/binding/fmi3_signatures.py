"""The FMI 3.0 C API as ctypes sees it (FMI 3.0 s.2.3 common, s.3.2 model exchange, s.4.2
co-simulation; clocks and scheduled execution are left out: no FMU of the project has them):
name -> (restype, argtypes). Pointers, arrays, callbacks and the instance environment are plain
addresses (c_void_p; None is NULL); fmi3Boolean is C's bool; strings passed by value are char*."""

from __future__ import annotations

from ctypes import c_bool, c_char_p, c_double, c_int, c_size_t, c_uint32
from ctypes import c_void_p as _P
from typing import Any

_S, _B, _F, _N, _I = c_char_p, c_bool, c_double, c_size_t, c_int  # fmi3String, Boolean, Float64, size_t, fmi3Status
_GET = [_P, _P, _N, _P, _N]  # (instance, vr[], nvr, values[], nValues)
_TYPES = (
    "Float32",
    "Float64",
    "Int8",
    "UInt8",
    "Int16",
    "UInt16",
    "Int32",
    "UInt32",
    "Int64",
    "UInt64",
    "Boolean",
    "String",
)

COMMON: dict[str, tuple[Any, list[Any]]] = {
    "fmi3GetVersion": (_S, []),
    "fmi3SetDebugLogging": (_I, [_P, _B, _N, _P]),
    "fmi3InstantiateModelExchange": (_P, [_S, _S, _S, _B, _B, _P, _P]),
    "fmi3InstantiateCoSimulation": (_P, [_S, _S, _S, _B, _B, _B, _B, _P, _N, _P, _P, _P]),
    "fmi3FreeInstance": (None, [_P]),
    "fmi3EnterInitializationMode": (_I, [_P, _B, _F, _F, _B, _F]),
    "fmi3ExitInitializationMode": (_I, [_P]),
    "fmi3EnterEventMode": (_I, [_P]),
    "fmi3Terminate": (_I, [_P]),
    "fmi3Reset": (_I, [_P]),
    **{f"fmi3Get{t}": (_I, _GET) for t in _TYPES},
    **{f"fmi3Set{t}": (_I, _GET) for t in _TYPES},
    "fmi3GetBinary": (_I, [_P, _P, _N, _P, _P, _N]),
    "fmi3SetBinary": (_I, [_P, _P, _N, _P, _P, _N]),
    "fmi3GetNumberOfVariableDependencies": (_I, [_P, c_uint32, _P]),
    "fmi3GetVariableDependencies": (_I, [_P, c_uint32, _P, _P, _P, _P, _N]),
    "fmi3GetFMUState": (_I, [_P, _P]),
    "fmi3SetFMUState": (_I, [_P, _P]),
    "fmi3FreeFMUState": (_I, [_P, _P]),
    "fmi3SerializedFMUStateSize": (_I, [_P, _P, _P]),
    "fmi3SerializeFMUState": (_I, [_P, _P, _P, _N]),
    "fmi3DeserializeFMUState": (_I, [_P, _P, _N, _P]),
    "fmi3GetDirectionalDerivative": (_I, [_P, _P, _N, _P, _N, _P, _N, _P, _N]),
    "fmi3GetAdjointDerivative": (_I, [_P, _P, _N, _P, _N, _P, _N, _P, _N]),
    "fmi3EnterConfigurationMode": (_I, [_P]),
    "fmi3ExitConfigurationMode": (_I, [_P]),
    "fmi3EvaluateDiscreteStates": (_I, [_P]),
    "fmi3UpdateDiscreteStates": (_I, [_P, _P, _P, _P, _P, _P, _P]),
}

MODEL_EXCHANGE: dict[str, tuple[Any, list[Any]]] = {
    "fmi3EnterContinuousTimeMode": (_I, [_P]),
    "fmi3CompletedIntegratorStep": (_I, [_P, _B, _P, _P]),
    "fmi3SetTime": (_I, [_P, _F]),
    "fmi3SetContinuousStates": (_I, [_P, _P, _N]),
    "fmi3GetContinuousStateDerivatives": (_I, [_P, _P, _N]),
    "fmi3GetEventIndicators": (_I, [_P, _P, _N]),
    "fmi3GetContinuousStates": (_I, [_P, _P, _N]),
    "fmi3GetNominalsOfContinuousStates": (_I, [_P, _P, _N]),
    "fmi3GetNumberOfEventIndicators": (_I, [_P, _P]),
    "fmi3GetNumberOfContinuousStates": (_I, [_P, _P]),
}

CO_SIMULATION: dict[str, tuple[Any, list[Any]]] = {
    "fmi3EnterStepMode": (_I, [_P]),
    "fmi3GetOutputDerivatives": (_I, [_P, _P, _N, _P, _P, _N]),
    "fmi3DoStep": (_I, [_P, _F, _F, _B, _P, _P, _P, _P]),
}

SIGNATURES = {**COMMON, **MODEL_EXCHANGE, **CO_SIMULATION}
