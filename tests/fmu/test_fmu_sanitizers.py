"""The FMU under AddressSanitizer + UndefinedBehaviorSanitizer: the C importer and the Python suites.

build-asan/ holds the FMU compiled with -fsanitize=address,undefined,float-cast-overflow
-fno-omit-frame-pointer -fno-sanitize-recover=all and tests/c/sb_importer (the same flags), a
small FMI importer in C with a real variadic logger. The importer does full runs (3000 steps with
inputs and 8 input derivatives, FMU state get/set, serialize, deserialize into a new instance,
terminate, reset, rerun bit-identically) for every friction model, then every error path (bad
instantiation arguments and URIs, invalid parameters and inputs, call order, bad steps, bad value
references, NULL pointers and components, every truncation and single-byte corruption of a state
blob). A sanitizer report or a failed check makes the exit code non-zero.

The Python fuzz, error and state suites run again against the sanitized binary in a child
pytest: `LD_PRELOAD=$(cc -print-file-name=libasan.so) ASAN_OPTIONS=detect_leaks=0
SB_FMU_BINARY=build-asan/ShroudedBlade.so .venv/bin/python -m pytest tests/fmu/test_fmu_fuzz.py`
(the interpreter is not instrumented, so libasan must be loaded first and leak checking is left to
the C importer, see tests/fmu/test_fmu_leaks.py).
"""

from __future__ import annotations

import os
import re
import subprocess
import sys
from pathlib import Path

import pytest

from tests.support import fmi2raw as F

pytestmark = pytest.mark.sanitizer

TESTS = Path(__file__).resolve().parents[1]


@pytest.fixture(scope="module")
def asan_build() -> tuple[Path, Path]:
    return F.build_asan()


def check_clean(proc: subprocess.CompletedProcess, what: str) -> None:
    report = F.SANITIZER_REPORT.search(proc.stderr)
    assert report is None, f"{what}: sanitizer report:\n{proc.stderr[-6000:]}"
    assert proc.returncode == 0, f"{what}: exit {proc.returncode}\n{proc.stdout[-3000:]}\n{proc.stderr[-6000:]}"


def test_c_importer_full_runs_and_error_paths(asan_build: tuple[Path, Path]) -> None:
    binary, importer = asan_build
    proc = subprocess.run(
        [str(importer), str(binary), "full"],
        capture_output=True,
        text=True,
        timeout=900,
        env=F.sanitizer_env(python=False),
    )
    check_clean(proc, "sb_importer full")
    assert " 0 failures" in proc.stdout, proc.stdout
    print(proc.stdout)


def run_python_suite(
    binary: Path, args: list[str], extra_env: dict[str, str] | None = None, timeout: float = 1800
) -> subprocess.CompletedProcess:
    """A child pytest against the sanitized FMU. -s: a sanitizer report must reach the real
    stderr (pytest's fd capture would swallow it when the sanitizer ends the process)."""
    env = F.sanitizer_env(python=True)
    env["SB_FMU_BINARY"] = str(binary)
    env["SB_FMU3_BINARY"] = str(F.ASAN_FMI3_BINARY)  # the FMI 3.0 rows and fuzz machine (fmi3raw.py)
    env.update(extra_env or {})
    return subprocess.run(
        [sys.executable, "-m", "pytest", "-q", "-s", "-p", "no:cacheprovider", "-o", "addopts=", *args],
        cwd=str(TESTS.parent),
        capture_output=True,
        text=True,
        timeout=timeout,
        env=env,
    )


def check_no_memory_errors(proc: subprocess.CompletedProcess, what: str) -> None:
    """No sanitizer report, no crash, and every test of the child run passed: a test that fails
    only on the sanitized build (e.g. a value read from uninitialised memory) fails this one."""
    out = proc.stdout + proc.stderr
    report = F.SANITIZER_REPORT.search(out)
    assert report is None, f"{what}: sanitizer report:\n{out[max(0, report.start() - 200) :][:8000]}"
    failed = [ln for ln in proc.stdout.splitlines() if ln.startswith(("FAILED", "ERROR"))]
    assert proc.returncode == 0 and not failed, (
        f"{what}: exit {proc.returncode} (1 a test failed, 98 UBSan, "
        f"99 ASan, <0 a signal)\n" + "\n".join(failed) + f"\n{proc.stdout[-3000:]}\n{proc.stderr[-6000:]}"
    )
    assert re.search(r"\d+ passed", proc.stdout), proc.stdout[-3000:]  # tests ran


def test_python_error_and_state_suites_under_asan(asan_build: tuple[Path, Path]) -> None:
    binary, _ = asan_build
    proc = run_python_suite(
        binary, ["tests/fmu/test_fmu_errors.py", "tests/fmu/test_fmu_state.py", "tests/fmu/test_fmu_threads.py"]
    )
    check_no_memory_errors(proc, "errors/state/threads suites under ASan")


def test_model_exchange_under_asan(asan_build: tuple[Path, Path]) -> None:
    """The raw model-exchange calls of tests/fmu/test_fmi2_me.py (sequence, events, invalid calls, FMU
    states) on the sanitizer build."""
    binary, _ = asan_build
    proc = run_python_suite(binary, ["tests/fmu/test_fmi2_me.py", "-k", "me_sequence or invalid_me or me_fmu_state"])
    check_no_memory_errors(proc, "model exchange under ASan")


def test_fuzz_under_asan(asan_build: tuple[Path, Path]) -> None:
    binary, _ = asan_build
    proc = run_python_suite(
        binary,
        ["tests/fmu/test_fmu_fuzz.py", "-k", "not long"],
        {"SB_FUZZ_EXAMPLES": os.environ.get("SB_ASAN_FUZZ_EXAMPLES", "300")},
    )
    check_no_memory_errors(proc, "fuzz under ASan")
    print([ln for ln in proc.stdout.splitlines() if ln.startswith("fuzz")])  # every machine


@pytest.mark.slow
def test_fuzz_under_asan_long(asan_build: tuple[Path, Path]) -> None:
    binary, _ = asan_build
    proc = run_python_suite(
        binary,
        ["tests/fmu/test_fmu_fuzz.py", "-k", "not long"],
        {"SB_FUZZ_EXAMPLES": "3000", "SB_FUZZ_RANDOM": "1"},
        timeout=7200,
    )
    check_no_memory_errors(proc, "long fuzz under ASan")
    print([ln for ln in proc.stdout.splitlines() if ln.startswith("fuzz")])  # every machine
