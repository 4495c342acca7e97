"""The one-mode FMUs' outputs as recorded from the FMUs built before the `modes` parameter existed
(tests/data/modes_m1_reference.json; tests/fmu/test_modes_m1_bitwise.py compares the current build
with them bit for bit).

Each scenario runs one FMU through fmpy.simulate_fmu and records, per variable, the SHA-256 of
the little-endian float64 bytes of every sample plus the last value as a hex float (for a message
that says how far a changed run moved). Record with
    python tests/support/modes_reference.py <dir with the old ShroudedBlade.fmu, fmi3/ShroudedBlade.fmu,
                                     BladeExternalContact.fmu> tests/data/modes_m1_reference.json
"""

from __future__ import annotations

import hashlib
import json
import sys
from pathlib import Path

import numpy as np
from fmpy import read_model_description, simulate_fmu

SENS = [
    f"d{r}_d{c}"
    for r in ("TipDisplacement", "TipVelocity", "JenkinsForce", "RunningMaximum", "Amplitude")
    for c in ("Q0", "V0", "F0", "B")
]

# name: (FMU file relative to the build directory, simulate_fmu keyword arguments, extra outputs)
SCENARIOS = {
    "cs_macroslip_tracked": (
        "ShroudedBlade.fmu",
        dict(stop_time=0.03, output_interval=1e-4, start_values={"Fw0": 100.0}),
        [],
    ),
    "cs_jenkins_consistent_runup": (
        "ShroudedBlade.fmu",
        dict(
            stop_time=0.03,
            output_interval=1e-4,
            start_values={"Fw0": 120.0, "frictionModel": 3, "formulation": 2, "projection": 2},
            input=np.array(
                [(0.0, 0.0, 4800.0), (0.03, 0.0, 5200.0)],
                dtype=[("time", float), ("aeroLoad", float), ("rotorSpeed", float)],
            ),
        ),
        [],
    ),
    "cs_coulomb_fixed_start": (
        "ShroudedBlade.fmu",
        dict(
            stop_time=0.02,
            output_interval=2e-4,
            start_values={
                "Fw0": 100.0,
                "frictionModel": 2,
                "amplitudeMode": 1,
                "tipDisplacement": 4e-5,
                "tipVelocity": -0.01,
                "maxStep": 2e-6,
            },
        ),
        [],
    ),
    "cs_sensitivities_jenkins": (
        "ShroudedBlade.fmu",
        dict(
            stop_time=0.012,
            output_interval=4e-4,
            start_values={"Fw0": 100.0, "frictionModel": 3, "sensitivities": True, "tipDisplacement": 5e-5},
        ),
        SENS,
    ),
    "cs_sensitivities_fixedB": (
        "ShroudedBlade.fmu",
        dict(
            stop_time=0.012,
            output_interval=4e-4,
            start_values={"Fw0": 100.0, "amplitudeMode": 1, "B": 5e-5, "sensitivities": True},
        ),
        SENS,
    ),
    "me_euler_jenkins": (
        "ShroudedBlade.fmu",
        dict(
            fmi_type="ModelExchange",
            solver="Euler",
            step_size=1e-6,
            stop_time=0.003,
            output_interval=1e-4,
            start_values={"Fw0": 100.0, "frictionModel": 3, "tipDisplacement": 5e-5},
        ),
        [],
    ),
    "fmi3_macroslip": (
        "fmi3/ShroudedBlade.fmu",
        dict(stop_time=0.02, output_interval=1e-4, start_values={"Fw0": 100.0, "frictionModel": 3}),
        [],
    ),
    "external_contact": (
        "BladeExternalContact.fmu",
        dict(
            stop_time=0.02,
            output_interval=1e-4,
            start_values={"Fw0": 100.0, "formulation": 2, "tipDisplacement": 1e-5},
            input=np.array(
                [(0.0, 0.0, 5000.0, 0.5, 0.0), (0.02, 0.0, 5000.0, -0.5, 0.2)],
                dtype=[
                    ("time", float),
                    ("aeroLoad", float),
                    ("rotorSpeed", float),
                    ("contactForce", float),
                    ("contactForce2", float),
                ],
            ),
        ),
        [],
    ),
}


def outputs_of(fmu: Path) -> list[str]:
    """The outputs the old FMU declared (the sensitivities were outputs then: left out here)."""
    md = read_model_description(str(fmu))
    return [
        v.name
        for v in md.modelVariables
        if v.causality == "output" and v.name not in SENS and v.type in ("Real", "Float64")
    ]


def run(build: Path, name: str, names: list[str] | None = None) -> dict[str, dict[str, str]]:
    """{variable: {"sha256": ..., "last": hex}} of scenario `name` on the FMUs in `build`."""
    rel, kw, extra = SCENARIOS[name]
    fmu = build / rel
    names = names if names is not None else outputs_of(fmu) + extra
    res = simulate_fmu(str(fmu), output=names, **kw)
    out = {}
    for n in names:
        col = np.ascontiguousarray(res[n], dtype="<f8")
        out[n] = {
            "sha256": hashlib.sha256(col.tobytes()).hexdigest(),
            "last": float(col[-1]).hex(),
            "samples": int(col.size),
        }
    return out


def main(build: str, out: str) -> None:
    rec = {name: run(Path(build), name) for name in SCENARIOS}
    Path(out).write_text(json.dumps(rec, indent=1, sort_keys=True) + "\n")


if __name__ == "__main__":
    main(*sys.argv[1:3])
