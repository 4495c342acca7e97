"""Raw ctypes prototypes of the FMI 2.0 model-exchange functions (FMI 2.0 s.3.2), for the tests
that drive a model-exchange instance of tests/fmi2raw.py: the model-exchange suite, the invalid-input
catalogue and the fuzz machine. Statuses are ints; array arguments take ctypes arrays or None (NULL).
NX and NZ come from modelDescription.xml, never from the code under test."""
from __future__ import annotations

import ctypes
import xml.etree.ElementTree as ET
from ctypes import POINTER, c_double, c_int, c_size_t, c_void_p

from fmi2raw import MODEL_DESCRIPTION

_ROOT = ET.parse(MODEL_DESCRIPTION).getroot()
NX = sum(1 for _ in _ROOT.iter("Derivatives") for _ in _)  # one <Unknown> per state derivative
NZ = int(_ROOT.get("numberOfEventIndicators"))


def _fn(lib, name: str, *argtypes):  # noqa: ANN001, ANN202
    """A fresh prototype bound to the binary (the shared binding's prototypes stay untouched)."""
    return ctypes.CFUNCTYPE(c_int, c_void_p, *argtypes)((name, lib.dll))


class EventInfo(ctypes.Structure):
    _fields_ = [("newDiscreteStatesNeeded", c_int), ("terminateSimulation", c_int),
                ("nominalsOfContinuousStatesChanged", c_int), ("valuesOfContinuousStatesChanged", c_int),
                ("nextEventTimeDefined", c_int), ("nextEventTime", c_double)]


class Me:
    """The model-exchange functions of one loaded binary (an Fmi2Library)."""

    def __init__(self, lib) -> None:  # noqa: ANN001
        arr = POINTER(c_double)
        self.get_x = _fn(lib, "fmi2GetContinuousStates", arr, c_size_t)
        self.set_x = _fn(lib, "fmi2SetContinuousStates", arr, c_size_t)
        self.get_dx = _fn(lib, "fmi2GetDerivatives", arr, c_size_t)
        self.get_z = _fn(lib, "fmi2GetEventIndicators", arr, c_size_t)
        self.nominals = _fn(lib, "fmi2GetNominalsOfContinuousStates", arr, c_size_t)
        self.set_time = _fn(lib, "fmi2SetTime", c_double)
        self.new_discrete = _fn(lib, "fmi2NewDiscreteStates", POINTER(EventInfo))
        self.enter_ct = _fn(lib, "fmi2EnterContinuousTimeMode")
        self.enter_event = _fn(lib, "fmi2EnterEventMode")
        self.completed = _fn(lib, "fmi2CompletedIntegratorStep", c_int, POINTER(c_int), POINTER(c_int))
        self.do_step = _fn(lib, "fmi2DoStep", c_double, c_double, c_int)


def arr(n: int, value: float = 0.0):  # noqa: ANN201
    return (c_double * n)(*([value] * n))
