"""Variable tables of the FMUs, generated from their model descriptions (the source of truth).

The descriptions are found by globbing (`DESCRIPTION_GLOBS`), so the tables follow the files when
they move. One table per FMU; an FMI 3.0 description of a model that also has an FMI 2.0 one is
shown as its differences from it. `python sitegen/variable_tables.py` prints the Markdown.
"""

from __future__ import annotations

import sys
import xml.etree.ElementTree as ET
from dataclasses import dataclass, field
from pathlib import Path

REPO = Path(__file__).resolve().parent.parent
DESCRIPTION_GLOBS = ("fmu_src/models/*/modelDescription*.xml",)  # one folder per FMU
# FMI 3.0 variable elements (FMI 2.0 has ScalarVariable with one type child instead)
FMI3_TYPES = {
    "Float64",
    "Float32",
    "Int64",
    "Int32",
    "Int16",
    "Int8",
    "UInt64",
    "UInt32",
    "UInt16",
    "UInt8",
    "Boolean",
    "String",
    "Binary",
    "Enumeration",
    "Clock",
}


@dataclass
class Variable:
    name: str
    vr: int
    causality: str
    variability: str
    type: str
    unit: str = ""
    start: str = ""
    min: str = ""
    max: str = ""
    description: str = ""
    min_open: bool = False  # the bound itself is excluded (the description's OpenBounds annotation)
    max_open: bool = False


@dataclass
class Description:
    path: Path
    model: str
    fmi_version: str
    interfaces: list[str]
    variables: list[Variable] = field(default_factory=list)


def _variable(name_el: ET.Element, type_el: ET.Element, type_name: str) -> Variable:
    a, t = name_el.attrib, type_el.attrib
    return Variable(
        a["name"],
        int(a["valueReference"]),
        a.get("causality", "local"),
        a.get("variability", "continuous"),
        type_name,
        t.get("unit", t.get("declaredType", "")),
        t.get("start", ""),
        t.get("min", ""),
        t.get("max", ""),
        a.get("description", ""),
    )


def parse(path: Path) -> Description | None:
    """The description at `path`, or None when the file is not an FMI model description."""
    root = ET.parse(path).getroot()
    if root.tag != "fmiModelDescription":
        return None
    interfaces = [el.tag for el in root if el.tag in ("CoSimulation", "ModelExchange", "ScheduledExecution")]
    d = Description(path, root.get("modelName", "?"), root.get("fmiVersion", "?"), interfaces)
    mv = root.find("ModelVariables")
    # FMI 2.0 <VendorAnnotations><Tool>, FMI 3.0 <Annotations><Annotation>: the open bounds (fmu_src/gen)
    ob = root.find("VendorAnnotations/Tool/OpenBounds")
    ob = ob if ob is not None else root.find("Annotations/Annotation/OpenBounds")
    open_low = set(ob.get("lower", "").split()) if ob is not None else set()
    open_high = set(ob.get("upper", "").split()) if ob is not None else set()
    for el in mv if mv is not None else []:
        if el.tag == "ScalarVariable":
            type_el = el[0]
            v = _variable(el, type_el, type_el.tag)
            of = type_el.get("derivative")
            if of and not v.description:  # FMI 2.0: `derivative` is the 1-based index of the state
                v.description = f"derivative of {mv[int(of) - 1].get('name')}"
        elif el.tag in FMI3_TYPES:
            v = _variable(el, el, el.tag)
            of = el.get("derivative")
            if of and not v.description:  # FMI 3.0: `derivative` is the state's value reference
                state = next((s.get("name") for s in mv if s.get("valueReference") == of), of)
                v.description = f"derivative of {state}"
        else:
            continue
        v.min_open, v.max_open = v.name in open_low, v.name in open_high
        d.variables.append(v)
    return d


def find_descriptions(repo: Path = REPO) -> list[Description]:
    """Every model description under `repo`'s known places, ShroudedBlade first, FMI 2.0 before 3.0."""
    paths = sorted({p.resolve() for g in DESCRIPTION_GLOBS for p in repo.glob(g) if p.is_file()})
    found = [d for d in map(parse, paths) if d is not None]
    return sorted(found, key=lambda d: (d.model != "ShroudedBlade", d.model, d.fmi_version))


def _cell(text: str) -> str:
    return text.replace("|", "\\|").replace("\n", " ")


def _code(text: str) -> str:
    return f"`{text}`" if text else ""


def _range(v: Variable) -> str:
    if not (v.min or v.max):
        return ""
    lb = "(" if v.min_open or not v.min else "["
    rb = ")" if v.max_open or not v.max else "]"
    return f"{lb}{v.min or '-inf'}, {v.max or 'inf'}{rb}"


HEADER = (
    "| name | vr | causality, variability | type [unit] | start | range | description |\n|---|---|---|---|---|---|---|"
)


def _row(v: Variable) -> str:
    cells = [
        _code(v.name),
        str(v.vr),
        f"{v.causality}, {v.variability}",
        f"{v.type} [{v.unit}]" if v.unit else v.type,
        v.start,
        _range(v),
        v.description,
    ]
    return "| " + " | ".join(_cell(c) for c in cells) + " |"


def table(d: Description) -> str:
    return "\n".join([HEADER, *(_row(v) for v in d.variables)])


def differences(base: Description, other: Description) -> str:
    """What `other` (e.g. the FMI 3.0 description) declares differently from `base`."""
    a = {v.name: v for v in base.variables}
    b = {v.name: v for v in other.variables}
    lines = []
    only = [b[n] for n in b if n not in a]
    gone = [a[n] for n in a if n not in b]
    if only:
        lines += [f"Only in FMI {other.fmi_version}:", "", HEADER, *(_row(v) for v in only), ""]
    if gone:
        lines += [
            f"Not in FMI {other.fmi_version} (its binary refuses these value references): "
            + ", ".join(_code(v.name) for v in gone)
            + ".",
            "",
        ]

    def declared(v: Variable) -> tuple:
        return v.vr, v.causality, v.variability, v.unit, v.start, v.min, v.max

    changed = [n for n in a if n in b and declared(a[n]) != declared(b[n])]
    lines.append(
        "Every other variable is declared as in FMI 2.0 (name, value reference, causality, "
        "variability, unit, start, range; FMI 3.0 type names)."
        if not changed
        else "Declared differently: " + ", ".join(_code(n) for n in changed) + "."
    )
    return "\n".join(lines)


def markdown(repo: Path = REPO, level: int = 2) -> str:
    """All tables, one section per description, headings at `level`."""
    descriptions = find_descriptions(repo)
    out = []
    for d in descriptions:
        rel = d.path.relative_to(repo.resolve())
        out += [
            f"{'#' * level} {d.model} (FMI {d.fmi_version})",
            "",
            f"From `{rel}`; interfaces: {', '.join(d.interfaces)}; {len(d.variables)} variables.",
            "",
        ]
        base = next(
            (b for b in descriptions if b.model == d.model and b.fmi_version.startswith("2") and b is not d), None
        )
        out += [differences(base, d) if base is not None else table(d), ""]
    return "\n".join(out)


if __name__ == "__main__":
    sys.stdout.write(markdown())
