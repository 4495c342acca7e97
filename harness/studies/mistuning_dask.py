"""The mistuning study on a real dask.distributed scheduler (a LocalCluster of worker processes):
the speed-up from 1 to 2 workers, a worker killed mid-run, and the cost of the cluster size
estimated from them. Every (variant, pattern) sweep is one dask task whose record lands in the
cache as soon as it finishes, so a rerun picks up the finished ones.

`python -m harness mistuning-dask [--out FILE]` writes the measurement as JSON (make run
does not run it: it takes a few minutes on 2 cores).

Killed worker: the study runs on 2 workers in a thread; when the first sweep has finished, one
worker process is killed (SIGKILL, its pid from the worker itself). The scheduler reassigns the
task that worker was computing; the study must complete with every record, and the lost task is
seen to start twice (each start leaves a marker file `<cache>/starts/<key>.<pid>`; the worker
killed is one that has started a sweep not yet in the cache).
"""

from __future__ import annotations

import json
import math
import os
import signal
import tempfile
import threading
import time
from dataclasses import replace
from pathlib import Path
from typing import Any

from harness.analysis.cache import PointCache
from harness.analysis.executor import Runner
from harness.files.atomic import atomic_write_text
from harness.studies import mistuning
from harness.studies.mistuning import Study

# the measured study: 6 blades, one level, 6 patterns, 9 speeds (7 sweeps)
MEASURED = replace(mistuning.SIZES["small"], levels=(0.05,), patterns=6, points=9)


def traced_task(job: tuple) -> dict:
    """mistuning._task, leaving a start marker per attempt (key and worker pid)."""
    cache_dir, key = job[4], job[3]
    marks = Path(cache_dir) / "starts"
    marks.mkdir(parents=True, exist_ok=True)
    (marks / f"{key}.{os.getpid()}").touch()
    return mistuning._task(job)


def starts(cache_dir: Path) -> dict[str, list[int]]:
    """key -> pids of the workers that started it."""
    out: dict[str, list[int]] = {}
    for f in (Path(cache_dir) / "starts").glob("*.*"):
        key, pid = f.name.split(".")
        out.setdefault(key, []).append(int(pid))
    return out


def cluster(workers: int):
    """A LocalCluster of `workers` single-threaded worker processes and its client."""
    from distributed import Client, LocalCluster  # optional dependency (extra `cluster`)

    lc = LocalCluster(n_workers=workers, threads_per_worker=1, processes=True, dashboard_address=None)
    return lc, Client(lc)


def timed(study: Study, workers: int) -> dict:
    """The study from an empty cache on a LocalCluster of `workers`: wall time and task time."""
    lc, client = cluster(workers)
    try:
        with tempfile.TemporaryDirectory() as d, Runner(scheduler=client, progress=False) as r:
            t0 = time.perf_counter()
            out = mistuning.run_study(study, r, Path(d))
            wall = time.perf_counter() - t0
    finally:
        client.close()
        lc.close()
    return {
        "workers": workers,
        "wall_s": wall,
        "sweeps": out["computed"],
        "task_s": out["task_wall_s"],
        "task_cpu_s": out["task_cpu_s"],
        "busy": out["task_wall_s"] / (workers * wall),
        "amplification": out["variants"]["friction"]["amplification"],
    }


def sweep_cpu(study: Study, n: int) -> float:
    """CPU seconds of one n-blade ring's sweep over `study`'s band (friction, the study's largest
    level, pattern 0, the peak refined as in the study)."""
    ring = mistuning.mistuned(
        mistuning.tuned_ring(replace(study, n=n), "friction"),
        study.parameter,
        mistuning.factors(n, study.levels[-1], study.seed, 0),
    )
    c0 = time.process_time()
    mistuning.sweep(ring, mistuning.speeds(study), study)
    return time.process_time() - c0


