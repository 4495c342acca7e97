"""Run the bladed disk: a ring of N blades coupled by shroud contacts, at one speed or over a speed band.

One speed: `python -m harness ring --blades N [--speed RPM] [--stop-time S] [--step H] [--order P]
[--master fmpy|c|libcosim|ecos] [--start-values NAME VALUE ...] [--mistuning SIGMA
[--mistuned-parameter EI|m0] [--seed S]] [--json]` prints the steady amplitude of every blade (max |q|
over the last excitation period, `amplitudes_m`), whether it settled (the per-period amplitude's
change over the last periods, `settled`, `movement`) and the phase lags of the first harmonic.
Over speed: `--speeds FROM TO --points K [--sweep up|down|both]` sweeps the C loop with the state
carried from speed to speed (harness/system/ring_sweep.py) and prints `speeds_rpm`, `amplitudes_m`
(per direction, K x N), `settled`, `movement`, and the located `peak_amplitude_m` at
`peak_speed_rpm`; `--csv` and `--plot` write the curves (mistuned: the tuned ring's overlaid).
`--speeds FROM TO --branches` prints the periodic steady states instead (harness/cli/ring_branches.py).
--start-values sets the variable on every FMU instance that has it (`d 1.0` opens every contact).
`--write-ssp DIR` writes the system instead (DIR/SystemStructure.ssd, the FMUs in DIR/resources/,
and DIR.ssp).
"""

from __future__ import annotations

import argparse
import json
import math
import sys
import tempfile
import time
from dataclasses import replace
from pathlib import Path
from typing import Any

from fmpy import read_model_description
import numpy as np

from harness.cli.options import add_start_values, parse_start_values
from harness.cli.ring_branches import run_branches
from harness.fmu.slave import build_ring_fmus
from harness.model.params import ParameterError
from harness.outputs import check_dir, check_file
from harness.studies import mistuning, run_plots
from harness.system import ring_c, ring_libcosim, ring_values, ssp
from harness.system.ring import Ring, RingDiverged, amplitudes, diverged_message, harmonic, run as ring_run
from harness.system.ring_sweep import DIRECTIONS, RingSweep, per_period_settling, period_step, sweep
from harness.system.ring_tables import write_curves_csv
from harness.system.ring_values import max_blades

MASTERS = ("fmpy", "c", "libcosim", "ecos")
EXTRAPOLATING = ("fmpy", "c")  # the masters that set input derivatives (ours)
SETTLE_RTOL, SETTLE_PERIODS = 1e-4, 5  # the settle rule (harness/system/ring_sweep.py)


