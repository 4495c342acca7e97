"""Mistuning study of the ring: random blade-to-blade scatter of one blade parameter
(EI, the bending stiffness, or m0, the shroud mass), relative standard deviation per level, patterns
from a seeded generator; every pattern is one ring run (harness/system/ring_c.py) on the Runner
(local process pool, or dask with a scheduler address), cached in its own file (PointCache), so a
killed study resumes where it stopped.

Amplification of a pattern = largest blade amplitude (max |q| over the last excitation period) /
the tuned ring's blade amplitude at the same speed, the speed being the tuned ring's resonance with
the contacts open (EO n / 60 = contact-free first bending frequency, Campbell crossing, from the
Galerkin reduction, harness.model.galerkin). Compared with Whitehead's bound (1 + sqrt(N)) / 2, a
theorem for linear rings with light damping. Variants: `friction` (the contacts as given),
`frictionless` (mu = 0: the shrouds impact, no friction) and `open` (d = 1 m: the contacts never
close, the blades are uncoupled). A ring that does not settle has no amplification (NaN), and a
variant whose tuned ring does not settle has none at all (its response is not periodic).

Numerics (docs/model.md s.8): every ring runs through the C communication loop
(harness/system/ring_c.py) at h = T / 160 = 2.5e-5 s with quadratic extrapolation (error 1e-3 of
max |q| against the monolithic reference). At h = 1e-4 s (linear extrapolation, stable but 25 % off) the
coupling's energy error makes the friction ring wander by 10-30 % from period to period and never
settle, tuned or not; at 2.5e-5 s it settles to 1e-4 within 0.1 s. Each record keeps `settle`, the
largest relative change of a blade amplitude between the last period and the period five periods
(20 ms, about one decay time 2 M / C0) earlier; the study reports the worst. h divides the
excitation period T, so every period is sampled at the same phases: max |q| over the communication
points carries the same sampling error (up to ~3e-3 where an impact sharpens the peak) in every
period, and `settle` sees the motion, not the sampling.
"""
from __future__ import annotations

import functools
import hashlib
import math
import time
from dataclasses import asdict, dataclass, field, replace
from pathlib import Path
from typing import Any, Sequence

from fmpy import read_model_description
import numpy as np

from harness.analysis.executor import PointCache, point_key
from harness.fmu.blade import BladeFMU
from harness.fmu.build import EXCITATION_FMU
from harness.fmu.slave import build_ring_fmus
from harness.model.excitation import AeroLoad
from harness.model.galerkin import galerkin
from harness.system.ring import Ring, amplitudes
from harness.system import ring_c
from harness.system.ring_values import settable

PARAMETERS = ("EI", "m0")  # the blade parameters a pattern scatters
# contact parameters on top of the ring's
VARIANTS = {"friction": {}, "frictionless": {"mu": 0.0}, "open": {"d": 1.0}}
CACHE_VERSION = 2  # bump when the meaning of a cached record changes


@dataclass(frozen=True)
class Study:
    n: int = 6
    levels: tuple[float, ...] = (0.005, 0.01, 0.02, 0.05)  # relative standard deviations
    patterns: int = 100
    parameter: str = "EI"
    seed: int = 1
    variants: tuple[str, ...] = ("friction", "frictionless")
    stop_time: float = 0.15  # [s] (transient 2 M / C0 = 0.022 s at c = 298 N s/m2)
    steps_per_period: int = 160  # h = T / 160 (2.5e-5 s at 4966 rpm): every period sampled at the same phases
    order: int = 2  # extrapolation order of the input derivatives
    speed: float | None = None  # [rpm]; None: the tuned resonance
    engine_order: int = 3
    fw0: float = 300.0
    blade: dict = field(default_factory=lambda: {"c": 298.0})
    contact: dict = field(default_factory=dict)


