"""Build the FMU (and the physics test library) with CMake into build/, once, under a file lock.

Used by `harness.fmu.blade` (build-if-needed) and the test session fixture. CMake decides what is out
of date; the lock keeps concurrent processes (pytest workers, sweeps) from building at once.
"""
from __future__ import annotations

import fcntl
import subprocess
import sys
from pathlib import Path

REPO_ROOT = Path(__file__).resolve().parents[2]
BUILD_DIR = REPO_ROOT / "build"
FMU_PATH = BUILD_DIR / "ShroudedBlade.fmu"
FMU3_PATH = BUILD_DIR / "fmi3" / "ShroudedBlade.fmu"  # FMI 3.0 co-simulation, CMake target fmu3
EXCITATION_FMU = BUILD_DIR / "Excitation.fmu"
PHYSICS_LIB = BUILD_DIR / "libsbphysics.so"


class BuildError(RuntimeError):
    """CMake failed; the message carries its output."""


def build(targets: tuple[str, ...] = ("fmu", "excitation_fmu", "sbphysics"), build_dir: Path = BUILD_DIR) -> Path:
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


# fmpy's CMake project (fmpy/c-code/CMakeLists.txt) links no library, and <SourceFiles> in FMI 2.0
# has no place to name one: without this the binary leaves sin/cos/acos undefined and loads only
# into processes that already hold libm (Python), not into a C master. STANDARD_LIBRARIES
# goes at the end of the link line, so it also holds with --as-needed.
REBUILD_CMAKE_OPTIONS = {"CMAKE_C_STANDARD_LIBRARIES:STRING": "-lm"}


def rebuild_binary(unzipdir: Path, build_dir: Path) -> None:
    """Compile an extracted FMU's `sources/` into its binaries/ with fmpy.build.build_platform_binary
    (+ REBUILD_CMAKE_OPTIONS), in a subprocess so CMake's output is captured (shown on failure)."""
    code = ("import sys; from fmpy.build import build_platform_binary; "
            f"build_platform_binary(sys.argv[1], build_dir=sys.argv[2], cmake_options={REBUILD_CMAKE_OPTIONS!r})")
    proc = subprocess.run([sys.executable, "-c", code, str(unzipdir), str(build_dir)], capture_output=True, text=True)
    if proc.returncode != 0:
        raise BuildError(f"fmpy.build.build_platform_binary failed:\n{proc.stdout[-3000:]}\n{proc.stderr[-3000:]}")
