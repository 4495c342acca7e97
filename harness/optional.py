"""Optional dependencies (pyproject extras `cluster`, `crosscheck`): imported where they are used,
with an error that names the extra to install instead of a bare ModuleNotFoundError."""

from __future__ import annotations

import importlib
from types import ModuleType

EXTRA = {"distributed": "cluster", "dask": "cluster", "libcosimpy": "crosscheck", "ecospy": "crosscheck"}


def require(module: str) -> ModuleType:
    """Import `module` (e.g. "libcosimpy.CosimExecution"), or raise ImportError naming its extra."""
    try:
        return importlib.import_module(module)
    except ModuleNotFoundError as e:
        root = module.split(".")[0]
        if e.name is None or e.name.split(".")[0] != root:
            raise  # the package is there but one of its own imports failed: show that
        raise ImportError(
            f"{root} is not installed: it is an optional dependency of the harness; install it with "
            f"pip install -e '.[{EXTRA.get(root, root)}]' (`make test` installs every extra)"
        ) from e
