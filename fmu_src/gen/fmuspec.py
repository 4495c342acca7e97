"""Read a model's variable spec (fmu_src/models/<Name>/model.toml) into a flat, checked model.

The spec is TOML (Python 3.11's tomllib, no third-party package). A model spec has a [model]
table (identity, FMI faces, sources), optional `include` files whose [[var]] definitions it may
place by name, and [[var]] entries in the order of the FMI 2.0 model description (that order
gives the ModelStructure indices). A [[var]] entry is one of

- a definition: name, vr, type, causality, ... (keys below);
- `use = "name"` or `use = ["a", "b"]`: definitions from an included file (a pattern by its name
  before "[", e.g. "modalDisplacement"), placed here; other
  keys of the entry override the included ones (e.g. a model's own description);
- a pattern: a definition with `for = {i = [1, 6]}` (or two indices, `{r = [1, 15], c = [1, 14]}`,
  expanded row-major); every string is a template whose `{expr}` parts are Python expressions of
  the indices, `k` (the 0-based element number), `range` and the lists of `[model.lists]`; `vr` is
  an expression; an element of `depends` may give several names separated by spaces.

Keys of a definition: name, vr, type (Real, Integer, Boolean), causality (parameter, input, output,
local), variability (default: fixed for parameters, else continuous), unit, start, min, max,
min_open, max_open (the bound itself excluded: the C table refuses it, the XML cannot say it),
description, comment (an XML comment before the variable), store ("par": a Real slot in the model
data's par[], "ipar": an Integer/Boolean slot in ipar[], "input": the input array in[] at C
constant `slot`), slot (the slot's name: Par<slot>/Ipar<slot>, default the name capitalized),
output (the C expression of the model's output number, for outputs and locals), depends (names
the output or derivative depends on, model-exchange semantics: states and inputs), derivative_of
(the state this local is the derivative of), me_only (a model-exchange local: no FMI 3.0 face).
"""

from __future__ import annotations

import tomllib
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any

TYPES = ("Real", "Integer", "Boolean")
CAUSALITIES = ("parameter", "input", "output", "local")
KEYS = {
    "array",
    "name",
    "vr",
    "type",
    "causality",
    "variability",
    "unit",
    "start",
    "min",
    "max",
    "min_open",
    "max_open",
    "description",
    "comment",
    "store",
    "slot",
    "output",
    "depends",
    "derivative_of",
    "me_only",
}


class SpecError(ValueError):
    """The spec is not usable; the message names the file and the entry."""


@dataclass
class Var:
    """One scalar variable of a model (patterns expanded)."""

    name: str
    vr: int
    type: str
    causality: str
    variability: str
    unit: str = ""
    start: Any = None
    min: float | None = None
    max: float | None = None
    min_open: bool = False
    max_open: bool = False
    description: str = ""
    comment: str = ""
    store: str = ""
    slot: str = ""
    output: str = ""
    depends: list[str] = field(default_factory=list)
    derivative_of: str = ""
    me_only: bool = False
    array: str = ""  # a pattern's name for C ("modalDisplacement"; default: the name before "[")
    elem: int = 0  # the element's number in its pattern (0-based)
    count: int = 1  # elements of its pattern, else 1

    @property
    def initial(self) -> str:
        """FMI initial attribute ('' for inputs)."""
        if self.causality == "parameter":
            return "exact"
        if self.causality == "input":
            return ""
        return "exact" if self.store else "calculated"


@dataclass
class Model:
    """A model spec read and expanded: identity, faces, sources and its variables in spec order."""

    path: Path
    name: str
    guid: str
    description: str
    info: dict[str, Any]
    vars: list[Var]
    units: dict[str, dict[str, Any]]
    log_categories: dict[str, str]

    def var(self, name: str) -> Var:
        for v in self.vars:
            if v.name == name:
                return v
        raise SpecError(f"{self.path}: no variable named {name!r}")


def _template(text: str, env: dict[str, Any], where: str) -> str:
    """`text` with every `{expr}` replaced by the value of expr in env."""
    out, i = [], 0
    while i < len(text):
        j = text.find("{", i)
        if j < 0:
            out.append(text[i:])
            break
        k = text.find("}", j)
        if k < 0:
            raise SpecError(f"{where}: unclosed '{{' in {text!r}")
        out.append(text[i:j])
        out.append(str(_eval(text[j + 1 : k], env, where)))
        i = k + 1
    return "".join(out)


def _eval(expr: str, env: dict[str, Any], where: str) -> Any:
    try:
        return eval(expr, {"__builtins__": {}}, env)  # the project's own spec: index arithmetic only
    except Exception as exc:
        raise SpecError(f"{where}: cannot evaluate {expr!r}: {exc}") from None


def _expand(entry: dict[str, Any], lists: dict[str, Any], where: str) -> list[dict[str, Any]]:
    """A pattern's elements (row-major over its indices), or the entry itself."""
    loops = entry.get("for")
    if loops is None:
        return [entry]
    names = list(loops)
    ranges = [range(loops[n][0], loops[n][1] + 1) for n in names]
    combos: list[dict[str, int]] = [{}]
    for n, r in zip(names, ranges):
        combos = [dict(c, **{n: x}) for c in combos for x in r]
    out = []
    for k, idx in enumerate(combos):
        env = dict(lists, **idx, k=k, range=range)
        e: dict[str, Any] = {}
        for key, val in entry.items():
            if key == "for":
                continue
            if key == "vr":
                e[key] = int(_eval(val, env, where)) if isinstance(val, str) else val + k
            elif key == "comment" and k > 0:
                continue
            elif isinstance(val, str):
                e[key] = _template(val, env, where)
            elif key == "depends":  # a template may give several names, separated by spaces
                e[key] = [name for x in val for name in _template(x, env, where).split()]
            else:
                e[key] = val
        e["array"] = entry.get("array", entry["name"].split("[")[0])
        e["_elem"], e["_count"] = k, len(combos)
        out.append(e)
    return out


