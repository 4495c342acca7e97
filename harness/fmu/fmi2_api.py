"""The FMI 2.0 C API as ctypes sees it: one signature table shared by the harness's raw calls
(BladeFMU's step loop, the period map) and the tests' binding (tests/fmi2raw.py). Every pointer
argument is a plain address (c_void_p; None is NULL) and statuses are ints, so the callers pass
preallocated buffers without conversions."""
from __future__ import annotations

import ctypes
from ctypes import c_char_p, c_double, c_int, c_size_t
from ctypes import c_void_p as _P
from typing import Any

SIGNATURES: dict[str, tuple[Any, list[Any]]] = {  # name: (restype, argtypes), FMI 2.0 section 2.1
    "fmi2GetTypesPlatform": (c_char_p, []),
    "fmi2GetVersion": (c_char_p, []),
    "fmi2SetDebugLogging": (c_int, [_P, c_int, c_size_t, _P]),
    "fmi2Instantiate": (_P, [c_char_p, c_int, c_char_p, c_char_p, _P, c_int, c_int]),
    "fmi2FreeInstance": (None, [_P]),
    "fmi2SetupExperiment": (c_int, [_P, c_int, c_double, c_double, c_int, c_double]),
    "fmi2EnterInitializationMode": (c_int, [_P]),
    "fmi2ExitInitializationMode": (c_int, [_P]),
    "fmi2Terminate": (c_int, [_P]),
    "fmi2Reset": (c_int, [_P]),
    "fmi2GetReal": (c_int, [_P, _P, c_size_t, _P]),
    "fmi2GetInteger": (c_int, [_P, _P, c_size_t, _P]),
    "fmi2GetBoolean": (c_int, [_P, _P, c_size_t, _P]),
    "fmi2GetString": (c_int, [_P, _P, c_size_t, _P]),
    "fmi2SetReal": (c_int, [_P, _P, c_size_t, _P]),
    "fmi2SetInteger": (c_int, [_P, _P, c_size_t, _P]),
    "fmi2SetBoolean": (c_int, [_P, _P, c_size_t, _P]),
    "fmi2SetString": (c_int, [_P, _P, c_size_t, _P]),
    "fmi2GetFMUstate": (c_int, [_P, _P]),
    "fmi2SetFMUstate": (c_int, [_P, _P]),
    "fmi2FreeFMUstate": (c_int, [_P, _P]),
    "fmi2SerializedFMUstateSize": (c_int, [_P, _P, _P]),
    "fmi2SerializeFMUstate": (c_int, [_P, _P, _P, c_size_t]),
    "fmi2DeSerializeFMUstate": (c_int, [_P, _P, c_size_t, _P]),
    "fmi2GetDirectionalDerivative": (c_int, [_P, _P, c_size_t, _P, c_size_t, _P, _P]),
    "fmi2SetRealInputDerivatives": (c_int, [_P, _P, c_size_t, _P, _P]),
    "fmi2GetRealOutputDerivatives": (c_int, [_P, _P, c_size_t, _P, _P]),
    "fmi2DoStep": (c_int, [_P, c_double, c_double, c_int]),
    "fmi2CancelStep": (c_int, [_P]),
    "fmi2GetStatus": (c_int, [_P, c_int, _P]),
    "fmi2GetRealStatus": (c_int, [_P, c_int, _P]),
    "fmi2GetIntegerStatus": (c_int, [_P, c_int, _P]),
    "fmi2GetBooleanStatus": (c_int, [_P, c_int, _P]),
    "fmi2GetStringStatus": (c_int, [_P, c_int, _P]),
}


def bind(dll: ctypes.CDLL, name: str) -> Any:
    """The exported function `name` of a loaded FMU binary as a ctypes function with its signature."""
    restype, argtypes = SIGNATURES[name]
    return ctypes.CFUNCTYPE(restype, *argtypes)((name, dll))


def declare(dll: ctypes.CDLL) -> None:
    """Set the signature of every FMI 2.0 function the library exports (attribute access)."""
    for name, (restype, argtypes) in SIGNATURES.items():
        if hasattr(dll, name):
            f = getattr(dll, name)
            f.restype, f.argtypes = restype, argtypes
