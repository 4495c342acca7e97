"""Figures of the reproduced studies, drawn with matplotlib's Agg backend straight to PNG files.

One function per figure kind: response curves of a parameter study (branches of periodic orbits
with stability over the harmonic-balance branches), the time response and spectrum
(paper Fig. 4/5), the hysteresis loop (Fig. 2), the Coulomb comparison (section 4) and the
Campbell diagram. Nothing is ever shown on screen; every function returns the path it wrote.
"""

from __future__ import annotations

from pathlib import Path
from typing import Any, Mapping, Sequence

import numpy as np

from harness.files.figures import plt, save_png

MM = 1e3  # m -> mm


def _save(fig: Any, path: Path | str) -> Path:
    return save_png(fig, path, dpi=110, tight=True)


def _colors(n: int) -> list:
    cmap = plt.get_cmap("viridis")
    return [cmap(x) for x in np.linspace(0.0, 0.9, max(n, 1))]


def study_branches(path: Path | str, title: str, curves: Sequence[dict]) -> Path:
    """Amplitude vs speed of a parameter study, one colour per value: left the fixed point B = A(B),
    right the Jenkins element (periodic orbits: stable bold, unstable faint), both over the
    harmonic-balance branches (thin dotted: stable, faint dots: unstable). Each curve dict: label,
    branches {"fixedPoint": [Branch], "jenkins": [Branch]}, hb (speed, B, stable), d [m]."""
    fig, axes = plt.subplots(1, 2, figsize=(13, 4.8), sharey=True)
    for c, col in zip(curves, _colors(len(curves))):
        for ax, model in zip(axes, ("fixedPoint", "jenkins")):
            _draw_branches(ax, c["branches"][model], col, c["label"])
            h = c["hb"]
            if len(h):
                st, un = h[h["stable"]], h[~h["stable"]]
                ax.plot(st["speed"], st["B"] * MM, ".", color=col, ms=1.2, alpha=0.7)
                ax.plot(un["speed"], un["B"] * MM, ".", color=col, ms=0.6, alpha=0.25)
            ax.axhline(c["d"] * MM, color=col, lw=0.6, ls=":")
    axes[0].set_title(
        "fixed point B = A(B): periodic orbits of the tracked-amplitude FMU\n"
        "bold stable, faint unstable; dots: harmonic balance (gating off); dotted: gap d",
        fontsize=8,
    )
    axes[1].set_title(
        "time-domain Jenkins element (frictionModel 3): periodic orbits of the FMU\n"
        "bold stable, faint unstable; dots: harmonic balance of the describing function",
        fontsize=8,
    )
    for ax in axes:
        ax.set_xlabel("rotor speed n [rpm]")
        ax.grid(alpha=0.3)
        _extrema_legend(ax)
        ax.legend(fontsize=7, loc="upper left")
    axes[0].set_ylabel("max |q| over a period [mm]")
    fig.suptitle(title)
    return _save(fig, path)


