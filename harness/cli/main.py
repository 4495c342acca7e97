"""Command line `python -m harness <command> ...`: argument parsing and error reporting only.

Commands live in their own modules of this package, registered in COMMANDS (name -> module path);
each module provides `configure_parser(parser)` and `run(args) -> int`, options shared by several
commands are in cli/options.py. Only the module of the command being run is imported (`--help`
and `--version` import none: no numpy, scipy or fmpy); the one-line help shown by `--help` is the
first sentence of each module's docstring (read without importing). Known user errors (bad
parameter, missing FMU, bad input signal, FMU failure) print one line `error: ...` saying what to
do and exit with code 2; option names follow fmpy's command line where they overlap.
"""

from __future__ import annotations

import argparse
import ast
import importlib
import importlib.util
import os
import re
import sys
from typing import Any, Sequence

from harness.paths import IN_CHECKOUT

# command name -> module (add your command with one line), imported only when it runs
COMMANDS: dict[str, str] = {
    "simulate": "harness.cli.simulate",
    "validate": "harness.cli.validate",
    "crosscheck": "harness.cli.crosscheck",
    "run": "harness.cli.run",
    "reproduce": "harness.cli.reproduce",
    "bench": "harness.cli.bench",
    "periodic": "harness.cli.periodic",
    "continue": "harness.cli.continuation",
    "ring": "harness.cli.ring",
    "mistuning": "harness.cli.mistuning",
    "campbell": "harness.cli.campbell",
    "ring-states": "harness.cli.ring_states",
    "ring-convergence": "harness.cli.ring_convergence",
    "ring-energy": "harness.cli.ring_energy",
    "ring-completeness": "harness.cli.ring_completeness",
    "ring-step-check": "harness.cli.ring_step_check",
    "mistuning-dask": "harness.cli.mistuning_dask",
}

EXIT_USAGE = 2
# validation commands that read and write the checkout's own files (bench/, crosscheck/): not for
# an installed package, whose directory must stay as installed
CHECKOUT_ONLY = ("bench", "crosscheck")


class _Parser(argparse.ArgumentParser):
    """argparse with one-line errors: `error: ... (see --help)`, exit code 2, and negative numbers
    in exponent form (`--start-values d -3e-5`) taken as values, not as unknown options."""

    def __init__(self, *args: Any, **kwargs: Any) -> None:
        super().__init__(*args, **kwargs)
        # argparse's own pattern misses -3e-5, -inf, -nan (private attribute, stable since 3.2)
        self._negative_number_matcher = re.compile(r"^-(\d+\.?\d*|\.\d+)([eE][-+]?\d+)?$|^-(inf|nan)$", re.I)

    def error(self, message: str) -> None:  # type: ignore[override]
        print(f"error: {message} (see `{self.prog} --help`)", file=sys.stderr)
        raise SystemExit(EXIT_USAGE)


def _summary(module: str) -> str:
    """First sentence of a module's docstring, without importing it."""
    try:
        spec = importlib.util.find_spec(module)
        if spec is None or spec.origin is None:
            return "(not available yet)"
        with open(spec.origin, encoding="utf-8") as fh:
            doc = ast.get_docstring(ast.parse(fh.read())) or ""
    except (ImportError, OSError, SyntaxError):
        return "(not available)"
    first = doc.strip().split("\n\n")[0].replace("\n", " ")
    return first.split(". ")[0].rstrip(".")


def _known_errors() -> tuple[type[BaseException], ...]:
    """The errors a user can cause, imported when a command runs (not for --help)."""
    from harness.fmu.binding.status import FmiError  # an FMU refused a call (names variable, value, range)
    from harness.fmu.blade import FMUError, FMUNotFoundError
    from harness.fmu.build import BuildError
    from harness.model.excitation import ExcitationError
    from harness.model.params import ParameterError
    from harness.outputs import OutputPathError

    return (ParameterError, ExcitationError, FMUNotFoundError, FMUError, FmiError, BuildError, OutputPathError)


