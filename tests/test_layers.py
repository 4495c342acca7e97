"""The harness imports one way (docs/layers.md): `lint-imports` checks the contracts of pyproject.toml
(the product layers cli > studies > system > analysis > fmu > model, and no product module importing
the validation packages reference, crosscheck, bench). The test fails with the tool's report."""
from __future__ import annotations

import os
import shutil
import subprocess
import sys
from pathlib import Path

REPO = Path(__file__).resolve().parents[1]


def lint_imports(root: Path = REPO) -> subprocess.CompletedProcess:
    """lint-imports on the package under `root` (first on the path) with root/pyproject.toml."""
    exe = shutil.which("lint-imports", path=str(Path(sys.executable).parent)) or shutil.which("lint-imports")
    assert exe, "lint-imports not found: install the test extra (pip install -e '.[test]')"
    env = dict(os.environ, PYTHONPATH=str(root))
    return subprocess.run([exe, "--no-cache"], cwd=root, env=env, capture_output=True, text=True, timeout=300)


def test_import_contracts_are_kept():
    res = lint_imports()
    assert res.returncode == 0, f"import contracts broken:\n{res.stdout}\n{res.stderr}"


def test_a_violating_import_is_reported(tmp_path):
    """The check can fail: the same contracts on a copy of the package in which the model imports
    the CLI and the analysis imports the cross-check."""
    pkg = tmp_path / "harness"
    shutil.copytree(REPO / "harness", pkg, ignore=shutil.ignore_patterns("__pycache__"))
    (pkg / "model" / "bad_up.py").write_text("import harness.cli.main\n")
    (pkg / "analysis" / "bad_validation.py").write_text("from harness.crosscheck import common\n")
    shutil.copy(REPO / "pyproject.toml", tmp_path / "pyproject.toml")
    res = lint_imports(tmp_path)
    assert res.returncode != 0, res.stdout
    assert "harness.model.bad_up -> harness.cli.main" in res.stdout, res.stdout
    assert "harness.analysis.bad_validation -> harness.crosscheck.common" in res.stdout, res.stdout
