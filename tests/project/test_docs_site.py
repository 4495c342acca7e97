"""The documentation site: `mkdocs build --strict` succeeds (a broken link, a missing page or a
failing docstring fails it, with mkdocs' output), the generated variable tables hold every variable
of every FMU the build makes (read from the built FMUs by fmpy, not by the generator), and every
relative link in README.md reaches a file, and README.md stays at most 150 lines."""

from __future__ import annotations

import importlib.util
import os
import re
import subprocess
import sys
from pathlib import Path

import pytest
from fmpy import read_model_description

from harness.fmu import build as _build

REPO = Path(__file__).resolve().parents[2]
# sitegen/ is not a package (the MkDocs hook imports it by path): loaded the same way here
_spec = importlib.util.spec_from_file_location("variable_tables", REPO / "sitegen" / "variable_tables.py")
variable_tables = sys.modules["variable_tables"] = importlib.util.module_from_spec(_spec)
_spec.loader.exec_module(variable_tables)

FMU_TARGETS = ("fmu", "fmu3", "excitation_fmu", "blade_external_fmu", "shroud_contact_fmu")


def test_mkdocs_build_strict(tmp_path):
    site = tmp_path / "site"
    env = dict(os.environ, NO_MKDOCS_2_WARNING="1")
    proc = subprocess.run(
        [sys.executable, "-m", "mkdocs", "build", "--strict", "-f", str(REPO / "mkdocs.yml"), "-d", str(site)],
        cwd=REPO,
        env=env,
        capture_output=True,
        text=True,
        timeout=600,
    )
    assert proc.returncode == 0, f"mkdocs build --strict failed:\n{proc.stdout}\n{proc.stderr}"
    # the generated pages are there: a report of `make run` and the variable tables
    assert "Claims of Nan et al." in (site / "generated" / "claims" / "index.html").read_text()
    variables = (site / "reference" / "variables" / "index.html").read_text()
    assert "dTipDisplacement_dQ0" in variables and "contactForce2" in variables
    assert (site / "results" / "ring_convergence.png").is_file()
    _check_math_and_no_network(site)


# the paper's equation numbers the model page must carry on its typeset equations
MODEL_TAGS = (1, 2, 3, 4, 5, 6, 7, 8, 10, 17, 20, 21, 24, 26, 27)
REMOTE = re.compile(r"""<(?:script|link|img)\b[^>]*\b(?:src|href)\s*=\s*["']?(?:https?:)?//""", re.I)


def _check_math_and_no_network(site: Path) -> None:
    """The equations are math markup for MathJax (arithmatex spans, \\tag{N} with the paper's
    numbers), the MathJax script is the site's own file, and no page loads a script, style sheet or
    image from the network (no CDN, no web fonts)."""
    model = (site / "model" / "index.html").read_text()
    spans = re.findall(r'class="arithmatex"', model)
    assert len(spans) >= 100, f"the model page has {len(spans)} math spans"
    assert all(f"\\tag{{{n}}}" in model for n in MODEL_TAGS), [n for n in MODEL_TAGS if f"\\tag{{{n}}}" not in model]
    # a control character in TeX is a lost backslash (\b, \f, \v, \t written through an escape):
    # MathJax shows "Math input error" there
    bad = [
        m
        for m in re.findall(r'class="arithmatex">(.*?)</(?:span|div)>', model, re.S)
        if re.search(r"[\x00-\x08\x0b\x0c\x0e-\x1f]", m)
    ]
    assert not bad, bad[:3]
    for page in ("reference/numerics", "periodic"):
        assert 'class="arithmatex"' in (site / page / "index.html").read_text(), page
    scripts = re.findall(r'<script src="([^"]+)"', model)
    mathjax = [src for src in scripts if "mathjax" in src.lower() and "config" not in src]
    assert mathjax, scripts
    served = (site / "model" / mathjax[0]).resolve()
    assert served.is_file() and b"MathJax" in served.read_bytes()[:200000], served
    # every figure of the findings opens at full resolution: its image is the target of a lightbox link
    findings = (site / "findings" / "results" / "index.html").read_text()
    images = re.findall(r'<img[^>]*src="([^"]+\.png)"', findings)
    linked = re.findall(r'<a class="glightbox"[^>]*href="([^"]+\.png)"', findings)
    assert len(images) >= 8 and sorted(images) == sorted(linked), (images, linked)
    remote = {
        str(p.relative_to(site)): m.group(0) for p in site.rglob("*.html") for m in [REMOTE.search(p.read_text())] if m
    }
    assert not remote, remote


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
    return [
        str(v.valueReference),
        f"{v.causality}, {v.variability}",
        f"{v.type} [{v.unit}]" if v.unit else v.type,
        v.start or "",
    ]


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
            equal = all(
                (o.valueReference, o.causality, o.variability, o.unit, o.start, o.min, o.max)
                == (n.valueReference, n.causality, n.variability, n.unit, n.start, n.min, n.max)
                for o, n in ((old[k], new[k]) for k in set(old) & set(new))
            )
            assert same == equal


def test_readme_links_reach_files():
    text = (REPO / "README.md").read_text()
    targets = [t for t in re.findall(r"\]\(([^)#]+)(?:#[^)]*)?\)", text) if "://" not in t]
    assert targets, "README.md links nowhere"
    missing = [t for t in targets if not (REPO / t).exists()]
    assert not missing, f"README.md links to missing files: {missing}"


README_MAX_LINES = 150  # the front page stays a page: details go to docs/


def test_readme_is_short():
    lines = (REPO / "README.md").read_text().splitlines()
    assert len(lines) <= README_MAX_LINES, f"README.md has {len(lines)} lines (at most {README_MAX_LINES})"