class _Version(argparse.Action):
    """--version: the installed distribution's version, looked up only when asked (0.1 s)."""

    def __init__(self, option_strings: Sequence[str], dest: str = argparse.SUPPRESS, **kwargs: Any) -> None:
        super().__init__(
            option_strings, dest, nargs=0, default=argparse.SUPPRESS, help="show the program's version number and exit"
        )

    def __call__(self, parser: argparse.ArgumentParser, *_: Any) -> None:
        from harness.version import version

        print(f"{parser.prog} {version()}")
        parser.exit()


def _prog() -> str:
    """`harness` when run as the installed console command, else `python -m harness`."""
    return "harness" if os.path.basename(sys.argv[0]) == "harness" else "python -m harness"


def build_parser(command: str | None) -> argparse.ArgumentParser:
    prog = _prog()
    parser = _Parser(
        prog=prog,
        description="ShroudedBlade: simulate the shrouded-blade FMU (harness.fmu_path('ShroudedBlade')), trace"
        " its periodic orbits over speed, reproduce the paper's studies and validate the FMU against the Python reference."
        f" Run `{prog} <command> --help` for the options of one command.",
        formatter_class=argparse.RawDescriptionHelpFormatter,
        epilog="examples:\n"
        f"  {prog} simulate --plot tip.png              # 0.3 s at 5000 rpm -> CSV + PNG\n"
        f"  {prog} simulate --speed 7000 --start-values d 4e-5 gating false\n"
        f"  {prog} periodic --speed 7000 --json          # every periodic orbit at 7000 rpm\n"
        f"  {prog} run --out DIR                         # the paper's studies into DIR\n"
        "Installed (pip install .), the FMUs come with the package; in a checkout they are built into\n"
        "build/ on first use (cmake + gcc). Results go where --out/--output-file say (default: under\n"
        "the current directory). Parameter names and defaults are those of modelDescription.xml\n"
        "(paper Table 1) plus Fw0 [N/m].",
    )
    parser.add_argument("--version", action=_Version)
    sub = parser.add_subparsers(dest="command", metavar="<command>", parser_class=_Parser)
    for name, module in COMMANDS.items():
        p = sub.add_parser(name, help=_summary(module), description=_summary(module) + ".")
        if name == command:
            importlib.import_module(module).configure_parser(p)
    return parser


def main(argv: Sequence[str] | None = None) -> int:
    argv = list(sys.argv[1:] if argv is None else argv)
    command = next((a for a in argv if not a.startswith("-")), None)
    if command is not None and command not in COMMANDS:
        print(
            f"error: unknown command {command!r}; commands: {', '.join(COMMANDS)} (see `{_prog()} --help`)",
            file=sys.stderr,
        )
        return EXIT_USAGE
    parser = build_parser(command)
    args = parser.parse_args(argv)
    if args.command is None:
        parser.print_help()
        return EXIT_USAGE
    if args.command in CHECKOUT_ONLY:
        if not IN_CHECKOUT:
            print(
                f"error: `{args.command}` runs in a checkout of the sources (it writes to its {args.command}/"
                " directory), not in an installed harness",
                file=sys.stderr,
            )
            return EXIT_USAGE
    module = importlib.import_module(COMMANDS[args.command])
    try:
        return int(module.run(args) or 0)
    except _known_errors() as exc:
        text = " ".join(str(exc).split("\n")[0].split())
        print(f"error: {text}", file=sys.stderr)
        return EXIT_USAGE
    except KeyboardInterrupt:
        print("error: interrupted", file=sys.stderr)
        return 130
    except OSError as exc:  # a file a command writes or reads, named as the system reports it
        where = f"{exc.filename}: " if exc.filename else ""
        print(f"error: {where}{exc.strerror or exc}", file=sys.stderr)
        return EXIT_USAGE
