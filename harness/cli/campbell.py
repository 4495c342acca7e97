"""Campbell diagram of the m-mode blade: its contact-free mode frequencies and their engine-order crossings.

`python -m harness campbell --modes M [--speed RPM | --speeds FROM TO [--points N]]
[--start-values NAME VALUE ...] [--plot out.png] [--json]` prints the FMU's modeFrequency[1..M]
[Hz] at one speed (key `frequencies_hz`: one value per mode), or per speed per mode over a range
(`speeds_rpm`, `frequencies_hz`: one list per speed), and the speeds where mode i crosses engine
order k = 1..8 (`crossings`, located by brentq; with --speed: over the FMU's whole speed range
0..30000 rpm). With M > 1 the consistent formulation is used unless --start-values sets
`formulation` (the printed one has one mode). --json prints one JSON object on stdout, nothing else.
"""

from __future__ import annotations

import argparse
import json

import numpy as np

from harness.cli.options import add_fmu_option, add_start_values, parse_start_values
from harness.fmu.blade import SPEED_RANGE, BladeFMU
from harness.model.params import ParameterError
from harness.studies.campbell_modes import (
    MAX_MODES,
    campbell,
    campbell_params,
    check_modes,
    check_speed,
    mode_frequencies,
    plot,
)

POINTS_RANGE = (2, 10001)


def configure_parser(p: argparse.ArgumentParser) -> None:
    add_fmu_option(p)
    p.add_argument("--modes", type=int, required=True, metavar="M", help=f"number of bending modes, 1..{MAX_MODES}")
    g = p.add_mutually_exclusive_group()
    g.add_argument(
        "--speed",
        type=float,
        metavar="RPM",
        help=f"one rotor speed [rpm] in [{SPEED_RANGE[0]:g}, {SPEED_RANGE[1]:g}] (default 5000)",
    )
    g.add_argument(
        "--speeds",
        type=float,
        nargs=2,
        metavar=("FROM", "TO"),
        help="a speed range [rpm], FROM < TO (default: none, one speed)",
    )
    p.add_argument(
        "--points",
        type=int,
        default=101,
        metavar="N",
        help=f"speeds on the grid of --speeds (default 101, {POINTS_RANGE[0]}..{POINTS_RANGE[1]})",
    )
    add_start_values(
        p,
        help="parameter name-value pairs, e.g. `--start-values m0 0.05 EI 400` (default: none, the"
        " model description's values)",
    )
    p.add_argument("--plot", metavar="PNG", help="write the diagram (with --speeds; default: none)")
    p.add_argument("--json", action="store_true", help="print the result as JSON on stdout")


def run(args: argparse.Namespace) -> int:
    m = check_modes(args.modes)
    overrides = parse_start_values(args.start_values)
    if "modes" in overrides:
        raise ParameterError("--start-values modes: give the number of modes with --modes M")
    params = campbell_params(overrides, m)
    if args.speeds is not None:
        lo, hi = (check_speed(v, w) for v, w in zip(args.speeds, ("--speeds FROM", "--speeds TO")))
        if not lo < hi:
            raise ParameterError(f"--speeds {lo:g} {hi:g}: FROM must be below TO")
        if not POINTS_RANGE[0] <= args.points <= POINTS_RANGE[1]:
            raise ParameterError(f"--points = {args.points} outside the range [{POINTS_RANGE[0]}, {POINTS_RANGE[1]}]")
        grid = np.linspace(lo, hi, args.points)
    else:
        speed = check_speed(5000.0 if args.speed is None else args.speed, "--speed")
        grid = np.linspace(*SPEED_RANGE, 301)
    if args.plot and args.speeds is None:
        raise ParameterError("--plot needs --speeds FROM TO (a diagram over a speed range)")
    with BladeFMU(args.fmu or None) as fmu:
        data = campbell(fmu, params, grid)
        out = data.as_dict()
        if args.speeds is None:
            out = {
                "modes": m,
                "speed_rpm": speed,
                "frequencies_hz": mode_frequencies(fmu, params, speed).tolist(),
                "crossings": out["crossings"],
            }
    if args.plot:
        plot(args.plot, data, int(params["engineOrder"]))
    if args.json:
        print(json.dumps(out, indent=1))
        return 0
    if args.speeds is None:
        print(f"{m} mode(s) at {speed:g} rpm: " + ", ".join(f"{f:.4f} Hz" for f in out["frequencies_hz"]))
    else:
        print(
            f"{m} mode(s) over {grid[0]:g}..{grid[-1]:g} rpm ({len(grid)} speeds); at the ends: "
            + "; ".join(
                ", ".join(f"{f:.2f}" for f in row) + " Hz" for row in (data.frequencies[0], data.frequencies[-1])
            )
        )
    for c in data.crossings:
        print(f"  mode {c.mode} crosses EO {c.engine_order} at {c.speed_rpm:.3f} rpm ({c.frequency_hz:.3f} Hz)")
    return 0
