"""Amplitude versus rotor speed: time-domain sweeps, the paper's fixed point, harmonic balance.

Three ways to get the response curve of one parameter set (MODEL.md sections 4-5):
- `time`: the FMU with the tracked amplitude (amplitudeMode 2). An up and a down sweep each carry
  the FMU state from one speed plateau to the next (like a run-up and a run-down test), so both
  branches of the hardening response and the jumps show. On each plateau the FMU runs until
  `harness.steady_state.analyze` finds the periodic steady state (capped at `max_time`); the
  amplitude is the FMU's `amplitude` output (max |q| over the last excitation period). The load
  phase stays continuous across plateaus. The speed grid refines itself: intervals where the
  amplitude changes by more than `refine_tol` of the curve's maximum, and the two intervals around
  the peak, are bisected (down to `min_dn`); the chain is then repaired downstream of each new
  point until it agrees with the old one again.
- `fixed`: the paper's procedure done properly: at each speed the FMU runs with a fixed B
  (amplitudeMode 1) to its steady state, A(B) = max |q|, and every root of A(B) = B is bracketed
  on a scan of B over (d, B_max] and refined by brentq (plus the open root B = A <= d).
- `hb`: harmonic balance from the independent reference (`harness.reference.harmonic_balance`):
  every branch, with stability.
Every plateau and every A(B) is cached on disk under its key (FMU hash, parameters, speed, start
state), so an interrupted sweep resumes without recomputing; tasks run on `executor.Runner`.
"""
from __future__ import annotations

import atexit
import hashlib
import math
import threading
import time as _time
from dataclasses import asdict, dataclass, field, replace
from pathlib import Path
from typing import Any, Iterable, Mapping, Sequence

import numpy as np

from harness import params as _params
from harness.executor import PointCache, Runner, decode_bytes, encode_bytes, point_key

ALGO_VERSION = 2  # bump when a change alters cached point results
MAX_RPM = 30000.0  # rotorSpeed range of the FMU (modelDescription.xml)
DIRECTIONS = ("up", "down")
METHODS = ("time", "fixed", "hb")
TIME_OUTPUTS = ["tipDisplacement", "amplitude"]


class ConfigError(_params.ParameterError):
    """A sweep/study configuration value is not acceptable; the message names it."""


# ---------------------------------------------------------------------------------------------
# Configuration
# ---------------------------------------------------------------------------------------------
@dataclass(frozen=True)
class SweepSettings:
    """How each point is computed (all of it enters the cache key of a point)."""

    steps_per_period: int = 8  # communication steps per excitation period (order-8 inputs: the
    # load's Taylor error (2 pi/8)^9/9! = 3e-7; >= 8 so that analyze() works on the raw samples)
    derivative_order: int = 8  # input derivative order set per step (0 = held inputs)
    rtol: float = 1e-2  # steady-state tolerance of harness.steady_state.analyze (conservative)
    min_periods: int = 3  # converged periods needed
    chunk_periods: int = 100  # periods simulated between two steady-state checks
    max_time: float = 1.0  # cap of simulated time per plateau / per A(B) evaluation [s]
    # grid refinement (time-domain sweeps)
    refine_levels: int = 4  # bisection rounds
    refine_tol: float = 0.08  # refine where |dA| > refine_tol * max A of the curve
    min_dn: float = 15.0  # smallest speed interval produced by bisection [rpm]
    agree_tol: float = 0.02  # chain repair stops when a recomputed point agrees within this
    # fixed point
    n_scan: int = 12  # B values scanned over (d, B_max]
    B_max: float | None = None  # [m]; None: 1.5 x the linear bound G Fw0 / (C0 omega)
    fixed_max_time: float = 0.6  # cap per A(B) evaluation [s] (contact damping settles it fast)

    def plateau_key(self) -> dict:
        return {k: getattr(self, k) for k in ("steps_per_period", "derivative_order", "rtol",
                                              "min_periods", "chunk_periods", "max_time")}

    def fixed_key(self) -> dict:
        return {k: getattr(self, k) for k in ("steps_per_period", "derivative_order", "rtol",
                                              "min_periods", "chunk_periods", "fixed_max_time")}


