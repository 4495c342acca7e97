"""harness.optional: a missing optional dependency is an ImportError that names the extra to
install; an installed one is imported; a broken import inside an installed package is not masked."""

from __future__ import annotations

import sys

import pytest

from harness import optional


def test_missing_optional_dependency_names_its_extra(monkeypatch):
    monkeypatch.setitem(optional.EXTRA, "sb_no_such_package", "cluster")
    with pytest.raises(ImportError, match=r"sb_no_such_package is not installed.*\.\[cluster\]"):
        optional.require("sb_no_such_package.sub")


def test_installed_dependency_is_imported():
    assert optional.require("json") is sys.modules["json"]


def test_a_failing_import_inside_an_installed_package_is_not_masked(tmp_path, monkeypatch):
    (tmp_path / "sb_broken_pkg").mkdir()
    (tmp_path / "sb_broken_pkg" / "__init__.py").write_text("import sb_missing_inner_dependency\n")
    monkeypatch.syspath_prepend(str(tmp_path))
    with pytest.raises(ModuleNotFoundError, match="sb_missing_inner_dependency"):
        optional.require("sb_broken_pkg")
