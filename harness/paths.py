"""Where the files are, kept outside the layers so none imports another for it: a checkout
(harness/ beside CMakeLists.txt and fmu_src/; also its editable install) builds its FMUs into
build/; an installed package (`pip install .`, a wheel) carries the FMUs CMake built at install
time in harness/fmus/, laid out as build/ (CMakeLists.txt install rules)."""

from __future__ import annotations

from pathlib import Path

PACKAGE_DIR = Path(__file__).resolve().parent
REPO_ROOT = PACKAGE_DIR.parent  # the checkout's root (when IN_CHECKOUT)
IN_CHECKOUT = (REPO_ROOT / "CMakeLists.txt").is_file() and (REPO_ROOT / "fmu_src").is_dir()
INSTALLED_DIR = PACKAGE_DIR / "fmus"
BUILD_DIR = REPO_ROOT / "build" if IN_CHECKOUT else INSTALLED_DIR
# where the commands write by default: under the current directory, never inside the installed
# package (`make run` passes --out results, the committed results of the checkout)
RESULTS_DIR = Path("shroudedblade-results")
DEFAULT_CACHE_DIR = RESULTS_DIR / "cache"