def configure_parser(p: argparse.ArgumentParser) -> None:
    p.add_argument("--blades", type=int, required=True, metavar="N", help="number of blades, >= 2")
    p.add_argument("--speed", type=float, default=5000.0, metavar="RPM", help="rotor speed [rpm] (default: 5000)")
    p.add_argument(
        "--stop-time", type=float, default=0.1, metavar="S", help="simulated time [s] at one speed (default: 0.1)"
    )
    p.add_argument(
        "--step",
        type=float,
        default=None,
        metavar="H",
        help="communication step [s] (default: T/160 at each speed, 2.5e-5 at 5000 rpm "
        "and EO 3: in whole ns for a single run, exact and aligned to the load phase in a sweep; a "
        "step that is not a whole fraction of the period T makes the per-period "
        "amplitude jitter with the grid's phase. At 1e-4 s the friction ring is stable with linear "
        "extrapolation but 25 %% off and never settles, docs/model.md s.8)",
    )
    p.add_argument(
        "--order",
        type=int,
        default=None,
        choices=range(0, 4),
        metavar="P",
        help="fmpy and c masters: extrapolation order of the input derivatives, 0..3 (default: 2)",
    )
    p.add_argument(
        "--master",
        choices=MASTERS,
        default="fmpy",
        help="co-simulation master at one speed: fmpy, c (the same data flow, loop in C), libcosim, "
        "ecos; a sweep runs on c (default: fmpy)",
    )
    add_start_values(
        p,
        help="set on every FMU instance that has it, e.g. `--start-values d 1.0 c 298 Fw0 300` "
        "(Fw0 [N/m], the blades' built-in load; default: the FMUs' values, Fw0 100 N/m)",
    )
    p.add_argument(
        "--mistuning",
        type=float,
        default=0.0,
        metavar="SIGMA",
        help="relative standard deviation of the mistuned parameter, e.g. 0.02 (default: 0, tuned)",
    )
    p.add_argument(
        "--mistuned-parameter",
        choices=("EI", "m0"),
        default="EI",
        help="blade parameter scattered by --mistuning (default: EI, the bending stiffness)",
    )
    p.add_argument("--seed", type=int, default=1, metavar="S", help="mistuning pattern seed (default: 1)")
    g = p.add_argument_group("forced response over a speed band (the C loop, state carried)")
    g.add_argument(
        "--speeds",
        type=float,
        nargs=2,
        default=None,
        metavar=("FROM", "TO"),
        help="speed band [rpm]; replaces --speed and --stop-time (default: none, one speed)",
    )
    g.add_argument(
        "--points", type=int, default=26, metavar="K", help="speeds in the band, evenly spaced (default: 26)"
    )
    g.add_argument(
        "--sweep",
        choices=DIRECTIONS,
        default="up",
        help="up: from rest at FROM; down: from rest at TO; both: up, then down from TO (default: up)",
    )
    g.add_argument(
        "--settle-rtol",
        type=float,
        default=SETTLE_RTOL,
        metavar="R",
        help="settled: per-period amplitude change below R x the largest blade's, over "
        f"{SETTLE_PERIODS} consecutive periods (default: {SETTLE_RTOL:g})",
    )
    g.add_argument(
        "--max-time",
        type=float,
        default=1.0,
        metavar="S",
        help="longest time at one speed [s]; a speed not settled by then is flagged (default: 1)",
    )
    g.add_argument(
        "--no-refine",
        action="store_true",
        help="report the largest settled sample as the peak (no extra speeds around it)",
    )
    g.add_argument(
        "--branches",
        action="store_true",
        help="the periodic steady states instead of a sweep: every branch of periodic orbits from "
        "every seed (travelling wave, runs from rest, a sweep up and down at --seed-points "
        "speeds), each point's stability and the bifurcations, and the largest stable steady "
        "state (harness/system/ring_orbits)",
    )
    g.add_argument(
        "--seed-points",
        type=int,
        default=None,
        metavar="K",
        help="with --branches: speeds of the seeds across the band (default: at most 300 rpm apart, at least 4)",
    )
    g.add_argument(
        "--seed-sweep",
        type=float,
        nargs="+",
        default=None,
        metavar="RPM",
        help="with --branches: speeds [rpm] of a further C-loop sweep up and down (increasing, at least 2; its "
        "peak located) whose settled states are seeds first, as the mistuning study passes its own (default: none)",
    )
    g.add_argument(
        "--steps-per-period",
        type=int,
        default=160,
        metavar="K",
        help="with --branches: communication steps per excitation period (default: 160, as the sweeps)",
    )
    g.add_argument(
        "--csv", metavar="PATH", help="write the curves: one row per direction, speed (and ring) (default: none)"
    )
    g.add_argument("--plot", metavar="PATH", help="write a PNG: amplitude vs speed per blade (default: none)")
    p.add_argument(
        "--write-ssp",
        metavar="DIR",
        help="write the ring as an SSP system to DIR and exit (default: none, run the ring)",
    )
    p.add_argument("--json", action="store_true", help="print one JSON object on stdout")


def speed_range() -> tuple[float, float]:
    """(min, max) [rpm] of the blade FMU's rotorSpeed."""
    rs = next(v for v in read_model_description(str(build_ring_fmus()[0])).modelVariables if v.name == "rotorSpeed")
    return float(rs.min), float(rs.max)


