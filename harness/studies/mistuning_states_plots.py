"""Figures and tables of the mistuning study on steady states (harness/studies/mistuning_states.py),
each a PNG with its CSV:
- mistuning_states: the tuned ring's and the worst pattern's branches (largest blade over speed;
  stable solid, unstable dashed) with the sweep's settled states over them (what a sweep finds);
- mistuning_states_amplification: per pattern, the amplification on stable steady states and the
  sweep's, against the level, with Whitehead's bound and the worst pattern found by the search.
The table mistuning_states.csv has one row per ring: the largest stable state (amplitude, speed),
the sweep's peak, both amplifications, and how far the engine looked (branches, seeds, seeds shot,
untraced orbits); mistuning_search.csv every ring of the worst-pattern search."""

from __future__ import annotations

from pathlib import Path

import matplotlib
import matplotlib.pyplot as plt
import numpy as np

from harness.files.tables import write_csv


def _search_counts(rec: dict) -> tuple[int, int, int, int]:
    """How far the engine looked for a ring: branches traced, seeds, seeds Newton ran from, and the
    orbits past the branch bound (untraced; 0 when every seed's branch was traced)."""
    return len(rec["branches"]), rec["seeds"], rec.get("seeds_shot", -1), len(rec.get("untraced", []))


matplotlib.use("Agg")


def _branches(ax, rec: dict, colour: str, label: str) -> None:
    first = True
    for b in rec["branches"]:
        s, a, st = np.array(b["speeds_rpm"]), np.array(b["largest_m"]) * 1e3, np.array(b["stable"], dtype=bool)
        for k in range(len(s) - 1):
            ls = "-" if st[k] and st[k + 1] else "--"
            ax.plot(
                s[k : k + 2],
                a[k : k + 2],
                color=colour,
                ls=ls,
                lw=1.2 if ls == "-" else 0.8,
                label=label if first else None,
            )
            first = False
    if np.isfinite(rec["peak_stable_amplitude_m"]):
        ax.plot(
            rec["peak_stable_speed_rpm"],
            rec["peak_stable_amplitude_m"] * 1e3,
            "*",
            color=colour,
            ms=11,
            mec="k",
            mew=0.5,
        )


def _worst(states: dict, level: int = -1) -> int:
    a = np.array(states["amplification"], dtype=float)[level]
    return int(np.nanargmax(a)) if np.isfinite(a).any() else 0


