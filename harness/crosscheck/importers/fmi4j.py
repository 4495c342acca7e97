"""FMI4j (JVM, Maven Central `info.laht.fmi4j:fmi-import`) as an importer, via crosscheck/java.

The Java driver (`crosscheck/java/src/main/java/shroudedblade/Fmi4jDriver.java`) reads the input
plan CSV written by `InputPlan.write_csv`, passes t_k and t_{k+1} - t_k from it to fmi2DoStep (so
the grid is the plan's own, nothing accumulated) and, for a plan of order > 0, sets the input
derivatives through FMI4j's `setRealInputDerivatives`. `build()` runs Maven (offline first, online
if the local repository lacks something); `run()` calls `java` and reads the output CSV back.
"""

from __future__ import annotations

import os
import re
import shutil
import subprocess
import tempfile
import time as _time
from pathlib import Path

import numpy as np

from harness.fmu.build import REPO_ROOT
from harness.crosscheck.common import Run, outputs, result_array
from harness.crosscheck.plan import InputPlan, Scenario

JAVA_DIR = REPO_ROOT / "crosscheck" / "java"
MAIN_CLASS = "shroudedblade.Fmi4jDriver"
ME_CLASS = "shroudedblade.Fmi4jMeDriver"  # model exchange (FMI4j has no bundled solver: RK4 + bisection)


class Fmi4jError(RuntimeError):
    """Maven or the Java driver failed; the message holds the command and its output."""


def version() -> str:
    """FMI4j version from the pom.xml property (the one Maven resolves)."""
    m = re.search(r"<fmi4j.version>([^<]+)</fmi4j.version>", (JAVA_DIR / "pom.xml").read_text())
    return m.group(1) if m else "?"


def _classpath() -> str:
    return f"{JAVA_DIR / 'target' / 'classes'}{os.pathsep}{JAVA_DIR / 'target' / 'lib' / '*'}"


def build(quiet: bool = True) -> None:
    """`mvn -B package` in crosscheck/java: offline (-o) first, then with Maven Central if needed."""
    mvn = shutil.which("mvn")
    if mvn is None:
        raise Fmi4jError("`mvn` not found: install Maven (Debian: apt-get install -y maven) and JDK 17")
    base = [mvn, "-B"] + (["-q"] if quiet else []) + ["-f", str(JAVA_DIR / "pom.xml"), "package"]
    proc = subprocess.run(base[:1] + ["-o"] + base[1:], capture_output=True, text=True)
    if proc.returncode != 0:
        proc = subprocess.run(base, capture_output=True, text=True)
    if proc.returncode != 0:
        raise Fmi4jError(f"`{' '.join(base)}` failed:\n{proc.stdout[-3000:]}\n{proc.stderr[-3000:]}")


def _is_built() -> bool:
    return (JAVA_DIR / "target" / "classes" / "shroudedblade" / "Fmi4jDriver.class").exists() and (
        JAVA_DIR / "target" / "lib"
    ).is_dir()


def run(
    fmu: Path,
    scenario: Scenario,
    plan: InputPlan,
    *,
    build_first: bool = True,
    model_exchange: bool = False,
    substep: float = 1e-6,
) -> Run:
    """Run the plan through FMI4j; the wall time is the driver's own (no JVM start-up), the one with
    the JVM's start-up is `extra["total_time"]` (neither goes into a note: notes are written to files).
    model_exchange: through FMI4j's ModelExchangeInstance (Fmi4jMeDriver: held inputs, RK4 with
    `substep` [s], events located by bisection); else co-simulation."""
    if build_first or not _is_built():
        build()
    java = shutil.which("java")
    if java is None:
        raise Fmi4jError("`java` not found: install a JDK 17 (Debian: apt-get install -y openjdk-17-jdk-headless)")
    outs = outputs(fmu)
    with tempfile.TemporaryDirectory(prefix="sb-fmi4j-") as tmp:
        plan_csv = plan.write_csv(Path(tmp) / "plan.csv")
        out_csv = Path(tmp) / "out.csv"
        # FMI4j extracts its JNI library and the FMU under java.io.tmpdir and leaves them: keep them in tmp
        cmd = [
            java,
            f"-Djava.io.tmpdir={tmp}",
            "-cp",
            _classpath(),
            ME_CLASS if model_exchange else MAIN_CLASS,
            "--fmu",
            str(Path(fmu).resolve()),
            "--plan",
            str(plan_csv),
            "--out",
            str(out_csv),
        ]
        if model_exchange:
            # --set takes Real parameters there (the FMU's Fw0 = 0 when the plan feeds aeroLoad)
            if any(not isinstance(v, float) for v in scenario.fmu_overrides().values()) or plan.order != 0:
                raise ValueError("the FMI4j model-exchange driver takes Real parameters only, with held inputs")
            cmd += ["--substep", repr(substep)]
        for name, value in scenario.fmu_overrides().items():
            cmd += ["--set", f"{name}={str(value).lower() if isinstance(value, bool) else value}"]
        t0 = _time.perf_counter()
        proc = subprocess.run(cmd, capture_output=True, text=True)
        total = _time.perf_counter() - t0
        if proc.returncode != 0:
            raise Fmi4jError(
                f"`{' '.join(cmd)}` exited {proc.returncode}:\n{proc.stdout[-2000:]}\n{proc.stderr[-2000:]}"
            )
        m = re.search(r"wallTime=([0-9.eE+-]+)", proc.stdout)
        wall = float(m.group(1)) if m else total
        data = np.genfromtxt(out_csv, delimiter=",", names=True, dtype=np.float64, deletechars="")
    names = [o.name for o in outs]
    if list(data.dtype.names) != ["time"] + names:
        raise Fmi4jError(f"FMI4j driver wrote columns {data.dtype.names}, expected time + {names}")
    inputs = "held" if plan.order == 0 else f"taylor{plan.order}"
    if model_exchange:
        m = re.search(r"events=(\d+)", proc.stdout)
        return Run(
            "FMI4j model exchange (Java driver, RK4)",
            version(),
            inputs,
            result_array(data["time"], {n: data[n] for n in names}),
            wall,
            note=f"ModelExchangeInstance, RK4 substep {substep!r} s, {m.group(1) if m else '?'} events located "
            "by bisection",
            extra={"total_time": total},
        )
    return Run(
        "FMI4j (Java driver)",
        version(),
        inputs,
        result_array(data["time"], {n: data[n] for n in names}),
        wall,
        note="t_k and h from the plan",
        extra={"total_time": total},
    )
