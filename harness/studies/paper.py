"""The paper's studies, reproduced with the FMU, written to results/.

`reproduce()` runs, for a chosen size ("quick" for tests, "default" for `make run`, "full"): the
four parameter studies of Fig. 6-9 (gap, shroud mass, contact angle, normal stiffness) as branches
of periodic orbits of the FMU with their stability (the paper's fixed point B = A(B) and the
time-domain Jenkins element; harness.studies.study_branches) over the harmonic-balance
branches; the section-4 comparison with the Coulomb model (branches too); Fig. 4/5 (time response
and spectrum at 5000 rpm), the paper's own iteration B <- A(B) at 5000 rpm (it 2-cycles, docs/model.md s.4) and a Campbell diagram. Each
figure is a PNG plus CSV files; their numbers are collected in a Summary record (StudySummary and
StudyRow per study, CoulombComparison, Fig45Summary, HysteresisLoop, HarmonicRange, CampbellSummary,
PaperIteration, Timing), which `claims.py` turns into the claims table and `Summary.as_dict` writes
to `summary.json`. The hysteresis loop of Fig. 2 (its HysteresisLoop record is in the Summary)
compares the FMU with the reference: harness.validation.reproduction runs it with these studies.
"""

from __future__ import annotations

import json
import math
import time as _time
from dataclasses import dataclass, field, fields, is_dataclass
from pathlib import Path
from typing import TYPE_CHECKING, Any, Mapping, Sequence

import numpy as np

from harness import digits
from harness.analysis.cache import fmu_identity
from harness.analysis.config import ConfigError
from harness.analysis.curves import hb_curve, hb_stable_peak, omega_of
from harness.paths import RESULTS_DIR
from harness.analysis.executor import Runner
from harness.files.tables import write_csv
from harness.files.atomic import atomic_write_text
from harness.analysis.periodic.branches import orbits_at
from harness.analysis.periodic.harmonics import branch_harmonics, summarize
from harness.analysis.periodic.period_map import PeriodMap
from harness.analysis.periodic.curve import trace_curve
from harness.analysis.steady_state import analyze
from harness.fmu.blade import BladeFMU
from harness.model import params as _params
from harness.model.excitation import LinearRamp
from harness.studies import plots
from harness.studies.campbell_modes import campbell_study
from harness.studies.mode2_crossing import Mode2Crossing, mode2_crossing
from harness.studies.modes_convergence import ModesConvergence, modes_convergence, modes_tasks
from harness.studies.study_branches import curve_tasks, write_coulomb, write_study

if TYPE_CHECKING:  # imported where they are used: they pull in the FMU binding
    from harness.studies.study_branches import CoulombComparison, StudySummary
    from harness.analysis.periodic.harmonics import HarmonicRange

PI = math.pi


@dataclass(frozen=True)
class Study:
    key: str  # gap | mass | angle | kn
    figure: str  # paper figure
    param: str  # FMU parameter varied
    values: tuple[float, ...]
    xlabel: str
    unit_scale: float  # value * unit_scale for labels
    unit: str

    def label(self, v: float) -> str:
        if self.param == "gamma":
            return f"gamma = pi/{PI / v:.0f}"
        if self.param == "kn":
            return f"kn = {v:.0e} N/m"
        return f"{self.param} = {v * self.unit_scale:g} {self.unit}"


STUDIES: dict[str, Study] = {
    "gap": Study("gap", "fig6", "d", (2e-5, 3e-5, 4e-5, 5e-5, 6e-5), "gap d [mm]", 1e3, "mm"),
    "mass": Study("mass", "fig7", "m0", (0.02, 0.04, 0.06, 0.08, 0.1), "shroud mass m0 [kg]", 1.0, "kg"),
    "angle": Study(
        "angle", "fig8", "gamma", (PI / 3, PI / 4, PI / 5, PI / 6, PI / 7), "contact angle [rad]", 1.0, "rad"
    ),
    "kn": Study("kn", "fig9", "kn", (1e5, 3e5, 1e6, 3e6, 1e7), "normal stiffness kn [N/m]", 1.0, "N/m"),
}


