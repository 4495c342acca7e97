"""Parameter sets for the ShroudedBlade FMU and the reference: names, defaults, units, validation.

The FMU's variable spec (fmu_src/models/ShroudedBlade/model.toml) is the single source of truth:
fmu_src/gen generates from it both the model description and the typed record
`ShroudedBladeParameters` (harness.model.records.shrouded_blade: every parameter with its type,
default, unit, bounds, open bounds and description), which this module's `specs()` reads; value
references and input ranges come from the model description. `validate()` turns any user mapping
into a complete, checked parameter dict or raises `ParameterError` naming the value, the accepted
range and where the value came from; `typed()` gives the same as the record.

Start values of the state (the outputs with initial="exact": tipDisplacement, tipVelocity,
dissipatedEnergy, jenkinsForce, runningMaximum; docs/model-notes.md s.7) are accepted too and set
on the FMU before initialization, but they are not defaults: `validate()` returns them only when
given, so a parameter set without them is what it always was (a run from rest). Their cross-field
rules (jenkinsForce inside the friction cone, frictionModel 3 only) are checked by the FMU, whose
message `BladeFMU` raises.
"""

from __future__ import annotations

import math
import xml.etree.ElementTree as ET
import zipfile
from dataclasses import dataclass, fields
from functools import lru_cache
from typing import Any, Mapping

from harness.model.records.shrouded_blade import STATE_STARTS, ShroudedBladeParameters
from harness.paths import BUILD_DIR, IN_CHECKOUT, REPO_ROOT

# in a checkout, in the model's folder (fmu_src/models/<Name>/); installed: inside the FMU
MODEL_DESCRIPTION = REPO_ROOT / "fmu_src" / "models" / "ShroudedBlade" / "modelDescription.xml"


class ParameterError(ValueError):
    """A parameter value or name is not acceptable; the message says which, why and what to do."""


@dataclass(frozen=True)
class ParamSpec:
    name: str
    type: str  # "Real", "Integer", "Boolean"
    default: Any
    unit: str
    low: float | None  # lower bound
    high: float | None  # upper bound
    low_open: bool = False  # True: value must be > low (not >=)
    high_open: bool = False
    description: str = ""
    start_value: bool = False  # start value of an initial="exact" output (not a default)

    def range_text(self) -> str:
        if self.type == "Boolean":
            return "true or false"
        lo = "-inf" if self.low is None else f"{self.low:g}"
        hi = "inf" if self.high is None else f"{self.high:g}"
        lb = "(" if (self.low is None or self.low_open) else "["
        rb = ")" if (self.high is None or self.high_open) else "]"
        unit = f" {self.unit}" if self.unit and self.unit != "1" else ""
        return f"{lb}{lo}, {hi}{rb}{unit}"


@lru_cache(maxsize=1)
def _model_description() -> ET.Element:
    """The checkout's modelDescription.xml, or an installed package's: the one inside its FMU."""
    if IN_CHECKOUT:
        return ET.parse(MODEL_DESCRIPTION).getroot()
    with zipfile.ZipFile(BUILD_DIR / "ShroudedBlade.fmu") as z:
        return ET.fromstring(z.read("modelDescription.xml"))


@lru_cache(maxsize=1)
def value_references() -> dict[str, int]:
    """name -> value reference of every FMU variable, in the order of modelDescription.xml."""
    return {sv.attrib["name"]: int(sv.attrib["valueReference"]) for sv in _model_description().iter("ScalarVariable")}


def value_reference(name: str) -> int:
    """The value reference of the FMU variable `name` (modelDescription.xml)."""
    try:
        return value_references()[name]
    except KeyError:
        raise KeyError(f"{name!r} is not a variable of modelDescription.xml") from None


def _spec(name: str, meta: Mapping[str, Any], default: Any, start_value: bool = False) -> ParamSpec:
    lo, hi = meta["min"], meta["max"]
    return ParamSpec(
        name=name,
        type=meta["type"],
        default=default,
        unit=meta["unit"],
        low=None if lo is None else float(lo),
        high=None if hi is None else float(hi),
        low_open=meta["min_open"],
        high_open=meta["max_open"],
        description=meta["description"],
        start_value=start_value,
    )


@lru_cache(maxsize=1)
def specs() -> dict[str, ParamSpec]:
    """All parameters by name (the record's fields in spec order), then the start values of the
    state (STATE_STARTS)."""
    out = {f.name: _spec(f.name, f.metadata, f.default) for f in fields(ShroudedBladeParameters)}
    out.update({name: _spec(name, meta, meta["start"], start_value=True) for name, meta in STATE_STARTS.items()})
    return out


