"""`python -m harness ring --blades N --speeds FROM TO --branches`: the ring's periodic steady states
over the band (harness/system/ring_orbits): every branch from every seed, each point's stability,
the bifurcations, and the largest stable steady state; `--csv` one row per point, `--plot` the
branches (stable solid, unstable dashed) with a sweep's settled points (up and down, --points
speeds) over them."""

from __future__ import annotations

import argparse
import json
import math
from typing import Any

import numpy as np

from harness.studies import run_plots
from harness.system.ring import Ring
from harness.system.ring_orbits.branches import ring_branches
from harness.system.ring_orbits.period_map import RingShootingSettings
from harness.system.ring_orbits.seeds import SweepPath
from harness.system.ring_sweep import sweep
from harness.system.ring_tables import write_branches_csv


def run_branches(ring: Ring, args: argparse.Namespace, common: dict[str, Any]) -> int:
    lo, hi = args.speeds
    r = ring_branches(
        ring,
        (lo, hi),
        points=args.seed_points,
        settings=RingShootingSettings(steps_per_period=args.steps_per_period),
        sweeps=() if args.seed_sweep is None else (SweepPath(tuple(args.seed_sweep), refine=True),),
    )
    out = {**common, **r.as_dict()}
    if args.plot:
        sw = sweep(
            ring,
            np.linspace(lo, hi, args.points),
            "both",
            rtol=args.settle_rtol,
            max_time=args.max_time,
            steps_per_period=args.steps_per_period,
        )
        out["sweep"] = {
            "speeds_rpm": sw.speeds_rpm.tolist(),
            "amplitudes_m": {d: a.tolist() for d, a in sw.amplitudes_m.items()},
            "settled": {d: a.tolist() for d, a in sw.settled.items()},
        }
        run_plots.ring_branches(
            args.plot,
            out,
            f"{ring.n}-blade ring, EO {ring.engine_order}, Fw0 = {ring.fw0:g} N/m: periodic steady states",
        )
    if args.csv:
        write_branches_csv(args.csv, r)
    if args.json:
        print(json.dumps(out, indent=1))
        return 0
    print(
        f"ring of {ring.n} blades, {lo:g}..{hi:g} rpm: {len(r.branches)} branches, {r.points} points, "
        f"{r.evaluations} periods simulated, {r.wall_time:.1f} s wall"
    )
    if math.isnan(r.peak_stable_amplitude):
        print("  no stable periodic orbit found")
    else:
        print(
            f"  largest stable steady state: blade {r.peak_stable_blade} {r.peak_stable_amplitude * 1e3:.6f} mm at "
            f"{r.peak_stable_speed:.1f} rpm"
        )
    for i, b in enumerate(r.branches):
        kinds = ", ".join(f"{x.kind} {x.speed:.0f}" for x in b.bifurcations) or "none"
        print(
            f"  branch {i}: {b.speeds.min():.0f}..{b.speeds.max():.0f} rpm, {len(b.orbits)} points, "
            f"{int(b.stable.sum())} stable; bifurcations: {kinds}"
        )
    if r.untraced:
        stable = [o for _, o in r.untraced if o.stable]
        largest = f", largest stable {max(o.amplitude for o in stable) * 1e3:.6f} mm" if stable else ""
        print(
            f"  {len(r.untraced)} further orbits from seeds past the branch cap (not continued; {len(stable)} stable"
            f"{largest})"
        )
    return 0