@dataclass(frozen=True)
class SweepSpec:
    """One response curve: a parameter set, a coarse speed grid, directions and methods."""

    params: Mapping[str, Any]
    speeds: Sequence[float]  # coarse grid [rpm]
    label: str = ""
    directions: Sequence[str] = DIRECTIONS
    methods: Sequence[str] = ("time", "hb")
    fixed_speeds: Sequence[float] | None = None  # speeds for `fixed` (default: `speeds`)
    hb_speeds: Sequence[float] | None = None  # speeds for `hb` (default: 200 over the range)
    settings: SweepSettings = SweepSettings()


def _num(name: str, value: Any, low: float | None = None, high: float | None = None,
         low_open: bool = False, integer: bool = False) -> float:
    try:
        v = float(value)
    except (TypeError, ValueError):
        raise ConfigError(f"{name} = {value!r} is not a number") from None
    if not math.isfinite(v):
        raise ConfigError(f"{name} = {value!r} is not finite")
    if integer and not v.is_integer():
        raise ConfigError(f"{name} = {value!r} must be an integer")
    if low is not None and (v < low or (low_open and v == low)):
        raise ConfigError(f"{name} = {value!r} must be {'>' if low_open else '>='} {low:g}")
    if high is not None and v > high:
        raise ConfigError(f"{name} = {value!r} must be <= {high:g}")
    return v


def _check_speeds(name: str, speeds: Any, label: str, at_least: int = 1) -> tuple[float, ...]:
    try:
        vals = [float(s) for s in speeds]
    except (TypeError, ValueError):
        raise ConfigError(f"{label}{name} = {speeds!r} must be a list of speeds in rpm") from None
    for s in vals:
        if not math.isfinite(s) or not 0 < s <= MAX_RPM:
            raise ConfigError(f"{label}{name} contains {s!r} rpm: every speed must be in (0, {MAX_RPM:g}] rpm")
    out = tuple(sorted(set(vals)))
    if len(out) < at_least:
        raise ConfigError(f"{label}{name} has {len(out)} distinct speed(s); a sweep needs at least {at_least}")
    return out


def validate_settings(s: SweepSettings) -> SweepSettings:
    # analyze() needs >= 8 samples per period (fewer: spline end effects keep it from converging)
    _num("steps_per_period", s.steps_per_period, 8, 4096, integer=True)
    _num("derivative_order", s.derivative_order, 0, 8, integer=True)
    _num("rtol", s.rtol, 0, 0.1, low_open=True)
    _num("min_periods", s.min_periods, 1, 1000, integer=True)
    _num("chunk_periods", s.chunk_periods, 1, 100000, integer=True)
    _num("max_time", s.max_time, 0, 1e4, low_open=True)
    _num("refine_levels", s.refine_levels, 0, 20, integer=True)
    _num("refine_tol", s.refine_tol, 0, 1, low_open=True)
    _num("min_dn", s.min_dn, 0, MAX_RPM, low_open=True)
    _num("agree_tol", s.agree_tol, 0, 1, low_open=True)
    _num("n_scan", s.n_scan, 3, 10000, integer=True)
    _num("fixed_max_time", s.fixed_max_time, 0, 1e4, low_open=True)
    if s.B_max is not None:
        _num("B_max", s.B_max, 0, 1.0, low_open=True)
    if s.derivative_order < 8 and s.steps_per_period < 64:
        # Held or low-order inputs need small steps: Taylor error (omega h)^(k+1)/(k+1)!.
        err = (2 * math.pi / s.steps_per_period) ** (s.derivative_order + 1) / math.factorial(s.derivative_order + 1)
        if err > 1e-3:
            raise ConfigError(f"steps_per_period = {s.steps_per_period} with derivative_order = "
                              f"{s.derivative_order} misrepresents the load (Taylor error {err:.2g} > 1e-3): "
                              "use more steps per period or derivative order 8")
    return s


