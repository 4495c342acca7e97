"""Figures of one command's run, each written atomically to a PNG: a simulation's tip response
over time (`simulate --plot`), a ring's blade amplitudes over a speed band (`ring --speeds ...
--plot`) and its branches of periodic steady states (`ring --speeds ... --branches --plot`)."""

from __future__ import annotations

from pathlib import Path
from typing import Any

import numpy as np

from harness.files.figures import plt, save_png


def simulation(path: str | Path, result: np.ndarray, title: str) -> Path:
    """`simulate --plot`: tipDisplacement and amplitude [mm] over time (else the first output)."""
    columns = result.dtype.names or ()
    names: list[str] = [n for n in ("tipDisplacement", "amplitude") if n in columns]
    if not names:
        names = [n for n in columns if n != "time"][:1]
    fig, ax = plt.subplots(figsize=(8, 4))
    for n in names:
        scale, unit = (1e3, "mm") if n in ("tipDisplacement", "amplitude") else (1.0, "")
        ax.plot(result["time"], result[n] * scale, label=f"{n} [{unit}]" if unit else n, lw=0.8)
    ax.set_xlabel("time [s]")
    ax.set_ylabel("tip displacement q and its amplitude [mm]" if "tipDisplacement" in names else names[0])
    ax.set_title(title)
    ax.grid(alpha=0.3)
    ax.legend()
    fig.tight_layout()
    return save_png(fig, path, dpi=120, tight=False)


def ring_sweep(path: str | Path, r: Any, tuned: Any, title: str) -> Path:
    """`ring --speeds ... --plot`: every blade's amplitude vs speed per sweep direction (the tuned
    ring's largest blade overlaid when `tuned` is given), unsettled speeds and the located peak marked."""
    fig, ax = plt.subplots(figsize=(9, 5.5))
    styles = {"up": "-", "down": "--"}
    colors = plt.get_cmap("tab10" if next(iter(r.amplitudes_m.values())).shape[1] <= 10 else "viridis")
    for d, a in r.amplitudes_m.items():
        N = a.shape[1]
        for i in range(N):
            ax.plot(
                r.speeds_rpm,
                a[:, i] * 1e3,
                styles[d],
                marker=".",
                lw=1,
                color=colors(i / max(N - 1, 1)),
                label=f"blade {i}" if d == next(iter(r.amplitudes_m)) and (N <= 10 or i in (0, N - 1)) else None,
            )
        bad = ~r.settled[d].all(axis=1)
        if bad.any():
            ax.plot(
                r.speeds_rpm[bad],
                a[bad].max(axis=1) * 1e3,
                "x",
                color="k",
                ms=7,
                label="not settled" if d == next(iter(r.amplitudes_m)) else None,
            )
    for d in r.amplitudes_m:
        pts = [(x["speed_rpm"], max(x["amplitudes_m"])) for x in r.refinement if x["direction"] == d and x["settled"]]
        if pts:
            ax.plot(
                *np.array(pts).T * [[1], [1e3]],
                "o" if d == "up" else "s",
                ms=3,
                mfc="none",
                color="r",
                label=f"peak refinement ({d}), largest blade",
            )
    if tuned is not None:
        for d, a in tuned.amplitudes_m.items():
            ax.plot(
                tuned.speeds_rpm,
                a.max(axis=1) * 1e3,
                styles[d],
                color="0.4",
                lw=2.5,
                alpha=0.6,
                label=f"tuned ring, largest blade ({d})",
            )
    if r.peak_direction:
        ax.plot(
            [r.peak_speed_rpm],
            [r.peak_amplitude_m * 1e3],
            "*",
            color="red",
            ms=14,
            label=f"peak {r.peak_amplitude_m * 1e3:.4f} mm at {r.peak_speed_rpm:.0f} rpm ({r.peak_direction})",
        )
    if len(r.amplitudes_m) > 1:
        ax.plot([], [], "k-", label="sweep up")
        ax.plot([], [], "k--", label="sweep down")
    ax.set_xlabel("rotor speed [rpm]")
    ax.set_ylabel("blade amplitude max|q| [mm]")
    ax.set_title(title)
    ax.grid(alpha=0.3)
    ax.legend(fontsize=7, ncol=2)
    fig.tight_layout()
    return save_png(fig, path, dpi=120, tight=False)


def ring_branches(path: str | Path, out: dict[str, Any], title: str) -> Path:
    """`ring --speeds ... --branches --plot`: the branches of periodic steady states of `out`
    (RingBranches.as_dict(), with a sweep's "sweep" entry if any): the largest blade, stable solid,
    unstable dashed, bifurcations marked, the sweep's settled points over them."""
    fig, ax = plt.subplots(figsize=(9, 5.5))
    colors = plt.get_cmap("tab10")
    for k, b in enumerate(out["branches"]):
        S, st = np.array(b["speeds_rpm"]), np.array(b["stable"])
        A = np.array(b["amplitudes_m"]).max(axis=1) * 1e3
        c = colors(k % 10)
        for i in range(len(S) - 1):
            both = bool(st[i] and st[i + 1])
            ax.plot(S[i : i + 2], A[i : i + 2], "-" if both else "--", color=c, lw=1.8 if both else 0.9)
        for x in b["bifurcations"]:
            ax.plot(
                [x["speed_rpm"]],
                [x["amplitude_m"] * 1e3],
                "o" if x["kind"] == "fold" else "d",
                ms=4,
                mfc="none",
                color=c,
            )
    un = out.get("untraced_orbits") or []
    if un:  # orbits from seeds past the branch bound: sampled, not continued
        ax.plot(
            [o["speed_rpm"] for o in un],
            [max(o["amplitudes_m"]) * 1e3 for o in un],
            "x",
            color="0.4",
            ms=5,
            label="orbit from a seed past the branch bound (not continued)",
        )
    sw = out.get("sweep")
    if sw:
        S = np.array(sw["speeds_rpm"])
        for d, a in sw["amplitudes_m"].items():
            a, ok = np.array(a), np.array(sw["settled"][d]).all(axis=1)
            ax.plot(
                S[ok],
                a[ok].max(axis=1) * 1e3,
                "^" if d == "up" else "v",
                ms=6,
                color="k",
                mfc="none",
                label=f"sweep {d}: settled, largest blade",
            )
    if out.get("peak_stable_amplitude_m") is not None:
        a, s = out["peak_stable_amplitude_m"], out["peak_stable_speed_rpm"]
        ax.plot([s], [a * 1e3], "*", color="red", ms=14, label=f"largest stable: {a * 1e3:.4f} mm at {s:.0f} rpm")
    ax.plot([], [], "k-", lw=1.8, label="stable (largest blade)")
    ax.plot([], [], "k--", lw=0.9, label="unstable")
    ax.plot([], [], "ko", mfc="none", ms=4, label="fold")
    ax.plot([], [], "kd", mfc="none", ms=4, label="branch point, Neimark-Sacker, period doubling")
    lo, hi = out["band_rpm"]
    ax.set_xlim(lo - 0.02 * (hi - lo), hi + 0.02 * (hi - lo))
    ax.set_xlabel("rotor speed [rpm]")
    ax.set_ylabel("largest blade amplitude max|q| [mm]")
    ax.set_title(title, fontsize=10)
    ax.grid(alpha=0.3)
    ax.legend(fontsize=7)
    fig.tight_layout()
    return save_png(fig, path, dpi=120, tight=False)
