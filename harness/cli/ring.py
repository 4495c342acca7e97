"""Run the bladed disk: a ring of N blades coupled by shroud contacts, in the fmpy master (its loop in
Python or in C), libcosim or Ecos.

`python -m harness ring --blades N [--speed RPM] [--stop-time S] [--step H] [--order P]
[--master fmpy|c|libcosim|ecos] [--start-values NAME VALUE ...] [--mistuning SIGMA [--mistuned-parameter
EI|m0] [--seed S]] [--json]` prints the steady amplitude of every blade (max |q| over the last
excitation period, key `amplitudes` [m]) and the phase lags of the first harmonic. --start-values sets
the variable on every FMU instance that has it (`d 1.0` opens every contact). `--write-ssp DIR` writes
the system instead (DIR/SystemStructure.ssd, the FMUs in DIR/resources/, and DIR.ssp).
"""
from __future__ import annotations

import argparse
import json
import math
import tempfile
import time
from pathlib import Path

from fmpy import read_model_description
import numpy as np

from harness.cli.simulate import parse_start_values
from harness.fmu.slave import build_ring_fmus
from harness.model.params import ParameterError
from harness.studies import mistuning
from harness.system import ring_c, ring_libcosim, ring_values, ssp
from harness.system.ring import Ring, amplitudes, harmonic, run as ring_run
from harness.system.ring_values import max_blades

MASTERS = ("fmpy", "c", "libcosim", "ecos")
EXTRAPOLATING = ("fmpy", "c")  # the masters that set input derivatives (ours)


def configure_parser(p: argparse.ArgumentParser) -> None:
    p.add_argument("--blades", type=int, required=True, metavar="N", help="number of blades, >= 2")
    p.add_argument("--speed", type=float, default=5000.0, metavar="RPM", help="rotor speed [rpm] (default 5000)")
    p.add_argument("--stop-time", type=float, default=0.1, metavar="S", help="simulated time [s] (default 0.1)")
    p.add_argument("--step", type=float, default=None, metavar="H",
                   help="communication step [s] (default 2.5e-5: at 1e-4 s the friction ring is stable with "
                        "linear extrapolation but 25 %% off and never settles, docs/model.md s.8)")
    p.add_argument("--order", type=int, default=None, choices=range(0, 4), metavar="P",
                   help="fmpy and c masters: extrapolation order of the input derivatives, 0..3 (default 2)")
    p.add_argument("--master", choices=MASTERS, default="fmpy",
                   help="co-simulation master: fmpy (default), c (the same data flow, loop in C), libcosim, ecos")
    p.add_argument("--start-values", nargs="+", default=[], metavar="NAME VALUE",
                   help="set on every FMU instance that has it, e.g. `--start-values d 1.0 c 298 Fw0 300`")
    p.add_argument("--mistuning", type=float, default=0.0, metavar="SIGMA",
                   help="relative standard deviation of the mistuned parameter, e.g. 0.02 (default 0: tuned)")
    p.add_argument("--mistuned-parameter", choices=("EI", "m0"), default="EI",
                   help="blade parameter scattered by --mistuning (default EI, the bending stiffness)")
    p.add_argument("--seed", type=int, default=1, help="mistuning pattern seed (default 1)")
    p.add_argument("--write-ssp", metavar="DIR", help="write the ring as an SSP system to DIR and exit")
    p.add_argument("--json", action="store_true", help="print one JSON object on stdout")


