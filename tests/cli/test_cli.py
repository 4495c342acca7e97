"""The command line: user errors give one line `error: ...`, exit code 2 and no traceback;
`simulate` writes a CSV (fmpy's format) and a PNG."""

from __future__ import annotations

import subprocess
import sys
from pathlib import Path

import numpy as np
import pytest
from fmpy.util import read_csv

REPO = Path(__file__).resolve().parents[2]


def harness(*args: str, cwd: Path = REPO) -> subprocess.CompletedProcess:
    return subprocess.run(
        [sys.executable, "-m", "harness", *args], capture_output=True, text=True, cwd=cwd, timeout=300
    )


@pytest.mark.parametrize(
    "args, expect",
    [
        (["simulate", "--fmu", "{fmu}", "--start-values", "gapp", "3e-5"], "unknown parameter 'gapp'"),
        (["simulate", "--fmu", "{fmu}", "--start-values", "d", "-3e-5"], "d = '-3e-5' m"),
        (["simulate", "--fmu", "{fmu}", "--speed", "nan"], "--speed nan is not a number"),
        (["simulate", "--fmu", "/nonexistent/ShroudedBlade.fmu"], "not found"),
        # what to do in both settings: leave the path out (installed: the package's FMU; checkout: make fmu)
        (
            ["simulate", "--fmu", "/nonexistent/ShroudedBlade.fmu"],
            "`pip install` again if it is missing; checkout: `make fmu`",
        ),
        (["periodic", "--fmu", "{dir}", "--speed", "7000"], "is a directory, not an FMU file"),
        (["simulate", "--fmu", "{dir}"], "(did you mean {dir}/never-loaded.fmu?)"),
        (["simulate", "--fmu", "{fmu}", "--start-values", "d"], "NAME VALUE pairs"),
        (
            ["simulate", "--fmu", "{fmu}", "--run-up", "4000", "50000", "0", "0.01", "--stop-time", "0.02"],
            "rotorSpeed = 50000 rpm",
        ),
        (["simulate", "--no-such-option"], "unrecognized arguments"),
        (["simulate", "--fmu", "{real}", "--output-variables", "tipDisp"], "unknown output(s) ['tipDisp']"),
        (["simulate", "--fmu", "{fmu}", "--derivative-order", "9"], "--derivative-order: invalid choice: 9"),
        (["frobnicate"], "unknown command 'frobnicate'"),
        # the other commands: every bad value and name is named as the user typed it
        (["periodic", "--fmu", "{fmu}", "--speed", "0"], "--speed 0.0 rpm"),
        (
            ["periodic", "--fmu", "{fmu}", "--speed", "7000", "--start-values", "bogus", "1"],
            "unknown parameter 'bogus' (from --start-values)",
        ),
        (["periodic", "--fmu", "{fmu}", "--speed", "7000", "--model", "x"], "--model: invalid choice: 'x'"),
        (["continue", "--fmu", "{fmu}", "--speed-range", "0", "5"], "--speed-range 0.0 5.0 rpm"),
        (["continue", "--fmu", "{fmu}", "--start-values", "kn", "nan"], "kn = 'nan' (from --start-values)"),
        (["continue", "--fmu", "{fmu}", "--seed-step", "-5"], "--seed-step -5.0 rpm"),
        (["reproduce", "--studies", "gapp"], "--studies: invalid choice: 'gapp'"),
        (["run", "--size", "huge"], "--size: invalid choice: 'huge'"),
        (["validate", "--max-step", "1"], "maxStep = 1.0 s is out of range"),
    ],
)
def test_user_errors_are_one_line(args, expect, tmp_path, fmu_path):
    # an existing file that is never opened as an FMU: every error here must come before that
    # ({real}: the error is about the FMU's own variables, so the real FMU is needed)
    fake = tmp_path / "never-loaded.fmu"
    fake.write_bytes(b"not an FMU")
    fill = {"{fmu}": str(fake), "{real}": str(fmu_path), "{dir}": str(tmp_path)}
    for key, value in fill.items():
        args, expect = [a.replace(key, value) for a in args], expect.replace(key, value)
    proc = harness(*args, cwd=tmp_path)
    assert proc.returncode == 2, proc.stderr
    lines = proc.stderr.strip().splitlines()
    assert len(lines) == 1, proc.stderr
    assert lines[0].startswith("error: ") and expect in lines[0], lines[0]
    assert "Traceback" not in proc.stderr


def test_help_lists_commands():
    proc = harness("--help")
    assert proc.returncode == 0
    assert "simulate" in proc.stdout and "validate" in proc.stdout
    sub = harness("simulate", "--help")
    assert sub.returncode == 0
    for opt in ("--start-time", "--stop-time", "--output-interval", "--start-values", "--output-file", "--fmi-logging"):
        assert opt in sub.stdout


def test_simulate_writes_csv_and_png(fmu_path, tmp_path):
    out, png = tmp_path / "res.csv", tmp_path / "res.png"
    proc = harness(
        "simulate",
        "--fmu",
        str(fmu_path),
        "--stop-time",
        "0.02",
        "--output-interval",
        "2e-4",
        "--start-values",
        "d",
        "4e-5",
        "gating",
        "false",
        "--output-file",
        str(out),
        "--plot",
        str(png),
        cwd=tmp_path,
    )
    assert proc.returncode == 0, proc.stderr
    res = read_csv(out)
    # every column says its unit (from the model description)
    assert res.dtype.names[:4] == ("time_s", "tipDisplacement_m", "tipVelocity_m_s", "normalForce_N")
    assert "dissipatedEnergy_J" in res.dtype.names and "regime" in res.dtype.names
    np.testing.assert_allclose(res["time_s"], np.arange(101) * 2e-4, rtol=0, atol=1e-12)
    assert np.max(np.abs(res["tipDisplacement_m"])) > 0
    assert png.read_bytes()[:8] == b"\x89PNG\r\n\x1a\n"
    assert not list(tmp_path.glob(".res.*"))  # no temporary files left behind