@lru_cache(maxsize=None)
def input_range(name: str) -> tuple[float, float]:
    """(min, max) of a Real input of the FMU, from modelDescription.xml (e.g. rotorSpeed [rpm])."""
    root = _model_description()
    for sv in root.iter("ScalarVariable"):
        if sv.get("name") == name and sv.get("causality") == "input":
            (typ,) = list(sv)
            return float(typ.get("min", "-inf")), float(typ.get("max", "inf"))
    raise KeyError(f"{name!r} is not an input of modelDescription.xml")


def defaults() -> dict[str, Any]:
    """Paper Table 1 defaults (docs/model.md section 1) for every parameter (start values of the
    state are not parameters: they are left out)."""
    return {name: s.default for name, s in specs().items() if not s.start_value}


def start_values(params: Mapping[str, Any]) -> dict[str, Any]:
    """The start values of the state in a validated parameter dict (empty for a run from rest)."""
    sp = specs()
    return {k: v for k, v in params.items() if sp[k].start_value}


def fmu_parameters(params: Mapping[str, Any], external_load: bool = True) -> dict[str, Any]:
    """The values of a validated parameter dict set on the FMU. With `external_load` (the single
    blade's drivers) the harness feeds the load F_w0 sin(EO Omega t) through the input aeroLoad,
    so the FMU's own built-in load is switched off: Fw0 = 0 on the FMU, else the load would count
    twice. Without, the FMU's Fw0 is the given amplitude (its built-in load, as on the ring)."""
    if not external_load:
        return dict(params)
    out = {k: v for k, v in params.items() if k != "Fw0"}
    out["Fw0"] = 0.0  # (set last, after the parameters proper)
    return out


def typed(params: Mapping[str, Any] | None = None, source: str = "") -> ShroudedBladeParameters:
    """`validate(params, source)` as the typed record (the start values of the state, which are
    not parameters, are refused here)."""
    p = validate(params, source)
    starts = sorted(k for k in p if specs()[k].start_value)
    if starts:
        where = f" (from {source})" if source else ""
        raise ParameterError(f"{', '.join(starts)}{where}: start values of the state, not parameters")
    return ShroudedBladeParameters(**p)


def _check_one(spec: ParamSpec, value: Any, source: str) -> Any:
    where = f" (from {source})" if source else ""
    if spec.type == "Boolean":
        if isinstance(value, bool):
            return value
        if isinstance(value, str) and value.lower() in ("true", "false", "1", "0"):
            return value.lower() in ("true", "1")
        if isinstance(value, (int, float)) and value in (0, 1):
            return bool(value)
        raise ParameterError(f"{spec.name} = {value!r}{where} is not a Boolean; accepted: {spec.range_text()}")
    try:
        if spec.type == "Integer":
            if isinstance(value, bool):
                raise TypeError
            fv = float(value)
            if not fv.is_integer():
                raise ParameterError(f"{spec.name} = {value!r}{where} must be an integer in {spec.range_text()}")
            num: Any = int(fv)
        else:
            if isinstance(value, bool):
                raise TypeError
            num = float(value)
    except (TypeError, ValueError) as exc:
        if isinstance(exc, ParameterError):
            raise
        raise ParameterError(f"{spec.name} = {value!r}{where} is not a number; accepted: {spec.range_text()}") from None
    if isinstance(num, float) and not math.isfinite(num):
        raise ParameterError(f"{spec.name} = {value!r}{where} is not finite; accepted: {spec.range_text()}")
    bad = False
    if spec.low is not None and (num < spec.low or (spec.low_open and num == spec.low)):
        bad = True
    if spec.high is not None and (num > spec.high or (spec.high_open and num == spec.high)):
        bad = True
    if bad:
        unit = f" {spec.unit}" if spec.unit and spec.unit != "1" else ""
        raise ParameterError(
            f"{spec.name} = {value!r}{unit}{where} is out of range; accepted: {spec.range_text()} ({spec.description})"
        )
    return num


def validate(params: Mapping[str, Any] | None = None, source: str = "") -> dict[str, Any]:
    """Complete `params` with the defaults and check every value; returns a new dict (start values
    of the state only when given).

    Raises ParameterError for an unknown name (listing the known ones) or a bad value (naming the
    value, the accepted range and `source`, e.g. "command line" or "sweep.toml").
    """
    sp = specs()
    out = defaults()
    for name, value in (params or {}).items():
        if name not in sp:
            where = f" (from {source})" if source else ""
            known = ", ".join(sorted(sp))
            raise ParameterError(f"unknown parameter {name!r}{where}; known parameters: {known}")
        out[name] = _check_one(sp[name], value, source)
    return out