def study_curves(path: Path | str, title: str, curves: Sequence[dict], gap: Sequence[float] | None = None) -> Path:
    """Amplitude vs speed, one colour per parameter value. Each curve dict: label, time (structured
    array: speed, direction, amplitude, reached), fixed (speed, B, reached), hb (speed, B, stable)."""
    has_hb = any(c.get("hb") is not None and len(c["hb"]) for c in curves)  # else one panel
    fig, axes = plt.subplots(1, 1 + has_hb, figsize=(13 if has_hb else 8, 4.8), sharey=True, squeeze=False)
    axes = axes[0]
    cols = _colors(len(curves))
    for c, col in zip(curves, cols):
        t = c.get("time")
        if t is not None and len(t):
            for direction, ls in (("up", "-"), ("down", "--")):
                b = t[t["direction"] == direction]
                b = b[np.argsort(b["speed"])]
                if len(b):
                    axes[0].plot(
                        b["speed"],
                        b["amp_hi"] * MM,
                        ls,
                        color=col,
                        lw=1.3,
                        label=f"{c['label']}" if direction == "up" else None,
                    )
                    axes[0].fill_between(b["speed"], b["amp_lo"] * MM, b["amp_hi"] * MM, color=col, alpha=0.12, lw=0)
                    nr = b[~b["reached"]]
                    if len(nr):
                        axes[0].plot(nr["speed"], nr["amp_hi"] * MM, "o", mfc="none", color=col, ms=2.5, lw=0)
        f = c.get("fixed")
        if f is not None and len(f):
            f = f[f["kind"] != "jump"]  # a jump of A(B) across the diagonal is not a fixed point
            ok = f[f["reached"]]
            bad = f[~f["reached"]]
            axes[0].plot(ok["speed"], ok["B"] * MM, "x", color=col, ms=5, lw=0)
            axes[0].plot(bad["speed"], bad["B"] * MM, "+", color=col, ms=6, lw=0)
        h = c.get("hb")
        if has_hb and h is not None and len(h):
            st = h[h["stable"]]
            un = h[~h["stable"]]
            axes[1].plot(st["speed"], st["B"] * MM, ".", color=col, ms=2.5, label=c["label"])
            axes[1].plot(un["speed"], un["B"] * MM, ".", color=col, ms=1.0, alpha=0.35)
    if gap:
        for i, g in enumerate(sorted(set(gap))):
            for ax in axes:
                ax.axhline(
                    g * MM, color="0.6", lw=0.8, ls=":", label="gap d (contact closes above)" if i == 0 else None
                )
                ax.annotate(
                    f"gap d = {g * MM:g} mm",
                    (1.0, g * MM),
                    xycoords=("axes fraction", "data"),
                    xytext=(-3, 3),
                    textcoords="offset points",
                    ha="right",
                    fontsize=7,
                    color="0.4",
                )
    axes[0].set_title(
        "FMU: up (solid) / down (dashed) sweeps, band = amplitude range of the final periods;\n"
        "o not steady within the cap, x fixed points A(B) = B, + not converged",
        fontsize=8,
    )
    if has_hb:
        axes[1].set_title("harmonic balance (reference): stable (bold), unstable (faint)")
        axes[1].legend(fontsize=7, loc="upper left", markerscale=4)
    for ax in axes:
        ax.set_xlabel("rotor speed n [rpm]")
        ax.grid(alpha=0.3)
    axes[0].set_ylabel("tip amplitude [mm]")
    axes[0].legend(fontsize=7, loc="upper right")
    fig.suptitle(title)
    fig.tight_layout()
    return _save(fig, path)


def time_response(path: Path | str, title: str, runs: Sequence[tuple[str, dict]], d: float, f_line: float) -> Path:
    """Fig. 4 (q(t), per-period max and settling time) and Fig. 5 (spectrum of the second half),
    one row per formulation; each run dict: res (time, tipDisplacement), t_per, per_max, t_settle,
    freq, amp."""
    fig, axes = plt.subplots(len(runs), 2, figsize=(13, 3.8 * len(runs)), squeeze=False, constrained_layout=True)
    for (label, r), (a, b) in zip(runs, axes):
        res = r["res"]
        a.plot(res["time"], res["tipDisplacement"] * MM, lw=0.4, label="q(t)")
        a.plot(r["t_per"], r["per_max"] * MM, "k-", lw=0.9, label="max |q| per period")
        a.axhline(d * MM, color="0.5", ls=":", lw=0.8, label="gap d")
        a.axhline(-d * MM, color="0.5", ls=":", lw=0.8)
        ts = r["t_settle"]
        a.axvline(
            ts if np.isfinite(ts) else res["time"][-1],
            color="red",
            lw=0.8,
            label=f"settled (2 %) at {ts:.3f} s" if np.isfinite(ts) else "never settles (irregular)",
        )
        a.set_xlabel("time [s]")
        a.set_ylabel("tip displacement q [mm]")
        a.set_title(label, fontsize=9)
        a.legend(fontsize=7, loc="lower right")
        a.grid(alpha=0.3)
        b.plot(r["freq"], r["amp"] * MM, lw=0.9)
        b.axvline(f_line, color="red", lw=0.6, ls="--", label=f"EO x n/60 = {f_line:.1f} Hz")
        b.set_xlim(0, 1000.0)
        b.set_xlabel("frequency [Hz]")
        b.set_ylabel("amplitude [mm]")
        b.set_title(f"{label}: spectrum of the second half (Hann)", fontsize=9)
        b.legend(fontsize=7)
        b.grid(alpha=0.3)
    fig.suptitle(title)
    return _save(fig, path)


