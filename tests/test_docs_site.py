"""The documentation site: `mkdocs build --strict` succeeds (a broken link, a missing page or a
failing docstring fails it, with mkdocs' output), the generated variable tables hold every variable
of every FMU the build makes (read from the built FMUs by fmpy, not by the generator), and every
relative link in README.md reaches a file."""
from __future__ import annotations

import os
import re
import subprocess
import sys
from pathlib import Path

import pytest
from fmpy import read_model_description

from harness.fmu import build as _build

REPO = Path(__file__).resolve().parent.parent
sys.path.insert(0, str(REPO / "sitegen"))
import variable_tables  # noqa: E402  (sitegen/ is not a package: the MkDocs hook imports it by path)

FMU_TARGETS = ("fmu", "fmu3", "excitation_fmu", "blade_external_fmu", "shroud_contact_fmu")


def test_mkdocs_build_strict(tmp_path):
    site = tmp_path / "site"
    env = dict(os.environ, NO_MKDOCS_2_WARNING="1")
    proc = subprocess.run([sys.executable, "-m", "mkdocs", "build", "--strict", "-f", str(REPO / "mkdocs.yml"),
                           "-d", str(site)], cwd=REPO, env=env, capture_output=True, text=True, timeout=600)
    assert proc.returncode == 0, f"mkdocs build --strict failed:\n{proc.stdout}\n{proc.stderr}"
    # the generated pages are there: a report of `make run` and the variable tables
    assert "Claims of Nan et al." in (site / "generated" / "claims" / "index.html").read_text()
    variables = (site / "reference" / "variables" / "index.html").read_text()
    assert "dTipDisplacement_dQ0" in variables and "contactForce2" in variables
    assert (site / "results" / "ring_convergence.png").is_file()


@pytest.fixture(scope="module")
def built_fmus() -> list[Path]:
    _build.build(FMU_TARGETS)
    found = sorted(p for p in (REPO / "build").rglob("*.fmu") if "fmi3" in p.parts or p.parent.name == "build")
    assert len(found) == len(FMU_TARGETS), found
    return found


def _sections(markdown: str) -> dict[str, str]:
    """'<model> (FMI <version>)' -> the text under that heading."""
    parts = re.split(r"^## (.+)$", markdown, flags=re.M)
    return dict(zip(parts[1::2], parts[2::2]))


def _rows(section: str) -> dict[str, list[str]]:
    """name -> the cells of its table row (name without backticks)."""
    rows = {}
    for line in section.splitlines():
        if line.startswith("| `"):
            cells = [c.strip() for c in re.split(r"(?<!\\)\|", line)[1:-1]]
            rows[cells[0].strip("`")] = cells
    return rows


def _expected(v) -> list[str]:
    """vr, causality and variability, type and unit, start: the cells as the FMU declares them."""
    return [str(v.valueReference), f"{v.causality}, {v.variability}", f"{v.type} [{v.unit}]" if v.unit else v.type,
            v.start or ""]


def test_variable_tables_hold_every_variable_of_every_fmu(built_fmus):
    sections = _sections(variable_tables.markdown(REPO))
    models = {p: read_model_description(str(p)) for p in built_fmus}
    assert set(sections) == {f"{md.modelName} (FMI {md.fmiVersion})" for md in models.values()}
    fmi2 = {md.modelName: md for md in models.values() if md.fmiVersion == "2.0"}
    for md in models.values():
        section = sections[f"{md.modelName} (FMI {md.fmiVersion})"]
        rows = _rows(section)
        base = fmi2.get(md.modelName) if md.fmiVersion != "2.0" else None
        if base is None:  # a full table: every variable, its row as the FMU declares it
            assert len(rows) == len(md.modelVariables)
            for v in md.modelVariables:
                got = rows[v.name]
                assert got[1:5] == _expected(v), (md.modelName, v.name)
        else:  # the differences from the FMI 2.0 description, and the claim that the rest is equal
            old = {v.name: v for v in base.modelVariables}
            new = {v.name: v for v in md.modelVariables}
            assert set(rows) == set(new) - set(old)
            for name in set(old) - set(new):
                assert f"`{name}`" in section.split("Not in FMI")[1].split("\n")[0]
            same = "Every other variable is declared as in FMI 2.0" in section
            equal = all((o.valueReference, o.causality, o.variability, o.unit, o.start, o.min, o.max)
                        == (n.valueReference, n.causality, n.variability, n.unit, n.start, n.min, n.max)
                        for o, n in ((old[k], new[k]) for k in set(old) & set(new)))
            assert same == equal


def test_readme_links_reach_files():
    text = (REPO / "README.md").read_text()
    targets = [t for t in re.findall(r"\]\(([^)#]+)(?:#[^)]*)?\)", text) if "://" not in t]
    assert targets, "README.md links nowhere"
    missing = [t for t in targets if not (REPO / t).exists()]
    assert not missing, f"README.md links to missing files: {missing}"
