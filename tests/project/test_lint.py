"""`ruff check` over harness/, tests/, bench/, the FMU generator fmu_src/gen/ and sitegen/ with the
rules of pyproject.toml ([tool.ruff.lint]: pyflakes F, syntax errors E9): an undefined name (the
kind that broke `make bench` unseen), an unused import or variable, an f-string without fields
fails the default tests."""
from __future__ import annotations

import subprocess
import sys

from harness.fmu.build import REPO_ROOT


def test_ruff_finds_nothing():
    import importlib.util
    assert importlib.util.find_spec("ruff"), "ruff is not installed: pip install -e '.[test]' (pyproject.toml)"
    proc = subprocess.run([sys.executable, "-m", "ruff", "check", "--output-format", "concise", "harness", "tests",
                           "bench", "fmu_src/gen", "sitegen"], cwd=REPO_ROOT, capture_output=True, text=True, timeout=300)
    assert proc.returncode == 0, proc.stdout + proc.stderr


def test_ruff_catches_an_undefined_name(tmp_path):
    bad = tmp_path / "bad.py"
    bad.write_text("def f():\n    return hysteresis\n")
    proc = subprocess.run([sys.executable, "-m", "ruff", "check", "--config", str(REPO_ROOT / "pyproject.toml"),
                           "--output-format", "concise", str(bad)], capture_output=True, text=True, timeout=60)
    assert proc.returncode == 1 and "F821" in proc.stdout, proc.stdout + proc.stderr
