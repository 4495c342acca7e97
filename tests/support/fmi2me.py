"""The FMI 2.0 model-exchange functions (FMI 2.0 s.3.2) of one loaded binary under short names, for
the tests that drive a model-exchange instance of tests/support/fmi2raw.py: the model-exchange suite, the
invalid-input catalogue and the fuzz machine. They are the package binding's raw functions
(harness.fmu.binding.fmi2_signatures): statuses are ints, arrays are ctypes arrays or None (NULL),
out-arguments are ctypes.byref(...). NX and NZ come from modelDescription.xml, never from the code
under test."""

from __future__ import annotations

import xml.etree.ElementTree as ET
from ctypes import c_double

from tests.support.fmi2raw import MODEL_DESCRIPTION, Fmi2Library

from harness.fmu.binding.fmi2 import EventInfo  # noqa: F401 (the tests' out-argument of new_discrete)

_ROOT = ET.parse(MODEL_DESCRIPTION).getroot()
NX = sum(1 for _ in _ROOT.iter("Derivatives") for _ in _)  # one <Unknown> per state derivative
NZ = int(_ROOT.get("numberOfEventIndicators"))


class Me:
    """The model-exchange functions of one loaded binary (an Fmi2Library)."""

    def __init__(self, lib: Fmi2Library) -> None:
        self.get_x = lib.fmi2GetContinuousStates
        self.set_x = lib.fmi2SetContinuousStates
        self.get_dx = lib.fmi2GetDerivatives
        self.get_z = lib.fmi2GetEventIndicators
        self.nominals = lib.fmi2GetNominalsOfContinuousStates
        self.set_time = lib.fmi2SetTime
        self.new_discrete = lib.fmi2NewDiscreteStates
        self.enter_ct = lib.fmi2EnterContinuousTimeMode
        self.enter_event = lib.fmi2EnterEventMode
        self.completed = lib.fmi2CompletedIntegratorStep
        self.do_step = lib.fmi2DoStep


def arr(n: int, value: float = 0.0):  # noqa: ANN201
    return (c_double * n)(*([value] * n))
