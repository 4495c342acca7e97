"""The ring (harness/system/ring.py) as an SSP 1.0 system: SystemStructure.ssd with N
BladeExternalContact and N ShroudContact components, their parameters as inline parameter sets (the
built-in load's Fw0, bladeIndex, bladeCount, engineOrder, and the constant rotorSpeed as the input's
start value) and the one-to-one
connections of harness/system/ring_libcosim.py; the FMUs in resources/.
`write(ring, out)` writes the directory `out` and the archive `out.ssp`; libcosim
(CosimExecution.from_ssp_file, `run_libcosim`) and Ecos (EcosSimulation(ssp_path=...), `run_ecos`)
load it. Every parameter set is named "initial": libcosim applies inline parameter bindings
whatever their name, Ecos only the set named at init.
`python -m harness ring --blades 36 --write-ssp build/ring36` writes one.
"""

from __future__ import annotations

import shutil
import zipfile
from pathlib import Path
from typing import Any, Mapping
from xml.sax.saxutils import quoteattr

import numpy as np

from harness.fmu.libcosim import last_error, samples
from harness.system.time_grid import to_ns
from harness.fmu.slave import BLADE_EXTERNAL_FMU, build_ring_fmus, variables_by_name
from harness.optional import require
from harness.system.ring import Ring

SSD = "http://ssp-standard.org/SSP1/SystemStructureDescription"
SSC = "http://ssp-standard.org/SSP1/SystemStructureCommon"
SSV = "http://ssp-standard.org/SSP1/SystemStructureParameterValues"

BLADE_IO = {
    "aeroLoad": "input",
    "rotorSpeed": "input",
    "contactForce": "input",
    "contactForce2": "input",
    "tipDisplacement": "output",
    "tipVelocity": "output",
    "dissipatedEnergy": "output",
    "contactWork": "output",
}
CONTACT_IO = {
    "displacementA": "input",
    "velocityA": "input",
    "displacementB": "input",
    "velocityB": "input",
    "rotorSpeed": "input",
    "forceA": "output",
    "forceB": "output",
    "normalForce": "output",
    "frictionForce": "output",
    "dissipatedEnergy": "output",
}


def connections(n: int) -> list[tuple[str, str, str, str]]:
    """(start element, start connector, end element, end connector) of the ring."""
    out = []
    for i in range(n):
        j = (i + 1) % n
        out += [
            (f"blade{i}", "tipDisplacement", f"contact{i}", "displacementA"),
            (f"blade{i}", "tipVelocity", f"contact{i}", "velocityA"),
            (f"blade{j}", "tipDisplacement", f"contact{i}", "displacementB"),
            (f"blade{j}", "tipVelocity", f"contact{i}", "velocityB"),
            (f"contact{i}", "forceA", f"blade{i}", "contactForce2"),
            (f"contact{i}", "forceB", f"blade{j}", "contactForce"),
        ]
    return out


def _value(v: Any) -> str:
    if isinstance(v, bool):
        return f'<ssv:Boolean value="{str(v).lower()}"/>'
    if isinstance(v, int):
        return f'<ssv:Integer value="{v}"/>'
    return f'<ssv:Real value="{float(v)!r}"/>'


def _component(name: str, source: str, io: Mapping[str, str], params: Mapping[str, Any]) -> str:
    conns = "".join(
        f'<ssd:Connector name={quoteattr(k)} kind="{kind}"><ssc:Real/></ssd:Connector>' for k, kind in io.items()
    )
    conns += "".join(
        f'<ssd:Connector name={quoteattr(k)} kind="parameter">'
        f"{'<ssc:Real/>' if isinstance(v, float) else ('<ssc:Boolean/>' if isinstance(v, bool) else '<ssc:Integer/>')}"
        f"</ssd:Connector>"
        for k, v in params.items()
        if k not in io
    )
    pars = "".join(f"<ssv:Parameter name={quoteattr(k)}>{_value(v)}</ssv:Parameter>" for k, v in params.items())
    binding = (
        (
            f"<ssd:ParameterBindings><ssd:ParameterBinding><ssd:ParameterValues>"
            f'<ssv:ParameterSet version="1.0" name="initial"><ssv:Parameters>{pars}</ssv:Parameters></ssv:ParameterSet>'
            f"</ssd:ParameterValues></ssd:ParameterBinding></ssd:ParameterBindings>"
        )
        if params
        else ""
    )
    return (
        f'<ssd:Component name="{name}" source="{source}" type="application/x-fmu-sharedlibrary">'
        f"<ssd:Connectors>{conns}</ssd:Connectors>{binding}</ssd:Component>"
    )