def validate_spec(spec: SweepSpec) -> SweepSpec:
    """Check everything before any work starts; returns a normalised copy. Raises ConfigError or
    ParameterError naming the bad value."""
    label = f"{spec.label}: " if spec.label else ""
    p = _params.validate(spec.params, source=spec.label or "sweep configuration")
    if p["engineOrder"] < 1:
        raise ConfigError(f"{label}engineOrder = {p['engineOrder']} must be >= 1")
    methods = tuple(spec.methods)
    for m in methods:
        if m not in METHODS:
            raise ConfigError(f"{label}method {m!r} is unknown; choose from {', '.join(METHODS)}")
    if not methods:
        raise ConfigError(f"{label}no method given; choose from {', '.join(METHODS)}")
    dirs = tuple(spec.directions)
    for d in dirs:
        if d not in DIRECTIONS:
            raise ConfigError(f"{label}direction {d!r} is unknown; choose from up, down")
    if "time" in methods and not dirs:
        raise ConfigError(f"{label}a time-domain sweep needs a direction (up, down)")
    speeds = _check_speeds("speeds", spec.speeds, label, at_least=2 if "time" in methods else 1)
    fixed = None if spec.fixed_speeds is None else _check_speeds("fixed_speeds", spec.fixed_speeds, label)
    hb = None if spec.hb_speeds is None else _check_speeds("hb_speeds", spec.hb_speeds, label)
    settings = validate_settings(spec.settings)
    return replace(spec, params=p, speeds=speeds, directions=dirs, methods=methods, fixed_speeds=fixed,
                   hb_speeds=hb, settings=settings)


def parse_speed_range(text: str) -> tuple[float, ...]:
    """'2000:10000:250' (start:stop:step, stop included) or '3000,5000,7000' -> speeds [rpm]."""
    try:
        if ":" in text:
            a, b, c = (float(x) for x in text.split(":"))
            if not (c > 0 and b >= a):
                raise ValueError
            n = int(math.floor((b - a) / c + 1e-9))
            return tuple(a + c * np.arange(n + 1))
        return tuple(float(x) for x in text.split(",") if x.strip())
    except ValueError:
        raise ConfigError(f"speed range {text!r}: use start:stop:step (e.g. 2000:10000:250) or a "
                          "comma list (e.g. 3000,5000,7000), in rpm") from None


# ---------------------------------------------------------------------------------------------
# FMU access inside a worker
# ---------------------------------------------------------------------------------------------
_LOCAL = threading.local()


def worker_fmu(path: str) -> Any:
    """One BladeFMU per worker (process or thread), created on first use, reset per run."""
    fmus = getattr(_LOCAL, "fmus", None)
    if fmus is None:
        fmus = _LOCAL.fmus = {}
    if path not in fmus:
        from harness.fmu import BladeFMU

        fmu = BladeFMU(path)
        fmu.__enter__()
        atexit.register(fmu.__exit__, None, None, None)
        fmus[path] = fmu
    return fmus[path]


_HASHES: dict[str, str] = {}


def fmu_identity(path: str | Path | None = None) -> tuple[str, str]:
    """(path, sha256 of the FMU file): the hash enters every cache key (a rebuilt FMU is new)."""
    if path is None:
        from harness.fmu import fmu_path

        path = fmu_path(build=True)
    path = str(Path(path).resolve())
    st = Path(path).stat()
    tag = f"{path}:{st.st_mtime_ns}:{st.st_size}"
    if tag not in _HASHES:
        _HASHES[tag] = hashlib.sha256(Path(path).read_bytes()).hexdigest()
    return path, _HASHES[tag]


# ---------------------------------------------------------------------------------------------
# Signals
# ---------------------------------------------------------------------------------------------
class PhasedSine:
    """f(t) = amplitude sin(phase + omega (t - t0)): the aero load on one constant-speed plateau,
    continuing the phase of the previous plateau (MODEL.md eq. 17 with a piecewise-constant n)."""

    breakpoints = np.zeros(0)

    def __init__(self, amplitude: float, omega: float, phase: float, t0: float):
        self.amplitude, self.omega, self.phase, self.t0 = float(amplitude), float(omega), float(phase), float(t0)

    def __call__(self, t):
        return self.amplitude * np.sin(self.phase + self.omega * (np.asarray(t, dtype=float) - self.t0))

    def derivatives(self, t, order: int) -> np.ndarray:
        x = self.phase + self.omega * (np.atleast_1d(np.asarray(t, dtype=float)) - self.t0)
        return np.array([self.amplitude * self.omega ** j * np.sin(x + j * math.pi / 2) for j in range(order + 1)])


def omega_of(params: Mapping[str, Any], speed: float) -> float:
    """Excitation circular frequency omega = engineOrder * 2 pi n / 60 [rad/s]."""
    return params["engineOrder"] * 2.0 * math.pi * speed / 60.0


