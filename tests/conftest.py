"""Shared fixtures: the FMU and the physics library built once per test session; the raw FMI
binding of the built FMU (or of $SB_FMU_BINARY, e.g. a sanitizer build) for the FMI-level tests."""

from __future__ import annotations

import os
from ctypes import byref
from pathlib import Path

import pytest
from fmpy.fmi1 import printLogMessage
from fmpy.fmi2 import fmi2CallbackFunctions, fmi2CallbackLoggerTYPE
from fmpy.logging import addLoggerProxy

from tests.support.fmi2raw import Fmi2Library
from harness.fmu import build as _build
from harness.fmu.blade import BladeFMU


# fmpy's native logger proxy (fmpy/logging) forwards the messages of every FMI 2.0 instance made with
# fmpy's default callbacks to ONE process-wide target: the logger of the last
# simulate_fmu(logger=...). When such a call raises (an FMU refusing its start values), fmpy frees
# that logger's callback while the target still points to it, and the next message of any FMU in the
# process jumps into freed memory (a segmentation fault in a later, unrelated test). After each test
# the target is set back to fmpy's own printLogMessage, whose callback lives as long as this module.
_PRINT_LOG_MESSAGE = fmi2CallbackLoggerTYPE(printLogMessage)


@pytest.fixture(autouse=True)
def _fmpy_logger_target_restored():
    yield
    callbacks = fmi2CallbackFunctions()
    callbacks.logger = _PRINT_LOG_MESSAGE
    addLoggerProxy(byref(callbacks))  # the proxy keeps callbacks.logger as its target


@pytest.fixture(scope="session")
def fmu_path() -> Path:
    """build/ShroudedBlade.fmu, built (if out of date) once per session."""
    return _build.build(("fmu",))


@pytest.fixture(scope="session")
def fmu3_path() -> Path:
    """build/fmi3/ShroudedBlade.fmu (FMI 3.0 co-simulation), built (if out of date) once per session."""
    _build.build(("fmu3",))
    return _build.FMU3_PATH


@pytest.fixture(scope="session")
def physics_lib() -> Path:
    """build/libsbphysics.so: blade.c and contact.c as a plain shared library for ctypes."""
    _build.build(("sbphysics",))
    return _build.PHYSICS_LIB


@pytest.fixture(scope="module")
def lib(request: pytest.FixtureRequest) -> Fmi2Library:
    """The raw FMI 2.0 binding (tests/support/fmi2raw.py) of the FMU under test."""
    if not os.environ.get("SB_FMU_BINARY"):
        request.getfixturevalue("fmu_path")  # build/ShroudedBlade.fmu, built once per session
    return Fmi2Library.get()


@pytest.fixture(scope="module")
def fmu(fmu_path: Path) -> BladeFMU:
    """The built FMU behind harness.fmu.blade.BladeFMU, one instance per test module."""
    with BladeFMU(fmu_path) as f:
        yield f
