"""A sweep that is interrupted (exception after k points, SIGINT, a killed worker) keeps every
finished point on disk and resumes without recomputing it; files are written atomically."""

from __future__ import annotations

import json
import os
import signal
import subprocess
import sys
import threading
import time
from pathlib import Path

import numpy as np
import pytest

from harness.analysis import executor as ex
from harness.analysis.cache import PointCache
from harness.files import atomic, tables
from harness.analysis import curves as sw
from harness.model.params import validate
from tests.analysis.test_sweep import assert_same

SETTINGS = sw.SweepSettings(refine_levels=1, max_time=0.25, rtol=1e-3)
SPEEDS = (4000.0, 5000.0, 6000.0, 7000.0)


def _spec() -> sw.SweepSpec:
    return sw.SweepSpec(validate({"kn": 1e6}), SPEEDS, methods=("time",), settings=SETTINGS)


# ---------------------------------------------------------------------------------------------
# Atomic files
# ---------------------------------------------------------------------------------------------
def test_atomic_write_never_leaves_a_partial_file(tmp_path, monkeypatch):
    target = tmp_path / "table.csv"
    atomic.atomic_write_text(target, "old complete content\n")

    def crash(src, dst):
        raise OSError("disk gone while renaming")

    monkeypatch.setattr(atomic.os, "replace", crash)
    with pytest.raises(OSError):
        atomic.atomic_write_text(target, "new content that never lands\n")
    monkeypatch.undo()
    assert target.read_text() == "old complete content\n"
    assert sorted(p.name for p in tmp_path.iterdir()) == ["table.csv"]  # no temporary left behind


def test_csv_roundtrip_and_cache_ignores_corrupt_entries(tmp_path):
    tab = np.zeros(3, dtype=[("speed", "f8"), ("direction", "U4"), ("amplitude", "f8"), ("reached", "?")])
    tab["speed"] = [1.0, 2.5, 1e4]
    tab["direction"] = ["up", "down", "up"]
    tab["amplitude"] = [1e-5, 3.14159e-5, 0.1 + 0.2]
    tab["reached"] = [True, False, True]
    tables.write_csv(tmp_path / "t.csv", tab, "comment")
    back = tables.read_csv(tmp_path / "t.csv")
    # 6 significant digits of the column's largest value (harness/digits.py): quantum 1e-6 here
    assert np.array_equal(back["amplitude"], [1e-5, 3.1e-5, 0.3])
    assert list(back["direction"]) == ["up", "down", "up"]
    cache = PointCache(tmp_path / "cache")
    cache.put("ab" * 16, {"x": 1.5})
    assert cache.get("ab" * 16) == {"x": 1.5}
    p = tmp_path / "cache" / "cd" / ("cd" * 16 + ".json")
    p.parent.mkdir(parents=True)
    p.write_text('{"x": 1.')  # a truncated file from some other writer: a miss, not a crash
    assert cache.get("cd" * 16) is None


# ---------------------------------------------------------------------------------------------
# Interrupted after k points: resume recomputes nothing that was finished
# ---------------------------------------------------------------------------------------------
class Stop(Exception):
    pass


def test_interrupted_sweep_resumes_without_recomputing(fmu_path, tmp_path, monkeypatch):
    real = sw.plateau
    computed: list[float] = []
    limit = {"n": 3}

    def counting(fmu, cache, fh, params, speed, start, s):
        rec = real(fmu, cache, fh, params, speed, start, s)
        if not rec.cached:
            computed.append(speed)
            if len(computed) >= limit["n"]:
                raise Stop()
        return rec

    monkeypatch.setattr(sw, "plateau", counting)
    with pytest.raises(Stop):
        sw.sweep(_spec(), fmu_path=fmu_path, cache_dir=tmp_path / "cache")
    first = list(computed)
    assert len(first) == 3
    computed.clear()
    limit["n"] = 10**9
    resumed = sw.sweep(_spec(), fmu_path=fmu_path, cache_dir=tmp_path / "cache")
    n_resumed = len(computed)
    # an uninterrupted run in a fresh cache: the number of points it computes and its results
    computed.clear()
    clean = sw.sweep(_spec(), fmu_path=fmu_path, cache_dir=tmp_path / "fresh")
    assert n_resumed == len(computed) - 3  # exactly the 3 finished points were not recomputed
    assert_same(resumed.time, clean.time)
    # a third run finds everything in the cache
    computed.clear()
    again = sw.sweep(_spec(), fmu_path=fmu_path, cache_dir=tmp_path / "cache")
    assert computed == []
    assert_same(again.time, clean.time)


