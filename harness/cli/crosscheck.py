"""Cross-tool validation: the same FMU in independent FMI importers (libcosim, Ecos, FMI4j), compared with fmpy.

`python -m harness crosscheck [--scenario NAME] [--tools LIST] [--stop-time S] [--deliverables]
[--output-file MD] [--fmu FILE]` prints the agreement table of harness.crosscheck.run and writes
it to crosscheck/agreement.md (a checkout only); exit code 1 on a disagreement.
"""

from __future__ import annotations

import argparse
from pathlib import Path

from harness.crosscheck.plan import SCENARIOS
from harness.crosscheck.run import AGREEMENT_FILE, TOOLS, crosscheck


def configure_parser(p: argparse.ArgumentParser) -> None:
    p.add_argument(
        "--fmu",
        type=Path,
        default=None,
        metavar="FILE",
        help="FMU to check (default: build/ShroudedBlade.fmu, built if needed)",
    )
    p.add_argument(
        "--scenario",
        choices=sorted(SCENARIOS) + ["all"],
        default="all",
        metavar="NAME",
        help="; ".join(f"{k}: {v.description}" for k, v in sorted(SCENARIOS.items()))
        + "; all: every one (default all)",
    )
    p.add_argument(
        "--stop-time",
        type=float,
        default=None,
        metavar="S",
        help="shorten the scenarios to this stop time [s] (default: each scenario's own, 0.3 s)",
    )
    p.add_argument(
        "--tools",
        default=",".join(TOOLS),
        metavar="LIST",
        help=f"comma-separated subset of {','.join(TOOLS)} (default all of them)",
    )
    p.add_argument(
        "--deliverables",
        action="store_true",
        help="also regenerate crosscheck/fmus/... and crosscheck/results/... and validate them",
    )
    p.add_argument(
        "--output-file",
        type=Path,
        default=AGREEMENT_FILE,
        metavar="MD",
        help="where to write the agreement table (default crosscheck/agreement.md of the checkout)",
    )


def run(args: argparse.Namespace) -> int:
    return crosscheck(args.fmu, args.scenario, args.stop_time, args.tools, args.deliverables, args.output_file)
