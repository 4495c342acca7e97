"""The public API's docstrings are numpy style with the sections the site's API reference renders as
tables: every name of `harness.__all__` / `harness.api.__all__` (and the public methods of its
classes) documents each parameter of its signature under "Parameters", and what it returns under
"Returns". Read the way mkdocstrings reads them (griffe, numpy parser: mkdocs.yml's docstring_style),
so a section the site would show as plain text fails here."""

from __future__ import annotations

import logging
import shutil
from pathlib import Path

import griffe
import pytest

import harness
import harness.api

REPO = Path(__file__).resolve().parents[2]
STYLE = "numpy"
#: the names documented as the public API (harness.__version__ is a string, not a callable)
PUBLIC = sorted((set(harness.__all__) | set(harness.api.__all__)) - {"__version__"})


def load_api(root: Path = REPO) -> griffe.Module:
    """harness.api as griffe sees it from the sources under `root` (no import)."""
    pkg = griffe.load("harness", search_paths=[str(root)], try_relative_path=False, docstring_parser=STYLE,
                      resolve_aliases=True, resolve_external=False)  # fmt: skip
    return pkg["api"]


def _sections(obj: griffe.Object, caplog: pytest.LogCaptureFixture) -> dict[str, list[object]]:
    """kind -> value of the numpy sections of obj's docstring; the parser's warnings are failures."""
    assert obj.docstring is not None and obj.docstring.value.strip(), f"{obj.path}: no docstring"
    caplog.clear()
    with caplog.at_level(logging.WARNING, logger="griffe"):
        parsed = obj.docstring.parse(STYLE)
    assert not caplog.records, f"{obj.path}: " + "; ".join(r.getMessage() for r in caplog.records)
    return {s.kind.value: s.value for s in parsed}


def problems(obj: griffe.Object, caplog: pytest.LogCaptureFixture) -> list[str]:
    """What is missing from the docstring of a function or class (empty: nothing)."""
    sections = _sections(obj, caplog)
    out = []
    params = [p.name for p in obj.parameters if p.name not in ("self", "cls")]
    documented = [p.name.lstrip("*") for p in sections.get("parameters", [])]
    if params and documented != params:
        out.append(f"{obj.path}: Parameters {documented}, the signature has {params}")
    if obj.is_function and obj.returns not in (None, "None") and "returns" not in sections:
        out.append(f"{obj.path}: no Returns section (returns {obj.returns})")
    return out


def public_objects(api: griffe.Module) -> list[griffe.Object]:
    """The exported functions and classes and the public methods of the classes."""
    out = []
    for name in PUBLIC:
        obj = api[name].final_target if api[name].is_alias else api[name]
        if obj.is_attribute:
            continue
        out.append(obj)
        if obj.is_class:
            out += [m for n, m in obj.members.items() if m.is_function and not n.startswith("_")]
    return out


@pytest.fixture(scope="module")
def api() -> griffe.Module:
    return load_api()


def test_every_public_name_is_documented(api, caplog):
    assert set(PUBLIC) <= set(api.members), sorted(set(PUBLIC) - set(api.members))
    objs = public_objects(api)
    assert len(objs) >= len(PUBLIC) - 1, [o.path for o in objs]
    bad = [p for obj in objs for p in problems(obj, caplog)]
    assert not bad, "\n".join(bad)


def test_constants_have_a_docstring(api):
    for name in PUBLIC:
        if api[name].is_attribute:
            assert api[name].docstring is not None, f"harness.api.{name}: no docstring"


def test_an_undocumented_parameter_is_found(tmp_path, caplog):
    """The check can fail: in a copy, fmu_path gains a parameter its docstring does not name."""
    shutil.copytree(REPO / "harness", tmp_path / "harness", ignore=shutil.ignore_patterns("__pycache__", "fmus"))
    f = tmp_path / "harness" / "api.py"
    text = f.read_text()
    assert 'def fmu_path(name: str = "ShroudedBlade") -> Path:' in text
    f.write_text(
        text.replace(
            'def fmu_path(name: str = "ShroudedBlade")', 'def fmu_path(name: str = "ShroudedBlade", x: int = 0)'
        )
    )
    api = load_api(tmp_path)
    found = problems(api["fmu_path"], caplog)
    assert found and "'x'" in found[0], found
