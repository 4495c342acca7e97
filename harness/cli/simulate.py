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
import os
import tempfile
from pathlib import Path
from typing import Any

from fmpy.util import write_csv
import matplotlib
import matplotlib.pyplot as plt
import numpy as np

from harness.analysis.steady_state import analyze
from harness.fmu.blade import SPEED_RANGE, BladeFMU, fmu_path
from harness.model.excitation import Constant, ExcitationError, LinearRamp
from harness.model.params import ParameterError, validate
from harness.outputs import check_file, with_unit, write_error

matplotlib.use("Agg")  # figures go straight to PNG files: no display

DEFAULT_OUTPUT = "ShroudedBlade_out.csv"


def configure_parser(p: argparse.ArgumentParser) -> None:
    add_fmu_option(p)
    p.add_argument("--start-time", type=float, default=0.0, metavar="S", help="start time [s] (default 0)")
    p.add_argument("--stop-time", type=float, default=0.3, metavar="S", help="stop time [s] (default 0.3)")
    p.add_argument("--output-interval", type=float, default=1e-4, metavar="S",
                   help="communication step = output interval [s] (default 1e-4)")
    p.add_argument("--start-values", nargs="+", default=[], metavar="NAME VALUE",
                   help="parameter name-value pairs, e.g. `--start-values d 4e-5 kn 1e6 gating false`;"
                        " names and units as in modelDescription.xml plus Fw0 (load amplitude fed through"
                        " aeroLoad, N/m, default 100); default: none (paper Table 1)")
    speed = p.add_mutually_exclusive_group()
    speed.add_argument("--speed", type=float, default=5000.0, metavar="RPM",
                       help="constant rotor speed [rpm] (default 5000)")
    speed.add_argument("--run-up", type=float, nargs=4, metavar=("N0", "N1", "T0", "T1"),
                       help="linear speed ramp: N0 rpm until T0 s, N1 rpm from T1 s on (default: none, constant --speed)")
    p.add_argument("--derivative-order", type=int, default=8, choices=range(0, 9), metavar="K",
                   help="input derivatives set per step, 0..8 (0 = inputs held over a step; default 8)")
    p.add_argument("--output-variables", nargs="+", metavar="NAME", help="outputs to record (default: all)")
    p.add_argument("--output-file", default=DEFAULT_OUTPUT, metavar="CSV",
                   help=f"CSV file for the results (default {DEFAULT_OUTPUT})")
    p.add_argument("--plot", metavar="PNG", help="also plot tipDisplacement and amplitude [mm] to this PNG file (default: no plot)")
    p.add_argument("--debug-logging", action="store_true", help="print all of the FMU's log messages (default: warnings and errors only)")
    p.add_argument("--fmi-logging", action="store_true", help="print every FMI call of the step loop (slow)")


def add_fmu_option(p: argparse.ArgumentParser) -> None:
    p.add_argument("--fmu", metavar="FILE",
                   help="the FMU file (a .fmu, not a directory; default: the harness's own: the installed"
                        " package's, or build/ShroudedBlade.fmu in a checkout, built if needed)")


def check_outputs(args: argparse.Namespace, *options: tuple[str, str]) -> None:
    """Refuse, before any work, an output file (attribute, option name) that cannot be written."""
    for attr, option in options:
        if getattr(args, attr, None):
            check_file(getattr(args, attr), option)


def parse_start_values(items: list[str]) -> dict[str, Any]:
    if len(items) % 2:
        raise ParameterError(f"--start-values needs NAME VALUE pairs; got {len(items)} item(s): {' '.join(items)}")
    return {items[i]: items[i + 1] for i in range(0, len(items), 2)}


def _atomic_path(target: Path, suffix: str) -> Path:
    try:
        target.parent.mkdir(parents=True, exist_ok=True)
        fd, tmp = tempfile.mkstemp(prefix=f".{target.name}.", suffix=suffix, dir=target.parent)
    except OSError as exc:  # name the user's path, not a temporary one
        raise write_error(target, exc) from None
    os.close(fd)
    umask = os.umask(0)
    os.umask(umask)
    os.chmod(tmp, 0o666 & ~umask)  # mkstemp makes 0600; results are ordinary files for the user's tools
    return Path(tmp)


