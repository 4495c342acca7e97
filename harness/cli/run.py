"""The main job: reproduce every study of the paper with the FMU and write results/ (make run).

`python -m harness run` = `python -m harness reproduce --size default` with all studies and
extras: Fig. 2, 4/5, 6-9 (the studies as branches of periodic orbits with their stability), the
section-4 Coulomb comparison and a Campbell diagram as PNG + CSV, summary.json and the claims
table claims.md. About a minute on 2 cores.
"""
from __future__ import annotations

import argparse

from harness.sweep.executor import RESULTS_DIR
from harness.cli.sweep import add_execution_options


def configure_parser(p: argparse.ArgumentParser) -> None:
    from harness.paper.studies import SIZES

    p.add_argument("--size", default="default", choices=list(SIZES), help="work size (default: default)")
    p.add_argument("--output-dir", default=str(RESULTS_DIR), metavar="DIR", help=f"where to write (default {RESULTS_DIR})")
    add_execution_options(p, cache=False)


def run(args: argparse.Namespace) -> int:
    from harness.cli.reproduce import reproduce_and_report

    return reproduce_and_report(args, args.size, None, True)
