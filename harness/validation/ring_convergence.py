"""Co-simulation vs monolithic reference for the ring: the error of the fmpy Jacobi
master (harness/system/ring.py) against harness/reference/ring.py as the communication step h
shrinks, per extrapolation order of the input derivatives, with the measured order (least-squares
slope of log error over log h on the finest points), and the largest stable h.

Error: max over blades and over the reference's output grid (every 1e-4 s up to stop_time) of
|q_cosim - q_ref|, relative to max |q_ref|. `python -m harness ring-convergence` writes
results/ring_convergence.csv and .png (log-log; also libcosim) and prints the table.
"""

from __future__ import annotations

import csv
import math
from dataclasses import dataclass
from pathlib import Path

import numpy as np

from harness import digits
from harness.files.figures import plt, save_png
from harness.reference.ring import MonolithicRing, RingSpec
from harness.system import ring_libcosim
from harness.system.ring import Ring, run

GRID = 1e-4  # reference output spacing [s]; every h divides it


@dataclass(frozen=True)
class Study:
    n: int = 4
    engine_order: int = 3
    fw0: float = 300.0
    c: float = 298.0
    stop_time: float = 0.05
    steps: tuple[float, ...] = (1e-4, 5e-5, 2.5e-5, 1.25e-5, 6.25e-6)
    orders: tuple[int, ...] = (0, 1, 2)

    def spec(self) -> RingSpec:
        return RingSpec(n=self.n, engine_order=self.engine_order, fw0=self.fw0, blade={"c": self.c})

    def ring(self, h: float, order: int) -> Ring:
        return Ring(
            n=self.n,
            engine_order=self.engine_order,
            fw0=self.fw0,
            blade={"c": self.c},
            step=h,
            stop_time=self.stop_time,
            order=order,
        )


def errors(study: Study, libcosim: bool = False) -> list[tuple[int | str, float, float]]:
    """(order, h, relative error) of the fmpy master per extrapolation order, and with libcosim
    (harness/system/ring_libcosim.py, held inputs) as order "libcosim"; inf where it diverged."""
    t = np.arange(round(study.stop_time / GRID) + 1) * GRID
    q = MonolithicRing(study.spec()).solve(t)["q"]
    rows: list[tuple[int | str, float, float]] = []
    masters: list[int | str] = [*study.orders, *(["libcosim"] if libcosim else [])]
    for p in masters:
        for h in study.steps:
            k = round(GRID / h)
            try:
                if p == "libcosim":
                    c = ring_libcosim.run(study.ring(h, 0))["q"][::k]
                else:
                    c = run(study.ring(h, int(p)))["q"][::k]
                e = float(np.abs(c - q).max() / np.abs(q).max())
            except Exception:  # an FMU refused a step (state out of range): diverged
                e = math.inf
            rows.append((p, h, e if math.isfinite(e) and e < 1.0 else math.inf))
    return rows


def measured_order(rows: list[tuple[int | str, float, float]], order: int | str, last: int = 3) -> float:
    """Least-squares slope of log(error) over log(h) on the `last` smallest steps."""
    pts = sorted((h, e) for p, h, e in rows if p == order and math.isfinite(e))[:last]
    x, y = np.log([h for h, _ in pts]), np.log([e for _, e in pts])
    return float(np.polyfit(x, y, 1)[0])


def write(rows: list[tuple[int | str, float, float]], out: Path) -> None:
    out.parent.mkdir(parents=True, exist_ok=True)
    with open(out.with_suffix(".csv"), "w", newline="") as f:
        w = csv.writer(f)
        w.writerow(["order", "h", "relative_error"])
        texts = [digits.column(r[k] for r in rows) for k in (1, 2)]
        w.writerows([r[0], h, e] for r, h, e in zip(rows, *texts))
    fig, ax = plt.subplots(figsize=(5, 4))
    for p in dict.fromkeys(r[0] for r in rows):
        pts = [(h, e) for q, h, e in rows if q == p and math.isfinite(e)]
        name = "libcosim (held inputs)" if p == "libcosim" else f"fmpy master, extrapolation order {p}"
        ax.loglog(*zip(*pts), "o-", label=f"{name} (measured {measured_order(rows, p):.2f})")
    ax.set_xlabel("communication step h [s]")
    ax.set_ylabel("max |q - q_ref| / max |q_ref|")
    ax.set_title("ring N = 4, EO = 3: Jacobi vs monolithic", fontsize=10)
    ax.legend(fontsize=7)
    fig.tight_layout()
    save_png(fig, out.with_suffix(".png"), dpi=120, tight=False)
