"""Check whether the ring engine's stability verdicts hold at finer steps: its orbits shot again at h = T/K.

`python -m harness ring-step-check [--blades 6] [--pattern SIGMA INDEX] [--speeds 5000 7500]
[--steps-per-period 160] [--finer 320 640] [--every 1] [--above 0] [--branches FILE] [--out results]`
runs harness.validation.ring_refine on the engine's branches of the mistuning study's tuned ring (or
one of its stiffness patterns): DIR/ring_step_check.csv (one row per orbit), DIR/ring_step_check.json
(the summary and the cost) and a short printed summary.
"""

from __future__ import annotations

import argparse
import json
import math
import time

from harness.cli.ring_check_options import check_ring, ring_options, the_ring
from harness.files.atomic import atomic_write_text
from harness.model.params import ParameterError
from harness.validation import ring_completeness as rc
from harness.validation import ring_refine as rr


def configure_parser(p: argparse.ArgumentParser) -> None:
    ring_options(p)
    p.add_argument(
        "--finer",
        type=int,
        nargs="+",
        default=[320, 640],
        metavar="K",
        help="the finer steps per period, increasing, each above --steps-per-period (default 320 640)",
    )
    p.add_argument("--every", type=int, default=1, metavar="N", help="every N-th orbit of the branches (default 1)")
    p.add_argument(
        "--above", type=float, default=0.0, metavar="A", help="only orbits with a blade above A [m] (default 0)"
    )


def check(args: argparse.Namespace) -> None:
    """Every argument against its range, before any work."""
    check_ring(args)
    steps = [args.steps_per_period, *args.finer]
    if any(b <= a for a, b in zip(steps, steps[1:])) or steps[-1] > 100000:
        finer = " ".join(str(k) for k in args.finer)
        raise ParameterError(
            f"--finer {finer}: need steps increasing from --steps-per-period {args.steps_per_period} up to 100000"
        )
    if not 1 <= args.every <= 10**6:
        raise ParameterError(f"--every {args.every} outside [1, 1000000]")
    if not (math.isfinite(args.above) and 0.0 <= args.above <= 1.0):
        raise ParameterError(f"--above {args.above!r} m outside [0, 1]")


def run(args: argparse.Namespace) -> int:
    check(args)
    ring = the_ring(args)
    steps = [args.steps_per_period, *args.finer]
    c0, w0 = time.process_time(), time.perf_counter()
    branches, xs, engine = rc.engine_branches(ring, tuple(args.speeds), args.branches, args.steps_per_period)
    rows = rr.refine(ring, branches, xs, steps, args.every, args.above)
    out = rr.summary(rows, steps)
    settings = {k: getattr(args, k) for k in ("blades", "pattern", "speeds", "steps_per_period", "every", "above")}
    cost = {"cpu_s": time.process_time() - c0, "wall_s": time.perf_counter() - w0}
    rr.write_csv(args.out / "ring_step_check.csv", rows, steps)
    record = {"settings": settings, "engine": engine, "cost": cost, **out}
    atomic_write_text(args.out / "ring_step_check.json", json.dumps(record, indent=1) + "\n")
    print(
        f"{ring.n}-blade ring, {args.speeds[0]:g}..{args.speeds[1]:g} rpm: {out['orbits']} of the engine's orbits at"
        f" h = T/{' T/'.join(str(k) for k in steps)}; {out['followed']} followed to T/{steps[-1]},"
        f" {out['changed']} changed their stability ({out['stable_to_unstable']} stable -> unstable,"
        f" {out['unstable_to_stable']} unstable -> stable)"
        + (f", the largest of them {out['changed_largest_m']:.4e} m at" if out["changed"] else "")
        + "".join(f" {v:g}" for v in out["changed_speeds_rpm"])
        + (" rpm" if out["changed"] else "")
    )
    print(
        f"  largest stable among the followed: {out['largest_stable_first_m']:.5e} m at T/{steps[0]},"
        f" {out['largest_stable_finest_m']:.5e} m at T/{steps[-1]}; {cost['cpu_s']:.0f} CPU s"
    )
    return 0
