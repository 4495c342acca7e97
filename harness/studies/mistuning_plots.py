"""Figures of the mistuning study (harness/studies/mistuning.py), each a PNG with its CSV:
amplitude vs speed (the tuned ring's largest blade and the worst pattern's, every blade of the
worst pattern thin), amplitude per blade around the disk at each ring's peak speed, amplification
vs mistuning level (mean and max, Whitehead's bound), histogram of the amplification at the
largest level. Points that did not settle are drawn hollow and left out of the peaks; patterns
without a settled point (amplification NaN) are left out of the curves and kept as NaN in the CSVs."""

from __future__ import annotations

from pathlib import Path

import numpy as np
from matplotlib.ticker import MaxNLocator

from harness.files.tables import write_csv
from harness.files.figures import plt, save_png

COLOURS = ("tab:blue", "tab:orange", "tab:green")  # one per variant, in every figure


def _worst(r: dict) -> tuple[int, np.ndarray]:
    """(pattern index, its K x N curves) of the largest amplification at the largest level."""
    a = np.array(r["amplification"], dtype=float)[-1]
    k = int(np.nanargmax(a)) if np.isfinite(a).any() else 0
    return k, np.array(r["amplitudes"], dtype=float)[-1, k]


def write(out: dict, directory: Path) -> list[Path]:
    d = Path(directory)
    d.mkdir(parents=True, exist_ok=True)
    n, levels, V, sp = out["n"], out["levels"], out["variants"], np.array(out["speeds_rpm"])
    sigma = f"sigma = {levels[-1]:g} ({out['parameter']})"
    files = []

    # amplitude vs speed: tuned against the worst pattern
    fig, ax = plt.subplots(figsize=(7, 4.5))
    rows = []
    for c, (v, r) in zip(COLOURS, V.items()):
        k, worst = _worst(r)
        tuned, ok_t = np.array(r["tuned"]), np.array(r["tuned_settled"])
        ax.plot(sp, worst * 1e3, color=c, lw=0.5, alpha=0.5)
        _curve(ax, sp, tuned.max(axis=1), ok_t.all(axis=1), c, "--", "s", f"{v}: tuned, largest blade")
        ok_w = ~np.isnan(worst).any(axis=1)
        _curve(ax, sp, worst.max(axis=1), ok_w, c, "-", "o", f"{v}: worst pattern ({k}), largest blade")
        rows += [(v, s, tuned[i].max(), int(ok_t[i].all()), k, worst[i].max()) for i, s in enumerate(sp)]
        # the located peaks the amplification divides (refined in speed, not the sampled maxima)
        t_peak = np.nanmax(np.array(r["tuned_peak_blades"] or [np.nan], dtype=float))
        w_peak = np.nanmax(np.array(r["peak_blades"], dtype=float)[-1, k])
        ax.plot(
            [r["tuned_peak_rpm"]],
            [t_peak * 1e3],
            "*",
            color=c,
            mfc="none",
            ms=12,
            ls="none",
            label=f"{v}: tuned, located peak",
        )
        ax.plot(
            [r["peak_rpm"][-1][k]],
            [w_peak * 1e3],
            "*",
            color=c,
            ms=12,
            ls="none",
            label=f"{v}: worst pattern, located peak",
        )
    ax.axvline(out["crossing_rpm"], color="grey", lw=0.8, ls=":", label="contact-free crossing")
    ax.set(xlabel="rotor speed [rpm]", ylabel="max |q| [mm]", title=f"N = {n}, {sigma}; thin: every blade of the worst")
    ax.legend(fontsize=8)
    files += _save(
        fig,
        d / "mistuning_response",
        rows,
        [
            ("variant", "U12"),
            ("speed_rpm", "f8"),
            ("tuned_m", "f8"),
            ("tuned_settled", "i4"),
            ("worst_pattern", "i4"),
            ("worst_m", "f8"),
        ],
    )

    # amplitude per blade around the disk, each ring at its own (located) peak speed
    fig, ax = plt.subplots(figsize=(6, 4))
    rows = []
    for c, (v, r) in zip(COLOURS, V.items()):
        k, _ = _worst(r)
        worst = np.array(r["peak_blades"], dtype=float)[-1, k]
        w_rpm = r["peak_rpm"][-1][k]
        tuned = np.array(r["tuned_peak_blades"] or [np.nan] * n, dtype=float)
        ax.plot(range(n), worst * 1e3, "o-", color=c, label=f"{v}: worst pattern {k} at {w_rpm:.0f} rpm")
        ax.plot(
            range(n),
            tuned * 1e3,
            "s--",
            color=c,
            mfc="none",
            lw=1.0,
            label=f"{v}: tuned at {r['tuned_peak_rpm']:.0f} rpm",
        )
        rows += [(v, i, r["tuned_peak_rpm"], tuned[i], w_rpm, worst[i]) for i in range(n)]
    ax.set(xlabel="blade", ylabel="max |q| [mm]", title=f"{sigma}: at each ring's peak speed")
    ax.legend(fontsize=8)
    files += _save(
        fig,
        d / "mistuning_blades",
        rows,
        [
            ("variant", "U12"),
            ("blade", "i4"),
            ("tuned_rpm", "f8"),
            ("tuned_m", "f8"),
            ("mistuned_rpm", "f8"),
            ("mistuned_m", "f8"),
        ],
    )

    files += amplification_figures(out, d)
    return files


