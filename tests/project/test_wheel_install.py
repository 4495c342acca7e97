"""The installable product: `python -m build` makes an sdist and from it a wheel (scikit-build-core
compiles the FMUs with CMake), the wheel installs into a fresh venv, and the installed `harness`
works from a directory outside the checkout, with the FMUs that came in the wheel.

Every expected value is computed here, in the test process, from the checkout (its pyproject.toml,
its build/ FMU, its model description), never typed in. Time: the module's setup (sdist + wheel
in isolated build environments, a fresh venv with the wheel and its dependencies from pip's cache)
measured 196 s at load average 7 on the 2 shared cores; with less load, `build --wheel` alone took
18 s and the venv with the install 31 s; the commands take about 10 s more.
"""

from __future__ import annotations

import json
import math
import os
import subprocess
import sys
import tomllib
import zipfile
from pathlib import Path

import pytest

pytestmark = pytest.mark.slow  # builds a wheel with CMake in a fresh venv: 2.5 min

REPO = Path(__file__).resolve().parents[2]
SPEED = 7000.0  # [rpm]
RTOL = 1e-9  # the wheel's FMU is compiled from the same sources with the same flags as build/'s


def _run(cmd: list[str], cwd: Path, timeout: float = 600) -> subprocess.CompletedProcess:
    env = {k: v for k, v in os.environ.items() if k not in ("PYTHONPATH", "PYTHONHOME", "VIRTUAL_ENV")}
    proc = subprocess.run(cmd, cwd=cwd, env=env, capture_output=True, text=True, timeout=timeout)
    assert proc.returncode == 0, f"{' '.join(cmd)} failed:\n{proc.stdout[-3000:]}\n{proc.stderr[-3000:]}"
    return proc


@pytest.fixture(scope="module")
def installed(tmp_path_factory: pytest.TempPathFactory) -> dict[str, Path]:
    """A venv with the wheel `python -m build` made from the checkout installed (and nothing else
    of ours), and an empty working directory outside the checkout."""
    base = tmp_path_factory.mktemp("wheel")
    dist = base / "dist"
    _run([sys.executable, "-m", "build", "--outdir", str(dist), str(REPO)], cwd=base)
    (wheel,) = dist.glob("*.whl")
    venv = base / "venv"
    _run([sys.executable, "-m", "venv", str(venv)], cwd=base)
    _run([str(venv / "bin" / "python"), "-m", "pip", "install", "--quiet", str(wheel)], cwd=base)
    work = base / "elsewhere"
    work.mkdir()
    site = Path(
        _run(
            [str(venv / "bin" / "python"), "-c", "import sysconfig; print(sysconfig.get_paths()['platlib'])"], cwd=work
        ).stdout.strip()
    )
    return {"venv": venv, "work": work, "package": site / "harness", "wheel": wheel}


def _files(root: Path) -> set[Path]:
    return {p for p in root.rglob("*") if "__pycache__" not in p.parts}


def test_wheel_carries_the_fmus(installed):
    names = set(zipfile.ZipFile(installed["wheel"]).namelist())
    for f in (
        "ShroudedBlade.fmu",
        "fmi3/ShroudedBlade.fmu",
        "Excitation.fmu",
        "BladeExternalContact.fmu",
        "ShroudContact.fmu",
        "libring_master.so",
    ):
        assert f"harness/fmus/{f}" in names
    assert not any(n.startswith(("results/", "tests/", "build/")) for n in names)


def test_version(installed):
    with open(REPO / "pyproject.toml", "rb") as fh:
        version = tomllib.load(fh)["project"]["version"]
    out = _run([str(installed["venv"] / "bin" / "harness"), "--version"], cwd=installed["work"]).stdout
    assert out.strip() == f"harness {version}"


def test_help_both_ways(installed):
    bin_ = installed["venv"] / "bin"
    for cmd in ([str(bin_ / "harness"), "--help"], [str(bin_ / "python"), "-m", "harness", "--help"]):
        out = _run(cmd, cwd=installed["work"]).stdout
        assert "periodic" in out and "simulate" in out


def test_fmu_path_is_the_installed_fmu(installed):
    out = _run(
        [str(installed["venv"] / "bin" / "python"), "-c", "import harness; print(harness.fmu_path('ShroudedBlade'))"],
        cwd=installed["work"],
    ).stdout.strip()
    path = Path(out)
    assert path == installed["package"] / "fmus" / "ShroudedBlade.fmu" and path.is_file()
    # the model description inside is the checkout's, byte for byte
    with zipfile.ZipFile(path) as z:
        assert (
            z.read("modelDescription.xml")
            == (REPO / "fmu_src" / "models" / "ShroudedBlade" / "modelDescription.xml").read_bytes()
        )


def test_periodic_json_matches_the_checkout(installed):
    """`harness periodic --speed 7000 --json` from the installed package = the orbits computed here
    with the checkout's build/ FMU."""
    from harness.fmu import build as _build
    from harness.fmu.blade import BladeFMU
    from harness.analysis.periodic.branches import orbits_at
    from harness.analysis.periodic.period_map import PeriodMap

    before = _files(installed["package"])
    out = _run(
        [str(installed["venv"] / "bin" / "harness"), "periodic", "--speed", f"{SPEED:g}", "--json"],
        cwd=installed["work"],
    ).stdout
    got = json.loads(out)["solutions"]
    with BladeFMU(_build.build(("fmu",))) as fmu:
        want = orbits_at(PeriodMap(fmu, {}, "fixedPoint"), SPEED)
    assert len(got) == len(want) >= 1
    for g, w in zip(got, want):
        assert g["stable"] == w.stable and g["label"] == w.label
        assert math.isclose(g["amplitude_m"], w.amplitude, rel_tol=RTOL)
        for gm, wm in zip(g["multipliers"], w.multipliers):
            assert math.isclose(gm["abs"], abs(wm), rel_tol=RTOL, abs_tol=1e-12)
    # nothing written into the installed package (results and caches go under the working directory)
    assert _files(installed["package"]) == before


def test_checkout_only_commands_refuse(installed):
    """bench and crosscheck write into the checkout's bench/ and crosscheck/: an installed harness
    says so instead of writing next to the package."""
    site = installed["package"].parent
    before = set(site.iterdir())
    for command in ("bench", "crosscheck"):
        proc = subprocess.run(
            [str(installed["venv"] / "bin" / "harness"), command],
            cwd=installed["work"],
            capture_output=True,
            text=True,
            timeout=120,
        )
        assert proc.returncode == 2 and "runs in a checkout" in proc.stderr, proc.stderr
    assert set(site.iterdir()) == before