def hysteresis(path: Path | str, panels: Sequence[dict]) -> Path:
    """Fig. 2: friction force vs tangential displacement; each panel: title, eq4 (du, F), fmu (du, F)."""
    fig, axes = plt.subplots(1, len(panels), figsize=(6.2 * len(panels), 4.6))
    axes = np.atleast_1d(axes)
    for ax, p in zip(axes, panels):
        E = p.get("energy", {})
        du, F = p["eq4"]
        ax.plot(
            du * 1e6,
            F,
            "-",
            lw=1.6,
            label=f"eq. 4 closed form, v = B cos(theta); loop {E.get('eq4', np.nan) * 1e6:.1f} µJ",
        )
        if p.get("jenkins") is not None:
            du3, F3 = p["jenkins"]
            ax.plot(
                du3 * 1e6,
                F3,
                ":",
                lw=1.8,
                label=f"reference Jenkins element, v = B cos(theta); {E.get('jenkins', np.nan) * 1e6:.1f} µJ",
            )
        if p.get("fmu") is not None:
            du2, F2 = p["fmu"]
            ax.plot(
                du2 * 1e6,
                F2,
                "--",
                lw=1.1,
                label=f"FMU element (frictionModel 3) in a steady run; {E.get('fmu', np.nan) * 1e6:.1f} µJ",
            )
        ax.set_xlabel("tangential displacement Δu [µm]")
        ax.set_ylabel("friction force F_f [N]")
        ax.set_title(p["title"], fontsize=9)
        ax.grid(alpha=0.3)
        ax.legend(fontsize=7)
    return _save(fig, path)


def coulomb(path: Path | str, rows: Mapping[str, Any]) -> Path:
    """Section 4: peak amplitude and resonant speed vs a parameter, macroslip vs Coulomb
    (`rows`: the CoulombComparison records of harness.studies.study_branches, per study)."""
    fig, axes = plt.subplots(2, len(rows), figsize=(6 * len(rows), 7.5), squeeze=False)
    for j, (name, r) in enumerate(rows.items()):
        x = np.asarray(r.x)
        for series, style, lab in ((r.macroslip, "o-", "macroslip (paper)"), (r.coulomb, "s--", "Coulomb")):
            axes[0, j].plot(x, np.asarray(series.peak) * MM, style, label=f"{lab}, fixed point (orbits)")
            axes[1, j].plot(x, series.speed, style, label=f"{lab}, fixed point (orbits)")
        for i in range(2):
            axes[i, j].set_xlabel(r.xlabel)
            axes[i, j].grid(alpha=0.3)
            if r.log:
                axes[i, j].set_xscale("log")
            if name == "angle":  # x is the divisor of the contact angle gamma = pi / x: say the angle
                axes[i, j].set_xticks(x, [f"π/{v:g}\n{180 / v:.1f}°" for v in x])
                axes[i, j].set_xlabel("contact angle γ [deg]")
        axes[0, j].set_ylabel("largest stable max|q| [mm]")
        axes[1, j].set_ylabel("its speed [rpm]")
        axes[0, j].legend(fontsize=7)
    fig.suptitle("Section 4: macroslip (eq. 4) vs traditional Coulomb model")
    fig.tight_layout()
    return _save(fig, path)


def campbell(
    path: Path | str,
    speed_rpm: np.ndarray,
    fnat: np.ndarray,
    orders: Sequence[int],
    eo: int,
    crossing: float,
    peaks: Sequence[tuple[float, float, str]] = (),
    crossings: Sequence[tuple[float, float, str]] = (),
    title: str | None = None,
) -> Path:
    """Campbell diagram: the contact-free bending frequencies vs speed (`fnat`: one column per mode,
    or a vector for one mode) with the engine-order lines, each labelled at its end, the EO `eo`
    crossing marked; the legend sits beside the axes so that it covers no crossing. `crossings`
    (speed, frequency, label): every located crossing of a mode with an engine order, as dots."""
    f = np.asarray(fnat, dtype=float).reshape(len(speed_rpm), -1)
    fig, ax = plt.subplots(figsize=(9.5, 5))
    top = max([float(np.max(f)) * 1.6, 1.0] + [1.05 * fr for _, fr, _ in peaks])
    for m in range(f.shape[1]):
        ax.plot(
            speed_rpm,
            f[:, m],
            ("-", "--", "-.")[m % 3],
            color="k",
            lw=1.6,
            label=f"bending mode {m + 1} (contact-free), FMU"
            if f.shape[1] > 1
            else "first bending (contact-free), FMU naturalFrequency",
        )
    _engine_order_lines(ax, speed_rpm, orders, eo, top)
    if np.isfinite(crossing):
        ax.plot([crossing], [eo * crossing / 60.0], "ro", ms=7, label=f"EO {eo} crossing {crossing:.0f} rpm")
    for sp, fr, lab in peaks:
        ax.plot([sp], [fr], "v", ms=6, label=lab)
    last = -np.inf  # crossings closer than 4 % of the speed range share the previous label
    for sp, fr, lab in sorted(crossings):
        ax.plot([sp], [fr], "o", color="red", ms=4)
        if sp - last > 0.04 * (speed_rpm[-1] - speed_rpm[0]):
            ax.annotate(lab, (sp, fr), xytext=(3, -9), textcoords="offset points", fontsize=6, color="red")
            last = sp
    if crossings:
        ax.plot([], [], "o", color="red", ms=4, label="crossing (located): its speed [rpm]")
    ax.set_xlabel("rotor speed n [rpm]")
    ax.set_ylabel("frequency [Hz]")
    ax.set_ylim(0, top)
    ax.set_xlim(float(speed_rpm[0]), float(speed_rpm[-1]) * 1.04)
    ax.grid(alpha=0.3)
    ax.set_title(
        title
        or f"Campbell diagram: bending frequency and engine orders 1-{max(orders)}; resonance where EO {eo} crosses it",
        fontsize=10,
    )
    ax.legend(fontsize=7, loc="upper left", bbox_to_anchor=(1.01, 1.0), borderaxespad=0.0)
    fig.tight_layout()
    return _save(fig, path)


