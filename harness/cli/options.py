"""Options shared by several commands, and their parsing: the FMU file, the parameter start
values, the output files checked before any work, where the work runs (workers, a dask scheduler,
the point cache)."""

from __future__ import annotations

import argparse
from typing import Any

from harness.analysis.config import ConfigError
from harness.paths import DEFAULT_CACHE_DIR
from harness.analysis.executor import Runner
from harness.model.params import ParameterError
from harness.outputs import check_file

# the --start-values help of the commands on the single blade (the ring's says what it sets where)
START_VALUES_HELP = (
    "parameter name-value pairs, e.g. `--start-values d 4e-5 kn 1e6 gating false` (names and units"
    " as in modelDescription.xml; default: none, paper Table 1)"
)


def add_fmu_option(p: argparse.ArgumentParser) -> None:
    p.add_argument(
        "--fmu",
        metavar="FILE",
        help="the FMU file (a .fmu, not a directory; default: the harness's own: the installed"
        " package's, or build/ShroudedBlade.fmu in a checkout, built if needed)",
    )


def add_start_values(p: argparse.ArgumentParser, help: str = START_VALUES_HELP) -> None:
    p.add_argument("--start-values", nargs="+", default=[], metavar="NAME VALUE", help=help)


def parse_start_values(items: list[str]) -> dict[str, Any]:
    """`--start-values` NAME VALUE pairs as a dict (values as given; the model validates them)."""
    if len(items) % 2:
        raise ParameterError(f"--start-values needs NAME VALUE pairs; got {len(items)} item(s): {' '.join(items)}")
    return {items[i]: items[i + 1] for i in range(0, len(items), 2)}


def check_outputs(args: argparse.Namespace, *options: tuple[str, str]) -> None:
    """Refuse, before any work, an output file (attribute, option name) that cannot be written."""
    for attr, option in options:
        if getattr(args, attr, None):
            check_file(getattr(args, attr), option)


def add_execution_options(p: argparse.ArgumentParser, cache: bool = True, fmu: bool = True) -> None:
    """Options shared by sweep / reproduce / run / mistuning: where and how the work runs (with
    `cache`, the per-point result cache of the transient sweeps; with `fmu`, the blade FMU to use)."""
    if fmu:
        add_fmu_option(p)
    p.add_argument(
        "--workers",
        type=int,
        default=None,
        metavar="N",
        help="local worker processes (default: number of CPUs; 1 = in this process)",
    )
    p.add_argument(
        "--scheduler",
        metavar="ADDRESS",
        help="run on a dask.distributed cluster, e.g. tcp://10.0.0.5:8786 (one FMU per worker;"
        " default: none, local processes)",
    )
    if cache:
        p.add_argument(
            "--cache-dir",
            default=str(DEFAULT_CACHE_DIR),
            metavar="DIR",
            help=f"per-point result cache, makes interrupted runs resumable (default {DEFAULT_CACHE_DIR})",
        )
        p.add_argument("--no-cache", action="store_true", help="compute every point again, store nothing")
    p.add_argument("--quiet", action="store_true", help="no progress bars")


def make_runner(args: argparse.Namespace) -> Runner:
    """The Runner of the execution options (after checking --workers)."""
    if args.workers is not None and args.workers < 1:
        raise ConfigError(f"--workers {args.workers} must be >= 1")
    return Runner(workers=args.workers, scheduler=args.scheduler, progress=not args.quiet)
