"""The mistuning study on steady states: for each ring (the tuned one and every pattern) the largest
response over its **stable** periodic steady states in the band, from the ring's periodic-orbit
engine (harness/system/ring_orbits: seeds from rest, from a sweep up and down and the travelling
wave, and every state the study's own sweep of that ring settled at, its peak's refinement included
(so the located peak a sweep reports is a seed and its branch is traced), Newton shooting on the co-simulation's period map, continuation across the band with
Floquet stability, branch switching). Amplification = that of the mistuned ring / that of the tuned
ring. A sweep's peak (harness/studies/mistuning.py) is what that sweep's path found: a stable state
it landed on, not the largest one there is, and it is kept beside this one as "what a sweep finds".

Each ring is one task on the Runner, cached in its own file (PointCache) under a key of the ring,
the band, the engine's settings and the FMUs' bytes, so a killed study resumes.
"""

from __future__ import annotations

import math
import time
from dataclasses import asdict, dataclass, replace
from pathlib import Path
from typing import Any, Callable, Sequence

import numpy as np

from harness.analysis.cache import PointCache, point_key
from harness.system.engine_identity import ring_engine_digest
from harness.studies import mistuning
from harness.studies.mistuning import Study
from harness.system.ring import Ring
from harness.system.ring_orbits.branches import MAX_BRANCHES, ring_branches
from harness.system.ring_orbits.period_map import RingShootingSettings
from harness.system.ring_orbits.seeds import SweepPath

CACHE_VERSION = 3  # bump when the meaning of a cached record changes (2: the study's sweep among the seeds;
# 3: every seed shot, the untraced orbits counted)


@dataclass(frozen=True)
class StatesSettings:
    """The engine's settings for every ring of the study."""

    seed_points: int | None = None  # speeds where seeds start (rest, sweep, wave); None: the engine's default, at
    # most 300 rpm apart (6 seeds across the band missed a pattern's largest stable branch near 5800 rpm)
    switch_branches: bool = True
    max_branches: int = MAX_BRANCHES  # a safety bound (branches.py): every seed's branch is traced
    steps_per_period: int = 160  # the sweeps' step h = T / 160


def study_sweep(study: Study) -> SweepPath:
    """The mistuning study's sweep (harness/studies/mistuning.py: its speeds, settle rule and located
    peak) as a seed path of the engine."""
    return SweepPath(
        tuple(float(s) for s in mistuning.speeds(study)),
        rtol=study.rtol,
        max_time=study.max_time,
        refine=True,
        speed_tol=study.speed_tol,
    )


def branches_record(
    ring: Ring, band: tuple[float, float], settings: StatesSettings, path: SweepPath | None = None
) -> dict:
    """One ring's branches (JSON-able), seeded by the sweep `path` too: the largest stable steady
    state (amplitude, speed, blade), per branch its speeds, largest blade amplitude and stability per
    point, its bifurcations, and the cost (periods of the ring simulated, wall and CPU seconds)."""
    t0, c0 = time.perf_counter(), time.process_time()
    rb = ring_branches(
        ring,
        band,
        points=settings.seed_points,
        # one thread per ring: the runner already runs one ring per core (threads on top would only
        # contend for the same cores)
        settings=RingShootingSettings(steps_per_period=settings.steps_per_period, workers=1),
        switch_branches=settings.switch_branches,
        max_branches=settings.max_branches,
        sweeps=() if path is None else (path,),
    )
    d = rb.as_dict()
    branches = [
        {
            "speeds_rpm": b["speeds_rpm"],
            "largest_m": [float(np.max(a)) for a in b["amplitudes_m"]],
            "stable": b["stable"],
            "bifurcations": b.get("bifurcations", []),
        }
        for b in d["branches"]
    ]
    nan = math.nan
    return {
        "peak_stable_amplitude_m": d["peak_stable_amplitude_m"] if d["peak_stable_amplitude_m"] is not None else nan,
        "peak_stable_speed_rpm": d["peak_stable_speed_rpm"] if d["peak_stable_speed_rpm"] is not None else nan,
        "peak_stable_blade": d["peak_stable_blade"] if d["peak_stable_blade"] is not None else -1,
        "branches": branches,
        "evaluations": int(d["evaluations"]),
        "seeds": int(d["seeds"]),
        "seeds_shot": int(d["seeds_shot"]),
        # orbits past the branch cap (not continued): speed, largest blade, stability
        "untraced": [
            {"speed_rpm": o["speed_rpm"], "largest_m": max(o["amplitudes_m"]), "stable": o["stable"]}
            for o in d["untraced_orbits"]
        ],
        "wall_s": time.perf_counter() - t0,
        "cpu_s": time.process_time() - c0,
    }


