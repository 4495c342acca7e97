"""Simulate the FMU once and write the outputs to CSV (and optionally a PNG plot).

`python -m harness simulate [--stop-time 0.3] [--output-interval 1e-4] [--speed 5000 | --run-up
N0 N1 T0 T1] [--start-values NAME VALUE ...] [--output-file out.csv] [--plot out.png]`. The
aerodynamic load is f_w = Fw0 sin(engineOrder * phase of the speed) with value and derivatives up
to --derivative-order set at every communication point. Files are written atomically (temporary
file + rename), so an interrupted run never leaves a truncated CSV.
"""

from __future__ import annotations

import argparse
import math
from pathlib import Path

import numpy as np

from harness.analysis.steady_state import analyze
from harness.cli.options import add_fmu_option, add_start_values, check_outputs, parse_start_values
from harness.fmu.blade import SPEED_RANGE, BladeFMU, fmu_path
from harness.model.excitation import Constant, ExcitationError, LinearRamp, Signal
from harness.model.params import validate
from harness.files.tables import write_result_csv
from harness.studies import run_plots

DEFAULT_OUTPUT = "ShroudedBlade_out.csv"


def configure_parser(p: argparse.ArgumentParser) -> None:
    add_fmu_option(p)
    p.add_argument("--start-time", type=float, default=0.0, metavar="S", help="start time [s] (default 0)")
    p.add_argument("--stop-time", type=float, default=0.3, metavar="S", help="stop time [s] (default 0.3)")
    p.add_argument(
        "--output-interval",
        type=float,
        default=1e-4,
        metavar="S",
        help="communication step = output interval [s] (default 1e-4)",
    )
    add_start_values(
        p,
        help="parameter name-value pairs, e.g. `--start-values d 4e-5 kn 1e6 gating false`;"
        " names and units as in modelDescription.xml plus Fw0 (load amplitude fed through"
        " aeroLoad, N/m, default 100); default: none (paper Table 1)",
    )
    speed = p.add_mutually_exclusive_group()
    speed.add_argument(
        "--speed", type=float, default=5000.0, metavar="RPM", help="constant rotor speed [rpm] (default 5000)"
    )
    speed.add_argument(
        "--run-up",
        type=float,
        nargs=4,
        metavar=("N0", "N1", "T0", "T1"),
        help="linear speed ramp: N0 rpm until T0 s, N1 rpm from T1 s on (default: none, constant --speed)",
    )
    p.add_argument(
        "--derivative-order",
        type=int,
        default=8,
        choices=range(0, 9),
        metavar="K",
        help="input derivatives set per step, 0..8 (0 = inputs held over a step; default 8)",
    )
    p.add_argument("--output-variables", nargs="+", metavar="NAME", help="outputs to record (default: all)")
    p.add_argument(
        "--output-file",
        default=DEFAULT_OUTPUT,
        metavar="CSV",
        help=f"CSV file for the results (default {DEFAULT_OUTPUT})",
    )
    p.add_argument(
        "--plot", metavar="PNG", help="also plot tipDisplacement and amplitude [mm] to this PNG file (default: no plot)"
    )
    p.add_argument(
        "--debug-logging",
        action="store_true",
        help="print all of the FMU's log messages (default: warnings and errors only)",
    )
    p.add_argument("--fmi-logging", action="store_true", help="print every FMI call of the step loop (slow)")


def run(args: argparse.Namespace) -> int:
    params = validate(parse_start_values(args.start_values), source="--start-values")
    check_outputs(args, ("output_file", "--output-file"), ("plot", "--plot"))
    speed: Signal
    if args.run_up is not None:
        n0, n1, t0, t1 = args.run_up
        speed = LinearRamp(n0, n1, t0, t1)
        speed_text = f"run-up {n0:g} -> {n1:g} rpm over [{t0:g}, {t1:g}] s"
    else:
        if not math.isfinite(args.speed):
            raise ExcitationError(f"--speed {args.speed!r} is not a number: give the rotor speed in rpm, e.g. 5000")
        speed = Constant(args.speed)
        speed_text = f"{args.speed:g} rpm"
    lo, hi = SPEED_RANGE
    for n in [args.speed] if args.run_up is None else args.run_up[:2]:
        if not lo <= n <= hi:
            raise ExcitationError(
                f"rotorSpeed = {n:g} rpm is outside [{lo:g}, {hi:g}] rpm: choose a speed in that range"
            )
    path = Path(args.fmu) if args.fmu else fmu_path(build=True)
    with BladeFMU(path, log=args.debug_logging, fmi_logging=args.fmi_logging) as fmu:
        res = fmu.run(
            params,
            args.stop_time,
            args.output_interval,
            speed_rpm=speed,
            outputs=args.output_variables,
            derivative_order=args.derivative_order,
            start_time=args.start_time,
        )
        variables = fmu.variables
    write_result_csv(args.output_file, res, variables)
    columns = res.dtype.names or ()
    print(f"wrote {len(res)} rows x {len(columns)} columns to {args.output_file}")
    if "tipDisplacement" in columns:
        q = res["tipDisplacement"]
        print(f"max |tipDisplacement| = {np.max(np.abs(q)) * 1e3:.6g} mm ({speed_text})")
        if args.run_up is None and args.speed > 0:
            period = 60.0 / (args.speed * params["engineOrder"])
            ss = analyze(res["time"], q, period)
            if ss.reached:
                print(
                    f"steady state: amplitude {ss.amplitude * 1e3:.6g} mm, first harmonic"
                    f" {ss.harmonic_amplitude * 1e3:.6g} mm, {ss.message}"
                )
            else:
                print(f"steady state: {ss.message}")
    if args.plot:
        run_plots.simulation(
            args.plot, res, f"ShroudedBlade: tip response, {speed_text}, load Fw0 = {params['Fw0']:g} N/m"
        )
        print(f"wrote {args.plot}")
    return 0