def ssd(ring: Ring) -> str:
    """The SystemStructure.ssd text."""
    n = ring.n
    speed = {"rotorSpeed": float(ring.speed)}  # the unconnected input's start value
    comps = []
    for i in range(n):
        comps.append(
            _component(
                f"blade{i}", "resources/BladeExternalContact.fmu", BLADE_IO, {**ring.blade_instance_params(i), **speed}
            )
        )
        comps.append(
            _component(
                f"contact{i}",
                "resources/ShroudContact.fmu",
                CONTACT_IO,
                {**dict(ring.contact), "engineOrder": int(ring.engine_order), **speed},
            )
        )
    conns = "".join(
        f'<ssd:Connection startElement="{a}" startConnector="{b}" endElement="{c}" endConnector="{d}"/>'
        for a, b, c, d in connections(n)
    )
    return (
        f'<?xml version="1.0" encoding="UTF-8"?>\n'
        f'<ssd:SystemStructureDescription xmlns:ssd="{SSD}" xmlns:ssc="{SSC}" xmlns:ssv="{SSV}" '
        f'version="1.0" name="ring{n}">\n<ssd:System name="ring{n}"><ssd:Elements>{"".join(comps)}</ssd:Elements>'
        f"<ssd:Connections>{conns}</ssd:Connections></ssd:System>\n"
        f'<ssd:DefaultExperiment startTime="0" stopTime="{ring.stop_time!r}"/>\n'
        f"</ssd:SystemStructureDescription>\n"
    )


def write(ring: Ring, out: Path) -> Path:
    """Writes the directory `out` (SystemStructure.ssd, resources/) and `out`.ssp; returns the directory."""
    bx, sc = build_ring_fmus()
    out = Path(out)
    shutil.rmtree(out, ignore_errors=True)
    (out / "resources").mkdir(parents=True)
    for p in (bx, sc):
        shutil.copy(p, out / "resources" / p.name)
    (out / "SystemStructure.ssd").write_text(ssd(ring))
    with zipfile.ZipFile(out.with_suffix(".ssp"), "w", zipfile.ZIP_DEFLATED) as z:
        for f in sorted(out.rglob("*")):
            if f.is_file():
                z.write(f, f.relative_to(out).as_posix())
    return out


def run_libcosim(ssp_dir: Path, ring: Ring) -> dict[str, float | Any]:
    """The SSP in libcosim (fixed step ring.step): time and every blade's tipDisplacement."""
    require("libcosimpy")
    # optional dependency (extra `crosscheck`): imported only when this runs
    from libcosimpy.CosimEnums import CosimVariableType
    from libcosimpy.CosimExecution import CosimExecution
    from libcosimpy.CosimLogging import CosimLogLevel, log_output_level
    from libcosimpy.CosimObserver import CosimObserver

    log_output_level(CosimLogLevel.ERROR)
    ex = CosimExecution.from_ssp_file(str(ssp_dir), step_size=to_ns(ring.step))
    K = ring.n_steps
    obs = CosimObserver.create_time_series(buffer_size=K + 16)
    ex.add_observer(observer=obs)
    idx = [ex.slave_index_from_instance_name(f"blade{i}") for i in range(ring.n)]
    vr = variables_by_name(ssp_dir / "resources" / BLADE_EXTERNAL_FMU.name)["tipDisplacement"][0]
    for k in idx:
        if k < 0 or not obs.start_time_series(k, vr, CosimVariableType.REAL):
            raise RuntimeError(f"libcosim: cannot observe the blades: {last_error()}")
    if not ex.step(K):
        raise RuntimeError(f"libcosim failed: {last_error()}")
    cols = [samples(obs, k, vr, "Real", K + 1) for k in idx]
    return {"time": np.asarray(cols[0][0], dtype=np.int64) / 1e9, "q": np.array([c[2] for c in cols]).T}


def run_ecos(ssp_dir: Path, ring: Ring) -> dict[str, Any]:
    """The SSP in Ecos (fixed step, parameter set "initial" applied at init): time and q."""
    require("ecospy")
    # optional dependency (extra `crosscheck`): imported only when this runs
    from ecospy import EcosSimulation

    sim = EcosSimulation(step_size=ring.step, ssp_path=str(ssp_dir))
    names = [f"blade{i}::tipDisplacement" for i in range(ring.n)]
    try:
        if not sim.init(0.0, "initial"):
            raise RuntimeError("ecos: simulation init failed")
        q = np.empty((ring.n_steps + 1, ring.n))
        t = np.empty(ring.n_steps + 1)
        q[0], t[0] = [sim.get_real(n) for n in names], sim.get_time()
        for k in range(ring.n_steps):
            t[k + 1] = sim.step()
            q[k + 1] = [sim.get_real(n) for n in names]
        sim.terminate()
    finally:
        sim.free()
    return {"time": t, "q": q}
