"""Every FMU binary links what it uses, so a C master without libm can load it, and
no co-simulation binary links model-exchange code.

For each FMU the build produces (ShroudedBlade, Excitation, BladeExternalContact; ShroudContact:
the ldd check, its outputs are 0 at rest) and for the same FMU rebuilt from its
own `sources/` by fmpy.build (harness.crosscheck.static.rebuild_from_sources):
- `ldd -r` on the binary reports no undefined symbol;
- tests/c/dlopen_step (a C program built here without -lm, checked to have no libm in its
  DT_NEEDED) dlopens it with RTLD_NOW, instantiates, takes one step and prints an output, which
  must equal what fmpy reads from the same binary after the same step (same code, same inputs:
  equal to the last bit).
Before the fix the Excitation binary failed both checks with `undefined symbol: sin`.
"""

from __future__ import annotations

import os
import re
import shutil
import subprocess
import zipfile
from pathlib import Path

import fmpy
import pytest
from fmpy import read_model_description
from fmpy.fmi2 import FMU2Slave

from harness.fmu import build as _build
from harness.crosscheck.static import rebuild_from_sources

LOADER_SRC = Path(__file__).resolve().parents[1] / "c" / "dlopen_step.c"
FMI_HEADERS = Path(fmpy.__file__).parent / "c-code"
# (FMU, output read after the step): naturalFrequency of the blade, aeroLoad (a sine) of the excitation
CASES = {
    "ShroudedBlade": (_build.FMU_PATH, "naturalFrequency"),
    "Excitation": (_build.EXCITATION_FMU, "aeroLoad"),
    "BladeExternalContact": (_build.BUILD_DIR / "BladeExternalContact.fmu", "naturalFrequency"),
}


def _needed(binary: Path) -> list[str]:
    out = subprocess.run(["readelf", "-d", str(binary)], capture_output=True, text=True, check=True).stdout
    return [line.split("[")[1].rstrip("]") for line in out.splitlines() if "(NEEDED)" in line]


@pytest.fixture(scope="module")
def loader(tmp_path_factory) -> Path:
    exe = tmp_path_factory.mktemp("loader") / "dlopen_step"
    subprocess.run(
        ["cc", "-std=c99", "-Wall", "-Wextra", "-Werror", f"-I{FMI_HEADERS}", str(LOADER_SRC), "-o", str(exe), "-ldl"],
        check=True,
    )
    assert not any(n.startswith("libm.") for n in _needed(exe)), "the loader must not hold libm itself"
    return exe


@pytest.fixture(scope="module")
def unpacked(tmp_path_factory) -> dict[tuple[str, str], Path]:
    """(model, 'built' | 'rebuilt') -> extracted FMU directory."""
    _build.build(("fmu", "excitation_fmu", "blade_external_fmu", "shroud_contact_fmu"))
    root = tmp_path_factory.mktemp("fmus")
    dirs = {}
    for model, (fmu, _) in CASES.items():
        rebuilt = rebuild_from_sources(fmu, root / f"{model}_rebuilt.fmu")
        for flavour, path in (("built", fmu), ("rebuilt", rebuilt)):
            d = root / f"{model}_{flavour}"
            with zipfile.ZipFile(path) as z:
                z.extractall(d)
            dirs[model, flavour] = d
    return dirs


def _fmpy_one_step(unzipdir: Path, output: str) -> float:
    md = read_model_description(str(unzipdir))
    vr = next(v.valueReference for v in md.modelVariables if v.name == output)
    fmu = FMU2Slave(
        guid=md.guid, unzipDirectory=str(unzipdir), modelIdentifier=md.coSimulation.modelIdentifier, instanceName="fmpy"
    )
    try:
        fmu.instantiate()
        fmu.setupExperiment(startTime=0.0, stopTime=1.0)
        fmu.enterInitializationMode()
        fmu.exitInitializationMode()
        fmu.doStep(0.0, 1e-4)
        return fmu.getReal([vr])[0]
    finally:
        fmu.terminate()
        fmu.freeInstance()


@pytest.mark.parametrize("flavour", ["built", "rebuilt"])
@pytest.mark.parametrize("model", list(CASES))
def test_binary_loads_in_a_c_master_without_libm(model, flavour, loader, unpacked):
    unzipdir = unpacked[model, flavour]
    binary = unzipdir / "binaries" / "linux64" / f"{model}.so"
    ldd = subprocess.run(["ldd", "-r", str(binary)], capture_output=True, text=True)
    assert "undefined symbol" not in ldd.stdout + ldd.stderr, ldd.stdout + ldd.stderr

    md = read_model_description(str(unzipdir))
    output = CASES[model][1]
    vr = next(v.valueReference for v in md.modelVariables if v.name == output)
    env = {k: v for k, v in os.environ.items() if k != "LD_PRELOAD"}
    proc = subprocess.run(
        [str(loader), str(binary), md.guid, (unzipdir / "resources").as_uri(), str(vr)],
        capture_output=True,
        text=True,
        env=env,
    )
    assert proc.returncode == 0, proc.stderr
    value = float(proc.stdout.split()[1])
    assert value == _fmpy_one_step(unzipdir, output)
    assert value != 0.0  # the output is a computed one (a frequency, a sine), not an untouched start value


