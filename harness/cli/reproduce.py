"""A chosen part of the paper's studies (figures 2 and 4-9, section 4, Campbell), without the mistuning study, into --out (default ./shroudedblade-results); `run` is the whole main job.

`python -m harness reproduce [--size quick|default|full] [--studies gap mass angle kn]
[--output-dir DIR] [--workers N | --scheduler ADDRESS]`. Writes one PNG and CSV files per
figure, summary.json and claims.md (paper claim | ours | settings | verdict); files are replaced
atomically. The studies are branches of periodic orbits (harness.studies.study_branches).
Fig. 2 compares the FMU's loop with the reference's: the studies come from
harness.validation.reproduction, the validation layer below the CLI (docs/layers.md).
"""

from __future__ import annotations

import argparse

from harness.paths import RESULTS_DIR
from harness.cli.options import add_execution_options
from harness.cli.reports import reproduce_and_report
from harness.studies.paper import SIZES, STUDIES


def configure_parser(p: argparse.ArgumentParser) -> None:
    p.add_argument(
        "--size",
        default="default",
        choices=list(SIZES),
        help="quick (a test run: extremes only, coarse grid), default (make run), full (fine grids)",
    )
    p.add_argument(
        "--studies",
        nargs="+",
        choices=list(STUDIES),
        metavar="STUDY",
        help=f"parameter studies to run (default all: {' '.join(STUDIES)})",
    )
    p.add_argument(
        "--no-extras",
        action="store_true",
        help="only the parameter studies (skip Fig. 2, 4/5, Campbell, Coulomb, paper iteration)",
    )
    p.add_argument(
        "--out",
        "--output-dir",
        dest="output_dir",
        default=str(RESULTS_DIR),
        metavar="DIR",
        help=f"where to write (default ./{RESULTS_DIR})",
    )
    add_execution_options(p, cache=False)


def run(args: argparse.Namespace) -> int:
    reproduce_and_report(args, args.size, args.studies, not args.no_extras)
    return 0
