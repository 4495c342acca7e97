"""Start values for a whole ring: `--start-values NAME VALUE ...` goes to every FMU instance that has
the variable (BladeExternalContact, ShroudContact), typed
and range-checked against the FMUs' model descriptions before any instance is made (the FMU's own
error would surface as an unexplained fmi2Error in the middle of a run). The load's Fw0 and
engineOrder are the ring's (every blade and contact gets them); its bladeIndex and bladeCount are
set by the ring itself.
"""

from __future__ import annotations

import math
from dataclasses import replace
from functools import lru_cache
from typing import Any, Mapping

from fmpy import read_model_description

from harness.fmu.slave import build_ring_fmus
from harness.model.params import ParameterError
from harness.system.ring import Ring

# what the ring sets itself (constant speed, the blade's place in the ring)
RING_OWNED = {
    "bladeIndex": "the ring (blade i)",
    "bladeCount": "--blades",
    "rotorSpeed": "--speed",
}


@lru_cache(maxsize=None)
def settable() -> dict[str, dict[str, tuple[str, float, float]]]:
    """{"blade"|"contact": {name: (type, min, max)}}: parameters and settable start
    values (initial="exact" outputs) of each ring FMU, inputs left out (the master sets them)."""
    bx, sc = build_ring_fmus()
    out: dict[str, dict[str, tuple[str, float, float]]] = {}
    for kind, path in (("blade", bx), ("contact", sc)):
        md = read_model_description(str(path))
        out[kind] = {
            v.name: (
                v.type,
                float(v.min) if v.min is not None else -math.inf,
                float(v.max) if v.max is not None else math.inf,
            )
            for v in md.modelVariables
            if v.causality == "parameter" or (v.causality == "output" and v.initial == "exact")
        }
    return out


def max_blades() -> int:
    """Largest ring the blade FMU describes (its built-in load's bladeCount max)."""
    return int(settable()["blade"]["bladeCount"][2])


def typed(name: str, text: Any, typ: str, lo: float, hi: float, origin: str) -> Any:
    """`text` as the variable's type, inside [lo, hi]; ParameterError naming the value otherwise."""
    try:
        if typ == "Boolean":
            if str(text).lower() not in ("true", "false", "1", "0"):
                raise ValueError
            return str(text).lower() in ("true", "1")
        value: float | int = int(text) if typ == "Integer" else float(text)
    except (TypeError, ValueError):
        raise ParameterError(f"{origin} {name} {text!r}: not a {typ} value") from None
    if not math.isfinite(value) or not lo <= value <= hi:
        raise ParameterError(f"{origin} {name} {text!r} outside [{lo:g}, {hi:g}] (the FMU's range)")
    return value


def apply(ring: Ring, values: Mapping[str, Any], origin: str = "--start-values") -> Ring:
    """`ring` with every value set on each instance that has the variable: blade and contact
    parameters into ring.blade / ring.contact, the load's Fw0 and engineOrder into ring.fw0 and
    ring.engine_order (the blades' and contacts' parameters alike); an unknown name, a name the
    ring sets itself, a bad type or range raises ParameterError naming it."""
    var = settable()
    blade, contact, fw0, eo = dict(ring.blade), dict(ring.contact), ring.fw0, ring.engine_order
    for name, text in values.items():
        if name in RING_OWNED:
            raise ParameterError(f"{origin} {name}: set by the ring ({RING_OWNED[name]}), not a start value")
        owners = [k for k in ("blade", "contact") if name in var[k]]
        if not owners:
            known = sorted(set().union(*var.values()) - set(RING_OWNED))
            raise ParameterError(f"{origin} {name}: no FMU of the ring has this variable; known: {', '.join(known)}")
        for kind in owners:
            v = typed(name, text, *var[kind][name], origin=origin)
            if name == "Fw0":
                fw0 = float(v)
            elif name == "engineOrder":
                eo = int(v)
            elif kind == "blade":
                blade[name] = v
            elif kind == "contact":
                contact[name] = v
    return replace(ring, blade=blade, contact=contact, fw0=fw0, engine_order=eo)
