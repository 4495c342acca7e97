"""Branches of periodic solutions over a speed range by continuation, to a CSV and a plot.

`python -m harness continue --speed-range LO HI [--model fixedB|fixedPoint|jenkins|coulomb]
[--start-values NAME VALUE ...] [--seed-step RPM] [--output-file branches.csv] [--plot branches.png] [--json]`
traces every branch found from the seed speeds (harness.analysis.periodic.branches) through its folds and
writes one CSV row per point (branch, speed, amplitude, B, state, stability, label, multipliers; to branches.csv by default, with --json only where --output-file asks);
the plot draws stable parts bold and unstable parts faint. Peaks and folds are located by
refinement (harness.analysis.periodic.extrema), not read off the sampled points. The paper's studies as branches are part
of `python -m harness run` (harness.studies.paper).
"""

from __future__ import annotations

import argparse
import json
import math
from pathlib import Path
from typing import Any

from harness.analysis.periodic.branches import BranchSettings, trace_branches
from harness.analysis.periodic.continuation import Branch, write_branches_csv
from harness.analysis.periodic.period_map import MODELS
from harness.cli.options import add_fmu_option, add_start_values, check_outputs, parse_start_values
from harness.fmu.blade import SPEED_RANGE, BladeFMU
from harness.model.params import ParameterError, validate
from harness.studies.plots import branches_figure

DEFAULT_CSV = "branches.csv"


def configure_parser(p: argparse.ArgumentParser) -> None:
    add_fmu_option(p)
    p.add_argument(
        "--speed-range",
        type=float,
        nargs=2,
        default=[3000.0, 10000.0],
        metavar=("LO", "HI"),
        help="speed range [rpm] (default 3000 10000)",
    )
    p.add_argument("--model", choices=MODELS, default="fixedPoint", help="as for `periodic` (default fixedPoint)")
    add_start_values(p)
    p.add_argument(
        "--seed-step",
        type=float,
        default=500.0,
        metavar="RPM",
        help="search every orbit at seed speeds this far apart (default 500 rpm)",
    )
    p.add_argument(
        "--output-file",
        metavar="CSV",
        help=f"branch CSV (default {DEFAULT_CSV}; with --json: no file unless this is given)",
    )
    p.add_argument("--plot", metavar="PNG", help="also plot the branches to this PNG file (default: no plot)")
    p.add_argument(
        "--json",
        action="store_true",
        help="print the branches with their located peaks and folds as JSON on stdout, nothing else",
    )


def run(args: argparse.Namespace) -> int:
    overrides = parse_start_values(args.start_values)
    validate(overrides, source="--start-values")  # named as the user gave them, before any work
    if not (math.isfinite(args.seed_step) and args.seed_step > 0):
        raise ParameterError(f"--seed-step {args.seed_step!r} rpm must be > 0")
    lo, hi = args.speed_range
    if not (math.isfinite(lo) and math.isfinite(hi) and 0.0 < lo < hi <= SPEED_RANGE[1]):
        raise ParameterError(f"--speed-range {lo!r} {hi!r} rpm: need 0 < LO < HI <= {SPEED_RANGE[1]:g}")
    if args.output_file is None and not args.json:  # --json prints the branches: a file only when asked
        args.output_file = DEFAULT_CSV
    check_outputs(args, ("output_file", "--output-file"), ("plot", "--plot"))
    with BladeFMU(args.fmu or None) as fmu:
        branches, stats = trace_branches(fmu, overrides, args.model, (lo, hi), BranchSettings(seed_step=args.seed_step))
    if args.output_file:
        write_branches_csv(Path(args.output_file), branches)
    if args.plot:
        branches_figure(Path(args.plot), {args.model: branches}, f"{args.model}, {overrides or 'Table 1'}")
    if args.json:
        print(
            json.dumps(
                {
                    "model": args.model,
                    "parameters": overrides,
                    "speed_range_rpm": [lo, hi],
                    "periods_simulated": stats.evaluations,
                    "output_file": args.output_file,
                    "branches": [branch_dict(b) for b in branches],
                },
                indent=1,
            )
        )
        return 0
    n = sum(len(b.points) for b in branches)
    print(
        f"{len(branches)} branch(es), {n} points, {stats.evaluations} periods simulated -> {args.output_file}"
        + (f", {args.plot}" if args.plot else "")
    )
    for i, b in enumerate(branches):
        print(f"  branch {i}: {b.speeds.min():.0f}..{b.speeds.max():.0f} rpm")
        for e in b.extrema:
            print(f"    {e.kind} at {e.speed:.2f} rpm, max|q| = {e.amplitude * 1e3:.6f} mm: {e.stability}")
        for lo_n, hi_n, kind in sampled_changes(b):
            print(f"    {kind} between {lo_n:.0f} and {hi_n:.0f} rpm (not located)")
    return 0


def sampled_changes(b: Branch) -> list[tuple[float, float, str]]:
    """(low, high [rpm], kind) of the stability changes that are not folds (period doubling,
    Neimark-Sacker): bracketed by the sampled points only."""
    out: list[tuple[float, float, str]] = []
    for j, kind in b.bifurcations():
        rest = [k for k in kind.split("+") if k != "fold"]
        if rest:
            lo_n, hi_n = sorted((b.points[j - 1].speed, b.points[j].speed))
            out.append((lo_n, hi_n, "+".join(rest)))
    return out


def branch_dict(b: Branch) -> dict[str, Any]:
    """A branch for --json: its points and its located peaks and folds."""
    return {
        "points": [
            {"speed_rpm": p.speed, "amplitude_m": p.amplitude, "stable": p.stable, "label": p.label} for p in b.points
        ],
        "peaks": [e.as_dict() for e in b.located("peak")],
        "folds": [e.as_dict() for e in b.located("fold")],
        "other_stability_changes": [
            {"from_rpm": lo_n, "to_rpm": hi_n, "kind": k} for lo_n, hi_n, k in sampled_changes(b)
        ],
        "end_reasons": b.end_reasons,
    }
