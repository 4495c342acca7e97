"""Validate the FMU against the independent Python reference and print a pass/fail table.

`python -m harness validate [--quick] [--fmu FILE] [--output-file CSV] [--max-step S]`: the cases of
harness.validation.validate (time domain against the reference's simulation, steady states
against harmonic balance); exit code 1 if any row fails.
"""

from __future__ import annotations

import argparse

from harness.cli.options import add_fmu_option, check_outputs
from harness.validation.validate import HEADER, MAX_STEP, TD_STEP, cases, format_row, run_validation, write_table


def configure_parser(p: argparse.ArgumentParser) -> None:
    p.add_argument(
        "--quick",
        action="store_true",
        help="reduced matrix: one option changed at a time, 5000 rpm and a run-up, one HB setting",
    )
    add_fmu_option(p)
    p.add_argument(
        "--output-file",
        metavar="CSV",
        help="also write the table to this CSV file (default: none, the table is printed only)",
    )
    p.add_argument(
        "--max-step",
        type=float,
        default=MAX_STEP,
        metavar="S",
        help=f"FMU internal step maxStep for the time-domain cases (default {MAX_STEP:g} s; the FMU's"
        " own default is 1e-5)",
    )


def run(args: argparse.Namespace) -> int:
    check_outputs(args, ("output_file", "--output-file"))  # before the cases run
    case_list = cases(quick=args.quick)
    print(
        f"validating the FMU against harness.reference: {len(case_list)} cases, communication step"
        f" {TD_STEP:g} s, maxStep {args.max_step:g} s"
    )
    print(HEADER)
    rows = run_validation(
        case_list, args.fmu, on_row=lambda r: print(format_row(r), flush=True), max_step=args.max_step
    )
    failed = [r for r in rows if not r.passed]
    if args.output_file:
        write_table(args.output_file, rows)
    print(f"{len(rows) - len(failed)} of {len(rows)} checks pass" + (f"; {len(failed)} FAIL" if failed else ""))
    return 1 if failed else 0
