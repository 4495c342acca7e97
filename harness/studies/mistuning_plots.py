"""Figures of the mistuning study (harness/studies/mistuning.py), each a PNG with its CSV:
amplitude per blade around the disk (the worst pattern of the largest level against the tuned ring),
amplification vs mistuning level (mean, max, Whitehead's bound), histogram of the amplification at
the largest level. Rings that did not settle (amplification NaN) are left out of the curves and
the histogram, and kept as NaN in the CSVs."""
from __future__ import annotations

from pathlib import Path

import matplotlib
import matplotlib.pyplot as plt
import numpy as np

from harness.analysis.executor import write_csv

matplotlib.use("Agg")  # figures go straight to PNG files: no display


def write(out: dict, directory: Path) -> list[Path]:
    d = Path(directory)
    d.mkdir(parents=True, exist_ok=True)
    n, levels, V = out["n"], out["levels"], out["variants"]
    files = []

    # amplitude per blade around the disk
    fig, ax = plt.subplots(figsize=(6, 4))
    rows = []
    for v, r in V.items():
        amp = np.array(r["amplitudes"])[-1]
        k = int(np.argmax(amp.max(axis=1)))
        note = "" if r.get("tuned_settled", True) else ", not periodic"
        ax.plot(range(n), amp[k] * 1e3, "o-", label=f"{v}: worst pattern ({k}{note})")
        ax.plot(range(n), np.array(r["tuned"]) * 1e3, "k--", lw=0.8)
        rows += [(v, i, r["tuned"][i], amp[k, i]) for i in range(n)]
    ax.set(xlabel="blade", ylabel="max |q| [mm]", title=f"sigma = {levels[-1]:g} ({out['parameter']}), dashed: tuned")
    ax.legend()
    files += _save(fig, d / "mistuning_blades", rows,
                   [("variant", "U12"), ("blade", "i4"), ("tuned_m", "f8"), ("mistuned_m", "f8")])

    # amplification vs level
    fig, ax = plt.subplots(figsize=(6, 4))
    rows = []
    for v, r in V.items():
        a = np.array(r["amplification"], dtype=float)  # NaN: a ring that did not settle
        if np.all(np.isnan(a)):
            ax.plot([], [], " ", label=f"{v}: not periodic (tuned ring does not settle)")
            continue
        with np.errstate(all="ignore"):
            hi, mean, lo = np.nanmax(a, axis=1), np.nanmean(a, axis=1), np.nanmin(a, axis=1)
        ax.plot(levels, hi, "o-", label=f"{v}: max")
        ax.plot(levels, mean, "s:", label=f"{v}: mean")
        rows += [(v, s, mean[i], hi[i], lo[i]) for i, s in enumerate(levels)]
    ax.axhline(out["whitehead"], color="r", label=f"Whitehead (1 + sqrt({n})) / 2")
    ax.set(xlabel="relative standard deviation", ylabel="amplification", title=f"N = {n}, {out['patterns']} patterns")
    ax.legend(fontsize=8)
    files += _save(fig, d / "mistuning_amplification", rows,
                   [("variant", "U12"), ("sigma", "f8"), ("mean", "f8"), ("max", "f8"), ("min", "f8")])

    # histogram at the largest level
    fig, ax = plt.subplots(figsize=(6, 4))
    rows = []
    for v, r in V.items():
        a = np.array(r["amplification"], dtype=float)[-1]
        ok = ~np.isnan(a)
        if ok.any():
            ax.hist(a[ok], bins=max(5, int(ok.sum()) // 5), alpha=0.6, label=v)
        rows += [(v, k, x) for k, x in enumerate(a)]
    ax.set(xlabel="amplification", ylabel="patterns", title=f"sigma = {levels[-1]:g}")
    ax.legend()
    files += _save(fig, d / "mistuning_histogram", rows, [("variant", "U12"), ("pattern", "i4"), ("amplification", "f8")])
    return files


def _save(fig, stem: Path, rows: list, dtype: list) -> list[Path]:
    fig.tight_layout()
    fig.savefig(stem.with_suffix(".png"), dpi=120)
    plt.close(fig)
    write_csv(stem.with_suffix(".csv"), np.array(rows, dtype=dtype))
    return [stem.with_suffix(".png"), stem.with_suffix(".csv")]