def write(states: dict, sweep: dict, directory: Path, search: dict | None = None) -> list[Path]:
    """The figures and the table into `directory`; `sweep` is harness.studies.mistuning.run_study's
    output for the same rings (its `friction` variant), `search` search_worst's (optional)."""
    d = Path(directory)
    d.mkdir(parents=True, exist_ok=True)
    files: list[Path] = []
    sw = sweep["variants"][states["variant"]]
    levels = list(sweep["levels"])
    n_pat = len(states["peak_m"][0]) if states["peak_m"] else 0
    k = _worst(states)

    fig, ax = plt.subplots(figsize=(7.5, 4.6))
    _branches(ax, states["tuned"], "tab:blue", "tuned ring: branches (stable solid, unstable dashed)")
    if n_pat:
        worst, name = states["patterns"][(len(levels) - 1) * n_pat + k], f"pattern {k} at sigma {levels[-1]:g}"
    else:  # no pattern on steady states: the search's worst
        worst, name = search["record"], f"worst found by the search at sigma {search['sigma']:g}"
        k = search["start_pattern"]
    _branches(ax, worst, "tab:red", f"{name}: branches")
    sp = np.array(sweep["speeds_rpm"])
    for curves, ok, colour, label in (
        (np.array(sw["tuned"]), np.array(sw["tuned_settled"]), "tab:blue", "tuned: what a sweep finds"),
        (np.array(sw["amplitudes"], dtype=float)[-1, k], None, "tab:red", f"pattern {k}: what a sweep finds"),
    ):
        top = curves.max(axis=1)
        good = ok.all(axis=1) if ok is not None else np.isfinite(top)
        ax.plot(sp[good], top[good] * 1e3, "o", mfc="none", color=colour, ms=5, label=label)
    for peak, rpm, colour in (
        (sw["tuned_peak_m"], sw["tuned_peak_rpm"], "tab:blue"),
        (sw["peak_m"][-1][k], sw["peak_rpm"][-1][k], "tab:red"),
    ):
        ax.plot(rpm, peak * 1e3, "X", color=colour, ms=8, mec="k", mew=0.5)
    ax.plot([], [], "X", color="grey", mec="k", mew=0.5, label="the sweep's located peak")
    ax.set(
        xlabel="rotor speed [rpm]",
        ylabel="largest blade max |q| [mm]",
        title=f"N = {sweep['n']}: steady states (stars: largest stable) and the sweep's states",
    )
    ax.legend(fontsize=7)
    fig.tight_layout()
    files.append(d / "mistuning_states.png")
    fig.savefig(files[-1], dpi=120)
    plt.close(fig)

    rows = [
        (
            "tuned",
            -1,
            float("nan"),
            states["tuned_peak_m"],
            states["tuned_peak_rpm"],
            1.0,
            sw["tuned_peak_m"],
            sw["tuned_peak_rpm"],
            1.0,
            *_search_counts(states["tuned"]),
        )
    ]
    sweep_amp = np.array(sw["amplification"], dtype=float)
    for li, s in enumerate(levels):
        for p in range(n_pat):
            rows.append(
                (
                    "pattern",
                    p,
                    s,
                    states["peak_m"][li][p],
                    states["peak_rpm"][li][p],
                    states["amplification"][li][p],
                    sw["peak_m"][li][p],
                    sw["peak_rpm"][li][p],
                    sweep_amp[li, p],
                    *_search_counts(states["patterns"][li * n_pat + p]),
                )
            )
    table = np.array(
        rows,
        dtype=[
            ("ring", "U8"),
            ("pattern", "i4"),
            ("sigma", "f8"),
            ("stable_peak_m", "f8"),
            ("stable_peak_rpm", "f8"),
            ("amplification", "f8"),
            ("sweep_peak_m", "f8"),
            ("sweep_peak_rpm", "f8"),
            ("sweep_amplification", "f8"),
            ("branches", "i4"),
            ("seeds", "i4"),
            ("seeds_shot", "i4"),
            ("untraced_orbits", "i4"),
        ],
    )
    files.append(d / "mistuning_states.csv")
    write_csv(
        files[-1], table, "largest stable steady state per ring (engine) and the sweep's peak (what a sweep finds)"
    )

    fig, ax = plt.subplots(figsize=(6, 4))
    amp = np.array(states["amplification"], dtype=float)
    for li, s in enumerate(levels):
        ax.plot(
            np.full(n_pat, s) - 0.0008,
            amp[li],
            "o",
            color="tab:blue",
            label="stable steady states" if li == 0 else None,
        )
        ax.plot(
            np.full(n_pat, s) + 0.0008,
            sweep_amp[li, :n_pat],
            "x",
            color="tab:grey",
            label="what a sweep finds" if li == 0 else None,
        )
    if search is not None:
        ax.plot(
            search["sigma"],
            search["amplification"],
            "*",
            color="tab:red",
            ms=12,
            label=f"worst found ({search['rings']} rings searched)",
        )
    ax.axhline(sweep["whitehead"], color="k", ls=":", label=f"Whitehead (1 + sqrt(N)) / 2 = {sweep['whitehead']:.3f}")
    ax.axhline(1.0, color="grey", lw=0.6)
    ax.set(xlabel="sigma (relative std of EI)", ylabel="amplification", title=f"N = {sweep['n']}")
    ax.legend(fontsize=7)
    fig.tight_layout()
    files.append(d / "mistuning_states_amplification.png")
    fig.savefig(files[-1], dpi=120)
    plt.close(fig)

    if search is not None:  # every ring the search ran: its z (factors 1 + sigma z) and amplification
        n = len(search["z"])
        rows = [(i, *z, a) for i, (z, a) in enumerate(search["history"])]
        table = np.array(rows, dtype=[("ring", "i4"), *[(f"z{j}", "f8") for j in range(n)], ("amplification", "f8")])
        files.append(d / "mistuning_search.csv")
        write_csv(
            files[-1],
            table,
            f"worst-pattern search at sigma {search['sigma']:g} from pattern "
            f"{search['start_pattern']}: EI_i = EI (1 + sigma z_i); ring 0 is the start",
        )
    return files
