"""`python -m harness campbell`: the FMU's mode frequencies and their engine-order crossings against the
reference's own m-mode reduction (harness.reference.modes: its frequencies, and crossings found by
its own dense scan + brentq), and its input errors (one line, exit 2, the value and the range)."""

from __future__ import annotations

import json
import subprocess
import sys
from pathlib import Path

import numpy as np
import pytest
from scipy.optimize import brentq

from harness.cli.main import main
from harness.reference.modes import modal_galerkin

REPO = Path(__file__).resolve().parents[2]


def harness(*args: str, cwd: Path = REPO) -> subprocess.CompletedProcess:
    return subprocess.run(
        [sys.executable, "-m", "harness", "campbell", *args], capture_output=True, text=True, cwd=cwd, timeout=300
    )


def reference_crossings(p: dict, m: int, lo: float, hi: float) -> list[tuple[int, int, float]]:
    """(mode, EO, speed) of every root of f_i(n) = EO n / 60 in [lo, hi], from the reference."""
    g = modal_galerkin(p, m)
    ns = np.linspace(lo, hi, 2001)
    grid = np.array([g.frequencies_hz(n) for n in ns])
    out = []
    for i in range(m):
        for k in range(1, 9):

            def gap(n: float) -> float:
                return float(g.frequencies_hz(n)[i]) - k * n / 60.0

            vals = grid[:, i] - k * ns / 60.0
            for j in np.nonzero((vals[:-1] > 0) != (vals[1:] > 0))[0]:
                out.append((i + 1, k, brentq(gap, ns[j], ns[j + 1], xtol=1e-8)))
    return sorted(out)


def test_one_speed_frequencies_and_crossings(fmu_path):
    proc = harness("--fmu", str(fmu_path), "--modes", "3", "--speed", "7000", "--start-values", "m0", "0.05", "--json")
    assert proc.returncode == 0, proc.stderr
    out = json.loads(proc.stdout)
    p = {"formulation": 2, "m0": 0.05}
    g = modal_galerkin(p, 3)
    # measured 4.4e-16 (two eigen solvers' roundoff); 1e-14 leaves room for another BLAS
    np.testing.assert_allclose(out["frequencies_hz"], g.frequencies_hz(7000.0), rtol=1e-14)
    got = sorted((c["mode"], c["engine_order"], c["speed_rpm"]) for c in out["crossings"])
    want = reference_crossings(p, 3, 0.0, 30000.0)
    assert [g[:2] for g in got] == [w[:2] for w in want]
    # measured 3.2e-12 (the reference's brentq stops at xtol 1e-8 rpm); tolerance 3e-11, 10x
    np.testing.assert_allclose([g[2] for g in got], [w[2] for w in want], rtol=3e-11)
    for c in out["crossings"]:
        # the crossing's frequency is the reference's frequency of that mode at the crossing speed
        # (not EO n / 60, which is how the command defines it): measured 2.8e-12, tolerance 3e-11
        ref = g.frequencies_hz(c["speed_rpm"])[c["mode"] - 1]
        assert c["frequency_hz"] == pytest.approx(ref, rel=3e-11)


def test_range_per_speed_per_mode_and_plot(fmu_path, tmp_path):
    png = tmp_path / "c.png"
    proc = harness(
        "--fmu",
        str(fmu_path),
        "--modes",
        "2",
        "--speeds",
        "1000",
        "13000",
        "--points",
        "13",
        "--json",
        "--plot",
        str(png),
    )
    assert proc.returncode == 0, proc.stderr
    out = json.loads(proc.stdout)
    assert out["speeds_rpm"] == pytest.approx(list(np.linspace(1000, 13000, 13)))
    f = np.array(out["frequencies_hz"])
    assert f.shape == (13, 2)
    g = modal_galerkin({"formulation": 2}, 2)
    np.testing.assert_allclose(f, [g.frequencies_hz(n) for n in out["speeds_rpm"]], rtol=1e-14)  # as above
    # the second mode crosses EO 8 inside the range (about 11670 rpm): located, not the grid's 1000-rpm step
    c28 = [c for c in out["crossings"] if (c["mode"], c["engine_order"]) == (2, 8)]
    want = [w for w in reference_crossings({"formulation": 2}, 2, 1000.0, 13000.0) if w[:2] == (2, 8)]
    assert len(c28) == 1 and len(want) == 1 and c28[0]["speed_rpm"] == pytest.approx(want[0][2], rel=3e-11)
    assert png.stat().st_size > 10000


@pytest.mark.parametrize(
    "args, expect",
    [
        (["--modes", "0"], "modes = 0 outside the range [1, 6]"),
        (["--modes", "7", "--speed", "5000"], "modes = 7 outside the range [1, 6]"),
        (["--modes", "2", "--speed", "-5"], "--speed = -5.0 rpm outside the FMU's rotorSpeed range [0, 30000]"),
        (["--modes", "2", "--speed", "nan"], "--speed = nan rpm outside"),
        (["--modes", "2", "--speeds", "0", "40000"], "--speeds TO = 40000.0 rpm outside"),
        (["--modes", "2", "--speeds", "9000", "3000"], "FROM must be below TO"),
        (["--modes", "2", "--speeds", "0", "9000", "--points", "1"], "--points = 1 outside the range [2, 10001]"),
        (["--modes", "2", "--speed", "100", "--speeds", "0", "10"], "not allowed with argument"),
        (
            ["--modes", "2", "--start-values", "modes", "3"],
            "--start-values modes: give the number of modes with --modes",
        ),
    ],
)
def test_bad_input_is_one_line(args, expect, tmp_path, capsys):
    """In-process (main() is what `python -m harness` runs; the process exit is checked once below)."""
    fake = tmp_path / "never-loaded.fmu"
    fake.write_bytes(b"not an FMU")
    try:
        code = main(["campbell", "--fmu", str(fake), *args])
    except SystemExit as exc:  # argparse's own errors
        code = exc.code
    err = capsys.readouterr().err
    assert code == 2, err
    lines = err.strip().splitlines()
    assert len(lines) == 1 and lines[0].startswith("error: ") and expect in lines[0], err


def test_bad_modes_exit_code_of_the_process(tmp_path):
    proc = harness("--modes", "7", cwd=tmp_path)
    assert proc.returncode == 2 and proc.stderr.strip() == "error: modes = 7 outside the range [1, 6]", proc.stderr
    assert "Traceback" not in proc.stderr
