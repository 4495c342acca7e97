"""matplotlib, set up once for every figure of the harness: the Agg backend (figures go straight to
PNG files, nothing is shown on screen), and a PNG written atomically (readers see the old file or
the complete new one)."""

from __future__ import annotations

import io
import os
from pathlib import Path
from typing import Any

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402  (after the backend is chosen)

from harness.files.atomic import atomic_write_bytes  # noqa: E402


def save_png(fig: Any, path: str | os.PathLike[str], dpi: int = 110, tight: bool = True) -> Path:
    """Write `fig` as a PNG to `path` atomically and close it; returns the path."""
    buf = io.BytesIO()
    try:
        fig.savefig(buf, format="png", dpi=dpi, **({"bbox_inches": "tight"} if tight else {}))
    finally:
        plt.close(fig)
    atomic_write_bytes(Path(path), buf.getvalue())
    return Path(path)


__all__ = ["plt", "save_png"]