# ---------------------------------------------------------------------------------------------
# One plateau of a time-domain sweep (tracked amplitude)
# ---------------------------------------------------------------------------------------------
@dataclass(frozen=True)
class Start:
    """Where a plateau starts: fresh (state None, at rest at t = 0) or a saved FMU state."""

    state: bytes | None = None
    time: float = 0.0  # [s]
    phase: float = 0.0  # aero load phase at `time` [rad], in [0, 2 pi)

    def key(self) -> Any:
        if self.state is None:
            return "rest"
        return [hashlib.sha256(self.state).hexdigest(), self.time, self.phase]


def _settle(fmu: Any, params: dict, speed: float, start: Start, s: SweepSettings, cap: float,
            outputs: list[str]) -> tuple[np.ndarray, Any, float, float]:
    """Run chunks at constant `speed` from `start` until analyze() finds the steady state or
    `cap` seconds are simulated. Returns (samples of the plateau, SteadyState, t_end, phase_end)."""
    from harness.steady_state import analyze

    omega = omega_of(params, speed)
    period = 2.0 * math.pi / omega
    h = period / s.steps_per_period
    aero = PhasedSine(params["Fw0"], omega, start.phase, start.time)
    if start.state is not None:
        from harness.fmu import FMUState

        st = FMUState(start.state)
        st.time, st.params = start.time, dict(params)
        fmu.set_state(st)
    t = start.time
    chunks: list[np.ndarray] = []
    spp = s.steps_per_period
    n_chunk = s.chunk_periods * spp
    n_cap = max(int(math.ceil(cap / period - 1e-9)), s.min_periods + 2) * spp  # whole periods
    n_done = 0
    window = (3 * s.min_periods + 4) * spp
    ss = None
    first = True
    while n_done < n_cap:
        n = min(n_chunk, n_cap - n_done)
        t_stop = start.time + (n_done + n) * h
        fresh = first and start.state is None
        # reset=False continues with the parameters already in the FMU (None: no re-validation)
        res = fmu.run(params if fresh else None, t_stop, h, aero=aero, speed=float(speed), outputs=outputs,
                      derivative_order=s.derivative_order, start_time=t, reset=fresh)
        if not first and len(res) and abs(res["time"][0] - t) <= 1e-12 * max(1.0, abs(t)):
            res = res[1:]  # the chunk's first row repeats the previous chunk's last one
        chunks.append(res)
        first = False
        n_done += n
        t = float(res["time"][-1])
        if n_done < (s.min_periods + 1) * spp:
            continue
        data = np.concatenate(chunks)
        # Cheap necessary condition first: analyze() needs the period maximum to change by less
        # than rtol over the last min_periods periods (with 2x slack for its spline refinement).
        last = np.abs(data["tipDisplacement"][-(s.min_periods + 1) * spp:]).reshape(s.min_periods + 1, spp)
        pm = last.max(axis=1)
        if np.max(np.abs(np.diff(pm))) > 2 * s.rtol * max(float(pm.max()), 1e-300):
            continue
        w = data[-(window + 1):]  # decide on the last periods only; the full record is analysed once
        ss = analyze(w["time"], w["tipDisplacement"], period, rtol=s.rtol, min_periods=s.min_periods)
        if ss.reached:
            break
    data = np.concatenate(chunks)
    if ss is not None and ss.reached:
        ss_full = analyze(data["time"], data["tipDisplacement"], period, rtol=s.rtol, min_periods=s.min_periods)
        if ss_full.reached:
            ss = ss_full  # same verdict, t_steady from the whole plateau
    else:
        w = data[-(window + 1):]
        ss = analyze(w["time"], w["tipDisplacement"], period, rtol=s.rtol, min_periods=s.min_periods)
    phase = (start.phase + omega * (t - start.time)) % (2.0 * math.pi)
    return data, ss, t, phase


