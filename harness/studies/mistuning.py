"""Mistuning study of the ring over a speed band: random blade-to-blade scatter of one blade
parameter (EI, the bending stiffness, or m0, the shroud mass), relative standard deviation per
level, patterns from a seeded generator. Every (variant, pattern) is one task: the ring's forced
response at `points` speeds across the band (harness/system/ring_sweep.py), run on the Runner (local
process pool, or dask with a scheduler address) and cached in its own file (PointCache), so a
killed study resumes where it stopped.

Amplification of a pattern = max over the band of the mistuned ring's largest blade amplitude /
max over the band of the tuned ring's, both from the same sweep. The band, 0.8x to 3x the
contact-free Campbell crossing (EO n / 60 = first bending frequency, 4966 rpm at EO 3; Galerkin
reduction, harness.model.galerkin), contains the response the shroud contacts stiffen and move
upwards: swept up, the tuned 6-blade ring leaves its travelling wave between 5500 and 6000 rpm
for a localised state that grows to 4.3e-5 m near 13500 rpm and falls back to the wave (3.8e-6 m)
by 14000 rpm; swept down it reaches its largest response, 4.67e-5 m, near 6200 rpm. A point
whose ring did not settle is flagged and left out of the maxima. Compared with Whitehead's bound
(1 + sqrt(N)) / 2, a theorem for linear rings with light damping. Variants: `friction` (the contacts as given),
`frictionless` (mu = 0: the shrouds impact, no friction) and `open` (d = 1 m: the contacts never
close, the blades are uncoupled).

Numerics: each task is one sweep up and then down the band (harness/system/ring_sweep.py): the C
communication loop from rest at the lowest speed, the state carried from speed to speed (up to the
highest, then back down: the ring is multistable, and each speed keeps the larger steady state), h = T / 160
at each speed with quadratic extrapolation (error ~1e-3 of max |q| against the monolithic
reference), every blade settled when its per-period amplitude changes by less than `rtol` of the
largest over 5 periods (at most `max_time` s per speed, else flagged), and the peak located by
refinement to `speed_tol` rpm.
"""

from __future__ import annotations

import functools
import math
import time
from dataclasses import asdict, dataclass, field, replace
from pathlib import Path
from typing import Any, Sequence

from fmpy import read_model_description
import numpy as np
import numpy.typing as npt

from harness.analysis.cache import PointCache, point_key
from harness.fmu.slave import build_ring_fmus
from harness.system.engine_identity import ring_engine_digest
from harness.model.galerkin import galerkin
from harness.system.ring import Ring
from harness.system import ring_sweep
from harness.system.ring_values import settable

PARAMETERS = ("EI", "m0")  # the blade parameters a pattern scatters
# contact parameters on top of the ring's
VARIANTS = {"friction": {}, "frictionless": {"mu": 0.0}, "open": {"d": 1.0}}
CACHE_VERSION = 4  # bump when the meaning of a cached record changes (4: a sweep up and down)
CROSSING_BAND = (0.8, 3.0)  # the band, as multiples of the contact-free crossing (3973-14898 rpm at EO 3)


@dataclass(frozen=True)
class Study:
    n: int = 6
    levels: tuple[float, ...] = (0.02, 0.05)  # relative standard deviations
    patterns: int = 10
    parameter: str = "EI"
    seed: int = 1
    variants: tuple[str, ...] = ("friction",)
    points: int = 23  # speeds across the band (0.1x the crossing apart: the crossing is one of them)
    band: tuple[float, float] | None = None  # [rpm]; None: CROSSING_BAND x the contact-free crossing
    rtol: float = 1e-4  # settled: per-period change of every blade amplitude / the largest, over 5 periods
    max_time: float = 1.0  # [s] at most at one speed (decay time 2 M / C0 = 0.022 s at c = 298 N s/m2)
    speed_tol: float = 10.0  # [rpm] the peak's location
    steps_per_period: int = 160  # h = T / 160 at each speed: every period sampled at the same phases
    order: int = 2  # extrapolation order of the input derivatives
    engine_order: int = 3
    fw0: float = 300.0
    blade: dict = field(default_factory=lambda: {"c": 298.0})
    contact: dict = field(default_factory=dict)
    # on stable steady states (harness/studies/mistuning_states.py, the ring's periodic-orbit engine)
    state_patterns: int = 0  # patterns per level taken to the engine (0: the sweeps only)
    search_budget: int = 0  # rings of the worst-pattern search at the largest level (0: none)


