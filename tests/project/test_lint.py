"""`ruff check` over harness/, tests/, bench/, the FMU generator fmu_src/gen/ and sitegen/ with the
rules of pyproject.toml ([tool.ruff.lint]: pyflakes F, syntax errors E9): an undefined name (the
kind that broke `make bench` unseen), an unused import or variable, an f-string without fields
fails the default tests; `ruff format --check` keeps one layout."""

from __future__ import annotations

import subprocess
import sys

from harness.fmu.build import REPO_ROOT


def test_ruff_finds_nothing():
    import importlib.util

    assert importlib.util.find_spec("ruff"), "ruff is not installed: pip install -e '.[test]' (pyproject.toml)"
    proc = subprocess.run(
        [
            sys.executable,
            "-m",
            "ruff",
            "check",
            "--output-format",
            "concise",
            "harness",
            "tests",
            "bench",
            "fmu_src/gen",
            "sitegen",
        ],
        cwd=REPO_ROOT,
        capture_output=True,
        text=True,
        timeout=300,
    )
    assert proc.returncode == 0, proc.stdout + proc.stderr


def test_ruff_catches_an_undefined_name(tmp_path):
    bad = tmp_path / "bad.py"
    bad.write_text("def f():\n    return hysteresis\n")
    proc = subprocess.run(
        [
            sys.executable,
            "-m",
            "ruff",
            "check",
            "--config",
            str(REPO_ROOT / "pyproject.toml"),
            "--output-format",
            "concise",
            str(bad),
        ],
        capture_output=True,
        text=True,
        timeout=60,
    )
    assert proc.returncode == 1 and "F821" in proc.stdout, proc.stdout + proc.stderr


def test_ruff_format_leaves_the_sources_unchanged():
    """`ruff format --check`: the code's layout is the formatter's (line length 120, pyproject.toml)."""
    proc = subprocess.run(
        [sys.executable, "-m", "ruff", "format", "--check", "harness", "tests", "bench", "fmu_src/gen", "sitegen"],
        cwd=REPO_ROOT,
        capture_output=True,
        text=True,
        timeout=300,
    )
    assert proc.returncode == 0, proc.stdout + proc.stderr


def test_ruff_format_catches_a_misformatted_file(tmp_path):
    bad = tmp_path / "bad.py"
    bad.write_text("x = [1,2 ,3]\n")
    proc = subprocess.run(
        [sys.executable, "-m", "ruff", "format", "--check", "--config", str(REPO_ROOT / "pyproject.toml"), str(bad)],
        capture_output=True,
        text=True,
        timeout=60,
    )
    assert proc.returncode == 1 and "bad.py" in proc.stdout + proc.stderr, proc.stdout + proc.stderr