def check(args: argparse.Namespace) -> None:
    """Every argument against its range, before any work; ParameterError names value and range."""
    nmax = max_blades()
    if not 2 <= args.blades <= nmax:
        raise ParameterError(f"--blades {args.blades} outside [2, {nmax}] (a ring; the blade FMU's bladeCount)")
    lo, hi = speed_range()
    speeds = args.speeds if args.speeds is not None else [args.speed]
    for s in speeds:
        if not (math.isfinite(s) and lo < s <= hi):
            opt = "--speeds" if args.speeds is not None else "--speed"
            raise ParameterError(f"{opt} {s!r} rpm outside ({lo:g}, {hi:g}] (BladeExternalContact's rotorSpeed)")
    if args.speeds is not None:
        if not args.speeds[0] < args.speeds[1]:
            raise ParameterError(f"--speeds {args.speeds[0]:g} {args.speeds[1]:g}: FROM must be below TO")
        if not 2 <= args.points <= 1000:
            raise ParameterError(f"--points {args.points} outside [2, 1000]")
        if args.master not in ("fmpy", "c"):
            raise ParameterError(f"--master {args.master}: a sweep runs on the C loop (c)")
        if not (math.isfinite(args.settle_rtol) and 0 < args.settle_rtol < 1):
            raise ParameterError(f"--settle-rtol {args.settle_rtol!r} outside (0, 1)")
        if not (math.isfinite(args.max_time) and args.max_time > 0):
            raise ParameterError(f"--max-time {args.max_time!r} s must be > 0")
        if args.seed_points is not None and not 2 <= args.seed_points <= 200:
            raise ParameterError(f"--seed-points {args.seed_points} outside [2, 200]")
        if args.seed_sweep is not None and not args.branches:
            raise ParameterError("--seed-sweep seeds --branches: add --branches")
        if args.seed_sweep is not None:
            for s in args.seed_sweep:
                if not (math.isfinite(s) and lo < s <= hi):
                    raise ParameterError(
                        f"--seed-sweep {s!r} rpm outside ({lo:g}, {hi:g}] (BladeExternalContact's rotorSpeed)"
                    )
            sp = args.seed_sweep
            if len(sp) < 2 or any(b <= a for a, b in zip(sp, sp[1:])):
                raise ParameterError(
                    f"--seed-sweep {' '.join(f'{v:g}' for v in sp)}: need at least 2 speeds, increasing"
                )
        if not 8 <= args.steps_per_period <= 100000:
            raise ParameterError(f"--steps-per-period {args.steps_per_period} outside [8, 100000]")
        if args.branches and args.master != "fmpy" and args.master != "c":
            raise ParameterError(f"--master {args.master}: --branches runs on the C loop (c)")
        for option, path in (("--csv", args.csv), ("--plot", args.plot)):
            if path is not None:
                check_file(path, option)
    elif args.csv or args.plot:
        raise ParameterError("--csv and --plot write the curves of a sweep: give --speeds FROM TO")
    elif args.seed_sweep is not None:
        raise ParameterError("--seed-sweep seeds --branches: give --speeds FROM TO --branches")
    elif args.branches:
        raise ParameterError("--branches traces the periodic orbits over a band: give --speeds FROM TO")
    if not (math.isfinite(args.stop_time) and args.stop_time > 0):
        raise ParameterError(f"--stop-time {args.stop_time!r} s must be > 0")
    if args.step is not None and not (math.isfinite(args.step) and 0 < args.step <= args.stop_time):
        raise ParameterError(f"--step {args.step!r} s outside (0, --stop-time = {args.stop_time:g}]")
    if not (math.isfinite(args.mistuning) and 0 <= args.mistuning <= 0.2):
        raise ParameterError(f"--mistuning {args.mistuning!r} outside [0, 0.2] (relative standard deviation)")
    if args.write_ssp:
        check_dir(args.write_ssp, "--write-ssp")
    if args.master not in EXTRAPOLATING and args.order not in (None, 0):
        raise ParameterError(
            f"--order {args.order}: only the fmpy and c masters extrapolate; libcosim and Ecos hold inputs"
        )


def make_ring(args: argparse.Namespace) -> Ring:
    order = (2 if args.order is None else args.order) if args.master in EXTRAPOLATING else 0
    ring = Ring(n=args.blades, speed=args.speed, stop_time=args.stop_time, step=args.step or 2.5e-5, order=order)
    ring = ring_values.apply(ring, parse_start_values(args.start_values))
    if args.step is None:  # T/160: the grid keeps its phase to the excitation, period after period
        ring = replace(ring, step=period_step(ring, ring.speed, 160))
    T = 60.0 / (ring.engine_order * ring.speed)
    if args.speeds is None and ring.n_steps * ring.step < T * (1 - 1e-9):
        raise ParameterError(
            f"--stop-time {args.stop_time:g} s shorter than one excitation period ({T:.6g} s): no steady amplitude"
        )
    if args.mistuning > 0:
        f = mistuning.factors(ring.n, args.mistuning, args.seed, 0)
        ring = mistuning.mistuned(ring, args.mistuned_parameter, f)
    return ring


