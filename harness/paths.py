"""Where the repository's files are: the one path every layer may need (model reads
modelDescription.xml, fmu builds into build/), kept outside the layers so none imports another for it."""
from __future__ import annotations

from pathlib import Path

REPO_ROOT = Path(__file__).resolve().parents[1]