SIZES = {
    # `make run`: 802 rings of 6 blades, 0.15 s each
    "small": Study(),
    # a cluster: 24 blades, the open (uncoupled) rings too
    "cluster": Study(n=24, variants=("friction", "frictionless", "open")),
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
    return math.sqrt(g.K0static / (engine_order ** 2 * g.M - g.K0omega2)) * 60 / (2 * math.pi)


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


def mistuned(ring: Ring, parameter: str, f: Sequence[float]) -> Ring:
    """`ring` with blade i's `parameter` = tuned value * f[i]."""
    if parameter not in PARAMETERS:
        raise ValueError(f"mistuned parameter {parameter!r}: one of {', '.join(PARAMETERS)}")
    base = blade_value(ring, parameter)
    return replace(ring, blade_each=tuple({parameter: base * float(x)} for x in f))


def tuned_ring(study: Study, variant: str) -> Ring:
    speed = study.speed or resonance_speed(study.blade, study.engine_order)
    period = 60 / (study.engine_order * speed)
    step = round(period / study.steps_per_period * 1e9) * 1e-9  # whole nanoseconds (libcosim's grid)
    return Ring(n=study.n, engine_order=study.engine_order, speed=speed, fw0=study.fw0, blade=dict(study.blade),
                contact={**study.contact, **VARIANTS[variant]}, step=step, stop_time=study.stop_time,
                order=study.order)


def single_blade_amplitude(study: Study, stop_time: float = 0.3) -> float:
    """ShroudedBlade alone (its built-in Jenkins contact: a rigid neighbour behind the gap d) at the
    study's speed, load and damping, run from rest: max |q| over the last period [m]."""
    speed = study.speed or resonance_speed(study.blade, study.engine_order)
    T = 60 / (study.engine_order * speed)
    p = {**study.blade, "Fw0": study.fw0, "engineOrder": study.engine_order, "frictionModel": 3}
    with BladeFMU() as f:
        r = f.run(p, stop_time, T / study.steps_per_period, aero=AeroLoad(study.fw0, study.engine_order, speed),
                  speed=speed, outputs=["tipDisplacement"])
    t, q = r["time"], r["tipDisplacement"]
    return float(np.abs(q[t >= t[-1] - T - 1e-12]).max())


def _fmu_digest() -> str:
    """The ring FMUs' bytes: a rebuilt FMU invalidates the cache."""
    h = hashlib.sha256()
    for p in (*build_ring_fmus(), EXCITATION_FMU):
        h.update(Path(p).read_bytes())
    return h.hexdigest()


SETTLE_PERIODS = 5  # the amplitude is compared with the one this many periods earlier
SETTLE_TOL = 1e-3  # a run whose amplitudes still move more than this is run twice as long ...
SETTLE_DOUBLINGS = 3  # ... at most this many times (then it is reported as it is)


def simulate(ring: Ring) -> dict:
    """One ring run (C loop): the steady amplitude of every blade [m], `settle`, the largest
    relative change of a blade amplitude over the last SETTLE_PERIODS periods, and the simulated
    time it took (doubled from ring.stop_time while settle > SETTLE_TOL)."""
    for _ in range(SETTLE_DOUBLINGS + 1):
        res = ring_c.run(ring)
        t, q = res["time"], res["q"]
        a = amplitudes(t, q, ring.omega)
        back = t <= t[-1] - SETTLE_PERIODS * 2 * math.pi / ring.omega + 1e-12
        settle = float(np.max(np.abs(a - amplitudes(t[back], q[back], ring.omega))) / np.max(a))
        if settle <= SETTLE_TOL:
            break
        ring = replace(ring, stop_time=2 * ring.stop_time)
    return {"amplitudes": [float(x) for x in a], "settle": settle, "stop_time": ring.stop_time}


def _task(job: tuple[Ring, str, str | None]) -> dict:
    """One pattern on a worker: run, store in the cache at once (atomic file), return the record."""
    ring, key, cache_dir = job
    t0 = time.perf_counter()
    rec = {**simulate(ring), "wall_s": time.perf_counter() - t0}
    PointCache(Path(cache_dir) if cache_dir else None).put(key, rec)
    return rec


def _variant(study: Study, recs: list[tuple[int, int, dict]]) -> dict:
    """One variant's results from its (level index or -1 for tuned, pattern, record) triples. A ring
    that did not settle (settle > SETTLE_TOL after the doublings) has no steady amplitude: its
    amplification is NaN, and if the tuned ring did not settle, every amplification of the variant
    is (the response is not periodic: no amplification factor exists)."""
    tuned_rec = next(r for li, _, r in recs if li == -1)
    tuned, ref = tuned_rec["amplitudes"], max(tuned_rec["amplitudes"])
    amps = np.full((len(study.levels), study.patterns, study.n), np.nan)
    settled = np.zeros((len(study.levels), study.patterns), dtype=bool)
    for li, k, r in recs:
        if li >= 0:
            amps[li, k] = r["amplitudes"]
            settled[li, k] = r["settle"] <= SETTLE_TOL
    tuned_settled = tuned_rec["settle"] <= SETTLE_TOL
    amplification = np.where(settled & tuned_settled, amps.max(axis=2) / ref, np.nan)
    return {"tuned": tuned, "tuned_spread": (max(tuned) - min(tuned)) / ref, "tuned_settled": tuned_settled,
            "amplitudes": amps.tolist(), "amplification": amplification.tolist(),
            "unsettled": int((~settled).sum()) + (0 if tuned_settled else 1),
            "settle_max": max(r["settle"] for *_, r in recs)}


def run_study(study: Study, runner: Any, cache_dir: Path | None) -> dict:
    """Every (variant, level, pattern) ring, cached ones read, the rest on `runner`; returns the
    tuned amplitudes, the amplitudes and amplifications per pattern, and how many were computed."""
    cache = PointCache(cache_dir)
    digest = _fmu_digest()
    jobs: list[tuple[str, int, int, Ring]] = []  # (variant, level index or -1 for tuned, pattern, ring)
    for v in study.variants:
        base = tuned_ring(study, v)
        jobs.append((v, -1, 0, base))
        for li, sigma in enumerate(study.levels):
            for k in range(study.patterns):
                jobs.append((v, li, k, mistuned(base, study.parameter, factors(study.n, sigma, study.seed, k))))
    keys = [point_key(kind="ring-mistuning", version=CACHE_VERSION, fmus=digest, ring=asdict(r)) for *_, r in jobs]
    records: dict[int, dict] = {}
    for i, key in enumerate(keys):
        rec = cache.get(key)
        if rec is not None:
            records[i] = rec
    todo = [i for i in range(len(jobs)) if i not in records]
    cdir = str(cache_dir) if cache_dir else None
    for i, rec in zip(todo, runner.map(_task, [(jobs[i][3], keys[i], cdir) for i in todo],
                                       desc="mistuning", unit="ring")):
        records[i] = rec
    out: dict[str, Any] = {"n": study.n, "levels": list(study.levels), "patterns": study.patterns,
                           "parameter": study.parameter, "seed": study.seed, "whitehead": whitehead(study.n),
                           "speed_rpm": jobs[0][3].speed, "computed": len(todo), "cached": len(jobs) - len(todo),
                           "single_blade": single_blade_amplitude(study),
                           "variants": {}}
    for v in study.variants:
        out["variants"][v] = _variant(study, [(j[1], j[2], records[i]) for i, j in enumerate(jobs) if j[0] == v])
    return out
