"""Which importer takes which flavour of the FMU (FMI 2.0 CS, FMI 2.0 ME, FMI 3.0 CS), tried as a
new user would: load the FMU, initialize, take a few steps, read an output.

build/ShroudedBlade.fmu carries both <CoSimulation> and <ModelExchange>: a co-simulation-only tool
simply picks the co-simulation face, so whether a tool imports model exchange is asked with
`me_only_copy()`, the same FMU with <CoSimulation> removed from its modelDescription.xml. libcosim
and Ecos are tried in a child process (`probe`, which runs `child_probe` there): both crash
(SIGSEGV) on an FMU they cannot use, which must not take the caller down.
"""

from __future__ import annotations

import re
import signal
import subprocess
import sys
import zipfile
from dataclasses import dataclass
from pathlib import Path

STEP = 1e-4  # [s] communication step of the probe
STEPS = 10


@dataclass(frozen=True)
class Observation:
    ok: bool
    text: str  # what happened, for the README table


def me_only_copy(fmu: Path, dest: Path) -> Path:
    """`fmu` with <CoSimulation> removed from modelDescription.xml (every other file unchanged)."""
    dest.parent.mkdir(parents=True, exist_ok=True)
    with zipfile.ZipFile(fmu) as src, zipfile.ZipFile(dest, "w", zipfile.ZIP_DEFLATED) as out:
        for item in src.infolist():
            data = src.read(item.filename)
            if item.filename == "modelDescription.xml":
                text, n = re.subn(r"\s*<CoSimulation\b.*?(/>|</CoSimulation>)", "", data.decode(), flags=re.S)
                if n != 1:
                    raise ValueError(f"{fmu}: expected one <CoSimulation> element, found {n}")
                data = text.encode()
            out.writestr(item, data)
    return dest


def _libcosim(fmu: str) -> float:
    # optional dependency (extra `crosscheck`): imported only when this runs
    from libcosimpy.CosimExecution import CosimExecution
    from libcosimpy.CosimLogging import CosimLogLevel, log_output_level
    from libcosimpy.CosimObserver import CosimObserver
    from libcosimpy.CosimSlave import CosimLocalSlave

    log_output_level(CosimLogLevel.ERROR)
    ex = CosimExecution.from_step_size(step_size=round(STEP * 1e9))
    idx = ex.add_local_slave(local_slave=CosimLocalSlave(fmu_path=fmu, instance_name="blade"))
    if idx < 0:
        raise RuntimeError("add_local_slave returned -1")
    observer = CosimObserver.create_last_value()
    ex.add_observer(observer=observer)
    if not ex.simulate_until(target_time=round(STEPS * STEP * 1e9)):
        raise RuntimeError("simulate_until failed")
    return observer.last_real_values(slave_index=idx, variable_references=[50])[0]


def _ecos(fmu: str) -> float:
    # optional dependency (extra `crosscheck`): imported only when this runs
    from ecospy import EcosSimulation, EcosSimulationStructure

    st = EcosSimulationStructure()
    st.add_model("blade", fmu)
    sim = EcosSimulation(structure=st, step_size=STEP)
    if not sim.init(0.0):
        raise RuntimeError("init failed")
    sim.step(STEPS)
    return sim.get_real("blade::tipDisplacement")


def probe(tool: str, fmu: Path, timeout: float = 120.0) -> Observation:
    """Load, initialize and step `fmu` in `tool` (libcosim or ecos) in a child process."""
    proc = subprocess.run(
        [sys.executable, "-c", _CHILD, tool, str(fmu)], capture_output=True, text=True, timeout=timeout
    )
    if proc.returncode == 0 and "tipDisplacement=" in proc.stdout:
        return Observation(True, f"ran {STEPS} steps of {STEP} s")
    if proc.returncode < 0:
        return Observation(False, f"the process died with {signal.Signals(-proc.returncode).name}")
    last = (proc.stderr.strip().splitlines() or ["no message"])[-1]
    return Observation(False, f"refused: {last[:200]}")


def child_probe(tool: str, fmu: str) -> int:
    """In the child process of `probe`: step `fmu` in `tool` and print the tip displacement reached."""
    q = {"libcosim": _libcosim, "ecos": _ecos}[tool](fmu)
    print(f"tipDisplacement={q!r}")
    return 0


# the child's program: `child_probe(TOOL, FMU)` with the arguments after -c
_CHILD = "import sys; from harness.crosscheck.flavours import child_probe; sys.exit(child_probe(*sys.argv[1:]))"
