"""Run many independent tasks on a local pool or on dask.

The studies are split into tasks (one branch curve, one ring sweep over speed) that
are mapped over a pool of worker processes (`concurrent.futures`, the default) or a
dask.distributed cluster (`scheduler="tcp://host:8786"`). A task stores every finished point at once
in the point cache (harness.analysis.cache), so an interrupted run (SIGINT, a killed worker, a
killed master) loses at most the points that were being computed: running the same command again
finds the finished points by their key and continues. A pool whose worker died is rebuilt and the
unfinished tasks are resubmitted (they resume from the cache).
"""

from __future__ import annotations

import importlib
import multiprocessing as mp
import os
import sys
import time
import warnings
from concurrent.futures import FIRST_COMPLETED, ProcessPoolExecutor, wait
from concurrent.futures.process import BrokenProcessPool
from dataclasses import dataclass, field
from typing import Any, Callable, Sequence

from tqdm.auto import tqdm

from harness.optional import require


# ---------------------------------------------------------------------------------------------
# Parallel map
# ---------------------------------------------------------------------------------------------
def _import_modules(modules: Sequence[str]) -> None:
    for name in modules:
        importlib.import_module(name)


@dataclass
class Runner:
    """Maps a picklable function over tasks: in-process, on a local process pool, or on dask.

    `workers=1` runs in the calling process (tests, debugging). `scheduler` (a dask.distributed
    address such as "tcp://10.0.0.5:8786", or an existing `distributed.Client`) sends the same
    function to a cluster. The pool is created on first use and kept until `close()`.
    """

    workers: int | None = None
    scheduler: Any = None
    progress: bool = True
    retries: int = 2
    stats: dict = field(default_factory=dict)
    _pool: ProcessPoolExecutor | None = None
    _client: Any = None
    _own_client: bool = False

    def __enter__(self) -> "Runner":
        return self

    def __exit__(self, *exc: Any) -> None:
        self.close()

    @property
    def n_workers(self) -> int:
        if self.scheduler is not None:
            client = self._dask_client()
            return max(1, len(client.scheduler_info().get("workers", {})))
        return self.workers or os.cpu_count() or 1

    def _dask_client(self) -> Any:
        if self._client is None:
            require("distributed")
            # optional dependency (extra `cluster`): imported only when this runs
            from distributed import Client

            if isinstance(self.scheduler, Client):
                self._client = self.scheduler
            else:
                self._client = Client(self.scheduler, timeout="20s")
                self._own_client = True
        return self._client

    def _local_pool(self) -> ProcessPoolExecutor:
        if self._pool is None:
            self._pool = ProcessPoolExecutor(max_workers=self.n_workers, mp_context=mp.get_context("spawn"))
        return self._pool

    def warm_up(self, *modules: str) -> None:
        """Start the local pool's workers now and import `modules` in them, without waiting: a
        spawned worker takes ~0.5 s to start, which then overlaps the caller's own work (e.g. the
        harmonic balance before the branches). No-op in-process and on dask."""
        if self.scheduler is not None or self.n_workers <= 1:
            return
        pool = self._local_pool()
        for _ in range(self.n_workers):
            pool.submit(_import_modules, modules)

    def close(self, kill: bool = False) -> None:
        if self._pool is not None:
            if kill:
                # Stop workers that are still computing (SIGINT sent only to the master): they
                # lose only their current point, everything finished is already on disk.
                for proc in list(getattr(self._pool, "_processes", {}).values()):
                    proc.terminate()
            self._pool.shutdown(wait=not kill, cancel_futures=True)
            self._pool = None
        if self._client is not None and self._own_client:
            self._client.close()
        self._client = None

    def steps(self, desc: str, total: int) -> "StepBar":
        """A progress bar over `total` named steps done in this process (see StepBar)."""
        return StepBar(desc, total, self.progress)

    def map(self, func: Callable[[Any], Any], tasks: Sequence[Any], desc: str = "", unit: str = "task") -> list[Any]:
        """`[func(t) for t in tasks]`, in parallel, with a progress bar; order preserved."""
        tasks = list(tasks)
        t0 = time.perf_counter()
        bar = tqdm(
            total=len(tasks),
            desc=desc,
            unit=unit,
            disable=not self.progress or not tasks,
            dynamic_ncols=True,
            leave=False,
        )
        try:
            if self.scheduler is not None:
                out = self._map_dask(func, tasks, bar)
            elif self.n_workers <= 1 or len(tasks) <= 1:
                out = []
                for t in tasks:
                    out.append(func(t))
                    bar.update(1)
            else:
                out = self._map_pool(func, tasks, bar)
        except KeyboardInterrupt:
            self.close(kill=True)
            print(
                "interrupted: every finished point is stored in the cache; run the same command again to resume",
                file=sys.stderr,
            )
            raise
        finally:
            bar.close()
        self.stats[desc or "map"] = self.stats.get(desc or "map", 0.0) + time.perf_counter() - t0
        return out

    def _map_pool(self, func: Callable[[Any], Any], tasks: list[Any], bar: Any) -> list[Any]:
        results: dict[int, Any] = {}
        attempts = 0
        while len(results) < len(tasks):
            pool = self._local_pool()
            todo = [i for i in range(len(tasks)) if i not in results]
            futures = {pool.submit(func, tasks[i]): i for i in todo}
            try:
                pending = set(futures)
                while pending:
                    done, pending = wait(pending, return_when=FIRST_COMPLETED)
                    for f in done:
                        results[futures[f]] = f.result()
                        bar.update(1)
            except BrokenProcessPool:
                attempts += 1
                self._pool = None
                if attempts > self.retries:
                    raise
                warnings.warn(
                    f"a worker process died; restarting the pool and resuming "
                    f"{len(tasks) - len(results)} unfinished task(s) from the cache "
                    f"(attempt {attempts}/{self.retries})",
                    RuntimeWarning,
                    stacklevel=2,
                )
        return [results[i] for i in range(len(tasks))]

    def _map_dask(self, func: Callable[[Any], Any], tasks: list[Any], bar: Any) -> list[Any]:
        require("distributed")
        # optional dependency (extra `cluster`): imported only when this runs
        from distributed import as_completed

        client = self._dask_client()
        futures = client.map(func, tasks, pure=False)
        index = {f.key: i for i, f in enumerate(futures)}
        results: dict[int, Any] = {}
        for f in as_completed(futures):
            results[index[f.key]] = f.result()
            bar.update(1)
        return [results[i] for i in range(len(tasks))]


class StepBar:
    """A progress bar over a sequence of named steps: `bar("Fig. 4/5")` closes the step before and
    names the one starting; `bar.close()` closes the last. A context manager."""

    def __init__(self, desc: str, total: int, enabled: bool = True):
        self.desc, self._started = desc, False
        self.bar = tqdm(total=total, desc=desc, unit="step", disable=not enabled, dynamic_ncols=True, leave=False)

    def __call__(self, name: str) -> None:
        if self._started:
            self.bar.update(1)
        self._started = True
        self.bar.set_description(f"{self.desc}: {name}")

    def close(self) -> None:
        if self._started:
            self.bar.update(1)
        self.bar.close()

    def __enter__(self) -> "StepBar":
        return self

    def __exit__(self, *exc: object) -> None:
        self.close()
