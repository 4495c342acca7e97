"""The C side of a model spec: the value-reference header and the variable table.

variables.h: identity (MODEL_IDENTIFIER, MODEL_NAME, MODEL_GUID), with model exchange the numbers
of event indicators and states the description declares, a value reference per variable
(vr_<name>, and vr_<array> for the first element of a pattern), the bounds of the scalar variables
that have them (min_<name>, max_<name>), and the slot enums of the model data (RealParam: par[],
IntParam: ipar[]). variables.inc: the rows of the model's VarInfo table sorted by value reference,
included by model.c inside `static const VarInfo VARS[] = { ... };` where the macros PAR(k),
IPAR(k) and INPUT(k) give the byte offset of a slot in the model's data.
"""

from __future__ import annotations

import math
import re

from fmuspec import Model, Var

CAUS = {"parameter": "CausParameter", "input": "CausInput", "output": "CausOutput", "local": "CausLocal"}
TYPE = {"Real": "VarReal", "Integer": "VarInteger", "Boolean": "VarBoolean"}


def c_ident(name: str) -> str:
    """A C identifier for a variable name: der(a[2]) -> der_a_2, s[1,2] -> s_1_2."""
    return re.sub(r"_+", "_", re.sub(r"\W", "_", name)).strip("_")


def c_double(x: float) -> str:
    if math.isinf(x):
        return "HUGE_VAL" if x > 0 else "-HUGE_VAL"
    return repr(float(x))


def _cap(s: str) -> str:
    return s[0].upper() + s[1:]


def slots(model: Model) -> dict[str, str]:
    """The C slot expression of every stored variable (Par<slot> + element, Ipar<slot>, the input's
    slot), by name."""
    out: dict[str, str] = {}
    for v in model.vars:
        if v.store == "input":
            out[v.name] = v.slot
        elif v.store:
            base = ("Par" if v.store == "par" else "Ipar") + _cap(v.slot or (v.array if v.count > 1 else v.name))
            out[v.name] = f"{base} + {v.elem}" if v.count > 1 else base
    return out


def _slot_enum(model: Model, store: str, prefix: str, total: str, type_name: str) -> list[str]:
    items, n = [], 0
    for v in model.vars:
        if v.store != store or v.elem != 0:
            continue
        items.append(f"    {prefix}{_cap(v.slot or (v.array if v.count > 1 else v.name))} = {n},")
        n += v.count
    if not items:
        return []
    return ["typedef enum {", *items, f"    {total} = {n}", f"}} {type_name};", ""]


def header(model: Model, spec_rel: str) -> str:
    guard = f"{c_ident(model.name).upper()}_VARIABLES_H"
    lines = [
        f"/* Generated from {spec_rel} by fmu_src/gen: edit the spec, not this file. */",
        f"#ifndef {guard}",
        f"#define {guard}",
        "",
        f"#define MODEL_IDENTIFIER {model.name}",
        f'#define MODEL_NAME "{model.name}"',
        f'#define MODEL_GUID "{model.guid}"',
        "",
    ]
    f2 = model.info.get("fmi2", {})
    if f2.get("model_exchange"):
        lines += [
            "/* model exchange: the FMI 2.0 description's numberOfEventIndicators and its states (the",
            " * variables with a der(...)) */",
            f"#define MODEL_EVENT_INDICATORS {f2.get('event_indicators', 0)}",
            f"#define MODEL_CONTINUOUS_STATES {sum(1 for v in model.vars if v.derivative_of)}",
            "",
        ]
    lines.append("/* value references */")
    for v in model.vars:
        if v.count > 1 and v.elem == 0:
            lines.append(f"#define vr_{c_ident(v.array)} {v.vr} /* first of {v.count} */")
        lines.append(f"#define vr_{c_ident(v.name)} {v.vr}")
    lines += ["", "/* bounds */"]
    for v in model.vars:
        if v.count == 1 and v.type == "Real":
            if v.min is not None:
                lines.append(f"#define min_{c_ident(v.name)} {c_double(v.min)}")
            if v.max is not None:
                lines.append(f"#define max_{c_ident(v.name)} {c_double(v.max)}")
        elif v.count == 1 and v.type == "Integer" and v.max is not None:
            lines.append(f"#define max_{c_ident(v.name)} {int(v.max)}")
    lines += ["", "/* slots of the model data: par[] (Real), ipar[] (Integer, Boolean) */"]
    lines += _slot_enum(model, "par", "Par", "PAR_NUM", "RealParam")
    lines += _slot_enum(model, "ipar", "Ipar", "IPAR_NUM", "IntParam")
    lines += ["#endif", ""]
    return "\n".join(lines)


def _row(v: Var, slot: dict[str, str]) -> str:
    c_unit = "" if v.unit in ("", "1") else v.unit
    if v.type == "Boolean":
        lo, hi, start = "0.0", "1.0", "1.0" if v.start else "0.0"
    else:
        lo = c_double(-math.inf if v.min is None else v.min)
        hi = c_double(math.inf if v.max is None else v.max)
        start = c_double(0.0 if v.start is None else v.start)
    if v.store == "par":
        offset = f"PAR({slot[v.name]})"
    elif v.store == "ipar":
        offset = f"IPAR({slot[v.name]})"
    elif v.store == "input":
        offset = f"INPUT({slot[v.name]})"
    else:
        offset = "VAR_NO_OFFSET"
    output = v.output if v.output else "-1"
    return (
        f'    {{.vr = {v.vr}, .name = "{v.name}", .type = {TYPE[v.type]}, .causality = {CAUS[v.causality]}, '
        f'.unit = "{c_unit}", .start = {start}, .lo = {lo}, .hi = {hi}, .loOpen = {int(v.min_open)}, '
        f".hiOpen = {int(v.max_open)}, .offset = {offset}, .output = {output}, .meOnly = {int(v.me_only)}}},"
    )


def table(model: Model, spec_rel: str) -> str:
    slot = slots(model)
    rows = [_row(v, slot) for v in sorted(model.vars, key=lambda v: v.vr)]
    return "\n".join(
        [f"/* Generated from {spec_rel} by fmu_src/gen: the rows of VARS, sorted by value reference. */", *rows, ""]
    )