@dataclass(frozen=True)
class Size:
    """How much work `reproduce` does."""

    name: str
    hb_speeds: tuple[float, ...]  # harmonic-balance speeds [rpm]
    values: Mapping[str, tuple[float, ...]] | None = None  # per-study values (None: all of STUDIES)
    fig45_time: float = 1.0  # [s] simulated for Fig. 4/5
    coulomb: bool = True
    iteration_steps: int = 12  # the paper's iteration B <- A_0.2s(B)
    speed_range: tuple[float, float] = (3000.0, 10000.0)  # branches of periodic orbits [rpm]
    seed_step: float = 500.0  # [rpm] between the speeds where every orbit is searched
    modes: tuple[int, ...] = (1, 2, 3, 4)  # the convergence study in m (empty: not run)
    campbell_modes: int = 3  # modes of the m-mode Campbell diagram (0: not drawn)


def _grid(a: float, b: float, step: float) -> tuple[float, ...]:
    return tuple(float(x) for x in np.arange(a, b + 0.5 * step, step))


SIZES: dict[str, Size] = {
    "quick": Size(
        "quick",
        hb_speeds=_grid(3000, 10000, 100),
        values={"gap": (2e-5, 6e-5), "mass": (0.02, 0.1), "angle": (PI / 3, PI / 7), "kn": (1e5, 1e7)},
        fig45_time=0.6,
        coulomb=False,
        iteration_steps=6,
        seed_step=1000.0,
        modes=(),
        campbell_modes=0,
    ),
    # branches to 12000 rpm: with kn = 1e7 the stable contact branches of the fixed point end in
    # their fold above 10000 rpm for d = 0.02 mm and gamma = pi/6..pi/4 (a peak at the range end
    # would be a missed solution).
    # Seeds every 1000 rpm: the 50 curves traced with seeds every 500 rpm have the same branches
    # (docs/periodic.md; tests/analysis/test_continuation.py checks two of them)
    "default": Size(
        "default",
        hb_speeds=_grid(2000, 12000, 40),
        speed_range=(3000.0, 12000.0),
        seed_step=1000.0,
    ),
    "full": Size(
        "full",
        hb_speeds=_grid(100, 12000, 20),
        fig45_time=2.0,
        speed_range=(2000.0, 12000.0),
        seed_step=250.0,
    ),
}


def base_params() -> dict[str, Any]:
    """The paper's base case: Table 1 with d = 0.03 mm, gamma = pi/3, m0 = 0.025 kg, kn = 1e7."""
    return _params.validate({}, source="paper Table 1")


# ---------------------------------------------------------------------------------------------
# Single runs with the FMU in this process
# ---------------------------------------------------------------------------------------------
def settling_time(time: np.ndarray, amp: np.ndarray, band: float = 0.02) -> float:
    """First time after which the amplitude stays within `band` of its final value; nan if it only
    enters the band in the last fifth of the record (never settles: irregular response)."""
    final = amp[-1]
    out = np.abs(amp - final) > band * abs(final)
    if not np.any(out):
        return float(time[0])
    last = int(np.nonzero(out)[0][-1])
    if last + 1 >= 0.8 * len(time):
        return math.nan
    return float(time[last + 1])