SIZES = {
    # `make run`: 6 blades, 2 levels x 10 patterns + the tuned ring: 21 sweeps of 23 speeds; the tuned
    # ring and the first pattern of each level also on stable steady states (3 rings of the engine)
    "small": Study(state_patterns=1),
    # a cluster: 24 blades, 4 levels x 100 patterns, the frictionless and open rings too, 45 speeds
    "cluster": Study(
        n=24, levels=(0.005, 0.01, 0.02, 0.05), patterns=100, points=45, variants=("friction", "frictionless", "open")
    ),
}


def whitehead(n: int) -> float:
    """Whitehead's largest amplification of a mistuned linear ring of n blades."""
    return (1 + math.sqrt(n)) / 2


def factors(n: int, sigma: float, seed: int, index: int) -> np.ndarray:
    """Pattern `index`: 1 + sigma z, z standard normal from a generator seeded (seed, index), the
    same z at every level (common random numbers: the levels differ in sigma only)."""
    f = 1.0 + sigma * np.random.default_rng([seed, index]).standard_normal(n)
    if np.any(f <= 0):
        raise ValueError(f"mistuning level {sigma} gives a non-positive factor {f.min():g}")
    return f


def resonance_speed(blade: dict, engine_order: int) -> float:
    """Speed [rpm] where engine_order n / 60 equals the contact-free first bending frequency:
    Omega^2 (EO^2 M - K0omega2) = K0static (Galerkin reduction, harness/model/galerkin.py)."""
    g = galerkin({k: v for k, v in blade.items() if k in ("EI", "rho", "A", "l", "c", "m0", "formulation")})
    return math.sqrt(g.K0static / (engine_order**2 * g.M - g.K0omega2)) * 60 / (2 * math.pi)


def band(study: Study) -> tuple[float, float]:
    """The speed band [rpm]: the study's, or CROSSING_BAND times the contact-free crossing."""
    if study.band is not None:
        return study.band
    n0 = resonance_speed(study.blade, study.engine_order)
    return CROSSING_BAND[0] * n0, CROSSING_BAND[1] * n0


def speeds(study: Study) -> np.ndarray:
    """The `points` speeds [rpm], evenly spaced across the band."""
    return np.linspace(*band(study), study.points)


@functools.lru_cache(maxsize=None)
def _start_value(name: str) -> float:
    """The blade FMU's start value of `name` (read once per process: the build check costs 0.3 s)."""
    assert name in settable()["blade"]
    md = read_model_description(str(build_ring_fmus()[0]))
    return float(next(v.start for v in md.modelVariables if v.name == name))


def blade_value(ring: Ring, name: str) -> float:
    """The tuned value of a blade parameter (the ring's, else the FMU's start value)."""
    if name in ring.blade:
        return float(ring.blade[name])
    return _start_value(name)


def mistuned(ring: Ring, parameter: str, f: Sequence[float] | npt.NDArray[np.float64]) -> Ring:
    """`ring` with blade i's `parameter` = tuned value * f[i]."""
    if parameter not in PARAMETERS:
        raise ValueError(f"mistuned parameter {parameter!r}: one of {', '.join(PARAMETERS)}")
    base = blade_value(ring, parameter)
    return replace(ring, blade_each=tuple({parameter: base * float(x)} for x in f))


def tuned_ring(study: Study, variant: str) -> Ring:
    """The tuned ring of `variant` (the sweep sets its speed and step at each point)."""
    return Ring(
        n=study.n,
        engine_order=study.engine_order,
        speed=band(study)[0],
        fw0=study.fw0,
        blade=dict(study.blade),
        contact={**study.contact, **VARIANTS[variant]},
        order=study.order,
    )


