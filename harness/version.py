"""The harness's version, kept outside the layers (like harness.paths) and free of numpy and fmpy
so that `harness --version` answers at once: the installed distribution's version; in a bare
checkout (not installed) pyproject.toml's, the one source of both."""

from __future__ import annotations

import sys
import tomllib
from functools import lru_cache
from pathlib import Path

from harness.paths import REPO_ROOT

DISTRIBUTION = "shroudedblade-harness"


def _installed() -> str | None:
    """The Version field of the distribution's METADATA on sys.path, as importlib.metadata finds it,
    read directly: importing importlib.metadata alone takes 0.1 s, a third of --version's budget."""
    stem = DISTRIBUTION.replace("-", "_")
    for entry in sys.path:
        for info in sorted(Path(entry or ".").glob(f"{stem}-*.dist-info")):
            try:
                with open(info / "METADATA", encoding="utf-8") as fh:
                    for line in fh:
                        if line.startswith("Version:"):
                            return line.split(":", 1)[1].strip()
                        if not line.strip():  # the headers end at the first empty line
                            break
            except OSError:
                continue
    return None


@lru_cache(maxsize=1)
def version() -> str:
    """The harness's version.

    Returns
    -------
    str
        The installed distribution's version, else pyproject.toml's (a bare checkout).
    """
    found = _installed()
    if found is not None:
        return found
    with open(REPO_ROOT / "pyproject.toml", "rb") as fh:
        return str(tomllib.load(fh)["project"]["version"])
