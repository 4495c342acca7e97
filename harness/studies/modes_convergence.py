"""Convergence in the number of bending modes m of the base case: does one mode suffice?

For m = 1..4 (consistent formulation: the printed eq. 26 has one mode only) the branches of
periodic orbits of the Jenkins element and of the fixed point B = A(B) over the study speed range
(harness.analysis.periodic, the same tracing as the paper's studies: CurveTask / trace_curve, so
they run on the same Runner), and of each: the peak (largest max |q| of a stable orbit, located
along the branch, harness.analysis.periodic.extrema), its speed and the root bending moment at the
peak, max |rootMoment| over the peak orbit's period (the FMU started on the orbit, 1024 samples
per period: a sampled maximum falls short of the true one by at most (2 pi / 1024)^2 / 8 = 5e-6 of
it). Each is compared with the largest m: relative differences, and the verdict of the claims row
(harness.studies.claims) "one mode suffices within X %", X the largest difference of m = 1.
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from pathlib import Path
from typing import Any, Mapping, Sequence

import numpy as np

from harness.files.tables import write_csv
from harness.analysis.periodic.branches import BranchSettings
from harness.analysis.periodic.period_map import PeriodMap
from harness.analysis.periodic.curve import Curve, CurveTask, peak_orbit
from harness.studies import plots

MODELS = ("jenkins", "fixedPoint")
LABEL = {"jenkins": "Jenkins element", "fixedPoint": "fixed point B = A(B)"}
SAMPLES = 1024  # per period, for max |rootMoment|


@dataclass(frozen=True)
class ModesRow:
    model: str
    modes: int
    peak: float  # [m] largest max |q| of a stable orbit (located)
    speed: float  # [rpm]
    root_moment: float  # [N m] max |rootMoment| over the peak orbit's period
    branches: int
    evaluations: int  # period-map evaluations of the curve (not written: see modes_convergence)


@dataclass(frozen=True)
class ModesConvergence:
    rows: list[ModesRow]
    speed_range: tuple[float, float]

    def reference(self, model: str) -> ModesRow:
        """The row with the most modes of a model (what the others are compared with)."""
        return max((r for r in self.rows if r.model == model), key=lambda r: r.modes)

    def differences(self, row: ModesRow) -> tuple[float, float, float]:
        """(peak, speed, root moment) of `row` relative to the reference row of its model."""
        ref = self.reference(row.model)
        return tuple((getattr(row, k) - getattr(ref, k)) / getattr(ref, k) for k in ("peak", "speed", "root_moment"))

    def one_mode_error(self) -> tuple[float, str]:
        """The largest |relative difference| of m = 1 from the most modes over both models and the
        three quantities, and which one it is (nan if a quantity is missing)."""
        worst, what = -1.0, ""
        for r in self.rows:
            if r.modes != 1:
                continue
            for name, d in zip(("peak amplitude", "peak speed", "root moment"), self.differences(r)):
                if not math.isfinite(d):
                    return math.nan, f"{LABEL[r.model]}: no {name}"
                if abs(d) > worst:
                    worst, what = abs(d), f"{name}, {LABEL[r.model]}"
        return worst, what

    def as_dict(self) -> dict:
        return {
            "speed_range": list(self.speed_range),
            "rows": [
                {
                    **{k: v for k, v in r.__dict__.items() if k != "evaluations"},
                    "d_peak": d[0],
                    "d_speed": d[1],
                    "d_root_moment": d[2],
                }
                for r in self.rows
                for d in [self.differences(r)]
            ],
        }


def modes_tasks(
    base: Mapping[str, Any],
    speed_range: tuple[float, float],
    seed_step: float,
    fmu_path: str | None,
    modes: Sequence[int] = (1, 2, 3, 4),
) -> list[CurveTask]:
    """One curve per (model, m), consistent formulation, the base case otherwise."""
    settings = BranchSettings(seed_step=seed_step)
    return [
        CurveTask("modes", float(m), model, dict(base, formulation=2, modes=int(m)), speed_range, fmu_path, settings)
        for model in MODELS
        for m in modes
    ]


def root_moment(fmu: Any, curve: Curve, orbit: Any) -> float:
    """max |rootMoment| [N m] over one period of the orbit (the FMU started on it at load phase 0)."""
    pm = PeriodMap(fmu, curve.task.params, curve.task.model)
    T = 2.0 * math.pi / (int(pm.p["engineOrder"]) * 2.0 * math.pi * orbit.speed / 60.0)
    r = fmu.run(
        dict(pm.p, **pm.start_values(orbit.x)),
        T,
        T / SAMPLES,
        speed_rpm=orbit.speed,
        outputs=["rootMoment"],
        input_fit="chebyshev",
        carry_values=True,
    )
    return float(np.max(np.abs(r["rootMoment"])))


def modes_convergence(fmu: Any, out: Path, curves: Sequence[Curve]) -> ModesConvergence:
    """Peaks and root moments of the traced curves; results/modes_convergence.csv and one figure per
    model (results/modes_convergence_<model>.png: the branches for every m)."""
    rows = []
    rng = curves[0].task.speed_range
    for c in sorted(curves, key=lambda c: (MODELS.index(c.task.model), c.task.value)):
        o = peak_orbit(c.branches, speed_range=rng)
        rm = math.nan if o is None else root_moment(fmu, c, o)
        a, n = (math.nan, math.nan) if o is None else (o.amplitude, o.speed)
        rows.append(ModesRow(c.task.model, int(c.task.value), a, n, rm, len(c.branches), c.stats.evaluations))
    conv = ModesConvergence(rows, rng)
    tab = np.zeros(
        len(rows),
        dtype=[
            ("model", "U12"),
            ("modes", "i4"),
            ("peak_m", "f8"),
            ("speed_rpm", "f8"),
            ("root_moment_Nm", "f8"),
            ("d_peak", "f8"),
            ("d_speed", "f8"),
            ("d_root_moment", "f8"),
            ("branches", "i4"),
        ],
    )
    for i, r in enumerate(rows):
        # without the period-map counts: for m > 1 they differ from run to run by up to 0.2 % (which
        # worker traced which curve before), the numbers do not; the files stay the same on a rerun
        tab[i] = (r.model, r.modes, r.peak, r.speed, r.root_moment, *conv.differences(r), r.branches)
    write_csv(
        out / "modes_convergence.csv",
        tab,
        f"Convergence in the number of modes m of the base case (consistent formulation), branches of periodic "
        f"orbits over {rng[0]:g}..{rng[1]:g} rpm: peak = largest max|q| of a stable orbit (located) [m], its "
        f"speed [rpm], root moment = max|rootMoment| over the peak orbit's period [N m]; d_* = relative "
        f"difference from the largest m of the same model",
    )
    for model in MODELS:
        mc = sorted((c for c in curves if c.task.model == model), key=lambda c: c.task.value)
        if mc:
            plots.branches_figure(
                out / f"modes_convergence_{model}.png",
                {f"m = {int(c.task.value)}": c.branches for c in mc},
                f"Base case (consistent formulation), {LABEL[model]}: m = 1..{int(mc[-1].task.value)} modes",
            )
    return conv
