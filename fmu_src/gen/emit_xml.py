"""The XML side of a model spec: the FMI 2.0 and FMI 3.0 model descriptions and the FMI 3.0 build
description (sources/buildDescription.xml).

FMI 2.0 gives the variables in spec order (ModelStructure refers to them by that 1-based index);
with model exchange it declares every variable, the states' derivatives and the dependencies on
states and inputs; co-simulation only, the dependencies are on inputs only. The FMI 3.0
co-simulation face adds the independent variable time (value reference 0), leaves out the
model-exchange locals (me_only) and names dependencies (inputs) by value reference.
"""

from __future__ import annotations

import re
from xml.sax.saxutils import escape

from fmuspec import Model, Var

GENERATION_TOOL = "ShroudedBlade fmu_src/gen (from the model's variable spec)"


def q(text: str) -> str:
    """An XML attribute value."""
    return escape(str(text), {'"': "&quot;", "'": "&apos;"})


def num(x: float | int | bool, typ: str) -> str:
    if typ == "Boolean":
        return "true" if x else "false"
    if typ == "Integer":
        return str(int(x))
    x = float(x)
    if x.is_integer() and abs(x) < 1e16:
        return str(int(x))
    return re.sub(r"e([+-])0*(\d)", lambda m: "e" + m.group(1).replace("+", "") + m.group(2), repr(x))  # 1e-5


def _bool(x: bool) -> str:
    return "true" if x else "false"


def c_sources(files: list[str]) -> list[str]:
    return [f for f in files if f.endswith(".c")]


def _units(model: Model, used: set[str]) -> list[str]:
    lines = ["  <UnitDefinitions>"]
    for name, base in model.units.items():
        if name in used:
            attrs = " ".join(f'{k}="{num(v, "Real")}"' if k != "factor" else f'factor="{v!r}"' for k, v in base.items())
            lines.append(f'    <Unit name="{q(name)}"><BaseUnit{" " + attrs if attrs else ""}/></Unit>')
    return lines + ["  </UnitDefinitions>", ""]


def _log(model: Model) -> list[str]:
    return (
        ["  <LogCategories>"]
        + [f'    <Category name="{q(n)}" description="{q(d)}"/>' for n, d in model.log_categories.items()]
        + ["  </LogCategories>", ""]
    )


def _experiment(model: Model) -> list[str]:
    e = model.info.get("default_experiment", {"startTime": 0, "stopTime": 0.3, "stepSize": 1e-4})
    attrs = " ".join(f'{k}="{num(v, "Real")}"' for k, v in e.items())
    return [f"  <DefaultExperiment {attrs}/>", ""]


TOOL = "ShroudedBlade"


def _open_bounds(model: Model, vars_: list[Var]) -> str:
    """<OpenBounds lower=".." upper=".."/>: the variables whose bound itself is excluded (min/max
    cannot say it), or '' if none."""
    lower = " ".join(v.name for v in vars_ if v.min_open)
    upper = " ".join(v.name for v in vars_ if v.max_open)
    return f'<OpenBounds lower="{q(lower)}" upper="{q(upper)}"/>' if lower or upper else ""


def _comment(v: Var) -> list[str]:
    if not v.comment:
        return []
    text = v.comment.strip().replace("--", "- -")
    return [f"    <!-- {text} -->"]


def _range_attrs(v: Var) -> str:
    out = ""
    if v.type != "Boolean":
        if v.min is not None:
            out += f' min="{num(v.min, v.type)}"'
        if v.max is not None:
            out += f' max="{num(v.max, v.type)}"'
    if v.initial != "calculated" and v.start is not None:
        out += f' start="{num(v.start, v.type)}"'
    return out


def _head(v: Var, index_attrs: str) -> str:
    init = f' initial="{v.initial}"' if v.initial else ""
    desc = f' description="{q(v.description)}"' if v.description else ""
    return (
        f'name="{q(v.name)}" valueReference="{v.vr}" causality="{v.causality}" variability="{v.variability}"'
        f"{init}{desc}{index_attrs}"
    )