def _engine_order_lines(ax: Any, speed: np.ndarray, orders: Sequence[int], eo: int, top: float) -> None:
    """Lines f = k n / 60 [Hz], the excitation order `eo` solid, each labelled inside the frame
    where it leaves the plot (right-aligned above its end, or below the top edge)."""
    for k in orders:
        line = k * speed / 60.0
        (h,) = ax.plot(speed, line, "-" if k == eo else ":", lw=1.2 if k == eo else 0.8)
        inside = np.nonzero(line <= top)[0]
        j = int(inside[-1]) if len(inside) else 0
        at_top = line[j] >= 0.97 * top
        ax.annotate(
            f"EO {k}",
            (speed[j], line[j]),
            xytext=(-3, -10 if at_top else 2),
            textcoords="offset points",
            ha="right",
            va="bottom",
            fontsize=7,
            color=h.get_color(),
        )


def _stable_runs(stable: np.ndarray) -> list[tuple[int, int, bool]]:
    """(start, stop, stable) of the runs of equal stability along a branch (neighbours share a point)."""
    runs, i = [], 0
    while i < len(stable):
        j = i
        while j + 1 < len(stable) and stable[j + 1] == stable[i]:
            j += 1
        runs.append((i, min(j + 2, len(stable)), bool(stable[i])))
        i = j + 1
    return runs


def _draw_branches(ax: Any, branches: Sequence[Any], color: Any, label: str, ls: str = "-") -> None:
    """Branches (harness.analysis.periodic.continuation.Branch) as max |q| [mm] over speed: stable parts
    bold, unstable parts faint; the label on the first stable part; located peaks as triangles,
    folds as crosses."""
    for b in branches:
        n, a = b.speeds, b.amplitudes * MM
        for i0, i1, s in _stable_runs(b.stable):
            ax.plot(
                n[i0:i1],
                a[i0:i1],
                color=color,
                lw=2.0 if s else 0.8,
                alpha=1.0 if s else 0.4,
                ls=ls,
                label=label if s else None,
            )
            if s:
                label = None
        for e in b.extrema:
            ax.plot(e.speed, e.amplitude * MM, marker="^" if e.kind == "peak" else "x", color=color, ms=5, ls="none")


def _extrema_legend(ax: Any) -> None:
    """Legend entries for the markers _draw_branches puts on every branch (grey: any colour)."""
    ax.plot([], [], marker="^", color="0.35", ms=5, ls="none", label="peak (located)")
    ax.plot([], [], marker="x", color="0.35", ms=5, ls="none", label="fold (located)")


def branches_figure(
    path: Path | str,
    models: dict[str, Sequence[Any]],
    title: str,
    hb: Sequence[tuple[np.ndarray, np.ndarray, np.ndarray]] | None = None,
) -> Path:
    """Periodic-orbit branches (harness.analysis.periodic.continuation.Branch) per model: max |q| [mm] over
    speed, stable parts bold, unstable parts faint; optional HB branches (speed, B, stable) dashed."""
    fig, ax = plt.subplots(figsize=(7.5, 4.8))
    for color, (name, branches) in zip(_colors(len(models)), models.items()):
        _draw_branches(ax, branches, color, name, ls="--" if "jenkins" in name else "-")
    if hb:
        for k, (n, B, st) in enumerate(hb):
            ax.plot(n, B * 1e3, "k--", lw=0.8, alpha=0.6, label="harmonic balance (gating off)" if k == 0 else None)
    ax.set_xlabel("rotor speed [rpm]")
    ax.set_ylabel("max |q| [mm]")
    ax.set_title(title, fontsize=9)
    ax.grid(alpha=0.3)
    _extrema_legend(ax)
    ax.legend(fontsize=8, title="bold: stable, faint: unstable", title_fontsize=8)
    return _save(fig, path)
