"""ctypes binding of build/libsbphysics.so (fmu_src/physics/blade.c and contact.c) for the physics tests.

The structures mirror fmu_src/physics/blade.h and contact.h field by field (C enums are ints);
`PhysicsLib` wraps each exported function in a small typed Python method that returns the C return
code next to the filled structure, so the tests can check both the values and the error paths.
"""

from __future__ import annotations

import ctypes
from ctypes import POINTER, byref, c_double, c_int
from pathlib import Path

FORMULATION_PRINTED, FORMULATION_CONSISTENT = 1, 2
MACROSLIP_DF, COULOMB_DF, MACROSLIP_TD = 1, 2, 3
PROJECTION_PAPER, PROJECTION_CONSISTENT = 1, 2
REGIME_OPEN, REGIME_STICK_SLIP, REGIME_FULL_STICK = 0, 1, 2
STATE_OPEN, STATE_STICK, STATE_SLIP = 0, 1, 2


class BladeParams(ctypes.Structure):
    _fields_ = [(n, c_double) for n in ("EI", "rho", "A", "l", "c", "m0")]


class BladeReduction(ctypes.Structure):
    _fields_ = [
        (n, c_double)
        for n in (
            "lambdaL",
            "U1",
            "U2",
            "U3",
            "U4",
            "U5",
            "intPhi",
            "u2",
            "M",
            "C0",
            "K0static",
            "K0omega2",
            "loadGain",
        )
    ]

    def as_dict(self) -> dict[str, float]:
        return {name: getattr(self, name) for name, _ in self._fields_}


class ContactParams(ctypes.Structure):
    _fields_ = [(n, c_double) for n in ("kn", "kdRatio", "mu", "gamma", "d")]


class DescribingFunction(ctypes.Structure):
    _fields_ = [("regime", c_int)] + [
        (n, c_double) for n in ("theta1", "theta2", "theta3", "fk", "fcOmega", "pk", "Keq", "CeqOmega")
    ]

    def as_dict(self) -> dict[str, float]:
        return {name: getattr(self, name) for name, _ in self._fields_}


class PhysicsLib:
    """Typed access to the exported functions of libsbphysics.so."""

    def __init__(self, path: Path | str) -> None:
        lib = ctypes.CDLL(str(path))
        lib.bladeReduce.argtypes = [POINTER(BladeParams), c_int, POINTER(BladeReduction)]
        lib.bladeReduce.restype = c_int
        lib.bladeK0.argtypes = [POINTER(BladeReduction), c_double]
        lib.bladeK0.restype = c_double
        lib.contactParamsValid.argtypes = [POINTER(ContactParams)]
        lib.contactParamsValid.restype = c_int
        lib.contactRegime.argtypes = [POINTER(ContactParams), c_double]
        lib.contactRegime.restype = c_int
        lib.contactModelRegime.argtypes = [POINTER(ContactParams), c_int, c_double]
        lib.contactModelRegime.restype = c_int
        lib.contactDescribe.argtypes = [POINTER(ContactParams), c_int, c_int, c_double, POINTER(DescribingFunction)]
        lib.contactDescribe.restype = c_int
        lib.contactNormalForce.argtypes = [POINTER(ContactParams), c_double]
        lib.contactNormalForce.restype = c_double
        lib.contactLoopFriction.argtypes = [POINTER(ContactParams), c_int, c_double, c_double]
        lib.contactLoopFriction.restype = c_double
        lib.contactLoopState.argtypes = [POINTER(ContactParams), c_int, c_double, c_double]
        lib.contactLoopState.restype = c_int
        self.lib = lib

    # --- blade.c ---
    def blade_reduce(self, formulation: int = FORMULATION_PRINTED, **params: float) -> tuple[int, BladeReduction]:
        out = BladeReduction()
        rc = self.lib.bladeReduce(byref(BladeParams(**params)), formulation, byref(out))
        return rc, out

    def blade_k0(self, red: BladeReduction, omega: float) -> float:
        return self.lib.bladeK0(byref(red), omega)

    # --- contact.c ---
    def params_valid(self, cp: ContactParams) -> bool:
        return bool(self.lib.contactParamsValid(byref(cp)))

    def regime(self, cp: ContactParams, B: float, model: int | None = None) -> int:
        if model is None:
            return self.lib.contactRegime(byref(cp), B)
        return self.lib.contactModelRegime(byref(cp), model, B)

    def describe(
        self, cp: ContactParams, B: float, model: int = MACROSLIP_DF, projection: int = PROJECTION_PAPER
    ) -> tuple[int, DescribingFunction]:
        out = DescribingFunction()
        rc = self.lib.contactDescribe(byref(cp), model, projection, B, byref(out))
        return rc, out

    def normal_force(self, cp: ContactParams, v: float) -> float:
        return self.lib.contactNormalForce(byref(cp), v)

    def loop_friction(self, cp: ContactParams, B: float, theta: float, model: int = MACROSLIP_DF) -> float:
        return self.lib.contactLoopFriction(byref(cp), model, B, theta)

    def loop_state(self, cp: ContactParams, B: float, theta: float, model: int = MACROSLIP_DF) -> int:
        return self.lib.contactLoopState(byref(cp), model, B, theta)