def fmi2(model: Model, sources: list[str], spec_rel: str) -> str:
    f2 = model.info.get("fmi2", {})
    me = bool(f2.get("model_exchange", False))
    vars_ = [v for v in model.vars]
    index = {v.name: i + 1 for i, v in enumerate(vars_)}
    states = {v.derivative_of for v in vars_ if v.derivative_of}
    state_flag = _bool(f2.get("can_get_and_set_state", True))
    files = [f'      <File name="{q(s)}"/>' for s in c_sources(sources)]
    lines = [
        '<?xml version="1.0" encoding="UTF-8"?>',
        f"<!-- Generated from {spec_rel} by fmu_src/gen: edit the spec, not this file. -->",
        "<fmiModelDescription",
        '  fmiVersion="2.0"',
        f'  modelName="{q(model.name)}"',
        f'  guid="{q(model.guid)}"',
        f'  description="{q(model.description)}"',
        f'  generationTool="{GENERATION_TOOL}"',
        f'  version="{q(model.info.get("version", "0.1.0"))}"',
        f'  variableNamingConvention="{model.info.get("naming", "structured")}"',
        f'  numberOfEventIndicators="{f2.get("event_indicators", 0)}">',
        "",
    ]
    if me:
        lines += [
            "  <ModelExchange",
            f'    modelIdentifier="{q(model.name)}"',
            '    needsExecutionTool="false"',
            '    completedIntegratorStepNotNeeded="true"',
            '    canBeInstantiatedOnlyOncePerProcess="false"',
            '    canNotUseMemoryManagementFunctions="true"',
            f'    canGetAndSetFMUstate="{state_flag}"',
            f'    canSerializeFMUstate="{state_flag}"',
            '    providesDirectionalDerivative="false">',
            "    <SourceFiles>",
            *files,
            "    </SourceFiles>",
            "  </ModelExchange>",
            "",
        ]
    lines += [
        "  <CoSimulation",
        f'    modelIdentifier="{q(model.name)}"',
        '    needsExecutionTool="false"',
        '    canHandleVariableCommunicationStepSize="true"',
        f'    canInterpolateInputs="{_bool(f2.get("can_interpolate_inputs", True))}"',
        '    maxOutputDerivativeOrder="0"',
        '    canRunAsynchronuously="false"',
        '    canBeInstantiatedOnlyOncePerProcess="false"',
        '    canNotUseMemoryManagementFunctions="true"',
        f'    canGetAndSetFMUstate="{state_flag}"',
        f'    canSerializeFMUstate="{state_flag}"',
        '    providesDirectionalDerivative="false">',
        "    <SourceFiles>",
        *files,
        "    </SourceFiles>",
        "  </CoSimulation>",
        "",
    ]
    lines += _units(model, {v.unit for v in vars_})
    lines += _log(model) + _experiment(model)
    bounds = _open_bounds(model, vars_)
    if bounds:
        lines += [
            "  <VendorAnnotations>",
            f'    <Tool name="{TOOL}">',
            "      <!-- the bounds a variable's min/max exclude (the value must differ from them) -->",
            f"      {bounds}",
            "    </Tool>",
            "  </VendorAnnotations>",
            "",
        ]
    lines.append("  <ModelVariables>")
    for v in vars_:
        lines += _comment(v)
        lines.append(f"    <ScalarVariable {_head(v, '')}>")
        unit = f' unit="{q(v.unit)}"' if v.unit else ""
        der = f' derivative="{index[v.derivative_of]}"' if v.derivative_of else ""
        lines.append(f"      <{v.type}{unit}{der}{_range_attrs(v)}/>")
        lines.append("    </ScalarVariable>")
    lines += ["  </ModelVariables>", ""]

    def deps(v: Var) -> str:
        keep = [index[d] for d in v.depends if model.var(d).causality == "input" or (me and d in states)]
        return " ".join(str(i) for i in sorted(set(keep)))

    outputs = [v for v in vars_ if v.causality == "output"]
    ders = [v for v in vars_ if v.derivative_of] if me else []
    initial = [
        v
        for v in vars_
        if (v.causality == "output" and v.initial == "calculated")
        or (me and (v.derivative_of or (v.name in states and v.initial == "calculated")))
    ]
    lines += ["  <ModelStructure>"]
    if outputs:
        lines += [
            "    <Outputs>",
            *[f'      <Unknown index="{index[v.name]}" dependencies="{deps(v)}"/>' for v in outputs],
            "    </Outputs>",
        ]
    if ders:
        lines += [
            "    <Derivatives>",
            *[f'      <Unknown index="{index[v.name]}" dependencies="{deps(v)}"/>' for v in ders],
            "    </Derivatives>",
        ]
    if initial:
        lines += [
            "    <InitialUnknowns>",
            *[f'      <Unknown index="{index[v.name]}"/>' for v in initial],
            "    </InitialUnknowns>",
        ]
    lines += ["  </ModelStructure>", "</fmiModelDescription>", ""]
    return "\n".join(lines)


