"""Benchmark the FMU and the harness and write bench/RESULTS.md (make bench; a checkout only).

`python -m harness bench [--size SIZE] [--workers N] [--skip-reproduce] [--only ring|ring-orbits|cli | --only-modes]
[--quick] [--output-file MD]`: the measurements of harness.bench, written to MD and its .json beside it.
"""

from __future__ import annotations

import argparse

from harness.bench import BENCH_DIR, run_bench


def configure_parser(p: argparse.ArgumentParser) -> None:
    p.add_argument(
        "--size",
        default="default",
        metavar="SIZE",
        help="reproduce size to time: quick, default or full (default: default)",
    )
    p.add_argument(
        "--workers",
        type=int,
        default=None,
        metavar="N",
        help="worker processes for reproduce (default: number of CPUs)",
    )
    p.add_argument("--skip-reproduce", action="store_true", help="do not time the whole reproduce")
    p.add_argument(
        "--output-file",
        default=str(BENCH_DIR / "RESULTS.md"),
        metavar="MD",
        help="where to write the results (default bench/RESULTS.md)",
    )
    p.add_argument(
        "--only",
        choices=("ring", "ring-orbits", "cli"),
        help="measure only this section and keep the others from the output file's .json (default: every section)",
    )
    p.add_argument(
        "--only-modes",
        action="store_true",
        help="measure only the cost per RK4 step vs the number of modes and write that section",
    )
    p.add_argument(
        "--quick",
        action="store_true",
        help="every row once at tiny sizes, in seconds (a check that each row runs; the numbers mean "
        "nothing): written to --output-file only when one is given, else printed",
    )


def run(args: argparse.Namespace) -> int:
    return run_bench(
        args.output_file, args.size, args.workers, args.skip_reproduce, args.only, args.only_modes, args.quick
    )