# ---------------------------------------------------------------------------------------------
# SIGINT to the command, and a worker process killed: finished points stay, the run resumes
# ---------------------------------------------------------------------------------------------
def _cache_files(d: Path) -> list[Path]:
    return sorted(d.glob("*/*.json")) if d.exists() else []


@pytest.mark.slow  # 33 s: a child sweep interrupted and rerun
def test_sigint_keeps_finished_points_and_rerun_completes(fmu_path, tmp_path):
    cache = tmp_path / "cache"
    out = tmp_path / "sweep.csv"
    cmd = [
        sys.executable,
        "-m",
        "harness",
        "sweep",
        "--fmu",
        str(fmu_path),
        "--speeds",
        "3000:8000:250",
        "--method",
        "time",
        "--refine",
        "1",
        "--max-time",
        "1.0",
        "--start-values",
        "kn",
        "1e6",
        "--workers",
        "2",
        "--quiet",
        "--cache-dir",
        str(cache),
        "--output-file",
        str(out),
    ]
    # SIGINT back to its default in the child: a test run started in the background of a shell
    # without job control inherits SIGINT ignored, and Python then never raises KeyboardInterrupt
    proc = subprocess.Popen(
        cmd,
        stdout=subprocess.PIPE,
        stderr=subprocess.PIPE,
        text=True,
        preexec_fn=lambda: signal.signal(signal.SIGINT, signal.SIG_DFL),
    )
    t0 = time.time()
    while len(_cache_files(cache)) < 3 and proc.poll() is None and time.time() - t0 < 120:
        time.sleep(0.05)
    assert proc.poll() is None, "the sweep finished before it could be interrupted: make it longer"
    proc.send_signal(signal.SIGINT)
    _, err = proc.communicate(timeout=60)
    assert proc.returncode == 130, err
    assert "run the same command again to resume" in err
    assert not out.exists()  # no half-written result table
    kept = _cache_files(cache)
    assert len(kept) >= 3
    for f in kept:
        json.loads(f.read_text())  # every stored point is complete
    before = {f.name for f in kept}
    done = subprocess.run(cmd, capture_output=True, text=True, timeout=300)
    assert done.returncode == 0, done.stderr
    assert before <= {f.name for f in _cache_files(cache)}  # nothing lost or replaced
    clean = tmp_path / "clean.csv"
    cmd_clean = [c if c != str(cache) else str(tmp_path / "cache2") for c in cmd]
    cmd_clean[cmd_clean.index(str(out))] = str(clean)
    assert subprocess.run(cmd_clean, capture_output=True, text=True, timeout=300).returncode == 0
    assert out.read_text() == clean.read_text()


def test_killed_worker_loses_only_its_point(fmu_path, tmp_path):
    spec = sw.SweepSpec(
        validate({"kn": 1e6}), tuple(np.arange(3000.0, 8001.0, 500.0)), methods=("time",), settings=SETTINGS
    )
    cache = tmp_path / "cache"
    runner = ex.Runner(workers=2, progress=False)
    killed: list[int] = []

    def killer() -> None:
        t0 = time.time()
        while time.time() - t0 < 120:
            if len(_cache_files(cache)) >= 2 and runner._pool is not None:
                procs = list(getattr(runner._pool, "_processes", {}).values())
                if procs:
                    os.kill(procs[0].pid, signal.SIGKILL)
                    killed.append(procs[0].pid)
                    return
            time.sleep(0.02)

    th = threading.Thread(target=killer)
    th.start()
    with pytest.warns(RuntimeWarning, match="worker process died"):
        with runner:
            res = sw.sweep(spec, runner, fmu_path=fmu_path, cache_dir=cache)
    th.join()
    assert killed
    clean = sw.sweep(spec, fmu_path=fmu_path, cache_dir=tmp_path / "fresh")
    assert_same(res.time, clean.time)
