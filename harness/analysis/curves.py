"""Amplitude versus rotor speed: time-domain sweeps, the paper's fixed point, harmonic balance.

Three ways to get the response curve of one parameter set (docs/model.md sections 4-5):
- `time`: the FMU with the tracked amplitude (amplitudeMode 2). An up and a down sweep each carry
  the FMU state from one speed plateau to the next (like a run-up and a run-down test), so both
  branches of the hardening response and the jumps show. On each plateau the FMU runs until
  `harness.analysis.steady_state.analyze` finds the periodic steady state (capped at `max_time`); the
  amplitude is the FMU's `amplitude` output (max |q| over the last excitation period). The load
  phase stays continuous across plateaus. The speed grid refines itself: intervals where the
  amplitude changes by more than `refine_tol` of the curve's maximum, and the two intervals around
  the peak, are bisected (down to `min_dn`); the chain is then repaired downstream of each new
  point until it agrees with the old one again.
- `fixed`: the paper's procedure done properly: at each speed the FMU runs with a fixed B
  (amplitudeMode 1) to its steady state, A(B) = max |q|, and every root of A(B) = B is bracketed
  on a scan of B over (d, B_max] and refined by brentq (plus the open root B = A <= d).
- `hb`: harmonic balance (`harness.analysis.harmonic_balance`):
  every branch, with stability.
Every plateau and every A(B) is cached on disk under its key (FMU hash, parameters, speed, start
state), so an interrupted sweep resumes without recomputing; tasks run on `executor.Runner`. A
chain returns PlateauPoint records, a fixed-point speed a FixedPointResult
(harness.analysis.fixed_point); `run_sweeps` collects them into a SweepResult's tables and SweepStats.
"""

from __future__ import annotations

import math
import time as _time
from dataclasses import asdict, dataclass, field, replace
from pathlib import Path
from typing import Any, Iterable, Mapping, Sequence

import numpy as np
from scipy.optimize import minimize_scalar

from harness.analysis.cache import PointCache, decode_bytes, encode_bytes, point_key
from harness.analysis.executor import Runner
from harness.analysis.plateau import PLATEAU_OUTPUTS, PhasedSine, Start, fmu_identity, omega_of, settle  # noqa: F401
from harness.analysis.harmonic_balance import harmonic_balance
from harness.analysis.config import (
    ALGO_VERSION,
    DIRECTIONS,  # noqa: F401
    MAX_RPM,  # noqa: F401
    METHODS,  # noqa: F401
    ConfigError,  # noqa: F401
    SweepSettings,
    SweepSpec,
    parse_speed_range,
    validate_settings,  # noqa: F401
    validate_spec,
)
from harness.analysis.fixed_point import FixedPointResult, FixedPointTask, fixed_refinement, run_fixed_point
from harness.fmu.pool import worker_fmu


@dataclass(frozen=True)
class PlateauPoint:
    """The steady state of the tracked-amplitude model on one speed plateau: one point of a
    time-domain sweep. The point cache stores its fields but `cached` and `direction`."""

    key: str  # its cache key
    speed: float  # [rpm]
    amplitude: float  # [m] the FMU's `amplitude` output at the end (max |q| of the last period)
    amp_lo: float  # [m] smallest period amplitude over the final window
    amp_hi: float  # [m] largest period amplitude over the final window
    amp_h1: float  # [m] first-harmonic amplitude of the steady-state analysis
    reached: bool  # periodic steady state found (else the run stopped at the cap)
    rel_change: float  # estimated relative distance from the periodic limit
    t_settle: float  # [s] from the plateau's start to the steady state (nan: not reached)
    sim_time: float  # [s] simulated on the plateau
    contact: int  # 1 if the final amplitude exceeds the gap d
    t_end: float  # [s] FMU time at the end
    phase_end: float  # [rad] load phase at the end
    state: str  # the FMU state at the end, serialized and base64-encoded ("" in run_chain's output)
    wall: float  # [s] wall time of the computation
    steps: int  # periods sampled
    message: str  # of the steady-state analysis
    cached: bool = False  # read from the cache
    direction: str = ""  # up | down (set by run_chain)

    def cache_record(self) -> dict[str, Any]:
        rec = asdict(self)
        del rec["cached"], rec["direction"]
        return rec