def test_loader_catches_a_binary_without_libm(loader, tmp_path):
    """The check can fail: the Excitation source compiled without -lm (as fmpy.build did before the
    fix) is refused by the loader with an undefined symbol."""
    with zipfile.ZipFile(_build.EXCITATION_FMU) as z:  # the shipped sources/, as fmpy.build compiles them
        z.extractall(tmp_path / "fmu")
    sources = tmp_path / "fmu" / "sources"
    files = read_model_description(str(_build.EXCITATION_FMU)).buildConfigurations[0].sourceFileSets[0].sourceFiles
    so = tmp_path / "Excitation.so"
    subprocess.run(
        [
            "cc",
            "-std=c99",
            "-shared",
            "-fPIC",
            "-O2",
            f"-I{FMI_HEADERS}",
            f"-I{sources}",
            *[str(sources / f) for f in files],
            "-o",
            str(so),
        ],
        check=True,
    )
    proc = subprocess.run([str(loader), str(so), "{x}", "file:///tmp", "10"], capture_output=True, text=True)
    assert proc.returncode == 1
    assert "undefined symbol" in proc.stderr
    shutil.rmtree(tmp_path, ignore_errors=True)


@pytest.mark.parametrize("flavour", ["built", "rebuilt"])
def test_shroud_contact_links_its_symbols(flavour, unpacked, tmp_path):
    """ShroudContact (outputs 0 at rest, so no loader value check): no undefined symbol, built and
    rebuilt from its sources/ by fmpy.build."""
    fmu = _build.BUILD_DIR / "ShroudContact.fmu"
    path = fmu if flavour == "built" else rebuild_from_sources(fmu, tmp_path / "ShroudContact_rebuilt.fmu")
    with zipfile.ZipFile(path) as z:
        z.extractall(tmp_path / "sc")
    binary = tmp_path / "sc" / "binaries" / "linux64" / "ShroudContact.so"
    ldd = subprocess.run(["ldd", "-r", str(binary)], capture_output=True, text=True)
    assert "undefined symbol" not in ldd.stdout + ldd.stderr, ldd.stdout + ldd.stderr
    assert any(n.startswith("libm.") for n in _needed(binary))


# --- model exchange only where it is offered -------------------------------------------------------
# The model-exchange code is fmi/fmi2_me.c (the FMI 2.0 face) and models/ShroudedBlade/model_me.c (the
# model's part, reached only through the table fmiModelExchange). The FMI 2.0 ShroudedBlade binary
# (co-simulation + model exchange) links both; the FMI 3.0 co-simulation binary and the FMI 2.0
# co-simulation-only FMUs link neither: no symbol of them is defined or referenced there (`nm`).
FMU_SRC = _build.REPO_ROOT / "fmu_src"
ME_SOURCES = (FMU_SRC / "fmi" / "fmi2_me.c", FMU_SRC / "models" / "ShroudedBlade" / "model_me.c")
_DEFINITION = re.compile(r"^(?:static\s+)?(?:const\s+)?\w[\w\s*]*?\b(\w+)\s*(?:\(|=|\[)", re.M)


def _defined(source: Path) -> set[str]:
    """Functions and file-scope objects a C file defines (declarations start in column 0 here)."""
    return {m.group(1) for m in _DEFINITION.finditer(source.read_text()) if not m.group(0).startswith("#")}


def _symbols(binary: Path) -> set[str]:
    """Every symbol name in the binary's symbol table, defined or undefined; compiler suffixes
    (eventUpdate.isra.0, holdContactState.part.0) stripped."""
    out = subprocess.run(["nm", str(binary)], capture_output=True, text=True, check=True).stdout
    return {line.split()[-1].split(".")[0] for line in out.splitlines() if line.strip()}


@pytest.fixture(scope="module")
def me_names() -> set[str]:
    """The names only the model-exchange files define (a static helper of the same name elsewhere,
    e.g. loadX, could not be told apart by name: left out), and fmiModelExchange (a co-simulation-only
    model defines it as NULL)."""
    _build.build(("fmu", "fmu3", "excitation_fmu", "blade_external_fmu", "shroud_contact_fmu"))
    others = set().union(*(_defined(c) for c in FMU_SRC.rglob("*.c") if c not in ME_SOURCES))
    names = set().union(*(_defined(c) for c in ME_SOURCES)) - others | {"fmiModelExchange"}
    # the parse found the face's functions and the model's table and hooks
    assert {
        "fmi2GetDerivatives",
        "fmi2NewDiscreteStates",
        "fmiModelExchange",
        "eventUpdate",
        "holdContactState",
        "heldOutputs",
    } <= names, sorted(names)
    return names


def test_the_fmi2_binary_links_model_exchange(me_names):
    """The check can see model-exchange code: in the FMI 2.0 ShroudedBlade binary, which offers it, are
    the exported fmi2 model-exchange functions and every function of the model's table (a function
    reached through a pointer is never inlined away)."""
    symbols = _symbols(_build.BUILD_DIR / "ShroudedBlade.so")
    table = {
        "getStates",
        "setStates",
        "nominals",
        "derivatives",
        "eventIndicators",
        "eventUpdate",
        "afterBuild",
        "heldOutputs",
        "fmiModelExchange",
    }
    assert table <= symbols, sorted(table - symbols)
    assert {n for n in me_names if n.startswith("fmi2")} <= symbols


@pytest.mark.parametrize(
    "binary", ["fmi3/ShroudedBlade.so", "Excitation.so", "BladeExternalContact.so", "ShroudContact.so"]
)
def test_co_simulation_binaries_link_no_model_exchange(binary, me_names):
    # a co-simulation-only model defines fmiModelExchange as NULL for the FMI 2.0 face; the FMI 3.0
    # binary has not even that
    allowed = set() if binary.startswith("fmi3/") else {"fmiModelExchange"}
    linked = (me_names - allowed) & _symbols(_build.BUILD_DIR / binary)
    assert not linked, f"{binary} links model-exchange code: {sorted(linked)}"