def amplification_figures(out: dict, d: Path) -> list[Path]:
    """Amplification vs mistuning level and its histogram at the largest level (PNG + CSV each):
    they need only the study's amplifications (`variants`: `amplification`, `peak_rpm`), `n`,
    `levels`, `patterns`, `speeds_rpm`, `parameter` and `whitehead`."""
    n, levels, V, sp = out["n"], out["levels"], out["variants"], np.array(out["speeds_rpm"])
    sigma = f"sigma = {levels[-1]:g} ({out['parameter']})"
    files = []
    # amplification vs level: filled markers the max, hollow the mean, one colour per variant
    fig, ax = plt.subplots(figsize=(6, 4))
    rows = []
    for j, (c, (v, r)) in enumerate(zip(COLOURS, V.items())):
        a = np.array(r["amplification"], dtype=float)  # NaN: no settled point
        if np.all(np.isnan(a)):
            ax.plot([], [], " ", label=f"{v}: no settled point")
            continue
        with np.errstate(all="ignore"):
            hi, mean, lo = np.nanmax(a, axis=1), np.nanmean(a, axis=1), np.nanmin(a, axis=1)
        # each curve starts at the tuned ring, amplification 1 at sigma = 0 by definition
        x = [0.0] + list(levels)
        ax.plot(x, [1.0, *hi], "o-", color=c, label=f"{v}: max", markevery=list(range(1, len(x))))
        ax.plot(
            x,
            [1.0, *mean],
            ("s", "D", "^")[j] + ":",
            color=c,
            mfc="none",
            ms=9 - 2 * j,
            label=f"{v}: mean",
            markevery=list(range(1, len(x))),
        )
        rows += [(v, s, mean[i], hi[i], lo[i]) for i, s in enumerate(levels)]
    ax.plot([0.0], [1.0], "k+", ms=10, label="tuned ring (1 by definition)")
    ax.set_xlim(-0.08 * max(levels), 1.12 * max(levels))
    # the y range from the data; Whitehead's bound as a line when it is near, else as a note at the top
    data = max([1.0] + [r[3] for r in rows if np.isfinite(r[3])])
    bound = f"Whitehead (1 + sqrt({n})) / 2 = {out['whitehead']:.3f}"
    if out["whitehead"] <= 1.3 * data:
        ax.axhline(out["whitehead"], color="r", label=bound)
        ax.set_ylim(0.95, 1.06 * max(data, out["whitehead"]))
    else:
        ax.set_ylim(0.95, 1.0 + 1.25 * (data - 1.0) + 0.05)
        ax.annotate(
            f"{bound}: far above",
            xy=(0.5, 0.97),
            xycoords="axes fraction",
            ha="center",
            va="top",
            color="r",
            fontsize=8,
        )
    ax.set(
        xlabel="relative standard deviation sigma",
        ylabel="amplification (band peak / tuned peak)",
        title=f"N = {n}, {out['patterns']} patterns, {sp[0]:.0f}-{sp[-1]:.0f} rpm",
    )
    ax.legend(fontsize=8, loc="upper left", bbox_to_anchor=(0.0, 0.9))  # below the note, above the curves
    files += _save(
        fig,
        d / "mistuning_amplification",
        rows,
        [("variant", "U12"), ("sigma", "f8"), ("mean", "f8"), ("max", "f8"), ("min", "f8")],
    )

    # histogram at the largest level
    fig, ax = plt.subplots(figsize=(6, 4))
    rows = []
    for c, (v, r) in zip(COLOURS, V.items()):
        a = np.array(r["amplification"], dtype=float)[-1]
        ok = ~np.isnan(a)
        if ok.any():  # edged bars, so that equal neighbours stay apart
            ax.hist(
                a[ok], bins=max(5, int(ok.sum()) // 5), alpha=0.6, color=c, label=v, edgecolor="black", linewidth=0.8
            )
        rows += [(v, k, x, r["peak_rpm"][-1][k]) for k, x in enumerate(a)]
    ax.yaxis.set_major_locator(MaxNLocator(integer=True))  # whole numbers of patterns
    ax.set(xlabel="amplification", ylabel="patterns", title=sigma)
    ax.legend()
    files += _save(
        fig,
        d / "mistuning_histogram",
        rows,
        [("variant", "U12"), ("pattern", "i4"), ("amplification", "f8"), ("peak_rpm", "f8")],
    )
    return files


def _curve(ax, x, y, settled, colour, ls, marker, label) -> None:
    """A curve with its settled points filled and the others hollow."""
    ax.plot(x, y * 1e3, ls, color=colour, label=label)
    ax.plot(x[settled], y[settled] * 1e3, marker, color=colour, ms=4, ls="none")
    ax.plot(x[~settled], y[~settled] * 1e3, marker, color=colour, mfc="none", ms=6, ls="none")


def _save(fig, stem: Path, rows: list, dtype: list) -> list[Path]:
    fig.tight_layout()
    save_png(fig, stem.with_suffix(".png"), dpi=120, tight=False)
    write_csv(stem.with_suffix(".csv"), np.array(rows, dtype=dtype))
    return [stem.with_suffix(".png"), stem.with_suffix(".csv")]