FMI3_TYPE = {"Real": "Float64", "Integer": "Int32", "Boolean": "Boolean"}


def fmi3(model: Model, spec_rel: str) -> str:
    vars_ = [v for v in model.vars if not v.me_only]
    f3 = model.info.get("fmi3", {})
    state_flag = _bool(f3.get("can_get_and_set_state", True))
    lines = [
        '<?xml version="1.0" encoding="UTF-8"?>',
        f"<!-- Generated from {spec_rel} by fmu_src/gen: edit the spec, not this file. The FMI 3.0",
        "     co-simulation face (fmu_src/fmi/fmi3_cs.c): the variables of the FMI 2.0 description but the",
        "     model-exchange locals, plus the independent variable time (value reference 0). -->",
        "<fmiModelDescription",
        '  fmiVersion="3.0"',
        f'  modelName="{q(model.name)}"',
        f'  instantiationToken="{q(model.guid)}"',
        f'  description="{q(model.description)}"',
        f'  generationTool="{GENERATION_TOOL}"',
        f'  version="{q(model.info.get("version", "0.1.0"))}"',
        f'  variableNamingConvention="{model.info.get("naming", "structured")}">',
        "",
        "  <CoSimulation",
        f'    modelIdentifier="{q(model.name)}"',
        '    needsExecutionTool="false"',
        '    canBeInstantiatedOnlyOncePerProcess="false"',
        f'    canGetAndSetFMUState="{state_flag}"',
        f'    canSerializeFMUState="{state_flag}"',
        '    providesDirectionalDerivatives="false"',
        '    providesAdjointDerivatives="false"',
        '    providesPerElementDependencies="false"',
        '    canHandleVariableCommunicationStepSize="true"',
        '    maxOutputDerivativeOrder="0"',
        '    providesIntermediateUpdate="false"',
        '    mightReturnEarlyFromDoStep="false"',
        '    canReturnEarlyAfterIntermediateUpdate="false"',
        '    hasEventMode="false"',
        '    providesEvaluateDiscreteStates="false"/>',
        "",
    ]
    lines += _units(model, {v.unit for v in vars_} | {"s"})
    lines += _log(model) + _experiment(model)
    lines += [
        "  <ModelVariables>",
        '    <Float64 name="time" valueReference="0" causality="independent" variability="continuous" '
        'description="simulation time" unit="s"/>',
    ]
    for v in vars_:
        lines += _comment(v)
        unit = f' unit="{q(v.unit)}"' if v.unit else ""
        lines.append(f"    <{FMI3_TYPE[v.type]} {_head(v, unit)}{_range_attrs(v)}/>")
    lines += ["  </ModelVariables>", "", "  <ModelStructure>"]
    for v in vars_:
        if v.causality == "output":
            dep = sorted({model.var(d).vr for d in v.depends if model.var(d).causality == "input"})
            lines.append(f'    <Output valueReference="{v.vr}" dependencies="{" ".join(map(str, dep))}"/>')
    for v in vars_:
        if v.causality == "output" and v.initial == "calculated":
            lines.append(f'    <InitialUnknown valueReference="{v.vr}"/>')
    lines += ["  </ModelStructure>"]
    bounds = _open_bounds(model, vars_)
    if bounds:
        lines += [
            "",
            "  <Annotations>",
            f'    <Annotation type="{TOOL}">',
            "      <!-- the bounds a variable's min/max exclude (the value must differ from them) -->",
            f"      {bounds}",
            "    </Annotation>",
            "  </Annotations>",
        ]
    lines += ["</fmiModelDescription>", ""]
    return "\n".join(lines)


def build_description3(model: Model, sources: list[str], spec_rel: str) -> str:
    files = [f'      <SourceFile name="{q(s)}"/>' for s in c_sources(sources)]
    return "\n".join(
        [
            '<?xml version="1.0" encoding="UTF-8"?>',
            f"<!-- Generated from {spec_rel} by fmu_src/gen: the .c files of sources/, includes",
            '     relative to sources/ (e.g. "fmi/log.h"), linked with libm. -->',
            '<fmiBuildDescription fmiVersion="3.0">',
            f'  <BuildConfiguration modelIdentifier="{q(model.name)}">',
            '    <SourceFileSet language="C99">',
            *files,
            '      <IncludeDirectory name="."/>',
            "    </SourceFileSet>",
            '    <Library name="m"/>',
            "  </BuildConfiguration>",
            "</fmiBuildDescription>",
            "",
        ]
    )
