"""The four parameter studies (Figs. 6-9) and the section-4 Coulomb comparison as periodic orbits.

Per study value: every branch of the paper's fixed point B = A(B) (the tracked-amplitude FMU's
periodic solutions, stable or not) and of the time-domain Jenkins element, traced by shooting and
continuation through the FMU (harness.sweep.periodic), drawn over the reference's harmonic-balance
branches (gating off). For the kn and angle studies also the Coulomb describing function's fixed
point (section 4). Written per study: `<fig>_<key>_branches.csv` (one row per orbit),
`<fig>_<key>_hb.csv`, `<fig>_<key>_summary.csv` (peaks, jump speeds, DF vs Jenkins) and
`<fig>_<key>.png` (stable bold, unstable faint).
"""
from __future__ import annotations

import math
from typing import Any, Mapping, Sequence

import numpy as np

from harness.paper import plots
from harness.sweep.executor import write_csv
from harness.sweep.periodic.branches import BranchSettings
from harness.sweep.periodic.continuation import write_branches_csv
from harness.sweep.periodic.studies import Curve, CurveTask, curve_summary

MODELS = ("fixedPoint", "jenkins")  # drawn for every study
COULOMB_STUDIES = ("kn", "angle")  # section 4: + the Coulomb DF's fixed point
SHORT = {"fixedPoint": "fp", "jenkins": "jenkins", "coulomb": "coulomb"}


def curve_tasks(studies: Mapping[str, Any], values: Mapping[str, Sequence[float]], base: Mapping[str, Any],
                speed_range: tuple[float, float], seed_step: float, fmu_path: str | None,
                coulomb: bool) -> list[CurveTask]:
    """One task per (study, value, model)."""
    out = []
    settings = BranchSettings(seed_step=seed_step)
    for key, vals in values.items():
        models = MODELS + (("coulomb",) if coulomb and key in COULOMB_STUDIES else ())
        for v in vals:
            p = dict(base, **{studies[key].param: v})
            out += [CurveTask(key, float(v), m, p, speed_range, fmu_path, settings) for m in models]
    return out


def hb_peak(hb: np.ndarray) -> tuple[float, float]:
    """(largest B on a stable harmonic-balance solution [m], its speed [rpm])."""
    st = hb[hb["stable"]] if len(hb) else hb
    if not len(st):
        return math.nan, math.nan
    i = int(np.argmax(st["B"]))
    return float(st["B"][i]), float(st["speed"][i])


def _stack(rows: list[tuple[float, np.ndarray]]) -> np.ndarray:
    if not rows:
        return np.zeros(0)
    dt = [("value", "f8")] + list(rows[0][1].dtype.descr)
    out = np.zeros(sum(len(a) for _, a in rows), dtype=dt)
    i = 0
    for v, a in rows:
        out["value"][i:i + len(a)] = v
        for n in a.dtype.names:
            out[n][i:i + len(a)] = a[n]
        i += len(a)
    return out


def _ranges(r: list[tuple[float, float, str]]) -> str:
    return "; ".join(f"{lo:.0f}-{hi:.0f} rpm {kind}" for lo, hi, kind in r)


def study_row(value: float, curves: Mapping[str, Curve], hb: np.ndarray) -> dict[str, Any]:
    """The numbers of one study value: per model peak (largest stable max |q|) and its speed, the
    jump speed, the unstable contact ranges; HB peak; DF (fixed point) vs Jenkins differences."""
    row: dict[str, Any] = {"value": value}
    for model, c in curves.items():
        s, k = curve_summary(c), SHORT[model]
        row.update({f"{k}_peak": s["peak"], f"{k}_speed": s["speed"], f"{k}_jump": s["jump"],
                    f"{k}_peak_any": s["peak_any"], f"{k}_unstable": _ranges(s["unstable_contact"]),
                    f"{k}_branches": s["branches"], f"{k}_evaluations": s["evaluations"]})
    row["hb_peak"], row["hb_speed"] = hb_peak(hb)
    if "jenkins" in curves and "fixedPoint" in curves:
        a_j, a_f = row["jenkins_peak"], row["fp_peak"]
        row["df_vs_jenkins_peak"] = (a_f - a_j) / a_j if a_j > 0 else math.nan
        row["df_vs_jenkins_speed"] = row["fp_speed"] - row["jenkins_speed"]
    return row


