"""Branches of periodic solutions over a speed range by continuation, to a CSV and a plot.

`python -m harness continue --speed-range LO HI [--model fixedB|fixedPoint|jenkins|coulomb]
[--start-values NAME VALUE ...] [--seed-step RPM] [--output-file branches.csv] [--plot branches.png]`
traces every branch found from the seed speeds (harness.sweep.periodic.branches) through its folds and
writes one CSV row per point (branch, speed, amplitude, B, state, stability, label, multipliers);
the plot draws stable parts bold and unstable parts faint. The paper's studies as branches are part
of `python -m harness run` (harness.paper.studies).
"""
from __future__ import annotations

import argparse
import math
from pathlib import Path

from harness.model.params import ParameterError
from harness.sweep.periodic.period_map import MODELS


def configure_parser(p: argparse.ArgumentParser) -> None:
    p.add_argument("--fmu", metavar="PATH", help="FMU file (default: the installed package's, or build/ShroudedBlade.fmu in a checkout, built if needed)")
    p.add_argument("--speed-range", type=float, nargs=2, default=[3000.0, 10000.0], metavar=("LO", "HI"),
                   help="speed range [rpm] (default 3000 10000)")
    p.add_argument("--model", choices=MODELS, default="fixedPoint", help="as for `periodic` (default fixedPoint)")
    p.add_argument("--start-values", nargs="+", default=[], metavar="NAME VALUE",
                   help="parameter name-value pairs, e.g. `--start-values d 4e-5 gating false`")
    p.add_argument("--seed-step", type=float, default=500.0, metavar="RPM",
                   help="search every orbit at seed speeds this far apart (default 500 rpm)")
    p.add_argument("--output-file", default="branches.csv", metavar="CSV", help="branch CSV (default branches.csv)")
    p.add_argument("--plot", metavar="PNG", help="also plot the branches to this PNG file")


def run(args: argparse.Namespace) -> int:
    from harness.fmu.blade import SPEED_RANGE, BladeFMU
    from harness.sweep.periodic.branches import BranchSettings, trace_branches
    from harness.sweep.periodic.continuation import write_branches_csv
    from harness.cli.simulate import parse_start_values

    overrides = parse_start_values(args.start_values)
    lo, hi = args.speed_range
    if not (math.isfinite(lo) and math.isfinite(hi) and 0.0 < lo < hi <= SPEED_RANGE[1]):
        raise ParameterError(f"--speed-range {lo!r} {hi!r} rpm: need 0 < LO < HI <= {SPEED_RANGE[1]:g}")
    with BladeFMU(args.fmu or None) as fmu:
        branches, stats = trace_branches(fmu, overrides, args.model, (lo, hi), BranchSettings(seed_step=args.seed_step))
    write_branches_csv(Path(args.output_file), branches)
    if args.plot:
        from harness.paper.plots import branches_figure
        branches_figure(Path(args.plot), {args.model: branches}, f"{args.model}, {overrides or 'Table 1'}")
    n = sum(len(b.points) for b in branches)
    print(f"{len(branches)} branch(es), {n} points, {stats.evaluations} periods simulated -> {args.output_file}"
          + (f", {args.plot}" if args.plot else ""))
    for i, b in enumerate(branches):
        bif = ", ".join(f"{k} at {b.points[j].speed:.0f} rpm" for j, k in b.bifurcations()) or "none"
        print(f"  branch {i}: {b.speeds.min():.0f}..{b.speeds.max():.0f} rpm, max|q| up to "
              f"{b.amplitudes.max() * 1e3:.5f} mm; stability changes: {bif}")
    return 0

