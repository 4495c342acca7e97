"""Every command that writes refuses an output path it cannot write, before any work: one line
`error: ...` naming that path as given, exit code 2, no traceback; and results land under the
current directory by default, never in the checkout's results/."""

from __future__ import annotations

import json
import os
import subprocess
import sys
from pathlib import Path

import pytest

REPO = Path(__file__).resolve().parents[2]

# (command, option taking the output path, other arguments making the run short)
WRITERS = [
    ("simulate", "--output-file", ["--stop-time", "0.01"]),
    ("simulate", "--plot", ["--stop-time", "0.01"]),
    ("continue", "--output-file", ["--speed-range", "6000", "6100"]),
    ("continue", "--plot", ["--speed-range", "6000", "6100"]),
    ("mistuning", "--cache-dir", []),
    ("reproduce", "--out", ["--size", "quick", "--studies", "gap", "--no-extras"]),
    ("run", "--out", ["--size", "quick"]),
    ("validate", "--output-file", ["--quick"]),
]


def harness(*args: str, cwd: Path) -> subprocess.CompletedProcess:
    env = {**os.environ, "PYTHONPATH": str(REPO)}
    return subprocess.run(
        [sys.executable, "-m", "harness", *args], capture_output=True, text=True, cwd=cwd, env=env, timeout=600
    )


def bad_paths(tmp: Path) -> dict[str, str]:
    (tmp / "a_file").write_text("x")
    (tmp / "a_dir.csv").mkdir()
    return {
        "proc": "/proc/sb_out/x.csv",  # a virtual file system: nothing can be created there
        "under a file": "a_file/sub/x.csv",
        "a directory": "a_dir.csv",
    }


# a directory is a bad path only for the options that take a file
CASES = [
    (c, o, r, k)
    for c, o, r in WRITERS
    for k in ("proc", "under a file", "a directory")
    if not (k == "a directory" and o in ("--out", "--cache-dir"))
]


@pytest.mark.parametrize("command,option,rest,kind", CASES, ids=[f"{c} {o} {k}" for c, o, _, k in CASES])
def test_bad_output_path_is_one_line_naming_it(command, option, rest, kind, tmp_path):
    path = bad_paths(tmp_path)[kind]
    proc = harness(command, option, path, *rest, cwd=tmp_path)
    lines = proc.stderr.strip().splitlines()
    assert proc.returncode == 2, proc.stderr
    assert len(lines) == 1 and lines[0].startswith("error: ") and path in lines[0], proc.stderr
    assert "Traceback" not in proc.stderr
    assert not (tmp_path / "shroudedblade-results").exists()  # refused before any work


def test_results_default_under_the_current_directory(tmp_path):
    before = {p: p.stat().st_mtime_ns for p in (REPO / "results").rglob("*") if p.is_file()}
    proc = harness("continue", "--speed-range", "6000", "6100", cwd=tmp_path)
    assert proc.returncode == 0, proc.stderr
    assert (tmp_path / "branches.csv").is_file()
    after = {p: p.stat().st_mtime_ns for p in (REPO / "results").rglob("*") if p.is_file()}
    assert after == before


def test_continue_json_writes_nothing_unless_asked(tmp_path):
    """`continue --json` prints the branches on stdout: no branches.csv (nor anything else) in the
    current directory; with --output-file it writes that file, whose rows are the printed points."""
    run = ["continue", "--speed-range", "6000", "6100", "--json"]
    quiet = harness(*run, cwd=tmp_path)
    assert quiet.returncode == 0, quiet.stderr
    printed = json.loads(quiet.stdout)
    assert printed["output_file"] is None and printed["branches"]
    assert list(tmp_path.iterdir()) == []

    asked = harness(*run, "--output-file", "b.csv", cwd=tmp_path)
    assert asked.returncode == 0, asked.stderr
    assert json.loads(asked.stdout)["output_file"] == "b.csv"
    rows = [ln for ln in (tmp_path / "b.csv").read_text().splitlines() if ln and not ln.startswith("#")]
    assert len(rows) - 1 == sum(len(b["points"]) for b in printed["branches"])  # header + one row a point
    assert sorted(p.name for p in tmp_path.iterdir()) == ["b.csv"]