def _make(e: dict[str, Any], where: str) -> Var:
    unknown = set(e) - KEYS - {"_elem", "_count"}
    if unknown:
        raise SpecError(f"{where}: unknown keys {sorted(unknown)} (known: {sorted(KEYS)})")
    for key in ("name", "vr", "type", "causality"):
        if key not in e:
            raise SpecError(f"{where}: {e.get('name', '?')!r} lacks {key!r}")
    if e["type"] not in TYPES or e["causality"] not in CAUSALITIES:
        raise SpecError(f"{where}: {e['name']!r}: type must be one of {TYPES}, causality one of {CAUSALITIES}")
    variability = e.get("variability", "fixed" if e["causality"] == "parameter" else "continuous")
    v = Var(
        name=e["name"],
        vr=int(e["vr"]),
        type=e["type"],
        causality=e["causality"],
        variability=variability,
        **{k: e[k] for k in KEYS - {"name", "vr", "type", "causality", "variability"} if k in e},
    )
    v.elem, v.count = e.get("_elem", 0), e.get("_count", 1)
    if v.store and v.store not in ("par", "ipar", "input"):
        raise SpecError(f"{where}: {v.name!r}: store must be par, ipar or input")
    if v.store == "input" and not v.slot:
        raise SpecError(f"{where}: input {v.name!r} needs slot (the C index of its row in in[])")
    if v.causality in ("output", "local") and not v.output:
        raise SpecError(f"{where}: {v.name!r} needs output (its C output number)")
    if v.causality in ("parameter", "input") and v.start is None:
        raise SpecError(f"{where}: {v.name!r} needs a start value")
    return v


def _read(path: Path) -> dict[str, Any]:
    try:
        with open(path, "rb") as f:
            return tomllib.load(f)
    except (OSError, tomllib.TOMLDecodeError) as exc:
        raise SpecError(f"{path}: {exc}") from None


def load(path: Path) -> Model:
    """The model of spec file `path`, its includes merged and patterns expanded; checked."""
    path = Path(path)
    doc = _read(path)
    info = doc.get("model", {})
    for key in ("name", "guid", "description"):
        if key not in info:
            raise SpecError(f"{path}: [model] lacks {key!r}")
    common = _read(path.parent.parent / "common.toml")
    lists = dict(info.get("lists", {}))
    shared: dict[str, dict[str, Any]] = {}
    for inc in info.get("include", []):
        inc_doc = _read(path.parent / inc)
        lists.update(inc_doc.get("lists", {}))
        for e in inc_doc.get("var", []):
            shared[e.get("array", e["name"].split("[")[0])] = e
    entries: list[tuple[dict[str, Any], str]] = []  # (expanded entry, where it is written)
    for n, e in enumerate(doc.get("var", [])):
        where = f"{path} [[var]] #{n + 1}"
        if "use" in e:
            names = e["use"] if isinstance(e["use"], list) else [e["use"]]
            for j, name in enumerate(names):
                if name not in shared:
                    raise SpecError(f"{where}: use = {name!r} is not defined in {info.get('include', [])}")
                # the entry's keys override the included ones; its comment goes before the first only
                over = {k: v for k, v in e.items() if k != "use" and (k != "comment" or j == 0)}
                entries += [(x, where) for x in _expand(dict(shared[name], **over), lists, where)]
        else:
            entries += [(x, where) for x in _expand(e, lists, where)]
    model_vars = [_make(e, where) for e, where in entries]
    model = Model(
        path=path,
        name=info["name"],
        guid=info["guid"],
        description=info["description"],
        info=info,
        vars=model_vars,
        units=common["units"],
        log_categories=info.get("log_categories", common["log_categories"]),
    )
    _check(model)
    return model


def _check(m: Model) -> None:
    seen_names: set[str] = set()
    seen_vrs: dict[int, str] = {}
    for v in m.vars:
        if v.name in seen_names:
            raise SpecError(f"{m.path}: variable {v.name!r} declared twice")
        if v.vr in seen_vrs:
            raise SpecError(f"{m.path}: value reference {v.vr} of {v.name!r} is taken by {seen_vrs[v.vr]!r}")
        if v.vr == 0 and m.info.get("fmi3"):
            raise SpecError(f"{m.path}: value reference 0 is the FMI 3.0 face's (time)")
        if v.unit and v.unit not in m.units:
            raise SpecError(f"{m.path}: {v.name!r} has unit {v.unit!r}, not in common.toml [units]")
        seen_names.add(v.name)
        seen_vrs[v.vr] = v.name
    for v in m.vars:
        for d in v.depends + ([v.derivative_of] if v.derivative_of else []):
            if d not in seen_names:
                raise SpecError(f"{m.path}: {v.name!r} refers to {d!r}, which is not a variable of the model")