def plateau(fmu: Any, cache: PointCache, fmu_hash: str, params: dict, speed: float, start: Start,
            s: SweepSettings) -> dict:
    """Steady state of the tracked-amplitude model at `speed` from `start` (cached)."""
    key = point_key(kind="plateau", v=ALGO_VERSION, fmu=fmu_hash, params=params, speed=speed,
                    start=start.key(), settings=s.plateau_key())
    rec = cache.get(key)
    if rec is not None:
        rec["cached"] = True
        return rec
    p = dict(params, amplitudeMode=2)
    t0 = _time.perf_counter()
    data, ss, t_end, phase = _settle(fmu, p, speed, start, s, s.max_time, TIME_OUTPUTS)
    window = (3 * s.min_periods + 4) * s.steps_per_period
    state = fmu.get_state()
    rec = {
        "key": key, "speed": float(speed), "amplitude": float(data["amplitude"][-1]),
        "amp_lo": float(np.min(data["amplitude"][-window:])), "amp_hi": float(np.max(data["amplitude"][-window:])),
        "amp_samples": float(ss.amplitude), "amp_h1": float(ss.harmonic_amplitude),
        "reached": bool(ss.reached), "rel_change": float(ss.rel_change),
        "t_settle": float(ss.t_steady - start.time) if ss.reached else math.nan,
        "sim_time": float(t_end - start.time), "contact": int(data["amplitude"][-1] > params["d"]),
        "t_end": t_end, "phase_end": phase, "state": encode_bytes(state),
        "wall": _time.perf_counter() - t0, "steps": int(len(data) - 1), "message": ss.message,
    }
    cache.put(key, rec)
    rec["cached"] = False
    return rec


def _start_after(rec: dict) -> Start:
    return Start(decode_bytes(rec["state"]), rec["t_end"], rec["phase_end"])


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


def _regular(r: dict) -> bool:
    """The period amplitude stays within 5 % over the final window (steady or slowly settling);
    otherwise the response is irregular (quasi-periodic/chaotic impacts) and its amplitude is a band."""
    return r["amp_hi"] - r["amp_lo"] <= 0.05 * r["amp_hi"]


def _overlap(a: dict, b: dict) -> bool:
    return a["amp_lo"] <= b["amp_hi"] and b["amp_lo"] <= a["amp_hi"]


def _refine_marks(recs: list[dict], s: SweepSettings) -> set[int]:
    """Intervals to bisect: the envelope (amp_hi) changes by more than refine_tol of its maximum
    and the two ends are not the same irregular band; plus the two intervals around a regular peak."""
    amps = np.array([r["amp_hi"] for r in recs])
    scale = float(np.max(amps)) if len(amps) else 0.0
    marks: set[int] = set()
    if scale <= 0:
        return marks
    for i in range(len(recs) - 1):
        a, b = recs[i], recs[i + 1]
        if abs(b["speed"] - a["speed"]) < 2 * s.min_dn:
            continue
        same_band = not _regular(a) and not _regular(b) and _overlap(a, b)
        if abs(amps[i + 1] - amps[i]) > s.refine_tol * scale and not same_band:
            marks.add(i)
    k = int(np.argmax(amps))
    if _regular(recs[k]):
        for i in (k - 1, k):
            if 0 <= i < len(recs) - 1 and abs(recs[i + 1]["speed"] - recs[i]["speed"]) >= 2 * s.min_dn:
                marks.add(i)
    return marks


def _agree(a: dict, b: dict, s: SweepSettings) -> bool:
    """Same branch: two regular points within agree_tol, or two irregular bands that overlap."""
    if _regular(a) and _regular(b):
        scale = max(abs(a["amp_hi"]), abs(b["amp_hi"]), 1e-300)
        return abs(a["amp_hi"] - b["amp_hi"]) <= s.agree_tol * scale
    return not _regular(a) and not _regular(b) and _overlap(a, b)


def run_chain(task: ChainTask) -> list[dict]:
    """Up or down sweep over task.speeds carrying the FMU state, refined; records in speed order
    of the sweep (without the state blobs)."""
    fmu = worker_fmu(task.fmu_path)
    cache = PointCache(None if task.cache_dir is None else Path(task.cache_dir))
    s = task.settings

    def point(speed: float, prev: dict | None) -> dict:
        start = Start() if prev is None else _start_after(prev)
        return plateau(fmu, cache, task.fmu_hash, task.params, speed, start, s)

    recs: list[dict] = []
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
                mid = 0.5 * (recs[i]["speed"] + recs[i + 1]["speed"])
                prev = point(mid, prev)
                new.append(prev)
                dirty = True
            old = recs[i + 1]
            if dirty:
                redo = point(old["speed"], prev)
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
    out = []
    for r in recs:
        r = {k: v for k, v in r.items() if k != "state"}
        r["direction"] = task.direction
        out.append(r)
    return out


