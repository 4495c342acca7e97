"""The four parameter studies (Figs. 6-9) and the section-4 Coulomb comparison as periodic orbits.

Per study value: every branch of the paper's fixed point B = A(B) (the tracked-amplitude FMU's
periodic solutions, stable or not) and of the time-domain Jenkins element, traced by shooting and
continuation through the FMU (harness.analysis.periodic), drawn over the harmonic-balance
branches (gating off). For the kn and angle studies also the Coulomb describing function's fixed
point (section 4). Written per study: `<fig>_<key>_branches.csv` (one row per orbit),
`<fig>_<key>_hb.csv`, `<fig>_<key>_summary.csv` (peaks, jump speeds, DF vs Jenkins) and
`<fig>_<key>.png` (stable bold, unstable faint). The numbers go on as records: a StudyRow per study
value, a StudySummary per study and a CoulombComparison per section-4 study (results/summary.json,
the claims table).
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from typing import Any, Mapping, Sequence

import numpy as np

from harness.studies import plots
from harness.files.tables import write_csv
from harness.analysis.periodic.branches import BranchSettings
from harness.analysis.periodic.continuation import write_branches_csv
from harness.analysis.periodic.curve import Curve, CurveSummary, CurveTask, curve_summary

MODELS = ("fixedPoint", "jenkins")  # drawn for every study
COULOMB_STUDIES = ("kn", "angle")  # section 4: + the Coulomb DF's fixed point


def curve_tasks(
    studies: Mapping[str, Any],
    values: Mapping[str, Sequence[float]],
    base: Mapping[str, Any],
    speed_range: tuple[float, float],
    seed_step: float,
    fmu_path: str | None,
    coulomb: bool,
) -> list[CurveTask]:
    """One task per (study, value, model)."""
    out = []
    settings = BranchSettings(seed_step=seed_step)
    for key, vals in values.items():
        models = MODELS + (("coulomb",) if coulomb and key in COULOMB_STUDIES else ())
        for v in vals:
            p = dict(base, **{studies[key].param: v})
            out += [CurveTask(key, float(v), m, p, speed_range, fmu_path, settings) for m in models]
    return out


def _stack(rows: list[tuple[float, np.ndarray]]) -> np.ndarray:
    if not rows:
        return np.zeros(0)
    dt = [("value", "f8")] + list(rows[0][1].dtype.descr)
    out = np.zeros(sum(len(a) for _, a in rows), dtype=dt)
    i = 0
    for v, a in rows:
        out["value"][i : i + len(a)] = v
        for n in a.dtype.names:
            out[n][i : i + len(a)] = a[n]
        i += len(a)
    return out


def _ranges(r: list[tuple[float, float, str]]) -> str:
    return "; ".join(f"{lo:.0f}-{hi:.0f} rpm {kind}" for lo, hi, kind in r)


@dataclass(frozen=True)
class StudyRow:
    """The numbers of one study value. Per model (fp: the fixed point B = A(B); jenkins: the
    Jenkins element; coulomb: the Coulomb DF's fixed point, traced for the section-4 studies only,
    None otherwise): the peak = largest max|q| of a stable orbit, its speed, the jump (where that
    stable branch ends in a fold, nan if it does not), the largest orbit stable or not, the unstable
    contact ranges, branches and period-map evaluations; the HB peak; DF (fp) vs Jenkins."""

    value: float  # the study parameter's value (Study.param, SI units)
    fp_peak: float  # [m]
    fp_speed: float  # [rpm]
    fp_jump: float  # [rpm]
    fp_peak_any: float  # [m]
    fp_unstable: str  # "low-high rpm kind; ..." of the unstable contact stretches
    fp_branches: int
    fp_evaluations: int
    jenkins_peak: float  # [m]
    jenkins_speed: float  # [rpm]
    jenkins_jump: float  # [rpm]
    jenkins_peak_any: float  # [m]
    jenkins_unstable: str
    jenkins_branches: int
    jenkins_evaluations: int
    hb_peak: float  # [m] largest B on a stable harmonic-balance solution, located
    hb_speed: float  # [rpm] its speed
    df_vs_jenkins_peak: float  # (fp_peak - jenkins_peak) / jenkins_peak (nan if jenkins_peak <= 0)
    df_vs_jenkins_speed: float  # [rpm] fp_speed - jenkins_speed
    coulomb_peak: float | None = None  # [m]
    coulomb_speed: float | None = None  # [rpm]
    coulomb_jump: float | None = None  # [rpm]
    coulomb_peak_any: float | None = None  # [m]
    coulomb_unstable: str | None = None
    coulomb_branches: int | None = None
    coulomb_evaluations: int | None = None


def _model_numbers(s: CurveSummary) -> tuple[float, float, float, float, str, int, int]:
    """One model's fields of StudyRow, in their order: peak, speed, jump, peak_any, unstable,
    branches, evaluations."""
    return s.peak, s.speed, s.jump, s.peak_any, _ranges(s.unstable_contact), s.branches, s.stats.evaluations


def study_row(value: float, curves: Mapping[str, Curve], hb_peak: tuple[float, float]) -> StudyRow:
    """The numbers of one study value: per model peak (largest stable max |q|) and its speed, the
    jump speed, the unstable contact ranges; the located HB peak (B, speed); DF (fixed point) vs Jenkins differences.
    `curves` holds the fixed point and the Jenkins element, and the Coulomb DF if it was traced."""
    fp, jk = curve_summary(curves["fixedPoint"]), curve_summary(curves["jenkins"])
    co = _model_numbers(curve_summary(curves["coulomb"])) if "coulomb" in curves else ()
    return StudyRow(
        value,
        *_model_numbers(fp),
        *_model_numbers(jk),
        *hb_peak,
        (fp.peak - jk.peak) / jk.peak if jk.peak > 0 else math.nan,
        fp.speed - jk.speed,
        *co,
    )


@dataclass(frozen=True)
class StudySummary:
    """One parameter study (Fig. 6-9): its rows, one per value, in the order of the values."""

    param: str  # FMU parameter varied
    figure: str  # fig6 .. fig9
    values: list[float]  # sorted
    rows: list[StudyRow]


@dataclass(frozen=True)
class PeakSeries:
    """One model's peaks along a section-4 study, in the order of CoulombComparison.x."""

    peak: list[float]  # [m] largest stable max|q|
    speed: list[float]  # [rpm] its speed


