"""The options the ring's checks share (ring-completeness, ring-step-check): which ring (the mistuning
study's tuned ring or one of its stiffness patterns), the band, the step, the engine's branches'
cache and the output directory; checked before any work."""

from __future__ import annotations

import argparse
import math
from pathlib import Path

from harness.cli.ring import speed_range
from harness.model.params import ParameterError
from harness.outputs import check_dir, check_file
from harness.system.ring import Ring
from harness.system.ring_values import max_blades
from harness.validation import ring_completeness as rc


def ring_options(p: argparse.ArgumentParser) -> None:
    p.add_argument("--blades", type=int, default=6, metavar="N", help="blades of the study's tuned ring (default 6)")
    p.add_argument(
        "--speeds",
        type=float,
        nargs=2,
        default=list(rc.BAND),
        metavar=("FROM", "TO"),
        help="the band [rpm] (default 5000 7500)",
    )
    p.add_argument(
        "--pattern",
        nargs=2,
        default=None,
        metavar=("SIGMA", "INDEX"),
        help="the study's blade stiffness pattern INDEX at level SIGMA (default: the tuned ring)",
    )
    steps = "communication steps per excitation period, h = T / K, of the engine and the runs (default 160)"
    p.add_argument("--steps-per-period", type=int, default=rc.STEPS, metavar="K", help=steps)
    p.add_argument(
        "--branches",
        type=Path,
        default=None,
        metavar="FILE",
        help="the engine's branches cached in FILE (.npz; default: none, computed each time)",
    )
    p.add_argument(
        "--out", type=Path, default=Path("results"), metavar="DIR", help="output directory (default results)"
    )


def check_ring(args: argparse.Namespace) -> None:
    """The shared options against their ranges (--pattern parsed into (sigma, index))."""
    nmax = max_blades()
    if not 2 <= args.blades <= nmax:
        raise ParameterError(f"--blades {args.blades} outside [2, {nmax}] (a ring; the blade FMU's bladeCount)")
    lo, hi = args.speeds
    smin, smax = speed_range()
    for s in (lo, hi):
        if not (math.isfinite(s) and smin < s <= smax):
            raise ParameterError(f"--speeds {s!r} rpm outside ({smin:g}, {smax:g}] (BladeExternalContact's rotorSpeed)")
    if not lo < hi:
        raise ParameterError(f"--speeds {lo:g} {hi:g}: FROM must be below TO")
    if args.pattern is not None:
        args.pattern = _pattern(args.pattern)
    if not 8 <= args.steps_per_period <= 100000:
        raise ParameterError(f"--steps-per-period {args.steps_per_period} outside [8, 100000]")
    if args.branches is not None:
        if args.branches.suffix != ".npz":
            raise ParameterError(f"--branches {args.branches}: need a file ending in .npz")
        check_file(args.branches, "--branches")
    check_dir(args.out, "--out")


def _pattern(values: list[str]) -> tuple[float, int]:
    """--pattern SIGMA INDEX checked: sigma in (0, 0.2] as the study's levels, a whole INDEX >= 0."""
    try:
        sigma = float(values[0])
    except ValueError:
        sigma = math.nan
    if not (math.isfinite(sigma) and 0.0 < sigma <= 0.2):
        raise ParameterError(f"--pattern SIGMA {values[0]!r} outside (0, 0.2] (relative standard deviation)")
    if not (values[1].isdigit() and int(values[1]) < 10**6):
        raise ParameterError(f"--pattern INDEX {values[1]!r}: need a whole number in [0, 999999]")
    return sigma, int(values[1])


def the_ring(args: argparse.Namespace) -> Ring:
    """The ring the checked options name."""
    try:
        return rc.study_ring(args.blades, args.pattern)
    except ValueError as e:  # a factor <= 0 (harness.studies.mistuning.factors)
        raise ParameterError(f"--pattern {args.pattern[0]:g} {args.pattern[1]}: {e}") from None
