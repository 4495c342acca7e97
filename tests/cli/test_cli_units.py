"""The quantities every command writes carry their units in their names, the same name for the same
quantity across commands: speed_rpm, amplitude_m, time_s, tipDisplacement_m (CSV headers and JSON keys)."""

from __future__ import annotations

import json
import subprocess
import sys
from pathlib import Path

REPO = Path(__file__).resolve().parents[2]


def harness(*args: str, cwd: Path) -> subprocess.CompletedProcess:
    proc = subprocess.run(
        [sys.executable, "-m", "harness", *args], capture_output=True, text=True, cwd=cwd, timeout=600
    )
    assert proc.returncode == 0, proc.stderr
    return proc


def _header(path: Path) -> list[str]:
    line = next(ln for ln in path.read_text().splitlines() if not ln.startswith("#"))
    return [h.strip('"') for h in line.split(",")]


def test_same_names_with_units_across_commands(tmp_path):
    harness("simulate", "--stop-time", "0.002", "--output-file", "sim.csv", cwd=tmp_path)
    harness("continue", "--speed-range", "6000", "6400", "--output-file", "branches.csv", cwd=tmp_path)
    periodic = json.loads(harness("periodic", "--speed", "6200", "--json", cwd=tmp_path).stdout)

    sim, branches = (_header(tmp_path / f) for f in ("sim.csv", "branches.csv"))
    assert sim[:2] == ["time_s", "tipDisplacement_m"] and "amplitude_m" in sim
    assert {"speed_rpm", "amplitude_m"} <= set(branches)
    assert periodic["speed_rpm"] == 6200.0 and "period_s" in periodic
    assert all({"speed_rpm", "amplitude_m"} <= set(s) for s in periodic["solutions"]) and periodic["solutions"]