def larger_state(sw: ring_sweep.RingSweep) -> tuple[np.ndarray, np.ndarray, np.ndarray, list[str]]:
    """Per speed, the steady state of the direction whose largest blade is larger (settled states
    before unsettled ones: the ring is multistable, and a sweep up misses what a sweep down finds):
    amplitudes, settled and movement (K x N) and the direction each speed took."""
    dirs = list(sw.amplitudes_m)
    top = np.stack([sw.amplitudes_m[d].max(axis=1) for d in dirs])  # directions x speeds
    ok = np.stack([sw.settled[d].all(axis=1) for d in dirs])
    pick = np.argmax(np.where(ok.any(axis=0), np.where(ok, top, -np.inf), top), axis=0)

    def take(field: dict) -> np.ndarray:
        return np.array([field[dirs[p]][j] for j, p in enumerate(pick)])

    return take(sw.amplitudes_m), take(sw.settled), take(sw.movement), [dirs[p] for p in pick]


def sweep(ring: Ring, speeds_rpm: Sequence[float], study: Study) -> dict:
    """The ring's forced response swept up and then down the speeds (harness/system/ring_sweep.py)
    as a JSON-able record: speeds_rpm (K); amplitudes_m, settled and movement (K x N) of the larger
    steady state at each speed and its direction; the located peak over both directions
    (peak_amplitude_m, peak_speed_rpm, peak_direction; NaN if no speed settled; peak_blades_m:
    every blade there), simulated time."""
    sw = ring_sweep.sweep(
        ring,
        speeds_rpm,
        "both",
        rtol=study.rtol,
        max_time=study.max_time,
        steps_per_period=study.steps_per_period,
        speed_tol=study.speed_tol,
    )
    amps, settled, moved, dirs = larger_state(sw)
    d = sw.peak_direction
    at_peak = [e["amplitudes_m"] for e in sw.refinement if e["direction"] == d and e["speed_rpm"] == sw.peak_speed_rpm]
    if d:
        at_peak += [a.tolist() for s, a in zip(sw.speeds_rpm, sw.amplitudes_m[d]) if s == sw.peak_speed_rpm]
    return {
        "speeds_rpm": sw.speeds_rpm.tolist(),
        "amplitudes_m": amps.tolist(),
        "settled": settled.tolist(),
        "movement": moved.tolist(),
        "direction": dirs,
        "peak_amplitude_m": float(sw.peak_amplitude_m),
        "peak_speed_rpm": float(sw.peak_speed_rpm),
        "peak_direction": d,
        "peak_at_band_edge": bool(sw.peak_at_band_edge),
        "peak_blades_m": at_peak[0] if at_peak else None,
        "simulated_s": float(sum(t.sum() for t in sw.time_at_speed_s.values())),
    }


def _task(job: tuple[Ring, list[float], Study, str, str | None]) -> dict:
    """One (variant, pattern) sweep on a worker: run, store in the cache at once (atomic file),
    return the record. A record already in the cache is returned as it is (dask recomputes a
    finished task whose result died with its worker: that costs a file read, not a sweep)."""
    ring, sp, study, key, cache_dir = job
    cache = PointCache(Path(cache_dir) if cache_dir else None)
    rec = cache.get(key)
    if rec is None:
        t0, c0 = time.perf_counter(), time.process_time()
        rec = {**sweep(ring, sp, study), "wall_s": time.perf_counter() - t0, "cpu_s": time.process_time() - c0}
        cache.put(key, rec)
    return rec