def _key(ring: Ring, band: tuple[float, float], settings: StatesSettings, path: SweepPath | None, digest: str) -> str:
    return point_key(
        kind="ring-mistuning-states",
        version=CACHE_VERSION,
        fmus=digest,
        ring=asdict(ring),
        band=[float(b) for b in band],
        settings=asdict(settings),
        sweep=None if path is None else asdict(path),
    )


def _task(job: tuple[Ring, tuple[float, float], StatesSettings, SweepPath | None, str, str | None]) -> dict:
    """One ring on a worker: its branches, stored in the cache at once (a cached one is read)."""
    ring, band, settings, path, key, cache_dir = job
    cache = PointCache(Path(cache_dir) if cache_dir else None)
    rec = cache.get(key)
    if rec is None:
        rec = branches_record(ring, band, settings, path)
        cache.put(key, rec)
    return rec


def evaluate(
    rings: Sequence[Ring],
    band: tuple[float, float],
    settings: StatesSettings,
    runner: Any,
    cache_dir: Path | None,
    desc: str = "steady states",
    path: SweepPath | None = None,
) -> list[dict]:
    """Every ring's branches record, seeded by the sweep `path` too (cached ones read, the rest on
    `runner`)."""
    digest = ring_engine_digest()
    cache = PointCache(cache_dir)
    keys = [_key(r, band, settings, path, digest) for r in rings]
    out: list[dict | None] = [cache.get(k) for k in keys]
    todo = [i for i, r in enumerate(out) if r is None]
    cdir = str(cache_dir) if cache_dir else None
    for i, rec in zip(
        todo, runner.map(_task, [(rings[i], band, settings, path, keys[i], cdir) for i in todo], desc=desc, unit="ring")
    ):
        out[i] = rec
    for i, r in enumerate(out):
        r["computed"] = i in todo  # type: ignore[index]
    return out  # type: ignore[return-value]


def run_states(
    study: Study, settings: StatesSettings, runner: Any, cache_dir: Path | None, variant: str = "friction"
) -> dict:
    """The tuned ring and the first `study.state_patterns` patterns of every level on their stable
    steady states: their largest stable response, the amplification on that definition, the cost."""
    band = mistuning.band(study)
    sub = replace(study, variants=(variant,), patterns=study.state_patterns)
    rings = [(lvl, k, r) for v, lvl, k, r in mistuning.jobs(sub)]
    study = sub
    t0 = time.perf_counter()
    recs = evaluate([r for *_, r in rings], band, settings, runner, cache_dir, path=study_sweep(study))
    tuned = recs[0]
    ref = tuned["peak_stable_amplitude_m"]
    peaks = np.full((len(study.levels), study.patterns), np.nan)
    speeds = np.full_like(peaks, np.nan)
    for (lvl, k, _), rec in zip(rings[1:], recs[1:]):
        peaks[lvl, k], speeds[lvl, k] = rec["peak_stable_amplitude_m"], rec["peak_stable_speed_rpm"]
    return {
        "band_rpm": list(band),
        "settings": asdict(settings),
        "variant": variant,
        "tuned": tuned,
        "patterns": [r for r in recs[1:]],
        "tuned_peak_m": ref,
        "tuned_peak_rpm": tuned["peak_stable_speed_rpm"],
        "peak_m": peaks.tolist(),
        "peak_rpm": speeds.tolist(),
        "amplification": (peaks / ref).tolist(),
        "rings": len(recs),
        "computed": sum(r["computed"] for r in recs),
        "wall_s": time.perf_counter() - t0,
        "task_wall_s": sum(r["wall_s"] for r in recs if r["computed"]),
        "task_cpu_s": sum(r["cpu_s"] for r in recs if r["computed"]),
        "evaluations": sum(r["evaluations"] for r in recs),
    }


