"""Generate a model's files from its variable spec (fmu_src/models/<Name>/model.toml).

    python fmu_src/gen/fmugen.py SPEC --out DIR        # CMake, at configure time, into the build tree
    python fmu_src/gen/fmugen.py SPEC --check          # 1 if a committed generated file drifted
    python fmu_src/gen/fmugen.py SPEC --update         # rewrite the committed generated files

Into DIR/models/<Name>/: variables.h (value references, bounds, slot enums), variables.inc (the
rows of the C variable table), modelDescription.xml (FMI 2.0), with an [model.fmi3] table
modelDescription3.xml and buildDescription3.xml (FMI 3.0), and sources.cmake (the files of each
face, relative to fmu_src/). A file is rewritten only when its text changes (no needless rebuild).
The model descriptions are also committed next to the spec (the FMU's public contract, read by
the Python package in a checkout before anything is built), and the model's parameters as a typed
Python record in harness/model/records/<model>.py (emit_py); --check compares them.
Python 3.11 standard library only.
"""

from __future__ import annotations

import argparse
import sys
import tomllib
from pathlib import Path

import emit_c
import emit_py
import emit_xml
import fmuspec

FMU_SRC = Path(__file__).resolve().parent.parent
RECORDS = FMU_SRC.parent / "harness" / "model" / "records"  # the typed parameter records (committed)


def expand_sources(items: list[str], groups: dict[str, list[str]], where: str) -> list[str]:
    """Source files relative to fmu_src/, "@group" replaced by the group's files (recursively)."""
    out: list[str] = []
    for item in items:
        if item.startswith("@"):
            if item[1:] not in groups:
                raise fmuspec.SpecError(f"{where}: no source group {item!r} in fmu_src/sources.toml")
            out += expand_sources(groups[item[1:]], groups, where)
        elif item not in out:
            out.append(item)
    return out


def generate(spec: Path) -> dict[str, str]:
    """File name -> text of everything generated from `spec`."""
    model = fmuspec.load(spec)
    spec = spec.resolve()
    rel = spec.relative_to(FMU_SRC.parent).as_posix() if spec.is_relative_to(FMU_SRC.parent) else spec.as_posix()
    with open(FMU_SRC / "sources.toml", "rb") as f:
        groups = tomllib.load(f)
    generated = [f"models/{model.name}/variables.h", f"models/{model.name}/variables.inc"]
    files = {"variables.h": emit_c.header(model, rel), "variables.inc": emit_c.table(model, rel)}
    faces = {"FMI2": model.info.get("fmi2")}
    if "fmi3" in model.info:
        faces["FMI3"] = model.info["fmi3"]
    cmake = [f"# Generated from {rel} by fmu_src/gen: the files of each face, relative to fmu_src/."]
    sources: dict[str, list[str]] = {}
    for face, table in faces.items():
        if table is None:
            raise fmuspec.SpecError(f"{spec}: [model.fmi2] is missing")
        sources[face] = expand_sources(table["sources"], groups, f"{spec} [model.{face.lower()}]")
        cmake.append(f"set({model.name}_{face}_FILES {' '.join(sources[face])})")
    cmake.append(f"set({model.name}_GENERATED_FILES {' '.join(generated)})")
    files["sources.cmake"] = "\n".join(cmake) + "\n"
    files["modelDescription.xml"] = emit_xml.fmi2(model, sources["FMI2"], rel)
    if "FMI3" in sources:
        files["modelDescription3.xml"] = emit_xml.fmi3(model, rel)
        files["buildDescription3.xml"] = emit_xml.build_description3(model, sources["FMI3"], rel)
    return files


COMMITTED = ("modelDescription.xml", "modelDescription3.xml")


def committed(spec: Path) -> dict[Path, str]:
    """The committed generated files of `spec` (path -> text): its model descriptions, next to it,
    and its typed parameter record in the Python package."""
    files = generate(spec)
    model = fmuspec.load(spec)
    out = {spec.parent / name: files[name] for name in COMMITTED if name in files}
    spec = spec.resolve()
    rel = spec.relative_to(FMU_SRC.parent).as_posix() if spec.is_relative_to(FMU_SRC.parent) else spec.as_posix()
    out[RECORDS / f"{emit_py.module_name(model)}.py"] = emit_py.record(model, rel)
    return out


def write_if_changed(path: Path, text: str) -> None:
    if not path.exists() or path.read_text() != text:
        path.parent.mkdir(parents=True, exist_ok=True)
        path.write_text(text)


def main(argv: list[str] | None = None) -> int:
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("spec", type=Path, nargs="+", help="model spec(s), fmu_src/models/<Name>/model.toml")
    ap.add_argument("--out", type=Path, help="generated tree root (CMake: <build>/generated)")
    ap.add_argument("--check", action="store_true", help="fail if a committed model description differs")
    ap.add_argument("--update", action="store_true", help="rewrite the committed model descriptions")
    args = ap.parse_args(argv)
    drift = []
    try:
        for spec in args.spec:
            files = generate(spec)
            name = fmuspec.load(spec).name
            if args.out:
                for fname, text in files.items():
                    write_if_changed(args.out / "models" / name / fname, text)
            for path, text in committed(spec).items():
                if args.update:
                    write_if_changed(path, text)
                elif args.check and (not path.exists() or path.read_text() != text):
                    drift.append(str(path))
    except fmuspec.SpecError as exc:
        print(f"fmugen: {exc}", file=sys.stderr)
        return 2
    if drift:
        print(
            "fmugen: out of date with the spec (run fmu_src/gen/fmugen.py --update): " + ", ".join(drift),
            file=sys.stderr,
        )
        return 1
    return 0


if __name__ == "__main__":
    sys.exit(main())