def simulate(ring: Ring, master: str) -> dict[str, Any]:
    if master == "fmpy":
        return ring_run(ring)
    if master == "c":
        return ring_c.run(ring)
    if master == "libcosim":
        return ring_libcosim.run(ring)
    with tempfile.TemporaryDirectory() as d:
        return ssp.run_ecos(ssp.write(ring, Path(d) / "ring"), ring)


def _common(ring: Ring, args: argparse.Namespace) -> dict[str, Any]:
    return {
        "blades": ring.n,
        "engine_order": ring.engine_order,
        "order": ring.order,
        "blade_parameters": dict(ring.blade),
        "contact_parameters": dict(ring.contact),
        "Fw0_N_per_m": ring.fw0,
        "mistuning": {
            "sigma": args.mistuning,
            "parameter": args.mistuned_parameter,
            "seed": args.seed,
            "values": [b[args.mistuned_parameter] for b in ring.blade_each],
        },
    }


def _warn(lines: list[str]) -> None:
    for line in lines:
        print(f"warning: {line}", file=sys.stderr)


def run(args: argparse.Namespace) -> int:
    check(args)
    ring = make_ring(args)
    if args.write_ssp:
        out = ssp.write(ring, Path(args.write_ssp))
        print(json.dumps({"ssp": str(out), "archive": str(out.with_suffix(".ssp"))}) if args.json else out)
        return 0
    try:
        if args.branches:
            return run_branches(ring, args, _common(ring, args))
        return run_sweep(ring, args) if args.speeds is not None else run_one(ring, args)
    except RingDiverged as e:  # one line, exit 2 (the CLI's known errors)
        raise ParameterError(str(e)) from None


def _check_diverged(ring: Ring, res: dict[str, Any], master: str) -> None:
    """libcosim and Ecos run on their own: the same divergence check on the run they return."""
    bad = ~(np.abs(res["q"]) <= ring.q_limit)
    if bad.any():
        k, i = np.argwhere(bad)[0]
        raise RingDiverged(diverged_message(ring, int(k), float(res["time"][k]), int(i), float(res["q"][k, i]), master))


def run_one(ring: Ring, args: argparse.Namespace) -> int:
    t0 = time.perf_counter()
    res = simulate(ring, args.master)
    wall = time.perf_counter() - t0
    _check_diverged(ring, res, args.master)
    amp = amplitudes(res["time"], res["q"], ring.omega)
    c = harmonic(res, ring.omega)
    st = per_period_settling(res["time"], res["q"], ring.omega, SETTLE_RTOL, SETTLE_PERIODS)
    ok = st.settled if st.run is not None and len(st.changes) >= SETTLE_PERIODS else np.zeros(ring.n, dtype=bool)
    out = {
        **_common(ring, args),
        "master": args.master,
        "speed_rpm": ring.speed,
        "stop_time_s": ring.n_steps * ring.step,
        "step_s": ring.step,
        "amplitudes_m": [float(a) for a in amp],
        "settled": [bool(x) for x in ok],
        "movement": [float(x) for x in st.movement] if st.last is not None else None,
        "settle_rule": {"rtol": SETTLE_RTOL, "periods": SETTLE_PERIODS},
        "first_harmonic_m": [float(a) for a in np.abs(c)],
        "phase_lags_rad": [float(x) for x in np.angle(c / c[0])] if abs(c[0]) > 0 else None,
        "wall_time_s": wall,
    }
    if not ok.all():
        bad = np.flatnonzero(~ok)
        _warn(
            [
                f"blades {', '.join(map(str, bad))} not settled at {out['stop_time_s']:g} s: the per-period amplitude "
                f"still changes by up to {np.max(out['movement'] or [np.inf]):.2g} of the largest (rule: below "
                f"{SETTLE_RTOL:g} over {SETTLE_PERIODS} periods); run longer (--stop-time) before reading them "
                "as steady amplitudes"
            ]
        )
    if args.json:
        print(json.dumps(out, indent=1))
        return 0
    print(
        f"ring of {ring.n} blades, {ring.speed:g} rpm, EO {ring.engine_order}, {out['stop_time_s']:g} s "
        f"({args.master}, h = {ring.step:g} s, {wall:.2f} s wall)"
    )
    for i, a in enumerate(amp):
        print(f"  blade {i}: max|q| = {a * 1e3:.6f} mm{'' if ok[i] else '  (not settled)'}")
    return 0


