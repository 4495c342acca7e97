"""Zip an FMU's staging folder into its .fmu, byte for byte the same on every build.

    python fmu_src/gen/pack_fmu.py STAGE OUT

The archive holds every file under STAGE in sorted path order, each with the same fixed time
stamp (1980-01-01 00:00, the earliest a zip can store) and permissions (0644, 0755 for the
binaries) and no directory entries: the bytes depend only on the files' contents and names, so a
rebuild of unchanged sources gives the same .fmu (a committed FMU stays unchanged).
Python 3.11 standard library only.
"""

from __future__ import annotations

import sys
import zipfile
from pathlib import Path

FIXED_TIME = (1980, 1, 1, 0, 0, 0)


def pack(stage: Path, out: Path) -> None:
    files = sorted(p for p in stage.rglob("*") if p.is_file())
    tmp = out.with_name(out.name + ".tmp")
    with zipfile.ZipFile(tmp, "w", compression=zipfile.ZIP_DEFLATED, compresslevel=9) as z:
        for path in files:
            rel = path.relative_to(stage).as_posix()
            info = zipfile.ZipInfo(rel, date_time=FIXED_TIME)
            info.compress_type = zipfile.ZIP_DEFLATED
            info.create_system = 3  # Unix, so that external_attr holds the mode
            mode = 0o755 if rel.startswith("binaries/") else 0o644
            info.external_attr = (0o100000 | mode) << 16
            z.writestr(info, path.read_bytes(), compresslevel=9)
    tmp.replace(out)


if __name__ == "__main__":
    if len(sys.argv) != 3:
        sys.exit(__doc__)
    pack(Path(sys.argv[1]), Path(sys.argv[2]))