# ---------------------------------------------------------------------------------------------
# The paper's fixed point A(B) = B at one speed
# ---------------------------------------------------------------------------------------------
@dataclass(frozen=True)
class FixedPointTask:
    params: dict
    speed: float
    settings: SweepSettings
    fmu_path: str
    fmu_hash: str
    cache_dir: str | None


FIXED_OUTPUTS = ["tipDisplacement", "tipVelocity", "amplitude"]


def hermite_max_abs(t: np.ndarray, q: np.ndarray, v: np.ndarray) -> float:
    """max |q| of the piecewise cubic Hermite interpolant through (t, q, q') (exact stationary points)."""
    h = np.diff(t)
    q0, q1, m0, m1 = q[:-1], q[1:], v[:-1] * h, v[1:] * h
    # p(s) = q0 + m0 s + (3(q1-q0) - 2 m0 - m1) s^2 + (2(q0-q1) + m0 + m1) s^3,  p'(s) = 0
    c2 = 3 * (q1 - q0) - 2 * m0 - m1
    c3 = 2 * (q0 - q1) + m0 + m1
    A, B, C = 3 * c3, 2 * c2, m0
    best = float(np.max(np.abs(q)))
    disc = B * B - 4 * A * C
    ok = disc >= 0
    sq = np.sqrt(np.where(ok, disc, 0.0))
    with np.errstate(divide="ignore", invalid="ignore"):
        lin = np.abs(A) < 1e-300
        r1 = np.where(lin, -C / np.where(B == 0, np.inf, B), (-B + sq) / (2 * A))
        r2 = np.where(lin, np.nan, (-B - sq) / (2 * A))
    for r in (r1, r2):
        sel = ok & np.isfinite(r) & (r > 0) & (r < 1)
        if np.any(sel):
            s_ = r[sel]
            val = q0[sel] + m0[sel] * s_ + c2[sel] * s_ ** 2 + c3[sel] * s_ ** 3
            best = max(best, float(np.max(np.abs(val))))
    return best


def amplitude_for(fmu: Any, cache: PointCache, fmu_hash: str, params: dict, speed: float, B: float,
                  s: SweepSettings, cap_factor: float = 1.0) -> dict:
    """A(B): steady max |q| of the FMU with the amplitude fixed at B (amplitudeMode 1), from rest.
    Also `peak_all`: max |q| over the whole run, transient included (Hermite-refined)."""
    key = point_key(kind="A(B)", v=ALGO_VERSION, fmu=fmu_hash, params=params, speed=speed, B=B,
                    settings=s.fixed_key(), cap_factor=cap_factor)
    rec = cache.get(key)
    if rec is not None:
        return rec
    p = dict(params, amplitudeMode=1, B=float(B))
    t0 = _time.perf_counter()
    data, ss, t_end, _ = _settle(fmu, p, speed, Start(), s, s.fixed_max_time * cap_factor, FIXED_OUTPUTS)
    rec = {"B": float(B), "A": float(ss.amplitude), "A_h1": float(ss.harmonic_amplitude),
           "reached": bool(ss.reached), "rel_change": float(ss.rel_change), "sim_time": t_end,
           "peak_all": hermite_max_abs(data["time"], data["tipDisplacement"], data["tipVelocity"]),
           "wall": _time.perf_counter() - t0, "message": ss.message}
    cache.put(key, rec)
    return rec


def linear_bound(params: Mapping[str, Any], speed: float) -> float:
    """G Fw0 / (C0 omega) [m]: the contact-free resonant amplitude bound at this speed."""
    from harness.reference import galerkin

    g = galerkin(params, params["formulation"])
    return g.loadGain * params["Fw0"] / (g.C0 * omega_of(params, speed))


