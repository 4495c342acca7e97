"""The harness imports one way (docs/layers.md): `lint-imports` checks the contracts of pyproject.toml
(the layers cli > bench > validation | crosscheck > studies | api > system > analysis > fmu > model,
the reference importing only the model, and nothing but validation reaching the reference). The
test fails with the tool's report; the contracts carry no exceptions (`ignore_imports`)."""

from __future__ import annotations

import os
import re
import shutil
import subprocess
import sys
from pathlib import Path

REPO = Path(__file__).resolve().parents[2]


def lint_imports(root: Path = REPO) -> subprocess.CompletedProcess:
    """lint-imports on the package under `root` (first on the path) with root/pyproject.toml."""
    exe = shutil.which("lint-imports", path=str(Path(sys.executable).parent)) or shutil.which("lint-imports")
    assert exe, "lint-imports not found: install the test extra (pip install -e '.[test]')"
    env = dict(os.environ, PYTHONPATH=str(root))
    return subprocess.run([exe, "--no-cache"], cwd=root, env=env, capture_output=True, text=True, timeout=300)


def test_import_contracts_are_kept():
    res = lint_imports()
    assert res.returncode == 0, f"import contracts broken:\n{res.stdout}\n{res.stderr}"


def test_the_contracts_have_no_exceptions():
    config = (REPO / "pyproject.toml").read_text()
    assert "ignore_imports" not in config[config.index("[tool.importlinter]") :]


def test_a_violating_import_is_reported(tmp_path):
    """The check can fail: the same contracts on a copy of the package (renamed `harness_copy`, so
    that no installed `harness` shadows it) in which the model imports the CLI, the analysis
    imports the cross-check, the reference imports the analysis and the studies the reference."""
    pkg = tmp_path / "harness_copy"
    shutil.copytree(REPO / "harness", pkg, ignore=shutil.ignore_patterns("__pycache__", "fmus"))
    for f in pkg.rglob("*.py"):
        f.write_text(re.sub(r"\bharness\b(?=[. ])", "harness_copy", f.read_text()))
    (pkg / "model" / "bad_up.py").write_text("import harness_copy.cli.main\n")
    (pkg / "analysis" / "bad_validation.py").write_text("from harness_copy.crosscheck import common\n")
    (pkg / "reference" / "bad_product.py").write_text("import harness_copy.analysis.curves\n")
    (pkg / "studies" / "bad_oracle.py").write_text("import harness_copy.reference.contact\n")
    config = (REPO / "pyproject.toml").read_text()
    config = re.sub(r"\bharness\b(?=[.\"])", "harness_copy", config[config.index("[tool.importlinter]") :])
    (tmp_path / "pyproject.toml").write_text(config)
    res = lint_imports(tmp_path)
    assert res.returncode != 0, res.stdout
    assert "harness_copy.model.bad_up -> harness_copy.cli.main" in res.stdout, res.stdout
    assert "harness_copy.analysis.bad_validation -> harness_copy.crosscheck.common" in res.stdout, res.stdout
    assert "harness_copy.reference.bad_product -> harness_copy.analysis.curves" in res.stdout, res.stdout
    assert "harness_copy.studies.bad_oracle -> harness_copy.reference.contact" in res.stdout, res.stdout
