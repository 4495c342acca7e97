"""Many FMU instances in parallel threads give exactly the serial results (no shared mutable state).

Each thread owns one instance (FMI 2.0 allows concurrent calls on different instances); ctypes
releases the GIL during every FMI call, so the instances really run at the same time on the
available cores. Every instance gets different parameters, so a global variable written by one
instance and read by another (a cache, a static buffer, a shared log buffer) would change some
result. The reference is the same runs done one after the other; the comparison is exact
(np.array_equal) because the computation is deterministic and must not depend on scheduling.
State get/serialize/deserialize and logging (with all categories enabled, so the logger is
called concurrently from several threads) are exercised in the threads too.
"""

from __future__ import annotations

import threading

import numpy as np
import pytest

from tests.support import fmi2raw as F
from tests.support.fmi2raw import OK, Fmi2Library, Instance

N_STEPS = 600
H = 1e-4

# eight different parameter sets (all friction models, formulations, speeds, gaps)
RUNS = [
    ({}, 5000.0),
    ({"frictionModel": 2, "amplitudeMode": 1}, 5200.0),
    ({"frictionModel": 3}, 4800.0),
    ({"frictionModel": 3, "d": 2e-5, "mu": 0.2}, 6000.0),
    ({"formulation": 2, "projection": 2}, 5000.0),
    ({"gating": False, "kn": 1e6}, 7000.0),
    ({"d": 5e-5, "engineOrder": 2}, 5000.0),
    ({"m0": 0.05, "gamma": 0.5}, 3000.0),
]


def one_run(lib: Fmi2Library, params: dict, speed: float, logging: bool) -> tuple[np.ndarray, bytes, np.ndarray]:
    """A run of N_STEPS; halfway the state is serialized, and the second half is repeated from
    the deserialized state. Returns (outputs, blob, repeated second half)."""
    with Instance(lib, logging_on=logging) as c:
        assert c.initialize(params) == OK, c.log_text()
        st, first = F.run_steps(c, 0.0, H, N_STEPS // 2, speed=speed, Fw0=200.0)
        assert st in (OK, F.WARNING), c.log_text()
        st, s = c.get_state()
        st2, blob = c.serialize(s)
        assert st == OK and st2 == OK
        st, second = F.run_steps(c, N_STEPS // 2 * H, H, N_STEPS // 2, speed=speed, Fw0=200.0)
        assert st in (OK, F.WARNING), c.log_text()
        c.free_state(s)
        st, s = c.deserialize(blob)
        assert st == OK and c.set_state(s) == OK
        st, again = F.run_steps(c, N_STEPS // 2 * H, H, N_STEPS // 2, speed=speed, Fw0=200.0)
        assert st in (OK, F.WARNING)
        c.free_state(s)
        return np.vstack([first, second]), blob, again


@pytest.mark.parametrize("logging", [False, True], ids=["quiet", "logging"])
def test_threads_match_serial(lib: Fmi2Library, logging: bool) -> None:
    serial = [one_run(lib, p, n, logging) for p, n in RUNS]
    for out, _, again in serial:  # each run is also self-consistent
        assert np.array_equal(out[N_STEPS // 2 :], again)
    # the runs differ from each other (otherwise the test could not see cross-talk)
    assert len({out.tobytes() for out, _, _ in serial}) == len(RUNS)

    results: list = [None] * len(RUNS)
    errors: list = []
    barrier = threading.Barrier(len(RUNS))

    def work(i: int) -> None:
        try:
            barrier.wait()
            results[i] = one_run(lib, *RUNS[i], logging)
        except BaseException as exc:  # noqa: BLE001 - reported below
            errors.append((i, repr(exc)))

    for _ in range(2):
        threads = [threading.Thread(target=work, args=(i,)) for i in range(len(RUNS))]
        for t in threads:
            t.start()
        for t in threads:
            t.join()
        assert not errors, errors
        for i, ((out, blob, again), (sout, sblob, sagain)) in enumerate(zip(results, serial)):
            assert np.array_equal(out, sout), f"run {i} differs in a thread"
            assert blob == sblob, f"run {i}: serialized state differs in a thread"
            assert np.array_equal(again, sagain)


def test_many_instances_alive_at_once(lib: Fmi2Library) -> None:
    # 64 instances interleaved step by step in one thread: the same as each one alone
    alone = []
    for i in range(8):
        with Instance(lib, logging_on=False) as c:
            assert c.initialize({"d": 2e-5 + 1e-6 * i}) == OK
            alone.append(F.run_steps(c, 0.0, H, 50)[1])
    insts = [Instance(lib, logging_on=False) for _ in range(64)]
    try:
        for k, c in enumerate(insts):
            assert c.initialize({"d": 2e-5 + 1e-6 * (k % 8)}) == OK
        rows: list[list] = [[] for _ in insts]
        for step in range(50):
            for k, c in enumerate(insts):
                st, out = F.run_steps(c, step * H, H, 1)
                assert st == OK
                rows[k].append(out[0])
        for k in range(64):
            assert np.array_equal(np.array(rows[k]), alone[k % 8])
    finally:
        for c in insts:
            c.free()