def cost(m: dict, size: Study, workers: int) -> dict:
    """The cluster size's cost on `workers` dedicated single-core workers, from the measurement:
    CPU per sweep = the measured size.n-blade sweep's CPU x size.points / its points (the
    refinement counted as if it grew with the points: an upper estimate); the workers kept busy
    as measured with 2 workers (task time / (workers x wall)); whole sweeps per worker."""
    sweeps = len(mistuning.jobs(size))
    per_sweep = m["sweep_cpu_s"][str(size.n)] * size.points / m["sweep_points"]
    wall = math.ceil(sweeps / workers) * per_sweep / m["two_workers"]["busy"]
    return {
        "workers": workers,
        "sweeps": sweeps,
        "sweep_cpu_s": per_sweep,
        "wall_h": wall / 3600,
        "worker_hours": workers * wall / 3600,
    }


def killed(study: Study, cache_dir: Path, wait_s: float = 600.0) -> dict:
    """The study on 2 workers with one worker killed once the first sweep is in the cache."""
    lc, client = cluster(2)
    result: dict[str, Any] = {}
    try:
        pids = client.run(os.getpid)  # worker address -> pid
        with Runner(scheduler=client, progress=False) as r:
            th = threading.Thread(
                target=lambda: result.update(out=mistuning.run_study(study, r, cache_dir, task=traced_task))
            )
            t0 = time.perf_counter()
            th.start()
            cache = PointCache(cache_dir)
            running = []
            while not running and time.perf_counter() - t0 < wait_s:
                time.sleep(0.02)
                if cache.count() >= 1:  # a sweep finished: kill a worker inside another one
                    running = [
                        (k, p)
                        for k, ps in starts(cache_dir).items()
                        for p in ps
                        if cache.get(k) is None and p in pids.values()
                    ]
            lost, victim_pid = running[0]
            done_before = cache.count()
            os.kill(victim_pid, signal.SIGKILL)
            killed_at = time.perf_counter() - t0
            th.join(wait_s)
            wall = time.perf_counter() - t0
    finally:
        client.close()
        lc.close()
    marks = starts(cache_dir)
    rerun = sorted(k for k, p in marks.items() if victim_pid in p and len(p) > 1)
    out = result.get("out")
    return {
        "completed": out is not None and out["computed"] + out["cached"] == len(mistuning.jobs(study)),
        "records": PointCache(cache_dir).count(),
        "sweeps": len(mistuning.jobs(study)),
        "finished_before_kill": done_before,
        "killed_at_s": killed_at,
        "wall_s": wall,
        "victim_pid": victim_pid,
        "lost": lost,
        "started_twice": rerun,
        "amplification": out["variants"]["friction"]["amplification"] if out else None,
    }


def measure(study: Study = MEASURED) -> dict:
    one, two = timed(study, 1), timed(study, 2)
    with tempfile.TemporaryDirectory() as d:
        kill = killed(study, Path(d))
    per_sweep = one["task_s"] / one["sweeps"]
    small = mistuning.SIZES["small"]  # the band and grid of make run's study
    m = {
        "sweep_points": small.points,
        "sweep_cpu_s": {str(n): sweep_cpu(small, n) for n in (small.n, mistuning.SIZES["cluster"].n)},
    }
    m["two_workers"] = two
    m["cluster_cost"] = [cost(m, mistuning.SIZES["cluster"], k) for k in (1, 2, 8, 32, 128)]
    return {
        **m,
        "study": {"n": study.n, "levels": list(study.levels), "patterns": study.patterns, "points": study.points},
        "one_worker": one,
        "two_workers": two,
        "speed_up": one["wall_s"] / two["wall_s"],
        "efficiency": one["wall_s"] / (2 * two["wall_s"]),
        "sweep_s": per_sweep,
        "killed_worker": kill,
        "cpus": os.cpu_count(),
        "load_average": os.getloadavg(),
    }


def write_measurement(path: str | Path) -> dict:
    """`measure()`, written to `path` as JSON (atomically); returns it."""
    m = measure()
    atomic_write_text(path, json.dumps(m, indent=1))
    return m