def check(args: argparse.Namespace) -> None:
    """Every argument against its range, before any work; ParameterError names value and range."""
    nmax = max_blades()
    if not 2 <= args.blades <= nmax:
        raise ParameterError(f"--blades {args.blades} outside [2, {nmax}] (a ring; the Excitation FMU's bladeCount)")

    rs = next(v for v in read_model_description(str(build_ring_fmus()[0])).modelVariables if v.name == "rotorSpeed")
    lo, hi = float(rs.min), float(rs.max)
    if not (math.isfinite(args.speed) and lo < args.speed <= hi):
        raise ParameterError(f"--speed {args.speed!r} rpm outside ({lo:g}, {hi:g}] (BladeExternalContact's rotorSpeed)")
    if not (math.isfinite(args.stop_time) and args.stop_time > 0):
        raise ParameterError(f"--stop-time {args.stop_time!r} s must be > 0")
    if args.step is not None and not (math.isfinite(args.step) and 0 < args.step <= args.stop_time):
        raise ParameterError(f"--step {args.step!r} s outside (0, --stop-time = {args.stop_time:g}]")
    if not (math.isfinite(args.mistuning) and 0 <= args.mistuning <= 0.2):
        raise ParameterError(f"--mistuning {args.mistuning!r} outside [0, 0.2] (relative standard deviation)")
    if args.master not in EXTRAPOLATING and args.order not in (None, 0):
        raise ParameterError(f"--order {args.order}: only the fmpy and c masters extrapolate; libcosim and Ecos "
                             "hold inputs")


def make_ring(args: argparse.Namespace):
    step = args.step if args.step is not None else 2.5e-5
    order = (2 if args.order is None else args.order) if args.master in EXTRAPOLATING else 0
    ring = Ring(n=args.blades, speed=args.speed, stop_time=args.stop_time, step=step, order=order)
    ring = ring_values.apply(ring, parse_start_values(args.start_values))
    T = 60.0 / (ring.engine_order * ring.speed)
    if ring.n_steps * ring.step < T * (1 - 1e-9):
        raise ParameterError(f"--stop-time {args.stop_time:g} s shorter than one excitation period ({T:.6g} s):"
                             " no steady amplitude")
    if args.mistuning > 0:
        f = mistuning.factors(ring.n, args.mistuning, args.seed, 0)
        ring = mistuning.mistuned(ring, args.mistuned_parameter, f)
    return ring


def simulate(ring, master: str) -> dict:
    if master == "fmpy":
        return ring_run(ring)
    if master == "c":
        return ring_c.run(ring)
    if master == "libcosim":
        return ring_libcosim.run(ring)
    with tempfile.TemporaryDirectory() as d:
        return ssp.run_ecos(ssp.write(ring, Path(d) / "ring"), ring)


def run(args: argparse.Namespace) -> int:
    check(args)
    ring = make_ring(args)
    if args.write_ssp:
        out = ssp.write(ring, Path(args.write_ssp))
        print(json.dumps({"ssp": str(out), "archive": str(out.with_suffix(".ssp"))}) if args.json else out)
        return 0
    t0 = time.perf_counter()
    res = simulate(ring, args.master)
    wall = time.perf_counter() - t0
    amp = amplitudes(res["time"], res["q"], ring.omega)
    c = harmonic(res, ring.omega)
    out = {"blades": ring.n, "master": args.master, "speed_rpm": ring.speed, "engine_order": ring.engine_order,
           "stop_time_s": ring.n_steps * ring.step, "step_s": ring.step, "order": ring.order,
           "blade_parameters": dict(ring.blade), "contact_parameters": dict(ring.contact), "Fw0": ring.fw0,
           "mistuning": {"sigma": args.mistuning, "parameter": args.mistuned_parameter, "seed": args.seed,
                         "values": [b[args.mistuned_parameter] for b in ring.blade_each]},
           "amplitudes": [float(a) for a in amp],
           "first_harmonic": [float(a) for a in np.abs(c)],
           "phase_lags_rad": [float(x) for x in np.angle(c / c[0])] if abs(c[0]) > 0 else None,
           "wall_time_s": wall}
    if args.json:
        print(json.dumps(out, indent=1))
        return 0
    print(f"ring of {ring.n} blades, {ring.speed:g} rpm, EO {ring.engine_order}, {out['stop_time_s']:g} s "
          f"({args.master}, h = {ring.step:g} s, {wall:.2f} s wall)")
    for i, a in enumerate(amp):
        print(f"  blade {i}: max|q| = {a * 1e3:.6f} mm")
    return 0
