"""MkDocs hooks (mkdocs.yml `hooks:`): the generated parts of the site, made at build time.

Written pages live in docs/. Generated ones are never copied there by hand: the reports that
`make run`, `make bench` and `make crosscheck` write (results/claims.md, bench/RESULTS.md,
crosscheck/agreement.md) become pages under generated/, the figures and CSVs of results/ are
served under results/, and a page holding the VARIABLE_TABLES marker gets the variable tables of
every model description (variable_tables.py). MathJax (the file mkdocs.yml's extra_javascript
names) is copied from the installed package django-static-mathjax, so the site typesets its
equations without the network.
"""

from __future__ import annotations

import importlib.util
from pathlib import Path

from mkdocs.structure.files import File

import variable_tables

REPO = Path(__file__).resolve().parent.parent
# site page -> (report in the repository, the command that writes it)
REPORTS = {
    "generated/claims.md": ("results/claims.md", "make run"),
    "generated/bench.md": ("bench/RESULTS.md", "make bench"),
    "generated/agreement.md": ("crosscheck/agreement.md", "make crosscheck"),
}
RESULT_FILES = ("results/**/*.png", "results/**/*.csv", "results/**/*.json")
VARIABLE_TABLES = "<!-- variable tables -->"
MATHJAX_SITE = "javascripts/mathjax/tex-svg.js"  # SVG output: one file, its fonts inside


def mathjax_script() -> Path:
    """MathJax's combined TeX-to-SVG script in the installed package (the docs extra)."""
    spec = importlib.util.find_spec("mathjax")
    script = (
        Path(next(iter(spec.submodule_search_locations))) / "static" / "mathjax" / "es5" / "tex-svg.js"
        if spec and spec.submodule_search_locations
        else None
    )
    if script is None or not script.is_file():
        raise FileNotFoundError(
            "MathJax not installed: pip install django-static-mathjax (in the docs extra: pip install -e '.[docs]')"
        )
    return script


def _report_page(source: str, command: str) -> str:
    text = (REPO / source).read_text()
    note = (
        f'!!! note "Generated report"\n    This page is `{source}` as `{command}` last wrote it; '
        "it is included at build time, not edited here.\n\n"
    )
    head, _, rest = text.partition("\n")
    return f"{head}\n\n{note}{rest}" if head.startswith("# ") else note + text


def on_files(files, config):
    files.append(File.generated(config, MATHJAX_SITE, abs_src_path=str(mathjax_script())))
    for uri, (source, command) in REPORTS.items():
        files.append(File.generated(config, uri, content=_report_page(source, command)))
    for pattern in RESULT_FILES:
        for path in sorted(REPO.glob(pattern)):
            files.append(File.generated(config, path.relative_to(REPO).as_posix(), abs_src_path=str(path)))
    return files


def on_page_markdown(markdown, page, config, files):
    if VARIABLE_TABLES in markdown:
        markdown = markdown.replace(VARIABLE_TABLES, variable_tables.markdown(REPO))
    return markdown
