"""The FMI 2.0 C API as ctypes sees it (FMI 2.0 s.2.1 common, s.3.2 model exchange, s.4.2
co-simulation): name -> (restype, argtypes). Every pointer or array argument is a plain address
(c_void_p; None is NULL) so callers pass preallocated buffers without conversions; fmi2Boolean and
the enums (fmi2Status, fmi2Type, fmi2StatusKind) are C ints; strings passed by value are char*."""

from __future__ import annotations

from ctypes import c_char_p, c_double, c_int, c_size_t
from ctypes import c_void_p as _P
from typing import Any

_S, _R, _I, _N = c_char_p, c_double, c_int, c_size_t  # fmi2String, fmi2Real, fmi2Integer/Boolean/enums, size_t
_VALUES = [_P, _P, _N, _P]  # (c, vr[], nvr, value[])

COMMON: dict[str, tuple[Any, list[Any]]] = {
    "fmi2GetTypesPlatform": (_S, []),
    "fmi2GetVersion": (_S, []),
    "fmi2SetDebugLogging": (_I, [_P, _I, _N, _P]),
    "fmi2Instantiate": (_P, [_S, _I, _S, _S, _P, _I, _I]),
    "fmi2FreeInstance": (None, [_P]),
    "fmi2SetupExperiment": (_I, [_P, _I, _R, _R, _I, _R]),
    "fmi2EnterInitializationMode": (_I, [_P]),
    "fmi2ExitInitializationMode": (_I, [_P]),
    "fmi2Terminate": (_I, [_P]),
    "fmi2Reset": (_I, [_P]),
    "fmi2GetReal": (_I, _VALUES),
    "fmi2GetInteger": (_I, _VALUES),
    "fmi2GetBoolean": (_I, _VALUES),
    "fmi2GetString": (_I, _VALUES),
    "fmi2SetReal": (_I, _VALUES),
    "fmi2SetInteger": (_I, _VALUES),
    "fmi2SetBoolean": (_I, _VALUES),
    "fmi2SetString": (_I, _VALUES),
    "fmi2GetFMUstate": (_I, [_P, _P]),
    "fmi2SetFMUstate": (_I, [_P, _P]),
    "fmi2FreeFMUstate": (_I, [_P, _P]),
    "fmi2SerializedFMUstateSize": (_I, [_P, _P, _P]),
    "fmi2SerializeFMUstate": (_I, [_P, _P, _P, _N]),
    "fmi2DeSerializeFMUstate": (_I, [_P, _P, _N, _P]),
    "fmi2GetDirectionalDerivative": (_I, [_P, _P, _N, _P, _N, _P, _P]),
}

MODEL_EXCHANGE: dict[str, tuple[Any, list[Any]]] = {
    "fmi2EnterEventMode": (_I, [_P]),
    "fmi2NewDiscreteStates": (_I, [_P, _P]),
    "fmi2EnterContinuousTimeMode": (_I, [_P]),
    "fmi2CompletedIntegratorStep": (_I, [_P, _I, _P, _P]),
    "fmi2SetTime": (_I, [_P, _R]),
    "fmi2SetContinuousStates": (_I, [_P, _P, _N]),
    "fmi2GetDerivatives": (_I, [_P, _P, _N]),
    "fmi2GetEventIndicators": (_I, [_P, _P, _N]),
    "fmi2GetContinuousStates": (_I, [_P, _P, _N]),
    "fmi2GetNominalsOfContinuousStates": (_I, [_P, _P, _N]),
}

CO_SIMULATION: dict[str, tuple[Any, list[Any]]] = {
    "fmi2SetRealInputDerivatives": (_I, [_P, _P, _N, _P, _P]),
    "fmi2GetRealOutputDerivatives": (_I, [_P, _P, _N, _P, _P]),
    "fmi2DoStep": (_I, [_P, _R, _R, _I]),
    "fmi2CancelStep": (_I, [_P]),
    "fmi2GetStatus": (_I, [_P, _I, _P]),
    "fmi2GetRealStatus": (_I, [_P, _I, _P]),
    "fmi2GetIntegerStatus": (_I, [_P, _I, _P]),
    "fmi2GetBooleanStatus": (_I, [_P, _I, _P]),
    "fmi2GetStringStatus": (_I, [_P, _I, _P]),
}

SIGNATURES = {**COMMON, **MODEL_EXCHANGE, **CO_SIMULATION}