def _variant(study: Study, recs: list[tuple[int, int, dict]]) -> dict:
    """One variant's results from its (level index or -1 for tuned, pattern, sweep record)
    triples. A pattern without a settled point has no amplification (NaN); if the tuned ring has
    none, no pattern has."""
    tuned = next(r for li, _, r in recs if li == -1)
    ref = tuned["peak_amplitude_m"]
    K = len(tuned["speeds_rpm"])
    curves = np.full((len(study.levels), study.patterns, K, study.n), np.nan)
    peaks = np.full((len(study.levels), study.patterns), np.nan)
    peak_speeds = np.full_like(peaks, np.nan)
    at_peak = np.full((len(study.levels), study.patterns, study.n), np.nan)
    for li, k, r in recs:
        if li >= 0:
            curves[li, k] = r["amplitudes_m"]
            peaks[li, k], peak_speeds[li, k] = r["peak_amplitude_m"], r["peak_speed_rpm"]
            if r["peak_blades_m"] is not None:
                at_peak[li, k] = r["peak_blades_m"]
    return {
        "tuned": tuned["amplitudes_m"],
        "tuned_settled": tuned["settled"],
        "tuned_peak_m": ref,
        "tuned_peak_rpm": tuned["peak_speed_rpm"],
        "tuned_peak_at_edge": bool(tuned["peak_at_band_edge"]),
        "tuned_peak_direction": tuned["peak_direction"],
        "tuned_peak_blades": tuned["peak_blades_m"],
        "amplitudes": curves.tolist(),
        "peak_m": peaks.tolist(),
        "peak_rpm": peak_speeds.tolist(),
        "peak_blades": at_peak.tolist(),
        "amplification": (peaks / ref).tolist(),
        "unsettled_points": int(sum((~np.array(r["settled"])).any(axis=1).sum() for *_, r in recs)),
        "points": len(recs) * K,
        "movement_max": max(float(np.max(r["movement"])) for *_, r in recs),
    }


def jobs(study: Study) -> list[tuple[str, int, int, Ring]]:
    """Every (variant, level index or -1 for tuned, pattern, ring) of the study."""
    out = []
    for v in study.variants:
        base = tuned_ring(study, v)
        out.append((v, -1, 0, base))
        for li, sigma in enumerate(study.levels):
            for k in range(study.patterns):
                out.append((v, li, k, mistuned(base, study.parameter, factors(study.n, sigma, study.seed, k))))
    return out


def run_study(study: Study, runner: Any, cache_dir: Path | None, task: Any = None) -> dict:
    """Every (variant, level, pattern) sweep, cached ones read, the rest on `runner` (each a call of
    `task`, default `_task`); returns the tuned curves, the curves, peaks and amplifications per
    pattern, and how many were computed."""
    cache = PointCache(cache_dir)
    digest = ring_engine_digest()
    sp = [float(s) for s in speeds(study)]
    todo_jobs = jobs(study)
    numerics = {k: getattr(study, k) for k in ("rtol", "max_time", "speed_tol", "steps_per_period")}
    keys = [
        point_key(
            kind="ring-mistuning-sweep", version=CACHE_VERSION, fmus=digest, ring=asdict(r), speeds=sp, **numerics
        )
        for *_, r in todo_jobs
    ]
    records: dict[int, dict] = {}
    for i, key in enumerate(keys):
        rec = cache.get(key)
        if rec is not None:
            records[i] = rec
    todo = [i for i in range(len(todo_jobs)) if i not in records]
    cdir = str(cache_dir) if cache_dir else None
    t0 = time.perf_counter()
    for i, rec in zip(
        todo,
        runner.map(
            task or _task, [(todo_jobs[i][3], sp, study, keys[i], cdir) for i in todo], desc="mistuning", unit="sweep"
        ),
    ):
        records[i] = rec
    out: dict[str, Any] = {
        "n": study.n,
        "levels": list(study.levels),
        "patterns": study.patterns,
        "parameter": study.parameter,
        "seed": study.seed,
        "whitehead": whitehead(study.n),
        "speeds_rpm": sp,
        "crossing_rpm": resonance_speed(study.blade, study.engine_order),
        "computed": len(todo),
        "cached": len(todo_jobs) - len(todo),
        "wall_s": time.perf_counter() - t0,
        "task_wall_s": sum(records[i]["wall_s"] for i in todo),
        "task_cpu_s": sum(records[i].get("cpu_s", math.nan) for i in todo),
        "variants": {},
    }
    for v in study.variants:
        out["variants"][v] = _variant(study, [(j[1], j[2], records[i]) for i, j in enumerate(todo_jobs) if j[0] == v])
    return out