def plateau(
    fmu: Any, cache: PointCache, fmu_hash: str, params: dict, speed: float, start: Start, s: SweepSettings
) -> PlateauPoint:
    """Steady state of the tracked-amplitude model at `speed` from `start` (cached)."""
    key = point_key(
        kind="plateau",
        v=ALGO_VERSION,
        fmu=fmu_hash,
        params=params,
        speed=speed,
        start=start.key(),
        settings=s.plateau_key(),
    )
    rec = cache.get(key)
    if rec is not None:
        return PlateauPoint(**rec, cached=True)
    p = dict(params, amplitudeMode=2)
    t0 = _time.perf_counter()
    data, ss, t_end, phase = settle(fmu, p, speed, start, s, s.max_time, list(PLATEAU_OUTPUTS))
    window = 3 * s.min_periods + 4  # periods (settle samples once per period)
    state = fmu.get_state()
    rec = PlateauPoint(
        key=key,
        speed=float(speed),
        amplitude=float(data["amplitude"][-1]),
        amp_lo=float(np.min(data["amplitude"][-window:])),
        amp_hi=float(np.max(data["amplitude"][-window:])),
        amp_h1=float(ss.harmonic_amplitude),
        reached=bool(ss.reached),
        rel_change=float(ss.rel_change),
        t_settle=float(ss.t_steady - start.time) if ss.reached else math.nan,
        sim_time=float(t_end - start.time),
        contact=int(data["amplitude"][-1] > params["d"]),
        t_end=t_end,
        phase_end=phase,
        state=encode_bytes(state),
        wall=_time.perf_counter() - t0,
        steps=int(len(data) - 1),
        message=ss.message,
    )
    cache.put(key, rec.cache_record())
    return rec


def _start_after(rec: PlateauPoint) -> Start:
    return Start(decode_bytes(rec.state), rec.t_end, rec.phase_end)


# ---------------------------------------------------------------------------------------------
# A chain: one direction of a time-domain sweep, with grid refinement and chain repair
# ---------------------------------------------------------------------------------------------
@dataclass(frozen=True)
class ChainTask:
    params: dict
    speeds: tuple[float, ...]  # coarse grid in sweep order
    direction: str
    settings: SweepSettings
    fmu_path: str
    fmu_hash: str
    cache_dir: str | None
    tag: str = ""  # for messages


def _regular(r: PlateauPoint) -> bool:
    """The period amplitude stays within 5 % over the final window (steady or slowly settling);
    otherwise the response is irregular (quasi-periodic/chaotic impacts) and its amplitude is a band."""
    return r.amp_hi - r.amp_lo <= 0.05 * r.amp_hi


def _overlap(a: PlateauPoint, b: PlateauPoint) -> bool:
    return a.amp_lo <= b.amp_hi and b.amp_lo <= a.amp_hi


def _refine_marks(recs: list[PlateauPoint], s: SweepSettings) -> set[int]:
    """Intervals to bisect: the envelope (amp_hi) changes by more than refine_tol of its maximum
    and the two ends are not the same irregular band; plus the two intervals around a regular peak."""
    amps = np.array([r.amp_hi for r in recs])
    scale = float(np.max(amps)) if len(amps) else 0.0
    marks: set[int] = set()
    if scale <= 0:
        return marks
    for i in range(len(recs) - 1):
        a, b = recs[i], recs[i + 1]
        if abs(b.speed - a.speed) < 2 * s.min_dn:
            continue
        same_band = not _regular(a) and not _regular(b) and _overlap(a, b)
        if abs(amps[i + 1] - amps[i]) > s.refine_tol * scale and not same_band:
            marks.add(i)
    k = int(np.argmax(amps))
    if _regular(recs[k]):
        for i in (k - 1, k):
            if 0 <= i < len(recs) - 1 and abs(recs[i + 1].speed - recs[i].speed) >= 2 * s.min_dn:
                marks.add(i)
    return marks


