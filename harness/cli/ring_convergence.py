"""The ring's co-simulation error against the monolithic reference as the communication step shrinks, per extrapolation order.

`python -m harness ring-convergence [--out PATH]` runs harness.validation.ring_convergence (the
fmpy master at orders 0-3 and libcosim), writes PATH.csv and PATH.png (default
results/ring_convergence) and prints the errors and the measured orders.
"""

from __future__ import annotations

import argparse
from pathlib import Path

from harness.outputs import check_dir
from harness.validation.ring_convergence import Study, errors, measured_order, write


def configure_parser(p: argparse.ArgumentParser) -> None:
    p.add_argument(
        "--out",
        type=Path,
        default=Path("results/ring_convergence"),
        metavar="PATH",
        help="the files' path without suffix (default results/ring_convergence)",
    )


def run(args: argparse.Namespace) -> int:
    check_dir(args.out.parent, "--out")  # before the runs
    rows = errors(Study(), libcosim=True)
    write(rows, args.out)
    for r in rows:
        print(*r)
    for p in dict.fromkeys(r[0] for r in rows):
        print(f"{p}: measured convergence order {measured_order(rows, p):.2f}")
    return 0
