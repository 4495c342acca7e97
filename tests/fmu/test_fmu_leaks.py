"""No memory leaks and no drift over many instantiate/free and reset cycles.

LeakSanitizer (part of AddressSanitizer on Linux) watches tests/c/sb_importer in its `leaks`
mode against the sanitized FMU (build-asan/): N instantiate/initialize/20 steps/free cycles (each
leaves one FMU state for fmi2FreeInstance to release, as the standard says it must) and M
fmi2Reset cycles on one instance (with state get/serialize/deserialize/free every 10th cycle and
fmi2Terminate every 2nd). Every cycle must give bit-identically the same outputs as the first
(checked inside the importer) and LeakSanitizer must report nothing at exit. The default run does
the full 1,000 instantiate/free and 10,000 reset cycles (about 5 s); the `slow` test ten times
more.
In this process (no sanitizer) the same cycles check that results never drift and that the
FMU never calls the memory callbacks.
"""

from __future__ import annotations

import subprocess
from pathlib import Path

import numpy as np
import pytest

from tests.support import fmi2raw as F
from tests.support.fmi2raw import OK, Fmi2Library, Instance


@pytest.fixture(scope="module")
def asan_build() -> tuple[Path, Path]:
    return F.build_asan()


def run_leak_cycles(asan_build: tuple[Path, Path], n_inst: int, n_reset: int) -> str:
    binary, importer = asan_build
    proc = subprocess.run(
        [str(importer), str(binary), "leaks", str(n_inst), str(n_reset)],
        capture_output=True,
        text=True,
        timeout=3600,
        env=F.sanitizer_env(python=False),
    )
    assert F.SANITIZER_REPORT.search(proc.stderr) is None, proc.stderr[-6000:]
    assert proc.returncode == 0, proc.stdout[-2000:] + proc.stderr[-4000:]
    assert f"leak cycles: {n_inst} instantiate/free, {n_reset} reset" in proc.stdout
    assert " 0 failures" in proc.stdout
    return proc.stdout


@pytest.mark.sanitizer  # the sanitized build (40 s): with the sanitizer tests in `make test-slow`
def test_leak_cycles_under_lsan(asan_build: tuple[Path, Path]) -> None:
    print(run_leak_cycles(asan_build, 1000, 10000))


@pytest.mark.slow
def test_leak_cycles_under_lsan_long(asan_build: tuple[Path, Path]) -> None:
    print(run_leak_cycles(asan_build, 10000, 100000))


def test_cycles_in_process_give_identical_results(lib: Fmi2Library) -> None:
    params = {"frictionModel": 3, "d": 2e-5}
    ref = None
    for _ in range(100):
        with Instance(lib, logging_on=False) as c:
            assert c.initialize(params) == OK
            st, out = F.run_steps(c, 0.0, 1e-4, 20, Fw0=300.0)
            assert st == OK
            c.get_state()  # left for fmi2FreeInstance
            ref = out if ref is None else ref
            assert np.array_equal(out, ref)
    with Instance(lib, logging_on=False) as c:
        for i in range(300):
            assert c.reset() == OK
            assert c.initialize(params) == OK
            st, out = F.run_steps(c, 0.0, 1e-4, 20, Fw0=300.0)
            assert st == OK and np.array_equal(out, ref), f"reset cycle {i} drifted"
            if i % 3 == 0:
                assert c.terminate() == OK
    assert lib.memory_callback_calls() == 0