def _agree(a: PlateauPoint, b: PlateauPoint, s: SweepSettings) -> bool:
    """Same branch: two regular points within agree_tol, or two irregular bands that overlap."""
    if _regular(a) and _regular(b):
        scale = max(abs(a.amp_hi), abs(b.amp_hi), 1e-300)
        return abs(a.amp_hi - b.amp_hi) <= s.agree_tol * scale
    return not _regular(a) and not _regular(b) and _overlap(a, b)


def run_chain(task: ChainTask) -> list[PlateauPoint]:
    """Up or down sweep over task.speeds carrying the FMU state, refined; its points in speed order
    of the sweep (without the state blobs, with the direction)."""
    fmu = worker_fmu(task.fmu_path)
    cache = PointCache(None if task.cache_dir is None else Path(task.cache_dir))
    s = task.settings

    def point(speed: float, prev: PlateauPoint | None) -> PlateauPoint:
        start = Start() if prev is None else _start_after(prev)
        return plateau(fmu, cache, task.fmu_hash, task.params, speed, start, s)

    recs: list[PlateauPoint] = []
    prev = None
    for sp in task.speeds:
        prev = point(sp, prev)
        recs.append(prev)
    for _level in range(s.refine_levels):
        marks = _refine_marks(recs, s)
        if not marks:
            break
        new = [recs[0]]
        prev = recs[0]
        dirty = False
        for i in range(len(recs) - 1):
            if i in marks:
                mid = 0.5 * (recs[i].speed + recs[i + 1].speed)
                prev = point(mid, prev)
                new.append(prev)
                dirty = True
            old = recs[i + 1]
            if dirty:
                redo = point(old.speed, prev)
                if _agree(redo, old, s):
                    dirty = False
                    prev = old  # the old downstream chain stays valid
                    new.append(old)
                else:
                    prev = redo
                    new.append(redo)
            else:
                prev = old
                new.append(old)
        recs = new
    return [replace(r, state="", direction=task.direction) for r in recs]


# ---------------------------------------------------------------------------------------------
# Harmonic balance
# ---------------------------------------------------------------------------------------------
def hb_curve(params: Mapping[str, Any], speeds: Iterable[float]) -> np.ndarray:
    """Every harmonic-balance solution at each speed: rows (speed, B, stable, phase)."""
    sp = np.asarray(list(speeds), dtype=float)
    rows = []
    for s, sols in zip(sp, harmonic_balance(params, sp) if len(sp) else []):
        for sol in sols:
            rows.append((float(s), float(sol.B), bool(sol.stable), float(sol.phase)))
    return np.array(rows, dtype=[("speed", "f8"), ("B", "f8"), ("stable", "?"), ("phase", "f8")])


def hb_stable_peak(params: Mapping[str, Any], curve: np.ndarray) -> tuple[float, float]:
    """(B [m], speed [rpm]) of the largest stable harmonic-balance solution, located: the largest
    stable B as a function of speed, maximised by Brent's bounded search between the sampled
    neighbours of the largest stable sample of `curve` (hb_curve's rows); nan if none is stable.
    Where the stable part ends in a fold, the maximum is that fold's edge."""
    st = curve[curve["stable"]] if len(curve) else curve
    if not len(st):
        return math.nan, math.nan
    k = int(np.argmax(st["B"]))
    speeds = np.unique(curve["speed"])
    i = int(np.searchsorted(speeds, st["speed"][k]))
    lo, hi = speeds[max(i - 1, 0)], speeds[min(i + 1, len(speeds) - 1)]

    def neg_stable_B(n: float) -> float:
        return -max((s.B for s in harmonic_balance(params, n) if s.stable), default=0.0)

    r = minimize_scalar(neg_stable_B, bounds=(lo, hi), method="bounded", options={"xatol": 1e-4})
    B, n = -float(r.fun), float(r.x)
    return (B, n) if B >= st["B"][k] else (float(st["B"][k]), float(st["speed"][k]))


