"""Shared fixtures: the FMU and the physics library built once per test session; the raw FMI
binding of the built FMU (or of $SB_FMU_BINARY, e.g. a sanitizer build) for the FMI-level tests."""
from __future__ import annotations

import os
from pathlib import Path

import pytest

from tests.support.fmi2raw import Fmi2Library
from harness.fmu import build as _build
from harness.fmu.blade import BladeFMU


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
