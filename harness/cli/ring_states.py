"""Which steady state a tuned ring settles on: the co-simulation against the monolithic reference, and the travelling wave's stability.

`python -m harness ring-states CASE [--stop S] [--rtol R ...]` prints the numbers of one case of
docs/findings/ring-steady-states.md (harness.validation.ring_states): a6400, a7000 (6 blades,
c = 298, 0.3 s by default) or b (8 blades, 5000 rpm, c = 29.8, 2 s by default, one reference run
per --rtol).
"""

from __future__ import annotations

import argparse

from harness.validation.ring_states import SETTINGS, case_a, case_b


def configure_parser(p: argparse.ArgumentParser) -> None:
    p.add_argument("case", choices=[*SETTINGS], help="the case of the findings page")
    p.add_argument(
        "--stop",
        type=float,
        default=None,
        metavar="S",
        help="horizon [s] (default: none, the case's own: 0.3 for the a cases, 2 for b)",
    )
    p.add_argument(
        "--rtol",
        type=float,
        nargs="+",
        default=[1e-9],
        metavar="R",
        help="the reference's tolerances, case b (default 1e-9)",
    )


def run(args: argparse.Namespace) -> int:
    if args.case.startswith("a"):
        case_a(args.case, args.stop or 0.3)
    else:
        case_b(args.stop or 2.0, tuple(args.rtol))
    return 0