# ---------------------------------------------------------------------------------------------
# Whole sweeps
# ---------------------------------------------------------------------------------------------
TIME_DTYPE = [
    ("speed", "f8"),
    ("direction", "U4"),
    ("amplitude", "f8"),
    ("amp_lo", "f8"),
    ("amp_hi", "f8"),
    ("amp_h1", "f8"),
    ("rel_change", "f8"),
    ("reached", "?"),
    ("t_settle", "f8"),
    ("sim_time", "f8"),
    ("contact", "i4"),
]
FIXED_DTYPE = [("speed", "f8"), ("B", "f8"), ("kind", "U7"), ("reached", "?"), ("slope", "f8")]


@dataclass
class SweepStats:
    """What the sweeps of one spec did (zero for a method not run); the wall times are those of
    all specs' tasks of that method together [s]."""

    plateaus: int = 0  # time-domain points computed or read from the cache
    sim_time: float = 0.0  # [s] simulated on them
    not_reached: int = 0  # of them without a steady state
    fixed_evals: int = 0  # A(B) evaluations of the fixed-point speeds
    wall_hb_all: float = 0.0
    wall_time_all: float = 0.0
    wall_fixed_all: float = 0.0


@dataclass
class SweepResult:
    spec: SweepSpec
    time: np.ndarray = field(default_factory=lambda: np.zeros(0, dtype=TIME_DTYPE))
    fixed: np.ndarray = field(default_factory=lambda: np.zeros(0, dtype=FIXED_DTYPE))
    hb: np.ndarray = field(
        default_factory=lambda: np.zeros(0, dtype=[("speed", "f8"), ("B", "f8"), ("stable", "?"), ("phase", "f8")])
    )
    fixed_speeds_failed: int = 0
    stats: SweepStats = field(default_factory=SweepStats)

    def branch(self, direction: str) -> np.ndarray:
        t = self.time[self.time["direction"] == direction]
        return t[np.argsort(t["speed"])]

    def peak(self, method: str = "time") -> tuple[float, float]:
        """(speed of the largest amplitude, that amplitude) of one method (nan if no data): the
        envelope amp_hi in the time domain, fixed points without jumps, stable HB branches."""
        fixed = self.fixed[self.fixed["kind"] != "jump"] if len(self.fixed) else self.fixed
        hb = self.hb[self.hb["stable"]] if len(self.hb) else self.hb
        arr, col = {"time": (self.time, "amp_hi"), "fixed": (fixed, "B"), "hb": (hb, "B")}[method]
        if len(arr) == 0:
            return math.nan, math.nan
        i = int(np.argmax(arr[col]))
        return float(arr["speed"][i]), float(arr[col][i])


def _hb_speeds(spec: SweepSpec) -> tuple[float, ...]:
    if spec.hb_speeds is not None:
        return tuple(spec.hb_speeds)
    return tuple(np.linspace(min(spec.speeds), max(spec.speeds), 200))


