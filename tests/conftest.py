"""Session fixtures: build the FMU and the physics library once per test session."""
from __future__ import annotations

from pathlib import Path

import pytest

from harness.fmu import build as _build


@pytest.fixture(scope="session")
def fmu_path() -> Path:
    """build/ShroudedBlade.fmu, built (if out of date) once per session."""
    return _build.build(("fmu",))


@pytest.fixture(scope="session")
def physics_lib() -> Path:
    """build/libsbphysics.so: blade.c and contact.c as a plain shared library for ctypes."""
    _build.build(("sbphysics",))
    return _build.PHYSICS_LIB