@dataclass(frozen=True)
class CoulombComparison:
    """Section 4 for one study: the macroslip fixed point against the Coulomb DF's."""

    x: list[float]  # the plot's abscissa: kn [N/m], or x of the contact angle pi / x
    xlabel: str
    log: bool  # logarithmic abscissa
    macroslip: PeakSeries
    coulomb: PeakSeries


SUMMARY_KEYS = (
    "value",
    "fp_peak",
    "fp_speed",
    "fp_jump",
    "fp_peak_any",
    "jenkins_peak",
    "jenkins_speed",
    "jenkins_jump",
    "hb_peak",
    "hb_speed",
    "df_vs_jenkins_peak",
    "df_vs_jenkins_speed",
)


def write_study(
    out: Any,
    st: Any,
    curves: Mapping[float, Mapping[str, Curve]],
    hb: Mapping[float, np.ndarray],
    hb_peaks: Mapping[float, tuple[float, float]],
) -> StudySummary:
    """CSV + PNG of one study; returns its summary (rows per value). hb_peaks: the located stable
    HB peak (B [m], speed [rpm]) per value (harness.analysis.curves.hb_stable_peak)."""
    stem = f"{st.figure}_{st.key}"
    values = sorted(curves)
    flat = [(v, m, b) for v in values for m in MODELS for b in curves[v][m].branches]
    write_branches_csv(out / f"{stem}_branches.csv", [b for _, _, b in flat], {"value": [v for v, _, _ in flat]})
    write_csv(
        out / f"{stem}_hb.csv",
        _stack([(v, hb[v]) for v in values]),
        f"{st.figure}: harmonic balance (reference, gating off), every branch; value = {st.param}; B [m]",
    )
    rows = [study_row(v, curves[v], hb_peaks[v]) for v in values]
    tab = np.array([tuple(getattr(r, k) for k in SUMMARY_KEYS) for r in rows], dtype=[(k, "f8") for k in SUMMARY_KEYS])
    write_csv(
        out / f"{stem}_summary.csv",
        tab,
        f"{st.figure}: per {st.param}: largest stable max|q| [m] and its speed [rpm] of the fixed point "
        "B = A(B) (fp) and the Jenkins element, the speed where that stable branch ends in a fold (jump), "
        "the largest orbit stable or not (peak_any), the HB peak, and (fp - jenkins) / jenkins",
    )
    plots.study_branches(
        out / f"{stem}.png",
        f"Paper {st.figure.replace('fig', 'Fig. ')}: {st.xlabel}",
        [
            {
                "label": st.label(v),
                "branches": {m: curves[v][m].branches for m in MODELS},
                "hb": hb[v],
                "d": float(curves[v][MODELS[0]].task.params["d"]),
            }
            for v in values
        ],
    )
    return StudySummary(st.param, st.figure, values, rows)


def write_coulomb(
    out: Any, studies: Mapping[str, Any], summaries: Mapping[str, StudySummary]
) -> dict[str, CoulombComparison]:
    """Section 4: peak and resonant speed of the macroslip and the Coulomb fixed point (branches),
    from the study summaries of the section-4 studies that were run."""
    rows: dict[str, CoulombComparison] = {}
    table = []
    for name in COULOMB_STUDIES:
        if name not in summaries:
            continue
        st = studies[name]
        # the study rows hold every model traced at the value, the Coulomb fixed point included
        mac = {r.value: r for r in summaries[name].rows if r.coulomb_peak is not None}
        xs = sorted(mac)
        rows[name] = CoulombComparison(
            x=xs if name == "kn" else [math.pi / v for v in xs],
            xlabel=st.xlabel if name == "kn" else "contact angle = pi / x",
            log=name == "kn",
            macroslip=PeakSeries([mac[v].fp_peak for v in xs], [mac[v].fp_speed for v in xs]),
            coulomb=PeakSeries([mac[v].coulomb_peak for v in xs], [mac[v].coulomb_speed for v in xs]),
        )
        for v in xs:
            table.append((name, v, mac[v].fp_peak, mac[v].fp_speed, mac[v].coulomb_peak, mac[v].coulomb_speed))
    tab = np.array(
        table,
        dtype=[
            ("study", "U5"),
            ("value", "f8"),
            ("macroslip_peak", "f8"),
            ("macroslip_speed", "f8"),
            ("coulomb_peak", "f8"),
            ("coulomb_speed", "f8"),
        ],
    )
    write_csv(
        out / "section4_coulomb.csv",
        tab,
        "Section 4: largest stable max|q| [m] and its speed [rpm] of the "
        "fixed point B = A(B) (periodic orbits of the FMU), macroslip vs Coulomb describing function",
    )
    if rows:
        plots.coulomb(out / "section4_coulomb.png", rows)
    return rows