def run_fixed_point(task: FixedPointTask) -> dict:
    """All roots of A(B) = B at one speed: the open root (B <= d) and every sign change of A(B) - B
    on a geometric scan of (d, B_max], refined by brentq. Non-converged evaluations are reported."""
    from scipy.optimize import brentq

    fmu = worker_fmu(task.fmu_path)
    cache = PointCache(None if task.cache_dir is None else Path(task.cache_dir))
    s, p, sp = task.settings, task.params, task.speed
    d = float(p["d"])
    evals: list[dict] = []

    def A(B: float, cap_factor: float = 1.0) -> dict:
        r = amplitude_for(fmu, cache, task.fmu_hash, p, sp, B, s, cap_factor)
        evals.append(r)
        return r

    roots: list[dict] = []
    B_max = s.B_max if s.B_max is not None else 1.5 * linear_bound(p, sp)
    # B <= d: regime open, the contact-free response; lightly damped (tau = 2M/C0 ~ 0.2 s), so it
    # gets at least 2 s (transient down to ~1e-4 of its start)
    open_run = A(0.5 * d, max(1.0, 2.0 / s.fixed_max_time)) if d > 0 else None
    if open_run is not None and open_run["A"] <= d:
        roots.append({"B": open_run["A"], "kind": "open", "reached": open_run["reached"], "slope": 0.0})
    # With gating (and for the time-domain element, which ignores B) nothing depends on B while
    # |q| <= d: if the contact-free run from rest never reaches d (1 % margin over the Hermite
    # maximum), every run with B > d is the same run, A(B) = A(open) < B: no contact root.
    skip = open_run is not None and p["gating"] and open_run["peak_all"] * 1.01 < d
    if int(p["frictionModel"]) == 3 and not skip:
        r = A(max(2.0 * d, 1e-9))  # the element needs no B: A(B) is one constant
        if r["A"] > d:
            roots.append({"B": r["A"], "kind": "contact", "reached": r["reached"], "slope": 0.0})
        skip = True
    B_lo = d * (1 + 1e-6) if d > 0 else B_max * 1e-4
    if not skip and B_max > B_lo:
        grid = np.geomspace(B_lo, B_max, s.n_scan)
        g = [A(float(B)) for B in grid]
        for i in range(len(grid) - 1):
            ga, gb = g[i]["A"] - grid[i], g[i + 1]["A"] - grid[i + 1]
            if ga == 0.0:
                roots.append({"B": float(grid[i]), "kind": "contact", "reached": g[i]["reached"], "slope": math.nan})
            if ga * gb >= 0:
                continue
            seen: list[dict] = []

            def f(B: float) -> float:
                r = A(B)
                seen.append(r)
                return r["A"] - B

            try:
                B = brentq(f, float(grid[i]), float(grid[i + 1]), xtol=1e-3 * max(d, 1e-9), rtol=1e-3, maxiter=30)
                rB = A(B)
                # A(B) continuous through the root, or a jump of A(B) across the diagonal?
                kind = "contact" if abs(rB["A"] - B) <= 0.02 * B else "jump"
                ok = all(r["reached"] for r in seen) and g[i]["reached"] and g[i + 1]["reached"]
            except (RuntimeError, ValueError):
                B, ok, kind = 0.5 * (grid[i] + grid[i + 1]), False, "jump"
            slope = ((g[i + 1]["A"] - g[i]["A"]) / (grid[i + 1] - grid[i]))
            roots.append({"B": float(B), "kind": kind, "reached": bool(ok), "slope": float(slope)})
    return {"speed": float(sp), "roots": roots, "n_evals": len(evals),
            "all_reached": all(r["reached"] for r in evals), "B_max": float(B_max)}


# ---------------------------------------------------------------------------------------------
# Harmonic balance (reference)
# ---------------------------------------------------------------------------------------------
def hb_curve(params: Mapping[str, Any], speeds: Iterable[float]) -> np.ndarray:
    """Every harmonic-balance solution at each speed: rows (speed, B, stable, phase)."""
    from harness.reference import harmonic_balance

    sp = np.asarray(list(speeds), dtype=float)
    rows = []
    for s, sols in zip(sp, harmonic_balance(params, sp) if len(sp) else []):
        for sol in sols:
            rows.append((float(s), float(sol.B), bool(sol.stable), float(sol.phase)))
    return np.array(rows, dtype=[("speed", "f8"), ("B", "f8"), ("stable", "?"), ("phase", "f8")])


# ---------------------------------------------------------------------------------------------
# Whole sweeps
# ---------------------------------------------------------------------------------------------
TIME_DTYPE = [("speed", "f8"), ("direction", "U4"), ("amplitude", "f8"), ("amp_lo", "f8"), ("amp_hi", "f8"),
              ("amp_h1", "f8"), ("rel_change", "f8"),
              ("reached", "?"), ("t_settle", "f8"), ("sim_time", "f8"), ("contact", "i4")]
FIXED_DTYPE = [("speed", "f8"), ("B", "f8"), ("kind", "U7"), ("reached", "?"), ("slope", "f8")]