def with_units(result: np.ndarray, variables: dict) -> np.ndarray:
    """`result` (time + FMU outputs) with each column named with its unit from the model description
    (`time_s`, `tipDisplacement_m`, ...), as every command's CSV and JSON names its quantities."""
    def unit(name: str) -> str | None:
        if name == "time":
            return "s"
        v = variables.get(name)
        return None if v is None else (v.unit or (v.declaredType.unit if v.declaredType else None))
    named = np.dtype({"names": [with_unit(n, unit(n)) for n in result.dtype.names],
                      "formats": [result.dtype.fields[n][0] for n in result.dtype.names],
                      "offsets": [result.dtype.fields[n][1] for n in result.dtype.names],
                      "itemsize": result.dtype.itemsize})
    return result.view(named).copy()  # a new dtype: the caller's array keeps its names


def write_csv_atomic(path: str | Path, result: np.ndarray) -> None:
    target = Path(path)
    tmp = _atomic_path(target, ".csv")
    try:
        write_csv(tmp, result)
        os.replace(tmp, target)
    finally:
        tmp.unlink(missing_ok=True)


def plot_atomic(path: str | Path, result: np.ndarray, title: str) -> None:
    names = [n for n in ("tipDisplacement", "amplitude") if n in result.dtype.names]
    if not names:
        names = [n for n in result.dtype.names if n != "time"][:1]
    fig, ax = plt.subplots(figsize=(8, 4))
    for n in names:
        scale, unit = (1e3, "mm") if n in ("tipDisplacement", "amplitude") else (1.0, "")
        ax.plot(result["time"], result[n] * scale, label=f"{n} [{unit}]" if unit else n, lw=0.8)
    ax.set_xlabel("time [s]")
    ax.set_ylabel("tip displacement q and its amplitude [mm]" if "tipDisplacement" in names else names[0])
    ax.set_title(title)
    ax.grid(alpha=0.3)
    ax.legend()
    fig.tight_layout()
    target = Path(path)
    tmp = _atomic_path(target, ".png")
    try:
        fig.savefig(tmp, dpi=120, format="png")
        os.replace(tmp, target)
    finally:
        plt.close(fig)
        tmp.unlink(missing_ok=True)


def run(args: argparse.Namespace) -> int:
    params = validate(parse_start_values(args.start_values), source="--start-values")
    check_outputs(args, ("output_file", "--output-file"), ("plot", "--plot"))
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
    for n in ([args.speed] if args.run_up is None else args.run_up[:2]):
        if not lo <= n <= hi:
            raise ExcitationError(f"rotorSpeed = {n:g} rpm is outside [{lo:g}, {hi:g}] rpm: choose a speed in that range")
    path = Path(args.fmu) if args.fmu else fmu_path(build=True)
    with BladeFMU(path, log=args.debug_logging, fmi_logging=args.fmi_logging) as fmu:
        res = fmu.run(params, args.stop_time, args.output_interval, speed=speed,
                      outputs=args.output_variables, derivative_order=args.derivative_order,
                      start_time=args.start_time)
        variables = fmu.variables
    write_csv_atomic(args.output_file, with_units(res, variables))
    print(f"wrote {len(res)} rows x {len(res.dtype.names)} columns to {args.output_file}")
    if "tipDisplacement" in res.dtype.names:
        q = res["tipDisplacement"]
        print(f"max |tipDisplacement| = {np.max(np.abs(q)) * 1e3:.6g} mm ({speed_text})")
        if args.run_up is None and args.speed > 0:
            period = 60.0 / (args.speed * params["engineOrder"])
            ss = analyze(res["time"], q, period)
            if ss.reached:
                print(f"steady state: amplitude {ss.amplitude * 1e3:.6g} mm, first harmonic"
                      f" {ss.harmonic_amplitude * 1e3:.6g} mm, {ss.message}")
            else:
                print(f"steady state: {ss.message}")
    if args.plot:
        plot_atomic(args.plot, res, f"ShroudedBlade: tip response, {speed_text}, load Fw0 = {params['Fw0']:g} N/m")
        print(f"wrote {args.plot}")
    return 0