def _sweep_json(r: RingSweep) -> dict[str, Any]:
    return {
        "speeds_rpm": r.speeds_rpm.tolist(),
        "sweep": list(r.amplitudes_m),
        "amplitudes_m": {d: a.tolist() for d, a in r.amplitudes_m.items()},
        "settled": {d: a.tolist() for d, a in r.settled.items()},
        "movement": {d: a.tolist() for d, a in r.movement.items()},
        "time_at_speed_s": {d: a.tolist() for d, a in r.time_at_speed_s.items()},
        "peak_amplitude_m": None if math.isnan(r.peak_amplitude_m) else r.peak_amplitude_m,
        "peak_speed_rpm": None if math.isnan(r.peak_speed_rpm) else r.peak_speed_rpm,
        "peak_direction": r.peak_direction or None,
        "peak_blade": r.peak_blade if r.peak_direction else None,
        "peak_at_band_edge": r.peak_at_band_edge,
        "refinement": r.refinement,
        "step_s": r.step_s.tolist(),
        "wall_time_s": r.wall_time_s,
    }


def run_sweep(ring: Ring, args: argparse.Namespace) -> int:
    speeds = np.linspace(args.speeds[0], args.speeds[1], args.points)
    step = args.step  # None: T/160 at the highest speed (ring_sweep.default_step)
    kw = dict(
        direction=args.sweep,
        rtol=args.settle_rtol,
        periods=SETTLE_PERIODS,
        max_time=args.max_time,
        step=step,
        refine=not args.no_refine,
    )
    r = sweep(ring, speeds, **kw)
    out = {
        **_common(ring, args),
        "master": "c",
        **_sweep_json(r),
        "settle_rule": {"rtol": args.settle_rtol, "periods": SETTLE_PERIODS, "max_time_s": args.max_time},
    }
    tuned = None
    if ring.blade_each:
        tuned = sweep(replace(ring, blade_each=()), speeds, **kw)
        out["tuned"] = _sweep_json(tuned)
    for d, s in r.settled.items():
        bad = [f"{v:g}" for v, row in zip(r.speeds_rpm, s) if not row.all()]
        if bad:
            _warn(
                [
                    f"sweep {d}: not settled within {args.max_time:g} s at {len(bad)} of {len(s)} speeds "
                    f"({', '.join(bad)} rpm); their amplitudes are the last period's, `movement` says by how much "
                    "they still change"
                ]
            )
    if r.peak_at_band_edge:
        _warn(
            [
                f"the largest settled amplitude is at the band's edge ({r.peak_speed_rpm:g} rpm): the peak may lie "
                "outside --speeds"
            ]
        )
    if args.csv:
        write_curves_csv(args.csv, r, tuned)
    if args.plot:
        run_plots.ring_sweep(
            args.plot, r, tuned, f"{ring.n}-blade ring, EO {ring.engine_order}, Fw0 = {ring.fw0:g} N/m"
        )
    if args.json:
        print(json.dumps(out, indent=1))
        return 0
    print(
        f"ring of {ring.n} blades, {speeds[0]:g}..{speeds[-1]:g} rpm ({len(speeds)} speeds, sweep {args.sweep}, "
        f"h = {r.step_s.min():.4g}..{r.step_s.max():.4g} s, {r.wall_time_s:.1f} s wall)"
    )
    if r.peak_direction:
        print(
            f"  peak: blade {r.peak_blade} {r.peak_amplitude_m * 1e3:.6f} mm at {r.peak_speed_rpm:.1f} rpm "
            f"(sweep {r.peak_direction})"
        )
    else:
        print("  peak: no speed settled")
    return 0
