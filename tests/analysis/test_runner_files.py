"""Files and the task runner: files are written atomically, a CSV round-trips at the writer's
digits, the point cache reads a corrupt entry as a miss, and a local pool whose worker is killed
(SIGKILL, mid-run) is rebuilt and gives every task's result, each finished task computed once."""

from __future__ import annotations

import os
import signal
import threading
import time
from pathlib import Path

import numpy as np
import pytest

from harness.analysis import executor as ex
from harness.analysis.cache import PointCache
from harness.files import atomic, tables


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
# A killed worker: the pool is rebuilt, the unfinished tasks resume
# ---------------------------------------------------------------------------------------------
def cube_slowly(task: tuple[int, str]) -> int:
    """x^3 after 0.2 s, as a point of a study would be: its result stored at once under `done`,
    and a finished one read back instead of computed again (as the point cache does)."""
    x, done = task
    out = Path(done) / f"{x}.txt"
    if out.exists():
        return int(out.read_text())
    (Path(done) / f"{x}.{os.getpid()}.started").write_text("")
    time.sleep(0.2)
    atomic.atomic_write_text(out, str(x**3))
    return x**3


def test_killed_worker_loses_only_its_task(tmp_path):
    tasks = [(x, str(tmp_path)) for x in range(12)]
    runner = ex.Runner(workers=2, progress=False)
    killed: list[int] = []

    def killer() -> None:
        t0 = time.time()
        while time.time() - t0 < 60:
            procs = list(getattr(runner._pool, "_processes", {}).values()) if runner._pool else []
            if len(list(tmp_path.glob("*.txt"))) >= 2 and procs:
                os.kill(procs[0].pid, signal.SIGKILL)
                killed.append(procs[0].pid)
                return
            time.sleep(0.01)

    th = threading.Thread(target=killer)
    th.start()
    with pytest.warns(RuntimeWarning, match="worker process died"), runner:
        out = runner.map(cube_slowly, tasks)
    th.join()
    assert killed and out == [x**3 for x in range(12)]
    assert all((tmp_path / f"{x}.txt").read_text() == str(x**3) for x in range(12))
    # a task runs again only if it was in flight when the worker died (two workers: at most two)
    assert 12 <= len(list(tmp_path.glob("*.started"))) <= 12 + 2
