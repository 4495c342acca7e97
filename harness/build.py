"""Build the FMU (and the physics test library) with CMake into build/, once, under a file lock.

Used by `harness.fmu` (build-if-needed) and the test session fixture. CMake decides what is out
of date; the lock keeps concurrent processes (pytest workers, sweeps) from building at once.
"""
from __future__ import annotations

import fcntl
import subprocess
import sys
from pathlib import Path

REPO_ROOT = Path(__file__).resolve().parent.parent
BUILD_DIR = REPO_ROOT / "build"
FMU_PATH = BUILD_DIR / "ShroudedBlade.fmu"
PHYSICS_LIB = BUILD_DIR / "libsbphysics.so"


class BuildError(RuntimeError):
    """CMake failed; the message carries its output."""


def build(targets: tuple[str, ...] = ("fmu", "sbphysics"), build_dir: Path = BUILD_DIR) -> Path:
    """Configure (first time) and build `targets`; returns the FMU path."""
    build_dir.mkdir(parents=True, exist_ok=True)
    with open(build_dir / ".build.lock", "w") as lock:
        fcntl.flock(lock, fcntl.LOCK_EX)
        cmds = []
        if not (build_dir / "CMakeCache.txt").exists():
            cmds.append(["cmake", "-S", str(REPO_ROOT), "-B", str(build_dir), "-DCMAKE_BUILD_TYPE=Release",
                         f"-DPython3_EXECUTABLE={sys.executable}"])
        cmds.append(["cmake", "--build", str(build_dir), "-j", "2", "--target", *targets])
        for cmd in cmds:
            proc = subprocess.run(cmd, capture_output=True, text=True)
            if proc.returncode != 0:
                raise BuildError(f"`{' '.join(cmd)}` failed:\n{proc.stdout[-4000:]}\n{proc.stderr[-4000:]}")
    return build_dir / "ShroudedBlade.fmu"