# ---------------------------------------------------------------------------------------------
# The worst pattern at one sigma
# ---------------------------------------------------------------------------------------------
@dataclass(frozen=True)
class Search:
    """A compass search (generalized pattern search) over z in [-z_max, z_max]^N, factors 1 + sigma z
    (the study's patterns, truncated at z_max standard deviations): from the start z, poll z +- step
    e_i (2N rings, run in parallel, in a seeded random order: a budget smaller than a poll covers
    random coordinates), move to the best improvement, else halve the step; stop when the budget of
    rings is spent or the step falls below step_min."""

    sigma: float = 0.05
    budget: int = 24  # rings evaluated (the start included)
    step: float = 0.5
    step_min: float = 0.125
    z_max: float = 2.0


def search_worst(
    study: Study, search: Search, start: Sequence[float], objective: Callable[[list[np.ndarray]], list[float]]
) -> dict:
    """The compass search of `search` from z = `start`; `objective(zs)` returns the amplification of
    every z (one ring each). Returns the best z, its factors and amplification, and the history."""
    z = np.clip(np.asarray(start, dtype=float), -search.z_max, search.z_max)
    best, history = -np.inf, []
    step, used, first = search.step, 0, True
    while used < search.budget and step >= search.step_min:
        polls = []
        for i in range(study.n):
            for s in (1.0, -1.0):
                c = z.copy()
                c[i] = np.clip(c[i] + s * step, -search.z_max, search.z_max)
                if not np.array_equal(c, z) and not any(np.array_equal(c, p) for p in polls):
                    polls.append(c)
        order = np.random.default_rng(len(history)).permutation(len(polls))  # a partial poll: random coordinates
        polls = [polls[i] for i in order]
        if first:  # the start goes with the first poll: one batch, run in parallel
            polls = [z] + polls
        polls = polls[: search.budget - used]
        values = objective(polls)
        used += len(polls)
        history += [(p.tolist(), v) for p, v in zip(polls, values)]
        if first:
            best, polls, values, first = values[0], polls[1:], values[1:], False
        k = int(np.nanargmax(values)) if len(values) and np.isfinite(values).any() else -1
        if k >= 0 and values[k] > best:
            z, best = polls[k], values[k]
        elif len(values):
            step /= 2
    return {
        "sigma": search.sigma,
        "z": z.tolist(),
        "factors": (1 + search.sigma * z).tolist(),
        "amplification": best,
        "rings": used,
        "budget": search.budget,
        "final_step": step,
        "history": history,
    }


def run_search(
    study: Study,
    states: dict,
    settings: StatesSettings,
    runner: Any,
    cache_dir: Path | None,
    sweep_amplification: Sequence[float] | None = None,
) -> dict:
    """The worst pattern at the study's largest level on stable steady states: a compass search
    (Search) of `study.search_budget` rings from the worst pattern at that level on steady states
    (`states`), or, when no pattern was taken there, from the sweeps' worst (`sweep_amplification`
    of the level's patterns: the Monte-Carlo worst of what a sweep finds)."""
    sigma = study.levels[-1]
    amp = np.array(states["amplification"], dtype=float)[-1] if states["amplification"] else np.array([])
    if np.isfinite(amp).any():
        k0, origin = int(np.nanargmax(amp)), "steady states"
    else:
        k0, origin = int(np.nanargmax(np.asarray(sweep_amplification, dtype=float))), "sweeps"
    start = (mistuning.factors(study.n, sigma, study.seed, k0) - 1) / sigma
    base = mistuning.tuned_ring(study, states["variant"])
    band = tuple(states["band_rpm"])
    tuned = states["tuned_peak_m"]

    seen: dict[bytes, dict] = {}

    def objective(zs: list[np.ndarray]) -> list[float]:
        rings = [mistuning.mistuned(base, study.parameter, 1 + sigma * np.asarray(z)) for z in zs]
        recs = evaluate(rings, band, settings, runner, cache_dir, "worst-pattern search", study_sweep(study))
        seen.update({np.asarray(z, dtype=float).tobytes(): r for z, r in zip(zs, recs)})
        return [
            r["peak_stable_amplitude_m"] / tuned if np.isfinite(r["peak_stable_amplitude_m"]) else -np.inf for r in recs
        ]

    t0 = time.perf_counter()
    out = search_worst(study, Search(sigma=sigma, budget=study.search_budget), start, objective)
    best = seen[np.asarray(out["z"], dtype=float).tobytes()]
    return {
        **out,
        "record": best,
        "start_pattern": k0,
        "start_from": origin,
        "start_amplification": out["history"][0][1],
        "wall_s": time.perf_counter() - t0,
        "whitehead": mistuning.whitehead(study.n),
    }