SUMMARY_KEYS = ("value", "fp_peak", "fp_speed", "fp_jump", "fp_peak_any", "jenkins_peak", "jenkins_speed",
                "jenkins_jump", "hb_peak", "hb_speed", "df_vs_jenkins_peak", "df_vs_jenkins_speed")


def write_study(out: Any, st: Any, curves: Mapping[float, Mapping[str, Curve]],
                hb: Mapping[float, np.ndarray]) -> dict[str, Any]:
    """CSV + PNG of one study; returns its summary (rows per value)."""
    stem = f"{st.figure}_{st.key}"
    values = sorted(curves)
    flat = [(v, m, b) for v in values for m in MODELS for b in curves[v][m].branches]
    write_branches_csv(out / f"{stem}_branches.csv", [b for _, _, b in flat], {"value": [v for v, _, _ in flat]})
    write_csv(out / f"{stem}_hb.csv", _stack([(v, hb[v]) for v in values]),
              f"{st.figure}: harmonic balance (reference, gating off), every branch; value = {st.param}; B [m]")
    rows = [study_row(v, curves[v], hb[v]) for v in values]
    tab = np.array([tuple(r.get(k, math.nan) for k in SUMMARY_KEYS) for r in rows],
                   dtype=[(k, "f8") for k in SUMMARY_KEYS])
    write_csv(out / f"{stem}_summary.csv", tab,
              f"{st.figure}: per {st.param}: largest stable max|q| [m] and its speed [rpm] of the fixed point "
              "B = A(B) (fp) and the Jenkins element, the speed where that stable branch ends in a fold (jump), "
              "the largest orbit stable or not (peak_any), the HB peak, and (fp - jenkins) / jenkins")
    plots.study_branches(out / f"{stem}.png", f"Paper {st.figure.replace('fig', 'Fig. ')}: {st.xlabel}",
                         [{"label": st.label(v), "branches": {m: curves[v][m].branches for m in MODELS},
                           "hb": hb[v], "d": float(curves[v][MODELS[0]].task.params["d"])} for v in values])
    return {"param": st.param, "figure": st.figure, "values": values, "rows": rows}


def write_coulomb(out: Any, studies: Mapping[str, Any], summary: Mapping[str, Any]) -> dict[str, Any]:
    """Section 4: peak and resonant speed of the macroslip and the Coulomb fixed point (branches)."""
    rows: dict[str, dict] = {}
    table = []
    for name in COULOMB_STUDIES:
        if name not in summary["studies"]:
            continue
        st = studies[name]
        # the study rows hold every model traced at the value, the Coulomb fixed point included
        mac = {r["value"]: r for r in summary["studies"][name]["rows"] if "coulomb_peak" in r}
        xs = sorted(mac)
        rows[name] = {
            "x": xs if name == "kn" else [math.pi / v for v in xs],
            "xlabel": st.xlabel if name == "kn" else "contact angle = pi / x", "log": name == "kn",
            "macroslip": {"peak": [mac[v]["fp_peak"] for v in xs], "speed": [mac[v]["fp_speed"] for v in xs]},
            "coulomb": {"peak": [mac[v]["coulomb_peak"] for v in xs], "speed": [mac[v]["coulomb_speed"] for v in xs]},
        }
        for v in xs:
            table.append((name, v, mac[v]["fp_peak"], mac[v]["fp_speed"], mac[v]["coulomb_peak"],
                          mac[v]["coulomb_speed"]))
    tab = np.array(table, dtype=[("study", "U5"), ("value", "f8"), ("macroslip_peak", "f8"),
                                 ("macroslip_speed", "f8"), ("coulomb_peak", "f8"), ("coulomb_speed", "f8")])
    write_csv(out / "section4_coulomb.csv", tab, "Section 4: largest stable max|q| [m] and its speed [rpm] of the "
              "fixed point B = A(B) (periodic orbits of the FMU), macroslip vs Coulomb describing function")
    if rows:
        plots.coulomb(out / "section4_coulomb.png", rows)
    return rows
