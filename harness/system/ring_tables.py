"""The ring's results as CSV tables, written atomically: a sweep's curves (`ring --speeds ... --csv`)
and the branches of periodic steady states (`ring --speeds ... --branches --csv`)."""

from __future__ import annotations

from pathlib import Path

from harness.files.atomic import atomic_write_text
from harness.system.ring_orbits.branches import RingBranches
from harness.system.ring_sweep import RingSweep


def write_curves_csv(path: str | Path, r: RingSweep, tuned: RingSweep | None = None) -> None:
    """The curves of a sweep (and of the tuned ring beside a mistuned one) as CSV, atomically: one
    row per ring, direction and speed; every blade's amplitude [m], settled flag and movement."""
    N = next(iter(r.amplitudes_m.values())).shape[1]
    head = (
        ["ring", "direction", "speed_rpm"]
        + [f"amplitude{i}_m" for i in range(N)]
        + [f"settled{i}" for i in range(N)]
        + [f"movement{i}" for i in range(N)]
    )
    rows = []
    for name, sw in (("mistuned" if tuned else "tuned", r), ("tuned", tuned)):
        if sw is None:
            continue
        for d in sw.amplitudes_m:
            for j, s in enumerate(sw.speeds_rpm):
                rows.append(
                    [name, d, repr(float(s))]
                    + [repr(float(x)) for x in sw.amplitudes_m[d][j]]
                    + [str(int(x)) for x in sw.settled[d][j]]
                    + [repr(float(x)) for x in sw.movement[d][j]]
                )
    atomic_write_text(path, "\n".join(",".join(x) for x in [head, *rows]) + "\n")


def write_branches_csv(path: str | Path, r: RingBranches) -> None:
    """One row per point: branch, kind (point, peak, fold, or a bifurcation's kind), speed, stable,
    largest |multiplier|, period residual, then every blade's max |q|."""
    N = r.branches[0].amplitudes.shape[1] if r.branches else 0
    head = ["branch", "kind", "speed_rpm", "stable", "max_multiplier", "period_residual"] + [
        f"amplitude{i}_m" for i in range(N)
    ]
    rows = [head]
    for k, b in enumerate(r.branches):
        for o in b.orbits:
            rows.append(
                [str(k), "point", repr(o.speed), str(int(o.stable)), repr(o.max_multiplier), repr(o.residual)]
                + [repr(float(a)) for a in o.amplitudes]
            )
        for o in b.peaks:
            rows.append(
                [str(k), "peak", repr(o.speed), str(int(o.stable)), repr(o.max_multiplier), repr(o.residual)]
                + [repr(float(a)) for a in o.amplitudes]
            )
        for x in b.bifurcations:
            rows.append([str(k), x.kind, repr(x.speed), "", "", ""] + [repr(float(a)) for a in x.amplitudes])
    atomic_write_text(path, "\n".join(",".join(row) for row in rows) + "\n")
