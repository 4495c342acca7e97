"""The second bending mode's engine-order crossing with the shroud contact, as branches of periodic orbits.

The base case with m = 2 modes (consistent formulation) excited in an engine order whose line
crosses the second mode inside the FMU's speed range (EO 8: contact-free crossing near 11670 rpm,
results/campbell_modes.csv): the branches of the Jenkins element and of the fixed point B = A(B)
over a window around the crossing, their located peaks and jumps (harness.analysis.periodic), and
where the contact moves the resonance from the contact-free crossing (harness.studies.campbell_modes).
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from pathlib import Path
from typing import Any, Mapping

from harness.analysis.periodic.branches import BranchSettings, trace_branches
from harness.analysis.periodic.continuation import write_branches_csv
from harness.analysis.periodic.curve import jump_speed, peak_orbit
from harness.fmu.blade import SPEED_RANGE
from harness.studies import plots
from harness.studies.campbell_modes import campbell, campbell_params

MODELS = ("jenkins", "fixedPoint")


@dataclass(frozen=True)
class CrossingBranch:
    model: str
    peak: float  # [m] largest max|q| of a stable orbit (located)
    speed: float  # [rpm]
    jump: float  # [rpm] the fold where that stable part ends (nan: none)


@dataclass(frozen=True)
class Mode2Crossing:
    engine_order: int
    free_crossing: float  # [rpm] contact-free crossing of mode 2 with the engine order
    branches: list[CrossingBranch]


def mode2_crossing(
    fmu: Any, out: Path, base: Mapping[str, Any], engine_order: int = 8, window: float = 0.15, seed_step: float = 500.0
) -> Mode2Crossing:
    """results/mode2_crossing_branches.csv and .png: the branches over [1 - window, 1 + window]
    times the contact-free crossing speed."""
    p = campbell_params(dict(base, formulation=2, engineOrder=engine_order), 2)
    top = SPEED_RANGE[1]  # the FMU's rotorSpeed max [rpm] (modelDescription.xml)
    rough = campbell(fmu, p, [8000.0, top], orders=(engine_order,))
    free = next((c.speed_rpm for c in rough.crossings if c.mode == 2), math.nan)
    if not math.isfinite(free):
        raise ValueError(f"mode 2 does not cross EO {engine_order} between 8000 and {top:g} rpm")
    rng = (free * (1 - window), min(free * (1 + window), top))
    rows, traced = [], {}
    for model in MODELS:
        br, _ = trace_branches(fmu, p, model, rng, BranchSettings(seed_step=seed_step))
        traced[model] = br
        o = peak_orbit(br, speed_range=rng)
        a, n = (math.nan, math.nan) if o is None else (o.amplitude, o.speed)
        rows.append(CrossingBranch(model, a, n, jump_speed(br, a, n)))
    every = [(m, b) for m in MODELS for b in traced[m]]
    write_branches_csv(out / "mode2_crossing_branches.csv", [b for _, b in every], {"model_set": [m for m, _ in every]})
    plots.branches_figure(
        out / "mode2_crossing.png",
        {m: traced[m] for m in MODELS},
        f"Base case, m = 2 (consistent), EO {engine_order}: the second mode's crossing "
        f"(contact-free {free:.0f} rpm) with the contact",
    )
    return Mode2Crossing(engine_order, free, rows)