def _response(fmu: Any, p: Mapping[str, Any], speed: float, t_stop: float) -> dict[str, Any]:
    """Run from rest, per-period max |q|, 2 % settling time, and the Hann spectrum of the last half
    (a whole number of periods, so the EO line falls on a bin)."""
    om = omega_of(p, speed)
    T = 2 * PI / om
    n_per = 64
    P = int(math.ceil(t_stop / T))
    res = fmu.run(dict(p), P * T, T / n_per, speed_rpm=speed, outputs=["tipDisplacement", "amplitude"])
    q = res["tipDisplacement"]
    per_max = np.abs(q[1:]).reshape(P, n_per).max(axis=1)
    t_per = T * (np.arange(P) + 1)
    ss = analyze(res["time"], q, T, rtol=1e-3, min_periods=3)
    half = q[-(P // 2) * n_per :]
    win = np.hanning(len(half))
    amp = np.abs(np.fft.rfft(half * win)) * 2.0 / np.sum(win)
    freq = np.fft.rfftfreq(len(half), T / n_per)
    k = int(np.argmax(amp[1:])) + 1
    return {
        "res": res,
        "per_max": per_max,
        "t_per": t_per,
        "ss": ss,
        "freq": freq,
        "amp": amp,
        "t_settle": settling_time(t_per, per_max, 0.02),
        "f_peak": float(freq[k]),
        "final": float(per_max[-1]),
        "band": (float(per_max[-P // 5 :].min()), float(per_max[-P // 5 :].max())),
    }


@dataclass(frozen=True)
class ResponseSummary:
    """One response from rest of Fig. 4/5 (the period maxima of |q| and the spectrum of the last half)."""

    t_settle_2pct: float  # [s] period maximum within 2 % of its final value from then on (nan: never)
    reached: bool  # periodic steady state found (rtol 1e-3)
    t_steady: float  # [s] when it was reached (nan: not reached); key "t_steady_rtol1e-3" in summary.json
    f_peak: float  # [Hz] largest spectral line
    amplitude: float  # [m] final period maximum of |q|
    band_last_fifth: tuple[float, float]  # [m] (min, max) of the period maxima over the last fifth
    max_abs_q: float  # [m] over the whole run
    line_at_f_expected: float  # [m] spectral line at engineOrder * n / 60
    largest_line: float  # [m]

    def as_dict(self) -> dict[str, Any]:
        d = {f.name: getattr(self, f.name) for f in fields(self)}
        d["t_steady_rtol1e-3"] = d.pop("t_steady")
        return d


@dataclass(frozen=True)
class Fig45Summary:
    """Fig. 4/5 at one speed: the paper's formulation (B fixed at the fixed-point root) and the
    tracked amplitude."""

    speed: float  # [rpm]
    d: float  # [m] gap
    f_expected: float  # [Hz] engineOrder * speed / 60
    B_root: float  # [m] the fixed-point root the paper's run holds B at
    paper: ResponseSummary
    tracked: ResponseSummary


def fig45(
    fmu: Any, out: Path, params: Mapping[str, Any], speed_rpm: float, t_stop: float, B_root: float
) -> Fig45Summary:
    """Paper Fig. 4/5: response from rest at `speed_rpm` and the spectrum of its second half, for the
    paper's formulation (amplitude fixed at the fixed-point root B_root, amplitudeMode 1) and for the
    tracked amplitude (amplitudeMode 2)."""
    p = dict(params)
    runs = {
        "paper": _response(fmu, dict(p, amplitudeMode=1, B=B_root), speed_rpm, t_stop),
        "tracked": _response(fmu, dict(p, amplitudeMode=2), speed_rpm, t_stop),
    }
    a, b = runs["paper"], runs["tracked"]
    tab = np.zeros(len(a["res"]), dtype=[("time", "f8"), ("q_paper", "f8"), ("q_tracked", "f8")])
    tab["time"], tab["q_paper"], tab["q_tracked"] = (
        a["res"]["time"],
        a["res"]["tipDisplacement"],
        b["res"]["tipDisplacement"],
    )
    write_csv(
        out / "fig4_time_response.csv",
        tab,
        f"Fig. 4: FMU tip displacement q [m] from rest at {speed_rpm:g} rpm; paper = amplitude fixed at the "
        f"fixed-point root B = {B_root:.6g} m (amplitudeMode 1), tracked = amplitudeMode 2",
    )
    spec = np.zeros(len(a["freq"]), dtype=[("frequency", "f8"), ("amp_paper", "f8"), ("amp_tracked", "f8")])
    spec["frequency"], spec["amp_paper"], spec["amp_tracked"] = a["freq"], a["amp"], b["amp"]
    write_csv(
        out / "fig5_spectrum.csv",
        spec,
        f"Fig. 5: single-sided amplitude spectrum [m] (Hann window) of the second half of the runs at {speed_rpm:g} rpm",
    )
    plots.time_response(
        out / "fig4_5_time_spectrum.png",
        f"Paper Fig. 4/5 at {speed_rpm:g} rpm, d = {p['d'] * 1e3:g} mm",
        [("paper: B fixed at the fixed-point root", a), ("tracked amplitude", b)],
        p["d"],
        p["engineOrder"] * speed_rpm / 60,
    )
    f_exp = p["engineOrder"] * speed_rpm / 60.0

    def summary(r: dict[str, Any]) -> ResponseSummary:
        return ResponseSummary(
            r["t_settle"],
            bool(r["ss"].reached),
            r["ss"].t_steady,
            r["f_peak"],
            r["final"],
            r["band"],
            float(np.max(np.abs(r["res"]["tipDisplacement"]))),
            float(r["amp"][int(np.argmin(np.abs(r["freq"] - f_exp)))]),
            float(np.max(r["amp"][1:])),
        )

    return Fig45Summary(speed_rpm, p["d"], f_exp, B_root, summary(a), summary(b))


def hb_vs_orbit(fmu: Any, out: Path, params: Mapping[str, Any], curves: Sequence[Any]) -> dict[str, HarmonicRange]:
    """The one-harmonic balance against the exact orbits of the base case's branches (fixed point
    and Jenkins element): Fourier content of each contact orbit (harness.analysis.periodic.harmonics), to
    `hb_vs_orbit.csv`; returns the ranges per model."""
    rows = []
    for model in ("fixedPoint", "jenkins"):
        base = [c for c in curves if c.task.model == model and dict(c.task.params) == dict(params)]
        if base:
            rows += branch_harmonics(fmu, params, model, base[0].branches)
    names = [
        "model",
        "speed",
        "stable",
        "amplitude",
        "a1",
        "higher",
        "a3",
        "hb",
        "higher_rel",
        "hb_vs_a1",
        "hb_vs_amplitude",
    ]
    tab = np.zeros(
        len(rows),
        dtype=[("model", "U10"), ("stable", "i4")] + [(n, "f8") for n in names if n not in ("model", "stable")],
    )
    for i, r in enumerate(rows):
        for n, v in r.as_dict().items():
            tab[n][i] = v
    write_csv(
        out / "hb_vs_orbit.csv",
        tab[names],
        "base case: exact periodic orbits (contact, >= 250 rpm apart along each branch) vs the one-harmonic "
        "balance (reference, gating off)\namplitude = max|q| [m]; a1, a3 = first, third harmonic [m]; higher = "
        "sqrt(sum_k>=2 a_k^2) [m]; hb = HB contact root nearest a1 [m] (nan: HB has none at that speed); higher_rel = higher / amplitude; "
        "hb_vs_a1 = (hb - a1) / a1; hb_vs_amplitude = (hb - amplitude) / amplitude",
    )
    return summarize(rows)


def _root_at(params: Mapping[str, Any], speed: float, fmu: Any) -> float:
    """The largest fixed point B = A(B) at `speed`: the largest B of every periodic orbit of the
    tracked-amplitude FMU found there (harness.analysis.periodic.search), 2 d if there is none."""
    orbits = orbits_at(PeriodMap(fmu, params, "fixedPoint"), speed)
    return max((o.B for o in orbits), default=2.0 * float(params["d"]))


def paper_iteration(
    fmu: Any, params: Mapping[str, Any], speed_rpm: float, B0: float, steps: int, t_int: float = 0.2
) -> list[float]:
    """The paper's section-3 procedure: B_{k+1} = max |q| over the last period of a t_int run from
    rest with the amplitude fixed at B_k (docs/model.md s.4: it falls into a 2-cycle near resonance)."""
    om = omega_of(params, speed_rpm)
    T = 2 * PI / om
    seq = [B0]
    for _ in range(steps):
        p = dict(params, amplitudeMode=1, B=seq[-1])
        res = fmu.run(p, T * math.ceil(t_int / T), T / 64, speed_rpm=speed_rpm, outputs=["tipDisplacement"])
        last = res[res["time"] >= res["time"][-1] - T * (1 + 1e-9)]
        seq.append(float(np.max(np.abs(last["tipDisplacement"]))))
    return seq


@dataclass(frozen=True)
class HysteresisLoop:
    """Fig. 2 at one normal stiffness: the energy dissipated per cycle by the friction loop."""

    kn: float  # [N/m]
    speed: float  # [rpm]
    B: float  # [m] the FMU's steady amplitude the loops are drawn at
    E_loop_fmu: float  # [J] loop area of the FMU's time-domain element (last period)
    E_loop_eq4: float  # [J] loop area of eq. 4 (closed form)
    E_pi_omega_B2_fc: float  # [J] pi omega B^2 fc of the describing function
    E_jenkins_prescribed: float  # [J] reference Jenkins element driven by v = B cos(theta)


@dataclass(frozen=True)
class CampbellSummary:
    """Where the first bending frequency of the contact-free blade crosses the engine-order line."""

    eo_crossing_rpm: float  # [rpm] (nan: no crossing below 10000 rpm)
    f_rest_hz: float  # [Hz] at standstill
    f_at_crossing_hz: float  # [Hz]


def campbell(
    fmu: Any, out: Path, params: Mapping[str, Any], peaks: Sequence[tuple[float, float, str]] = ()
) -> CampbellSummary:
    """naturalFrequency of the FMU along a 0..10000 rpm run-up (no load) with the EO lines."""
    r = fmu.run(
        dict(params),
        1.0,
        1e-3,
        speed_rpm=LinearRamp(0.0, 10000.0, 0.0, 1.0),
        aero=LinearRamp(0.0, 0.0, 0.0, 1.0),
        outputs=["naturalFrequency"],
    )
    n = 10000.0 * r["time"]
    f = r["naturalFrequency"]
    eo = int(params["engineOrder"])
    g = f - eo * n / 60.0
    idx = np.nonzero(np.sign(g[:-1]) != np.sign(g[1:]))[0]
    cross = math.nan
    if len(idx):
        i = int(idx[0])
        cross = float(n[i] - g[i] * (n[i + 1] - n[i]) / (g[i + 1] - g[i]))
    tab = np.zeros(
        len(n),
        dtype=[("time", "f8"), ("speed", "f8"), ("naturalFrequency", "f8")] + [(f"EO{k}", "f8") for k in range(1, 7)],
    )
    tab["time"], tab["speed"], tab["naturalFrequency"] = r["time"], n, f
    for k in range(1, 7):
        tab[f"EO{k}"] = k * n / 60.0
    write_csv(out / "campbell.csv", tab, "Campbell diagram: FMU naturalFrequency [Hz] along a run-up, EO lines k n/60")
    plots.campbell(out / "campbell.png", n, f, range(1, 7), eo, cross, peaks)
    return CampbellSummary(cross, float(f[0]), eo * cross / 60.0)


@dataclass(frozen=True)
class CampbellModesSummary:
    """The m-mode Campbell diagram's located crossings (mode, engine order, speed [rpm], frequency [Hz])."""

    modes: int
    crossings: list[dict]


# ---------------------------------------------------------------------------------------------
# Everything
# ---------------------------------------------------------------------------------------------
@dataclass(frozen=True)
class PaperIteration:
    """The paper's section-3 iteration B <- max|q| of a t_int run with B fixed."""

    speed: float  # [rpm]
    t_int: float  # [s] run per step
    B: list[float]  # [m] B_0 = 2 d, B_1, ...


@dataclass(frozen=True)
class Timing:
    """Where the wall time of `reproduce` went [s]; counts as floats."""

    hb_wall: float  # harmonic-balance branches (in this process)
    branches_wall: float  # the periodic-orbit curves, mapped over the Runner
    curves: float  # number of curves
    branches_evaluations: float  # period-map evaluations, summed over the curves
    branches_simulated_s: float  # blade time simulated, summed over the curves
    branches_fmi_s: float  # time in FMI calls, summed over the curves
    branches_worker_s: float  # the curves' wall times in their workers, summed
    extras_wall: float | None = None  # Fig. 2, 4/5, Campbell, HB vs orbit, iteration (None: not run)


@dataclass
class Summary:
    """Everything `reproduce` computed (results/summary.json; the claims table reads it). The extras
    are None when they were not run."""

    size: str  # Size.name
    base: dict[str, Any]  # the base parameter set (validated)
    studies: dict[str, StudySummary] = field(default_factory=dict)  # by study key
    coulomb: dict[str, CoulombComparison] | None = None  # section 4, by study key
    fig45: Fig45Summary | None = None
    hysteresis: dict[str, HysteresisLoop] | None = None  # by panel label
    hb_vs_orbit: dict[str, HarmonicRange] | None = None  # by model
    campbell: CampbellSummary | None = None
    campbell_modes: CampbellModesSummary | None = None
    modes: ModesConvergence | None = None  # convergence in the number of modes
    mode2_crossing: Mode2Crossing | None = None  # the second mode's EO 8 crossing with the contact
    paper_iteration: PaperIteration | None = None
    timing: Timing | None = None

    def as_dict(self) -> dict[str, Any]:
        """The JSON form of summary.json (records as objects, fields that are None left out)."""
        return _record_dict(self)


def _record_dict(o: Any) -> dict[str, Any]:
    return {f.name: _plain(getattr(o, f.name)) for f in fields(o) if getattr(o, f.name) is not None}


def _plain(o: Any) -> Any:
    """Records (by their own `as_dict` if they have one) and containers as plain dicts and lists."""
    if is_dataclass(o) and not isinstance(o, type):
        return o.as_dict() if hasattr(o, "as_dict") else _record_dict(o)
    if isinstance(o, dict):
        return {k: _plain(v) for k, v in o.items()}
    if isinstance(o, (list, tuple)):
        return [_plain(v) for v in o]
    return o


@dataclass
class Reproduction:
    summary: Summary
    claims: list = field(default_factory=list)  # the claim rows (claims.write_claims), once written


def validate_request(size: str | Size, studies: Sequence[str] | None) -> tuple[Size, list[str]]:
    if isinstance(size, str):
        if size not in SIZES:
            raise ConfigError(f"size {size!r} is unknown; choose from {', '.join(SIZES)}")
        size = SIZES[size]
    names = list(studies) if studies else list(STUDIES)
    for n in names:
        if n not in STUDIES:
            raise ConfigError(f"study {n!r} is unknown; choose from {', '.join(STUDIES)}")
    return size, names


def reproduce(
    out: Path | str = RESULTS_DIR,
    size: str | Size = "default",
    studies: Sequence[str] | None = None,
    runner: Runner | None = None,
    fmu_path: Path | str | None = None,
    extras: bool = True,
    base: Mapping[str, Any] | None = None,
) -> Reproduction:
    """`run_studies`, then summary.json into `out`. Without Fig. 2, which compares the FMU's
    friction loop with the reference's: harness.validation.reproduction adds it."""
    rep = run_studies(out, size, studies, runner, fmu_path, extras, base)
    write_summary(Path(out), rep.summary)
    return rep


def write_summary(out: Path, summary: Summary) -> None:
    """summary.json (the claims table reads it), replaced atomically; numbers with 6 significant
    digits (harness/digits.py), without the wall times (`timing`: they differ from run to run; `make
    bench` measures them), so that a rerun writes the same file."""
    d = {k: v for k, v in summary.as_dict().items() if k != "timing"}
    atomic_write_text(
        out / "summary.json", json.dumps(digits.rounded(d), indent=1, sort_keys=True, default=_json_default)
    )


def run_studies(
    out: Path | str = RESULTS_DIR,
    size: str | Size = "default",
    studies: Sequence[str] | None = None,
    runner: Runner | None = None,
    fmu_path: Path | str | None = None,
    extras: bool = True,
    base: Mapping[str, Any] | None = None,
) -> Reproduction:
    """Run the studies as branches of periodic orbits over the harmonic-balance branches (and, with
    `extras`, the Coulomb comparison, Fig. 4/5, Campbell, the m-mode Campbell diagram and the
    convergence in the number of modes, the paper's iteration), writing their files into `out`
    (all but summary.json). Nothing is cached: a curve takes about a second."""
    size, names = validate_request(size, studies)
    out = Path(out)
    base_p = _params.validate(base or {}, source="reproduce base parameters")
    values = {n: tuple((size.values or {}).get(n, STUDIES[n].values)) for n in names}
    for n in names:  # every parameter set is checked before any work starts
        for v in values[n]:
            _params.validate(dict(base_p, **{STUDIES[n].param: v}), source=f"{STUDIES[n].figure} {STUDIES[n].label(v)}")
    path, _ = fmu_identity(fmu_path)
    tasks = curve_tasks(STUDIES, values, base_p, size.speed_range, size.seed_step, path, extras and size.coulomb)
    out.mkdir(parents=True, exist_ok=True)
    own_runner = runner is None
    runner = runner or Runner()
    summary = Summary(size.name, base_p)
    rep = Reproduction(summary)
    try:
        runner.warm_up("harness.analysis.periodic.curve")  # the workers start while HB runs here
        t0 = _time.perf_counter()
        hb_params = {n: {v: dict(base_p, **{STUDIES[n].param: v}) for v in values[n]} for n in names}
        hb = {}
        with runner.steps("harmonic balance", len(names)) as step:
            for n in names:
                step(STUDIES[n].figure)
                hb[n] = {v: hb_curve(p, size.hb_speeds) for v, p in hb_params[n].items()}
        hb_peaks = {n: {v: hb_stable_peak(hb_params[n][v], hb[n][v]) for v in values[n]} for n in names}
        hb_wall = _time.perf_counter() - t0
        t0 = _time.perf_counter()
        done = runner.map(trace_curve, tasks, desc="periodic-orbit branches", unit="curve")
        branches_wall = _time.perf_counter() - t0
        curves: dict[str, dict[float, dict[str, Any]]] = {}
        for c in done:
            curves.setdefault(c.task.key, {}).setdefault(c.task.value, {})[c.task.model] = c
        for name in names:
            summary.studies[name] = write_study(out, STUDIES[name], curves[name], hb[name], hb_peaks[name])
        if extras and size.coulomb:
            summary.coulomb = write_coulomb(out, STUDIES, summary.studies)
        extras_wall = None
        if extras:
            t0 = _time.perf_counter()
            with BladeFMU(path) as fmu, runner.steps("extras", 6) as step:
                step("Fig. 4/5 time response")
                summary.fig45 = fig45(fmu, out, base_p, 5000.0, size.fig45_time, _root_at(base_p, 5000.0, fmu))
                step("harmonic balance vs the exact orbit")
                summary.hb_vs_orbit = hb_vs_orbit(fmu, out, base_p, done)
                peaks = []
                if "kn" in summary.studies:
                    for row in summary.studies["kn"].rows:
                        if math.isfinite(row.fp_speed):
                            peaks.append(
                                (
                                    row.fp_speed,
                                    base_p["engineOrder"] * row.fp_speed / 60,
                                    f"fixed-point peak, kn = {row.value:.0e} N/m",
                                )
                            )
                step("Campbell diagram")
                summary.campbell = campbell(fmu, out, base_p, peaks)
                step("Campbell diagram with more modes")
                if size.campbell_modes:
                    cm = campbell_study(fmu, out, base_p, size.campbell_modes)
                    summary.campbell_modes = CampbellModesSummary(cm.modes, cm.as_dict()["crossings"])
                    summary.mode2_crossing = mode2_crossing(fmu, out, base_p)
                step("convergence in the number of modes")
                if size.modes:
                    mc = runner.map(
                        trace_curve,
                        modes_tasks(base_p, size.speed_range, size.seed_step, path, size.modes),
                        desc="branches in the number of modes",
                        unit="curve",
                    )
                    summary.modes = modes_convergence(fmu, out, mc)
                step("the paper's iteration")
                seq = paper_iteration(fmu, base_p, 5000.0, 2 * base_p["d"], size.iteration_steps)
                summary.paper_iteration = PaperIteration(5000.0, 0.2, seq)
                it = np.zeros(len(seq), dtype=[("iteration", "i4"), ("B", "f8")])
                it["iteration"], it["B"] = np.arange(len(seq)), seq
                write_csv(
                    out / "paper_iteration.csv",
                    it,
                    "the paper's section-3 iteration B <- max|q| of a 0.2 s run with B fixed, 5000 rpm, base case",
                )
            extras_wall = _time.perf_counter() - t0
    finally:
        if own_runner:
            runner.close()
    stats = [c.stats for c in done]  # the branches_* timings are sums over the curves
    summary.timing = Timing(
        hb_wall,
        branches_wall,
        float(len(done)),
        float(sum(s.evaluations for s in stats)),
        float(sum(s.simulated_s for s in stats)),
        float(sum(s.fmi_s for s in stats)),
        float(sum(s.wall for s in stats)),
        extras_wall,
    )
    return rep


def _json_default(o: Any) -> Any:
    if isinstance(o, (np.floating, np.integer)):
        return o.item()
    if isinstance(o, np.bool_):
        return bool(o)
    raise TypeError(type(o).__name__)


__all__ = [
    "STUDIES",
    "SIZES",
    "Size",
    "Study",
    "Summary",
    "Reproduction",
    "reproduce",
    "run_studies",
    "write_summary",
    "settling_time",
    "paper_iteration",
]
