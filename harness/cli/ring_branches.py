"""`python -m harness ring --blades N --speeds FROM TO --branches`: the ring's periodic steady states
over the band (harness/system/ring_orbits): every branch from every seed, each point's stability,
the bifurcations, and the largest stable steady state; `--csv` one row per point, `--plot` the
branches (stable solid, unstable dashed) with a sweep's settled points (up and down, --points
speeds) over them."""
from __future__ import annotations

import argparse
import json
import math
from pathlib import Path

import numpy as np

from harness.system.ring import Ring
from harness.system.ring_orbits.branches import RingBranches, ring_branches
from harness.system.ring_orbits.period_map import RingShootingSettings
from harness.system.ring_sweep import RingSweep, sweep


def run_branches(ring: Ring, args: argparse.Namespace, common: dict) -> int:
    lo, hi = args.speeds
    r = ring_branches(ring, (lo, hi), points=args.seed_points,
                      settings=RingShootingSettings(steps_per_period=args.steps_per_period))
    out = {**common, **r.as_dict()}
    sw = None
    if args.plot:
        sw = sweep(ring, np.linspace(lo, hi, args.points), "both", rtol=args.settle_rtol, max_time=args.max_time,
                   steps_per_period=args.steps_per_period)
        out["sweep"] = {"speeds_rpm": sw.speeds_rpm.tolist(),
                        "amplitudes_m": {d: a.tolist() for d, a in sw.amplitudes_m.items()},
                        "settled": {d: a.tolist() for d, a in sw.settled.items()}}
        plot_branches(args.plot, r, sw, f"{ring.n}-blade ring, EO {ring.engine_order}, Fw0 = {ring.fw0:g} N/m: "
                      "periodic steady states")
    if args.csv:
        write_branches_csv(args.csv, r)
    if args.json:
        print(json.dumps(out, indent=1))
        return 0
    print(f"ring of {ring.n} blades, {lo:g}..{hi:g} rpm: {len(r.branches)} branches, {r.points} points, "
          f"{r.evaluations} periods simulated, {r.wall_time:.1f} s wall")
    if math.isnan(r.peak_stable_amplitude):
        print("  no stable periodic orbit found")
    else:
        print(f"  largest stable steady state: blade {r.peak_stable_blade} {r.peak_stable_amplitude * 1e3:.6f} mm at "
              f"{r.peak_stable_speed:.1f} rpm")
    for i, b in enumerate(r.branches):
        kinds = ", ".join(f"{x.kind} {x.speed:.0f}" for x in b.bifurcations) or "none"
        print(f"  branch {i}: {b.speeds.min():.0f}..{b.speeds.max():.0f} rpm, {len(b.orbits)} points, "
              f"{int(b.stable.sum())} stable; bifurcations: {kinds}")
    return 0


def write_branches_csv(path: str, r: RingBranches) -> None:
    """One row per point: branch, kind (point, peak, fold, or a bifurcation's kind), speed, stable,
    largest |multiplier|, period residual, then every blade's max |q|."""
    N = r.branches[0].amplitudes.shape[1] if r.branches else 0
    head = ["branch", "kind", "speed_rpm", "stable", "max_multiplier", "period_residual"] + \
        [f"amplitude{i}_m" for i in range(N)]
    rows = [head]
    for k, b in enumerate(r.branches):
        for o in b.orbits:
            rows.append([str(k), "point", repr(o.speed), str(int(o.stable)), repr(o.max_multiplier), repr(o.residual)]
                        + [repr(float(a)) for a in o.amplitudes])
        for o in b.peaks:
            rows.append([str(k), "peak", repr(o.speed), str(int(o.stable)), repr(o.max_multiplier), repr(o.residual)]
                        + [repr(float(a)) for a in o.amplitudes])
        for x in b.bifurcations:
            rows.append([str(k), x.kind, repr(x.speed), "", "", ""] + [repr(float(a)) for a in x.amplitudes])
    Path(path).write_text("\n".join(",".join(row) for row in rows) + "\n")


def plot_branches(path: str, r: RingBranches, sw: RingSweep | None, title: str) -> None:
    import matplotlib
    matplotlib.use("Agg")  # straight to a PNG file
    import matplotlib.pyplot as plt

    fig, ax = plt.subplots(figsize=(9, 5.5))
    colors = plt.get_cmap("tab10")
    for k, b in enumerate(r.branches):
        S, A, st = b.speeds, b.amplitudes.max(axis=1) * 1e3, b.stable
        c = colors(k % 10)
        for i in range(len(S) - 1):
            ax.plot(S[i:i + 2], A[i:i + 2], "-" if st[i] and st[i + 1] else "--", color=c, lw=1.6 if st[i] else 1.0)
        for x in b.bifurcations:
            ax.plot([x.speed], [x.amplitude * 1e3], "o" if x.kind == "fold" else "d", ms=4, mfc="none", color=c)
    if sw is not None:
        for d, a in sw.amplitudes_m.items():
            ok = sw.settled[d].all(axis=1)
            ax.plot(sw.speeds_rpm[ok], a[ok].max(axis=1) * 1e3, "^" if d == "up" else "v", ms=6, color="k",
                    mfc="none", label=f"sweep {d}: settled, largest blade")
    if not math.isnan(r.peak_stable_amplitude):
        ax.plot([r.peak_stable_speed], [r.peak_stable_amplitude * 1e3], "*", color="red", ms=14,
                label=f"largest stable: {r.peak_stable_amplitude * 1e3:.4f} mm at {r.peak_stable_speed:.0f} rpm")
    ax.plot([], [], "k-", label="stable (largest blade)")
    ax.plot([], [], "k--", label="unstable")
    ax.plot([], [], "ko", mfc="none", ms=4, label="fold")
    ax.plot([], [], "kd", mfc="none", ms=4, label="branch point / NS / PD")
    ax.set_xlabel("rotor speed [rpm]")
    ax.set_ylabel("largest blade amplitude max|q| [mm]")
    ax.set_title(title, fontsize=10)
    ax.grid(alpha=0.3)
    ax.legend(fontsize=7)
    fig.tight_layout()
    fig.savefig(path, dpi=120, format="png")
    plt.close(fig)