@dataclass
class SweepResult:
    spec: SweepSpec
    time: np.ndarray = field(default_factory=lambda: np.zeros(0, dtype=TIME_DTYPE))
    fixed: np.ndarray = field(default_factory=lambda: np.zeros(0, dtype=FIXED_DTYPE))
    hb: np.ndarray = field(default_factory=lambda: np.zeros(0, dtype=[("speed", "f8"), ("B", "f8"), ("stable", "?"), ("phase", "f8")]))
    fixed_speeds_failed: int = 0
    stats: dict = field(default_factory=dict)

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


def _fixed_refinement(specs: Sequence[SweepSpec], fixed: list, fixed_out: list, level: int) -> list:
    """Bisect the speed intervals next to each curve's largest fixed point where the largest root
    changes by more than refine_tol of it (the narrow low-kn peak falls between coarse speeds)."""
    extra = []
    for i, sp in enumerate(specs):
        s = sp.settings
        if level >= s.refine_levels:
            continue
        pts = sorted((o["speed"], max([r["B"] for r in o["roots"] if r["kind"] != "jump"], default=0.0))
                     for (j, _), o in zip(fixed, fixed_out) if j == i)
        if len(pts) < 2:
            continue
        speeds, amps = [x for x, _ in pts], [a for _, a in pts]
        k = int(np.argmax(amps))
        task0 = next(t for (j, t) in fixed if j == i)
        for a, b in ((k - 1, k), (k, k + 1)):
            if a < 0 or b >= len(pts) or speeds[b] - speeds[a] < 2 * s.min_dn:
                continue
            if abs(amps[b] - amps[a]) > s.refine_tol * amps[k]:
                extra.append((i, replace(task0, speed=0.5 * (speeds[a] + speeds[b]))))
    return extra


def run_sweeps(specs: Sequence[SweepSpec], runner: Runner | None = None, *, fmu_path: str | Path | None = None,
               cache_dir: str | Path | None = None, desc: str = "") -> list[SweepResult]:
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
            for s in (sp.fixed_speeds or sp.speeds):
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
        extra = _fixed_refinement(specs, fixed, fixed_out, level)
        if not extra:
            break
        fixed_out += runner.map(run_fixed_point, [t for _, t in extra], desc=f"{prefix}fixed points, refined",
                                unit="speed")
        fixed += extra
    t_fixed = _time.perf_counter() - t0
    per_spec_time: dict[int, list] = {}
    for (i, _), recs in zip(chains, chain_out):
        per_spec_time.setdefault(i, []).extend(recs)
    for i, recs in per_spec_time.items():
        results[i].time = np.array(
            [(r["speed"], r["direction"], r["amplitude"], r["amp_lo"], r["amp_hi"], r["amp_h1"], r["rel_change"],
              r["reached"], r["t_settle"],
              r["sim_time"], r["contact"]) for r in recs], dtype=TIME_DTYPE)
        results[i].stats["plateaus"] = len(recs)
        results[i].stats["sim_time"] = float(sum(r["sim_time"] for r in recs))
        results[i].stats["not_reached"] = int(sum(not r["reached"] for r in recs))
    per_spec_fixed: dict[int, list] = {}
    for (i, _), out in zip(fixed, fixed_out):
        per_spec_fixed.setdefault(i, []).append(out)
    for i, outs in per_spec_fixed.items():
        rows = [(o["speed"], r["B"], r["kind"], r["reached"], r["slope"]) for o in outs for r in o["roots"]]
        results[i].fixed = np.array(rows, dtype=FIXED_DTYPE)
        results[i].fixed_speeds_failed = int(sum(not o["all_reached"] for o in outs))
        results[i].stats["fixed_evals"] = int(sum(o["n_evals"] for o in outs))
    for r in results:
        r.stats.update({"wall_hb_all": t_hb, "wall_time_all": t_time, "wall_fixed_all": t_fixed})
    return results


def sweep(spec: SweepSpec, runner: Runner | None = None, **kw: Any) -> SweepResult:
    """One curve; see `run_sweeps`."""
    return run_sweeps([spec], runner, **kw)[0]


__all__ = ["ConfigError", "SweepSettings", "SweepSpec", "SweepResult", "validate_spec", "sweep",
           "run_sweeps", "run_chain", "run_fixed_point", "hb_curve", "parse_speed_range", "PhasedSine",
           "asdict"]
