"""ShroudedBlade harness: drive the FMU with fmpy, sweep, reproduce the paper, validate."""
from __future__ import annotations

from importlib import metadata as _metadata
from pathlib import Path

__all__ = ["__version__", "fmu_path"]


def _version() -> str:
    """The installed distribution's version; in a bare checkout (not installed) pyproject.toml's,
    the one source of both."""
    try:
        return _metadata.version("shroudedblade-harness")
    except _metadata.PackageNotFoundError:
        import tomllib
        with open(Path(__file__).resolve().parents[1] / "pyproject.toml", "rb") as fh:
            return str(tomllib.load(fh)["project"]["version"])


__version__ = _version()


def fmu_path(name: str = "ShroudedBlade") -> Path:
    """Path of the FMU `name`: "ShroudedBlade" (FMI 2.0 co-simulation and model exchange),
    "fmi3/ShroudedBlade" (FMI 3.0 co-simulation), "Excitation", "BladeExternalContact" or
    "ShroudContact". Installed: the FMU that came with the package (harness/fmus/); in a checkout:
    build/<name>.fmu, built with CMake if out of date. Raises KeyError for an unknown name."""
    from harness.fmu.build import fmu_file
    return fmu_file(name)
