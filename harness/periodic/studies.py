"""The paper's studies (Figs. 6-9) as branches of periodic orbits: fixed point and Jenkins element.

For every study value (harness.studies.STUDIES) the branches of the paper's fixed point B = A(B)
(the tracked-amplitude model's periodic solutions, with their stability) and of the time-domain
Jenkins element are traced over the speed range (harness.periodic.branches), one curve per task on
a process pool (one FMU instance per worker). Written per study: `<fig>_<key>_branches.csv` (one
row per point) and `<fig>_<key>_branches.png` (stable bold, unstable faint), plus a
summary per curve: peak amplitude and speed of each model and their difference (how far the
describing-function model can be trusted).
"""
from __future__ import annotations

import math
import time
from concurrent.futures import ProcessPoolExecutor
from pathlib import Path
from typing import Any

from harness.periodic.continuation import Branch, write_branches_csv

MODELS_DRAWN = ("fixedPoint", "jenkins")
SPEED_RANGE = (3000.0, 10000.0)


def _curve(task: tuple[str, float, str, tuple[float, float]]) -> tuple[str, float, str, list[Branch], dict]:
    from harness.fmu import BladeFMU
    from harness.periodic.branches import trace_branches
    from harness.studies import STUDIES

    key, value, model, rng = task
    t0 = time.perf_counter()
    with BladeFMU() as fmu:
        branches, stats = trace_branches(fmu, {STUDIES[key].param: value}, model, rng)
    stats["wall"] = time.perf_counter() - t0
    return key, value, model, branches, stats


def peak(branches: list[Branch]) -> tuple[float, float]:
    """(largest max |q| on a stable part [m], its speed [rpm]); nan if no stable contact point."""
    best = (math.nan, math.nan)
    for b in branches:
        for p in b.points:
            if p.stable and not p.amplitude <= best[0]:
                best = (p.amplitude, p.speed)
    return best


def run_studies(out: Path, workers: int = 2, keys: tuple[str, ...] = ("gap", "mass", "angle", "kn"),
                speed_range: tuple[float, float] = SPEED_RANGE) -> dict[str, Any]:
    from harness.plots import branches_figure
    from harness.studies import STUDIES

    out.mkdir(parents=True, exist_ok=True)
    tasks = [(k, v, m, speed_range) for k in keys for v in STUDIES[k].values for m in MODELS_DRAWN]
    t0 = time.perf_counter()
    with ProcessPoolExecutor(max_workers=workers) as pool:
        results = list(pool.map(_curve, tasks))
    wall = time.perf_counter() - t0
    summary: dict[str, Any] = {"wall": wall, "workers": workers, "curves": []}
    for k in keys:
        st = STUDIES[k]
        rows = [r for r in results if r[0] == k]
        per_value: dict[float, dict[str, list[Branch]]] = {}
        for _, v, m, br, stats in rows:
            per_value.setdefault(v, {})[m] = br
            summary["curves"].append({"study": k, "value": v, "model": m, "branches": len(br),
                                      "points": sum(len(b.points) for b in br), **stats})
        all_br = [b for v in per_value for m in MODELS_DRAWN for b in per_value[v][m]]
        write_branches_csv(out / f"{st.figure}_{k}_branches.csv", all_br)
        for v, models in per_value.items():
            (a_fp, n_fp), (a_j, n_j) = peak(models["fixedPoint"]), peak(models["jenkins"])
            summary.setdefault("peaks", []).append({
                "study": k, "value": v, "fixedPoint_peak_m": a_fp, "fixedPoint_speed_rpm": n_fp,
                "jenkins_peak_m": a_j, "jenkins_speed_rpm": n_j,
                "peak_rel_diff": (a_fp - a_j) / a_j if a_j > 0 else math.nan, "speed_diff_rpm": n_fp - n_j})
        branches_figure(out / f"{st.figure}_{k}_branches.png",
                        {f"{m} ({st.label(v)})": per_value[v][m] for v in per_value for m in MODELS_DRAWN},
                        f"{st.figure}: periodic orbits by shooting + continuation")
    return summary
