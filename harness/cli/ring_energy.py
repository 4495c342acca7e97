"""The co-simulated ring's energy balance over its last excitation period, per communication step and extrapolation order.

`python -m harness ring-energy [--stop S] [--orders P ...] [--steps H ...] [--conserving]` prints,
relative to the aero work, the residual, the coupling error, the stored and the spring energy
change (harness.system.energy), for the plain master or the energy-conserving one.
"""

from __future__ import annotations

import argparse

from harness.system.energy import step_study


def configure_parser(p: argparse.ArgumentParser) -> None:
    p.add_argument(
        "--stop",
        type=float,
        default=0.2,
        metavar="S",
        help="run length [s]; the window is its last period (default 0.2)",
    )
    p.add_argument(
        "--orders",
        type=int,
        nargs="+",
        default=[1, 2, 3],
        metavar="P",
        help="extrapolation orders of the input derivatives (default 1 2 3)",
    )
    p.add_argument(
        "--steps",
        type=float,
        nargs="+",
        default=[1e-4, 5e-5, 2.5e-5, 1.25e-5, 6.25e-6],
        metavar="H",
        help="communication steps [s] (default 1e-4 5e-5 2.5e-5 1.25e-5 6.25e-6)",
    )
    p.add_argument("--conserving", action="store_true", help="with the energy-conserving correction")


def run(args: argparse.Namespace) -> int:
    print("order h[s] residual/aero coupling_error/aero stored/aero springs/aero amplitude_change wall[s]")
    for p, h, bal, wall in step_study(args.stop, args.orders, args.steps, args.conserving):
        if bal is None:
            print(p, h, "failed: an FMU refused a step (diverged)", flush=True)
            continue
        W = bal.aero
        print(
            p,
            h,
            f"{bal.residual / W:.3e} {bal.coupling_error / W:.3e} {bal.stored / W:.3e} "
            f"{bal.springs / W:.3e} {bal.amplitude_change:.2e} {wall:.1f}",
            flush=True,
        )
    return 0
