"""Every periodic solution of the FMU at one rotor speed, by shooting, with its Floquet stability.

`python -m harness periodic --speed RPM [--model fixedB|fixedPoint|jenkins|coulomb]
[--start-values NAME VALUE ...] [--json]` prints each orbit found (harness.analysis.periodic.search): its
amplitude max |q| [m], the B [m] of the describing function where it applies, the Floquet
multipliers, stability and label, and the FMU start values that start a run on it. --json prints
one JSON object on stdout, nothing else.
"""

from __future__ import annotations

import argparse
import json
import math

from harness.analysis.periodic.branches import orbits_at
from harness.analysis.periodic.period_map import MODELS, PeriodMap, STATE_STARTS
from harness.cli.options import add_fmu_option, add_start_values, parse_start_values
from harness.fmu.blade import SPEED_RANGE, BladeFMU
from harness.model.params import ParameterError, input_range, validate
from harness.analysis.periodic.shooting import describe


def configure_parser(p: argparse.ArgumentParser) -> None:
    add_fmu_option(p)
    p.add_argument(
        "--speed",
        type=float,
        required=True,
        metavar="RPM",
        help=f"rotor speed [rpm], in (0, {input_range('rotorSpeed')[1]:g}] (required)",
    )
    p.add_argument(
        "--model",
        choices=MODELS,
        default="fixedPoint",
        help="fixedB: B fixed (parameter B); fixedPoint: the paper's B = A(B) (default); jenkins: "
        "the time-domain macroslip element; coulomb: the Coulomb describing function with B = A(B)",
    )
    add_start_values(p)
    p.add_argument("--json", action="store_true", help="print the solutions as JSON on stdout")


def run(args: argparse.Namespace) -> int:
    overrides = parse_start_values(args.start_values)
    bad = [k for k in overrides if k in STATE_STARTS or k.startswith("modal")]
    if bad:
        raise ParameterError(
            f"--start-values {bad[0]}: the state at the section is what shooting solves for; give parameters only"
        )
    validate(overrides, source="--start-values")  # named as the user gave them, before any work
    if not (math.isfinite(args.speed) and 0.0 < args.speed <= SPEED_RANGE[1]):
        raise ParameterError(f"--speed {args.speed!r} rpm outside (0, {SPEED_RANGE[1]:g}] (the FMU's rotorSpeed range)")
    with BladeFMU(args.fmu or None) as fmu:
        pm = PeriodMap(fmu, overrides, args.model)
        orbits = orbits_at(pm, args.speed)
    out = {
        "speed_rpm": args.speed,
        "model": args.model,
        "parameters": overrides,
        "period_s": 2 * math.pi / (int(pm.p["engineOrder"]) * 2 * math.pi * args.speed / 60.0),
        "solutions": [o.as_dict() for o in orbits],
        "periods_simulated": pm.evaluations,
    }
    if args.json:
        print(json.dumps(out, indent=1))
        return 0
    print(
        f"{len(orbits)} periodic solution(s) of model {args.model} at {args.speed:g} rpm "
        f"({pm.evaluations} periods simulated):"
    )
    for o in orbits:
        B = "" if math.isnan(o.B) else f", B = {o.B * 1e3:.6f} mm"
        mus = ", ".join(f"{abs(m):.4f}" for m in o.multipliers)
        print(f"  max|q| = {o.amplitude * 1e3:.6f} mm{B}: {describe(o.multipliers)}  (|mu| = {mus})")
    return 0
