"""Static checks of the FMU archive: fmu-manipulation-toolbox's checker and fmpy's validation.

`fmutool -input X.fmu -check` validates modelDescription.xml against the FMI 2.0 XSD and checks the
rules the schema cannot express (causality/variability/initial combinations, start values,
ModelStructure completeness and dependencies); it exits non-zero and logs `ERROR` lines on any
violation. `fmpy.validation.validate_fmu` is fmpy's own schema + consistency check. Both are run
as separate processes/calls and their messages are kept for the report.
"""

from __future__ import annotations

import shutil
import subprocess
import sys
import tempfile
import time as _time
import zipfile
from dataclasses import dataclass, field
from importlib.metadata import version as dist_version
from pathlib import Path

import fmpy
from fmpy.validation import validate_fmu

from harness.fmu.build import rebuild_binary


@dataclass
class StaticResult:
    tool: str
    version: str
    ok: bool
    wall_time: float
    messages: list[str] = field(default_factory=list)
    command: str = ""


def _fmutool() -> list[str]:
    exe = Path(sys.executable).parent / "fmutool"
    if exe.exists():
        return [str(exe)]
    found = shutil.which("fmutool")
    if found:
        return [found]
    raise FileNotFoundError("fmutool not found: pip install fmu-manipulation-toolbox")


def fmutool_check(fmu: Path) -> StaticResult:
    """fmu-manipulation-toolbox's `-check` (XSD + semantic rules); ok iff exit code 0 and no ERROR."""
    cmd = _fmutool() + ["-input", str(fmu), "-check"]
    t0 = _time.perf_counter()
    proc = subprocess.run(cmd, capture_output=True, text=True)
    wall = _time.perf_counter() - t0
    lines = [ln.rstrip() for ln in (proc.stdout + proc.stderr).splitlines() if ln.strip()]
    errors = [ln for ln in lines if ln.startswith("ERROR")]
    ok = proc.returncode == 0 and not errors
    return StaticResult(
        "fmu-manipulation-toolbox -check",
        dist_version("fmu-manipulation-toolbox"),
        ok,
        wall,
        errors if errors else lines,
        " ".join(cmd),
    )


def fmpy_validate(fmu: Path) -> StaticResult:
    """fmpy.validation.validate_fmu: the list of problems must be empty."""
    t0 = _time.perf_counter()
    problems = validate_fmu(str(fmu))
    return StaticResult(
        "fmpy validate_fmu",
        fmpy.__version__,
        not problems,
        _time.perf_counter() - t0,
        [str(p) for p in problems],
        f"fmpy.validation.validate_fmu({str(fmu)!r})",
    )


def rebuild_from_sources(fmu: Path, out_fmu: Path, build_dir: Path | None = None) -> Path:
    """Rebuild the FMU's binary from its own `sources/` with fmpy.build.build_platform_binary.

    The archive is extracted, its binaries/ removed, fmpy's CMake project compiles the files listed
    in <SourceFiles> with only sources/ and the FMI headers on the include path (linked with libm:
    harness.fmu.build.REBUILD_CMAKE_OPTIONS), and the result is zipped to `out_fmu`.
    """
    with tempfile.TemporaryDirectory(prefix="sb-rebuild-") as tmp:
        unzipdir = Path(tmp) / "fmu"
        with zipfile.ZipFile(fmu) as z:
            z.extractall(unzipdir)
        shutil.rmtree(unzipdir / "binaries", ignore_errors=True)
        bdir = Path(build_dir) if build_dir else Path(tmp) / "build"
        bdir.mkdir(parents=True, exist_ok=True)
        rebuild_binary(unzipdir, bdir)
        out_fmu = Path(out_fmu)
        out_fmu.parent.mkdir(parents=True, exist_ok=True)
        with zipfile.ZipFile(out_fmu, "w", zipfile.ZIP_DEFLATED) as z:
            for f in sorted(unzipdir.rglob("*")):
                if f.is_file():
                    z.write(f, f.relative_to(unzipdir).as_posix())
    return out_fmu
