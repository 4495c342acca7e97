"""Build the FMUs (and the physics test library) with CMake into build/, once, under a file lock.

Used by `harness.fmu.blade` (build-if-needed) and the test session fixture. CMake decides what is out
of date; the lock keeps concurrent processes (pytest workers, sweeps) from building at once. An
installed package has its FMUs already (harness/paths.py): there `build` only checks that they are.
"""

from __future__ import annotations

import fcntl
import subprocess
import sys
from pathlib import Path

from harness.paths import BUILD_DIR, IN_CHECKOUT, INSTALLED_DIR, REPO_ROOT

FMU_PATH = BUILD_DIR / "ShroudedBlade.fmu"
FMU3_PATH = BUILD_DIR / "fmi3" / "ShroudedBlade.fmu"  # FMI 3.0 co-simulation, CMake target fmu3
EXCITATION_FMU = BUILD_DIR / "Excitation.fmu"
PHYSICS_LIB = BUILD_DIR / "libsbphysics.so"
# CMake target -> its file under BUILD_DIR (those an installed package carries; sbphysics is for tests)
TARGET_FILES = {
    "fmu": "ShroudedBlade.fmu",
    "fmu3": "fmi3/ShroudedBlade.fmu",
    "excitation_fmu": "Excitation.fmu",
    "blade_external_fmu": "BladeExternalContact.fmu",
    "shroud_contact_fmu": "ShroudContact.fmu",
    "ring_master": "libring_master.so",
}


class BuildError(RuntimeError):
    """CMake failed; the message carries its output."""


def build(targets: tuple[str, ...] = ("fmu", "excitation_fmu", "sbphysics"), build_dir: Path = BUILD_DIR) -> Path:
    """Configure (first time) and build `targets`; returns the FMU path. Installed: checks that the
    targets' files are in the package (nothing to build)."""
    if not IN_CHECKOUT:
        return _installed(targets)
    build_dir.mkdir(parents=True, exist_ok=True)
    with open(build_dir / ".build.lock", "w") as lock:
        fcntl.flock(lock, fcntl.LOCK_EX)
        cmds = []
        if not (build_dir / "CMakeCache.txt").exists():
            cmds.append(
                [
                    "cmake",
                    "-S",
                    str(REPO_ROOT),
                    "-B",
                    str(build_dir),
                    "-DCMAKE_BUILD_TYPE=Release",
                    f"-DPython3_EXECUTABLE={sys.executable}",
                ]
            )
        cmds.append(["cmake", "--build", str(build_dir), "-j", "2", "--target", *targets])
        for cmd in cmds:
            proc = subprocess.run(cmd, capture_output=True, text=True)
            if proc.returncode != 0:
                raise BuildError(f"`{' '.join(cmd)}` failed:\n{proc.stdout[-4000:]}\n{proc.stderr[-4000:]}")
    return build_dir / "ShroudedBlade.fmu"


# FMU name (its file under BUILD_DIR without .fmu) -> CMake target
FMU_TARGETS = {f.removesuffix(".fmu"): t for t, f in TARGET_FILES.items() if f.endswith(".fmu")}


def fmu_file(name: str) -> Path:
    """The FMU `name` (a key of FMU_TARGETS): the installed package's, or the checkout's build/ one,
    built if out of date."""
    if name not in FMU_TARGETS:
        raise KeyError(f"no FMU named {name!r}: choose from {', '.join(FMU_TARGETS)}")
    build((FMU_TARGETS[name],))
    return BUILD_DIR / TARGET_FILES[FMU_TARGETS[name]]


def _installed(targets: tuple[str, ...]) -> Path:
    for t in targets:
        path = INSTALLED_DIR / TARGET_FILES.get(t, t)
        if not path.is_file():
            raise BuildError(
                f"{path} is not installed (CMake target {t!r}): the installed harness carries only"
                f" {', '.join(TARGET_FILES.values())}; reinstall it with `pip install` from the sources"
            )
    return INSTALLED_DIR / TARGET_FILES["fmu"]


# fmpy's CMake project (fmpy/c-code/CMakeLists.txt) links no library, and <SourceFiles> in FMI 2.0
# has no place to name one: without this the binary leaves sin/cos/acos undefined and loads only
# into processes that already hold libm (Python), not into a C master. STANDARD_LIBRARIES
# goes at the end of the link line, so it also holds with --as-needed.
REBUILD_CMAKE_OPTIONS = {"CMAKE_C_STANDARD_LIBRARIES:STRING": "-lm"}


def rebuild_binary(unzipdir: Path, build_dir: Path) -> None:
    """Compile an extracted FMU's `sources/` into its binaries/ with fmpy.build.build_platform_binary
    (+ REBUILD_CMAKE_OPTIONS), in a subprocess so CMake's output is captured (shown on failure)."""
    code = (
        "import sys; from fmpy.build import build_platform_binary; "
        f"build_platform_binary(sys.argv[1], build_dir=sys.argv[2], cmake_options={REBUILD_CMAKE_OPTIONS!r})"
    )
    proc = subprocess.run([sys.executable, "-c", code, str(unzipdir), str(build_dir)], capture_output=True, text=True)
    if proc.returncode != 0:
        raise BuildError(f"fmpy.build.build_platform_binary failed:\n{proc.stdout[-3000:]}\n{proc.stderr[-3000:]}")
