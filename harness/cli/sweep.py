"""Sweep the rotor speed for one parameter set: amplitude-speed curves from the FMU and the reference.

`python -m harness sweep [--speeds 3000:10000:250] [--direction up down] [--method time fixed hb]
[--start-values NAME VALUE ...] [--workers N | --scheduler ADDRESS] [--output-file sweep.csv]
[--plot sweep.png]`. `time` = FMU up/down sweeps carrying the state from speed to speed (tracked
amplitude, grid refined near peaks and jumps), `fixed` = the paper's fixed point A(B) = B per speed
(every root), `hb` = harmonic balance of the reference (every branch, stability). Every point is
cached (./shroudedblade-results/cache by default), so an interrupted sweep continues where it stopped when the
same command is run again. The configuration is checked completely before any work starts.
"""

from __future__ import annotations

import argparse

import numpy as np

from harness.analysis.config import SweepSettings
from harness.analysis.curves import ConfigError, SweepResult, SweepSpec, parse_speed_range, sweep, validate_spec
from harness.files.tables import write_csv
from harness.cli.options import add_execution_options, add_start_values, check_outputs, make_runner, parse_start_values
from harness.model.params import validate
from harness.outputs import check_dir
from harness.studies import plots

# column names with units, as in every command's CSV and JSON (continue: speed_rpm, amplitude_m)
OUT_DTYPE = [
    ("speed_rpm", "f8"),
    ("method", "U9"),
    ("amplitude_m", "f8"),
    ("band_lo_m", "f8"),
    ("band_hi_m", "f8"),
    ("steady", "i4"),
    ("stable", "i4"),
]


_DEFAULTS = SweepSettings()
# the settings' field names in messages -> the options that set them
_OPTIONS = {
    "rtol": "--rtol",
    "max_time": "--max-time",
    "refine_levels": "--refine",
    "steps_per_period": "--steps-per-period",
}


def option_names(message: str) -> str:
    """`message` with a leading settings field name (`max_time = -1.0 ...`) as its option (`--max-time`)."""
    field, sep, rest = message.partition(" = ")
    return f"{_OPTIONS[field]} {rest}" if sep and field in _OPTIONS else message


def configure_parser(p: argparse.ArgumentParser) -> None:
    p.add_argument(
        "--speeds",
        default="3000:10000:250",
        metavar="RANGE",
        help="coarse speed grid [rpm], start:stop:step or a comma list (default 3000:10000:250)",
    )
    p.add_argument(
        "--direction",
        nargs="+",
        default=["up", "down"],
        choices=["up", "down"],
        help="time-domain sweep directions (default: up down)",
    )
    p.add_argument(
        "--method",
        nargs="+",
        default=["time", "hb"],
        choices=["time", "fixed", "hb"],
        help="time (FMU, tracked amplitude), fixed (paper's fixed point), hb (reference); default time hb",
    )
    p.add_argument("--fixed-speeds", metavar="RANGE", help="speeds for --method fixed (default: --speeds)")
    add_start_values(p)
    p.add_argument(
        "--rtol",
        type=float,
        default=_DEFAULTS.rtol,
        metavar="R",
        help="steady-state tolerance per plateau: estimated relative distance from the periodic "
        f"limit (default {_DEFAULTS.rtol:g})",
    )
    p.add_argument(
        "--max-time",
        type=float,
        default=_DEFAULTS.max_time,
        metavar="S",
        help=f"simulated-time cap per speed plateau [s] (default {_DEFAULTS.max_time:g})",
    )
    p.add_argument(
        "--refine",
        type=int,
        default=4,
        metavar="LEVELS",
        help="bisection rounds near peaks and jumps (default 4, 0 = fixed grid)",
    )
    p.add_argument(
        "--steps-per-period",
        type=int,
        default=_DEFAULTS.steps_per_period,
        metavar="N",
        help="communication steps per excitation period, >= 2 (default "
        f"{_DEFAULTS.steps_per_period}, with 8 input derivatives)",
    )
    p.add_argument("--output-file", default="sweep.csv", metavar="CSV", help="result table (default sweep.csv)")
    p.add_argument("--plot", metavar="PNG", help="also plot the curves to this PNG file (default: no plot)")
    add_execution_options(p)


def to_table(res: SweepResult) -> np.ndarray:
    nan = float("nan")
    rows = [
        (r["speed"], f"time-{r['direction']}", r["amplitude"], r["amp_lo"], r["amp_hi"], int(r["reached"]), -1)
        for r in res.time
    ]
    rows += [
        (r["speed"], "fixed" if r["kind"] != "jump" else "fixed-jmp", r["B"], nan, nan, int(r["reached"]), -1)
        for r in res.fixed
    ]
    rows += [(r["speed"], "hb", r["B"], nan, nan, -1, int(r["stable"])) for r in res.hb]
    return np.array(sorted(rows, key=lambda r: (r[1], r[0])), dtype=OUT_DTYPE)


def run(args: argparse.Namespace) -> int:
    params = validate(parse_start_values(args.start_values), source="--start-values")
    settings = SweepSettings(
        rtol=args.rtol, max_time=args.max_time, refine_levels=args.refine, steps_per_period=args.steps_per_period
    )
    spec = SweepSpec(
        params,
        parse_speed_range(args.speeds),
        label="--speeds",
        directions=args.direction,
        methods=args.method,
        fixed_speeds=parse_speed_range(args.fixed_speeds) if args.fixed_speeds else None,
        settings=settings,
    )
    try:
        spec = validate_spec(spec)  # before any work
    except ConfigError as exc:  # name the option the user typed, not the setting's field
        raise ConfigError(option_names(str(exc))) from None
    runner = make_runner(args)
    check_outputs(args, ("output_file", "--output-file"), ("plot", "--plot"))  # the configuration is good
    if not args.no_cache:
        check_dir(args.cache_dir, "--cache-dir")
    with runner:
        res = sweep(spec, runner, fmu_path=args.fmu, cache_dir=None if args.no_cache else args.cache_dir)
    table = to_table(res)
    write_csv(
        args.output_file,
        table,
        "speed_rpm, amplitude_m (time-up/down: last period, band_lo_m..band_hi_m: range over the final periods; fixed: root of A(B) = B,"
        " fixed-jmp: A(B) jumps across B there, no root; hb: harmonic balance); steady: 1/0 (-1 n/a);"
        " stable: 1/0 (-1 n/a)",
    )
    print(f"wrote {len(table)} rows to {args.output_file}")
    for m in ("time", "fixed", "hb"):
        if m in spec.methods:
            sp, a = res.peak(m)
            print(f"{m:5s}: peak {a * 1e3:.5f} mm at {sp:.0f} rpm")
    if len(res.time):
        nr = int(np.sum(~res.time["reached"]))
        print(f"time domain: {len(res.time)} plateaus, {nr} without a periodic steady state within the cap")
    if args.plot:
        changed = parse_start_values(args.start_values)
        label = ", ".join(f"{k} = {v}" for k, v in changed.items()) or "paper Table 1 parameters"
        plots.study_curves(
            args.plot,
            f"Tip amplitude vs rotor speed: {label}, load Fw0 = {params['Fw0']:g} N/m",
            [{"label": label, "time": res.time, "fixed": res.fixed, "hb": res.hb}],
            [params["d"]],
        )
        print(f"wrote {args.plot}")
    return 0
