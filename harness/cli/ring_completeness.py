"""Check that the ring's periodic-orbit engine finds every stable steady state: runs from rest and from random starts against its branches.

`python -m harness ring-completeness [--blades 6] [--pattern SIGMA INDEX] [--speeds 5000 7500] [--spacing 10] [--random 3]
[--seed 1] [--settle 1e-6] [--max-periods 1500] [--steps-per-period 160] [--jobs 1] [--branches FILE] [--out results]` runs
harness.validation.ring_completeness on the mistuning study's tuned ring (or one of its stiffness
patterns): DIR/ring_completeness.csv
(one row per run), DIR/ring_completeness.json (the summary and the cost) and a short printed summary.
"""

from __future__ import annotations

import argparse
import json
import math
import time

import numpy as np

from harness.files.atomic import atomic_write_text
from harness.cli.ring_check_options import check_ring, ring_options, the_ring
from harness.model.params import ParameterError
from harness.system.ring_orbits.seeds import RANDOM_SEED
from harness.system.ring_orbits.symmetry import index_maps
from harness.validation import ring_completeness as rc
from harness.validation.ring_missed import follow


def configure_parser(p: argparse.ArgumentParser) -> None:
    ring_options(p)
    p.add_argument("--spacing", type=float, default=rc.SPACING, metavar="RPM", help="between grid speeds (default 10)")
    p.add_argument("--random", type=int, default=rc.RANDOM, metavar="K", help="random starts per speed (default 3)")
    p.add_argument("--seed", type=int, default=rc.SEED, metavar="S", help="their seed, not the engine's 2 (default 1)")
    p.add_argument(
        "--settle",
        type=float,
        default=rc.SETTLE,
        metavar="TOL",
        help="settled: scaled period residual below TOL (default 1e-6)",
    )
    p.add_argument(
        "--max-periods", type=int, default=rc.MAX_PERIODS, metavar="K", help="periods per run at most (default 1500)"
    )
    p.add_argument(
        "--follow-missed",
        action="store_true",
        help="continue every missed state's branch across the band (the engine's continuation) to see where it goes",
    )
    p.add_argument("--jobs", type=int, default=1, metavar="J", help="processes running the starts (default 1)")


def check(args: argparse.Namespace) -> None:
    """Every argument against its range, before any work."""
    check_ring(args)
    lo, hi = args.speeds
    if not (math.isfinite(args.spacing) and 0.1 <= args.spacing <= hi - lo):
        raise ParameterError(f"--spacing {args.spacing!r} rpm outside [0.1, TO - FROM = {hi - lo:g}]")
    if not 0 <= args.random <= 100:
        raise ParameterError(f"--random {args.random} outside [0, 100] (random starts per speed)")
    if not 0 <= args.seed < 2**63:
        raise ParameterError(f"--seed {args.seed} outside [0, 2^63)")
    if args.seed == RANDOM_SEED and args.random > 0:
        raise ParameterError(
            f"--seed {args.seed} is the engine's own random starts' seed: the check would start where the engine did"
        )
    if not (math.isfinite(args.settle) and 1e-12 <= args.settle <= 1e-2):
        raise ParameterError(f"--settle {args.settle!r} outside [1e-12, 1e-2] (scaled period residual)")
    if not 10 <= args.max_periods <= 10**6:
        raise ParameterError(f"--max-periods {args.max_periods} outside [10, 1000000]")
    if not 1 <= args.jobs <= 64:
        raise ParameterError(f"--jobs {args.jobs} outside [1, 64] (processes)")


def run(args: argparse.Namespace) -> int:
    check(args)
    lo, hi = args.speeds
    speeds = lo + args.spacing * np.arange(math.floor((hi - lo) / args.spacing + 1e-9) + 1)
    ring = the_ring(args)
    c0, w0 = time.process_time(), time.perf_counter()
    steps = args.steps_per_period
    branches, xs, engine = rc.engine_branches(ring, (lo, hi), args.branches, steps)
    runs, cost = rc.collect(ring, speeds, args.random, args.seed, args.settle, args.max_periods, args.jobs, steps=steps)
    cost["compare_periods"] = rc.compare(ring, runs, branches, xs, steps)
    cost["cpu_s_main_process"] = time.process_time() - c0  # the engine (if computed) and the comparison
    cost["wall_s"] = time.perf_counter() - w0
    out = rc.summary(runs, index_maps(ring))
    settings = {
        k: getattr(args, k)
        for k in (
            "blades",
            "pattern",
            "speeds",
            "spacing",
            "random",
            "seed",
            "settle",
            "max_periods",
            "steps_per_period",
            "jobs",
        )
    }
    if args.follow_missed:
        out["missed_branches"] = [
            follow(
                ring, (lo, hi), m["speed_rpm"], m["start"], args.seed, branches, args.settle, args.max_periods, steps
            )
            for m in out["missed"]
        ]
    record = {"settings": settings, "engine": engine, "cost": cost, **out}
    rc.write_csv(args.out / "ring_completeness.csv", runs)
    atomic_write_text(args.out / "ring_completeness.json", json.dumps(record, indent=1) + "\n")
    print(
        f"{ring.n}-blade ring, {lo:g}..{hi:g} rpm, {len(speeds)} speeds x {1 + args.random} starts: {out['runs']} runs, "
        f"{len(out['not_settled'])} not settled in {args.max_periods} periods, {out['settled_stable_orbits']} settled"
        f" stable orbits ({out['distinct_states']} distinct states), {out['on_branches']} on the engine's branches"
        f" ({out['on_branches_by_newton']} by Newton at the speed), {len(out['unstable_after_settling'])} unstable"
    )
    print(
        f"  engine: {engine['branches']} branches, {engine['points']} points; this check: "
        f"{cost['settle_periods'] + cost['polish_periods'] + cost['compare_periods']} periods, {cost['cpu_s']:.0f} CPU s"
    )
    for m in out["missed"]:
        amps = " ".join(f"{a:.4e}" for a in m["amplitudes_m"])
        print(f"  MISSED {m['speed_rpm']:.1f} rpm ({m['start']}): {amps} m, |mu| {m['max_multiplier']:.4f}")
    for f in out.get("missed_branches", []):
        print(f"  the branch through {f['speed_rpm']:.1f} rpm ({f['start']}): {json.dumps(f)}")
    return 0