def run_sweeps(
    specs: Sequence[SweepSpec],
    runner: Runner | None = None,
    *,
    fmu_path: str | Path | None = None,
    cache_dir: str | Path | None = None,
    desc: str = "",
) -> list[SweepResult]:
    """Validate every spec (before any work), then map all their tasks over `runner` at once."""
    specs = [validate_spec(sp) for sp in specs]
    runner = runner or Runner(workers=1, progress=False)
    need_fmu = any(m in sp.methods for sp in specs for m in ("time", "fixed"))
    path, fhash = fmu_identity(fmu_path) if need_fmu else ("", "")
    cdir = None if cache_dir is None else str(cache_dir)
    chains: list[tuple[int, ChainTask]] = []
    fixed: list[tuple[int, FixedPointTask]] = []
    for i, sp in enumerate(specs):
        p = dict(sp.params)
        if "time" in sp.methods:
            for d in sp.directions:
                order = tuple(sp.speeds) if d == "up" else tuple(reversed(sp.speeds))
                chains.append((i, ChainTask(p, order, d, sp.settings, path, fhash, cdir, sp.label)))
        if "fixed" in sp.methods:
            for s in sp.fixed_speeds or sp.speeds:
                fixed.append((i, FixedPointTask(p, float(s), sp.settings, path, fhash, cdir)))
    results = [SweepResult(sp) for sp in specs]
    prefix = f"{desc}: " if desc else ""
    t0 = _time.perf_counter()
    for i, sp in enumerate(specs):
        if "hb" in sp.methods:
            results[i].hb = hb_curve(sp.params, _hb_speeds(sp))
    t_hb = _time.perf_counter() - t0
    t0 = _time.perf_counter()
    chain_out = runner.map(run_chain, [t for _, t in chains], desc=f"{prefix}time-domain sweeps", unit="sweep")
    t_time = _time.perf_counter() - t0
    t0 = _time.perf_counter()
    fixed_out = runner.map(run_fixed_point, [t for _, t in fixed], desc=f"{prefix}fixed points", unit="speed")
    for level in range(max((sp.settings.refine_levels for sp in specs), default=0)):
        extra = fixed_refinement(specs, fixed, fixed_out, level)
        if not extra:
            break
        fixed_out += runner.map(
            run_fixed_point, [t for _, t in extra], desc=f"{prefix}fixed points, refined", unit="speed"
        )
        fixed += extra
    t_fixed = _time.perf_counter() - t0
    per_spec_time: dict[int, list[PlateauPoint]] = {}
    for (i, _), recs in zip(chains, chain_out):
        per_spec_time.setdefault(i, []).extend(recs)
    for i, recs in per_spec_time.items():
        results[i].time = np.array(
            [
                (
                    r.speed,
                    r.direction,
                    r.amplitude,
                    r.amp_lo,
                    r.amp_hi,
                    r.amp_h1,
                    r.rel_change,
                    r.reached,
                    r.t_settle,
                    r.sim_time,
                    r.contact,
                )
                for r in recs
            ],
            dtype=TIME_DTYPE,
        )
        results[i].stats.plateaus = len(recs)
        results[i].stats.sim_time = float(sum(r.sim_time for r in recs))
        results[i].stats.not_reached = int(sum(not r.reached for r in recs))
    per_spec_fixed: dict[int, list[FixedPointResult]] = {}
    for (i, _), out in zip(fixed, fixed_out):
        per_spec_fixed.setdefault(i, []).append(out)
    for i, outs in per_spec_fixed.items():
        rows = [(o.speed, r.B, r.kind, r.reached, r.slope) for o in outs for r in o.roots]
        results[i].fixed = np.array(rows, dtype=FIXED_DTYPE)
        results[i].fixed_speeds_failed = int(sum(not o.all_reached for o in outs))
        results[i].stats.fixed_evals = int(sum(o.n_evals for o in outs))
    for r in results:
        r.stats.wall_hb_all, r.stats.wall_time_all, r.stats.wall_fixed_all = t_hb, t_time, t_fixed
    return results


def sweep(spec: SweepSpec, runner: Runner | None = None, **kw: Any) -> SweepResult:
    """One curve; see `run_sweeps`."""
    return run_sweeps([spec], runner, **kw)[0]


__all__ = [
    "ConfigError",
    "SweepSettings",
    "SweepSpec",
    "SweepResult",
    "SweepStats",
    "PlateauPoint",
    "validate_spec",
    "sweep",
    "run_sweeps",
    "run_chain",
    "hb_curve",
    "hb_stable_peak",
    "parse_speed_range",
    "PhasedSine",
]
