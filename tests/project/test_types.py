"""The type checker on the public API and the modules outside the layers: mypy --strict on the
files of pyproject.toml's [tool.mypy] (harness/__init__.py, harness/api.py, ...). The test fails
with mypy's report; a second run on a copy with one annotation broken shows that it can fail."""

from __future__ import annotations

import os
import shutil
import subprocess
import sys
from pathlib import Path

REPO = Path(__file__).resolve().parents[2]


def mypy(root: Path) -> subprocess.CompletedProcess:
    """mypy with root/pyproject.toml's settings on the package under `root` (no cache kept)."""
    env = dict(os.environ, PYTHONPATH=str(root))
    return subprocess.run(
        [sys.executable, "-m", "mypy", "--config-file", str(root / "pyproject.toml"), "--cache-dir", os.devnull],
        cwd=root,
        env=env,
        capture_output=True,
        text=True,
        timeout=600,
    )


def test_public_modules_are_strictly_typed():
    res = mypy(REPO)
    assert res.returncode == 0, f"mypy --strict found:\n{res.stdout}\n{res.stderr}"


def test_a_type_error_is_reported(tmp_path):
    """The check can fail: in a copy, version() is declared to return an int."""
    shutil.copytree(REPO / "harness", tmp_path / "harness", ignore=shutil.ignore_patterns("__pycache__", "fmus"))
    shutil.copy(REPO / "pyproject.toml", tmp_path / "pyproject.toml")
    f = tmp_path / "harness" / "version.py"
    f.write_text(f.read_text().replace("def version() -> str:", "def version() -> int:"))
    res = mypy(tmp_path)
    assert res.returncode != 0 and "harness/version.py" in res.stdout, res.stdout
