"""The FMI cross-check deliverables of ShroudedBlade, generated from the built FMU (never by hand).

Layout (modelica/fmi-cross-check rules, `fmus/2.0/cs/linux64/<Tool>/<version>/<Model>/`):
`ShroudedBlade.fmu` (a copy of build/ShroudedBlade.fmu), `ShroudedBlade_in.csv` (time, aeroLoad,
rotorSpeed on the communication grid, quoted header), `ShroudedBlade_ref.csv` (time + 7 outputs,
quoted header, < 1 MB), `ShroudedBlade_ref.opt` (StartTime, StopTime, StepSize, RelTol) and
README.md. The reference is what fmpy, the cross-check's own reference importer, computes:
`simulate_fmu` with the `_in.csv` table read back from the file, one communication step per row,
inputs held over each step (co-simulation without input derivatives, as libcosim, Ecos and the
FMI4j driver do too). The reference variables are the outputs that fmpy's band check
(`fmpy.util.validate_result`, a 1000-point band) resolves: outputs with jumps shorter than the band
spacing (normalForce, frictionForce, Keq, Ceq, contactState) fail even against themselves and are left out.
Importer results are filed under `results/.../<Importer>/<ver>/ShroudedBlade/<ver>/ShroudedBlade/`
with `_out.csv` and `passed`/`failed`; `python -m fmpy.cross_check.validate_vendor_repo <root>`
checks the whole tree.

The same layout holds three flavours (`fmus/<2.0|3.0>/<cs|me>/linux64/...`): FMI 2.0 co-simulation,
FMI 2.0 model exchange (the same FMU file, which carries both) and FMI 3.0 co-simulation
(build/fmi3/ShroudedBlade.fmu). The model-exchange `_in.csv` writes the held inputs as steps (each
t_k twice: the value before and after), because a model-exchange importer interpolates the table
linearly; its reference is fmpy's CVode at RelTol ME_REL_TOL. The FMI 3.0 reference is fmpy's
simulate_fmu as for 2.0 (the outputs are bit-identical to FMI 2.0's, tests/fmu/test_fmi3.py).
"""

from __future__ import annotations

import shutil
import subprocess
import sys
import tempfile
import xml.etree.ElementTree as ET
import zipfile
from dataclasses import dataclass, replace
from pathlib import Path

import fmpy
from fmpy import simulate_fmu
from fmpy.util import read_csv, read_ref_opt_file, validate_result, write_csv
import numpy as np

from harness.crosscheck.common import MODEL_NAME, as_float_result, max_rel_diff
from harness.crosscheck.importers import ecos as xe, fmi4j as xj, libcosim as xl
from harness.crosscheck.importers.fmpy import run_simulate_fmu, run_slave_loop
from harness.crosscheck.plan import Scenario, make_plan
from harness.crosscheck.static import rebuild_from_sources
from harness.fmu.build import REPO_ROOT

DEFAULT_ROOT = REPO_ROOT / "crosscheck"
TOOL = MODEL_NAME  # the exporting "tool" is this project's own build
#: <= 10 variables in the reference (cross-check rules); time is the first column on top of these.
#: Only outputs that pass validate_result against themselves (see the module docstring).
REF_VARIABLES = ["tipDisplacement", "tipVelocity", "amplitude", "dissipatedEnergy", "naturalFrequency", "regime"]
INTEGER_VARIABLES = ["regime"]
REL_TOL = 1e-6  # reported in _ref.opt; the FMU's fixed-step RK4 does not use it
ME_REL_TOL = 1e-9  # CVode's relative tolerance for the model-exchange reference (in its _ref.opt)
FLAVOURS = (("2.0", "cs"), ("2.0", "me"), ("3.0", "cs"))  # (FMI version, interface) folders


def fmu_version(fmu: Path) -> str:
    with zipfile.ZipFile(fmu) as z:
        root = ET.fromstring(z.read("modelDescription.xml"))
    return root.get("version") or "0"


def model_dir(root: Path, version: str, fmi: str = "2.0", kind: str = "cs") -> Path:
    return Path(root) / "fmus" / fmi / kind / "linux64" / TOOL / version / MODEL_NAME


@dataclass
class Deliverables:
    directory: Path
    fmu: Path
    in_csv: Path
    ref_csv: Path
    ref_opt: Path
    readme: Path
    fmi: str = "2.0"  # FMI version folder
    kind: str = "cs"  # cs | me


def held_steps(table: np.ndarray) -> np.ndarray:
    """A held input table (value at t_k kept until t_{k+1}) as steps for linear interpolation: row k
    at t_k, then the same values again at t_{k+1} before row k+1 (repeated times are steps)."""
    out = np.empty(2 * len(table) - 1, dtype=table.dtype)
    out[0::2] = table
    out[1::2] = table[:-1]
    out["time"][1::2] = table["time"][1:]
    return out


def me_reference(fmu: Path, scenario: Scenario, table: np.ndarray, rel_tol: float, names: list[str]) -> np.ndarray:
    """fmpy's model exchange (CVode at `rel_tol`) with the step input table, output every step. fmpy
    accumulates its output times (t += interval: 0.09999999999999781 for 0.1); where no input step
    makes it land on the grid, the times are put back on start + k interval (a few 1e-15 s) so that
    the reference reaches StopTime."""
    res = simulate_fmu(
        str(fmu),
        fmi_type="ModelExchange",
        solver="CVode",
        relative_tolerance=rel_tol,
        start_time=scenario.start_time,
        stop_time=scenario.stop_time,
        output_interval=scenario.step,
        input=table,
        output=names,
        record_events=False,
    )
    grid = scenario.start_time + scenario.step * np.round((res["time"] - scenario.start_time) / scenario.step)
    if np.max(np.abs(grid - res["time"])) <= 1e-9 * scenario.step:
        res["time"] = grid
    return res


def deliverable_scenario(scenario: Scenario) -> Scenario:
    """`scenario` as the deliverables run it: every start value at the FMU's default, so the load is
    the FMU's built-in one (Fw0 = 100 N/m) and `_in.csv` feeds aeroLoad = 0 (cross-check rules: an
    experiment is the inputs and the default start values)."""
    return replace(scenario, builtin_load=True)


def generate(
    fmu: Path, scenario: Scenario, root: Path = DEFAULT_ROOT, fmi: str = "2.0", kind: str = "cs"
) -> Deliverables:
    """Write the deliverables of `scenario` (as `deliverable_scenario` makes it) for `fmu` (an FMI
    `fmi` FMU, used as `kind`) under `root`; returns the paths."""
    scenario = deliverable_scenario(scenario)
    if scenario.fmu_overrides():
        raise ValueError("the cross-check FMU runs with its default parameters: pick a scenario without overrides")
    if (fmi, kind) not in FLAVOURS:
        raise ValueError(f"no deliverables for FMI {fmi} {kind}")
    version = fmu_version(fmu)
    d = model_dir(root, version, fmi, kind)
    if d.exists():
        shutil.rmtree(d)
    d.mkdir(parents=True)
    out = Deliverables(
        d,
        d / f"{MODEL_NAME}.fmu",
        d / f"{MODEL_NAME}_in.csv",
        d / f"{MODEL_NAME}_ref.csv",
        d / f"{MODEL_NAME}_ref.opt",
        d / "README.md",
        fmi,
        kind,
    )
    shutil.copyfile(fmu, out.fmu)

    held = make_plan(scenario, 0).input_table()
    write_csv(out.in_csv, held_steps(held) if kind == "me" else held)
    table = read_csv(out.in_csv)  # the reference uses exactly the numbers in the file
    if kind == "me":
        res = me_reference(out.fmu, scenario, table, ME_REL_TOL, REF_VARIABLES)
    else:
        res = simulate_fmu(
            str(out.fmu),
            start_time=scenario.start_time,
            stop_time=scenario.stop_time,
            output_interval=scenario.step,
            input=table,
            output=REF_VARIABLES,
        )
    write_csv(out.ref_csv, as_float_result(res, REF_VARIABLES))
    _integer_columns(out.ref_csv, INTEGER_VARIABLES)

    out.ref_opt.write_text(
        f"StartTime, {scenario.start_time!r}\nStopTime, {scenario.stop_time!r}\n"
        f"StepSize, {scenario.step!r}\nRelTol, {ME_REL_TOL if kind == 'me' else REL_TOL!r}\n"
    )
    out.readme.write_text(_readme(scenario, version, fmi, kind))
    return out


def _integer_columns(csv: Path, names: list[str]) -> None:
    lines = csv.read_text().splitlines()
    header = [h.strip('"') for h in lines[0].split(",")]
    idx = [header.index(n) for n in names]
    rows = [lines[0]]
    for ln in lines[1:]:
        f = ln.split(",")
        for i in idx:
            f[i] = str(int(round(float(f[i]))))
        rows.append(",".join(f))
    csv.write_text("\n".join(rows) + "\n")


_FLAVOUR_TEXT = {
    ("2.0", "cs"): "FMI 2.0 co-simulation",
    ("2.0", "me"): "FMI 2.0 model exchange",
    ("3.0", "cs"): "FMI 3.0 co-simulation",
}


def _flavour_notes(scenario: Scenario, fmi: str, kind: str) -> str:
    if kind == "me":
        return f"""
Model exchange: the same archive as fmus/2.0/cs (it carries <ModelExchange> too): 5 continuous
states (q, dq/dt, excitationPhase, dissipatedEnergy, sliderPosition), 11 event indicators (contact
gate, stick/slip, period end, extremum, the describing function's loop phases: state events only).
`{MODEL_NAME}_in.csv` holds the same inputs as the co-simulation folder, written as steps (every
time twice: the value before and after), so that linear interpolation gives the held inputs.
Reference: fmpy.simulate_fmu(fmi_type="ModelExchange", solver="CVode", relative_tolerance={ME_REL_TOL!r}),
output every {scenario.step!r} s, to StopTime {scenario.stop_time!r} s only: the default response is
sensitive (see below), and integrations that differ by 4e-6 at 0.02 s (fmpy applies the input steps
at its own solver points, FMI4j's RK4 and the co-simulation FMU hold them exactly) drift apart after
~0.12 s; up to 0.1 s fmpy, FMI4j and the co-simulation reference agree within 1.3e-4 (relative, in q).
"""
    if fmi == "3.0":
        return """
FMI 3.0: build/fmi3/ShroudedBlade.fmu, from the same C sources with the FMI 3.0 face
(fmu_src/fmi/fmi3_cs.c), instantiationToken = the FMI 2.0 guid, `time` is vr 0. FMI 3.0 has no
function to set input derivatives: inputs are held over each step. Given the same communication
points its outputs are bit-identical to the FMI 2.0 co-simulation FMU's (tests/fmu/test_fmi3.py).
"""
    return ""


def _readme(scenario: Scenario, version: str, fmi: str = "2.0", kind: str = "cs") -> str:
    return f"""# {MODEL_NAME} {version}: {_FLAVOUR_TEXT[(fmi, kind)]}, linux64
{_flavour_notes(scenario, fmi, kind)}
Reduced-order model of a shrouded turbine blade rubbing/impacting its neighbours (m-mode Galerkin
model, m = 1..6 by the `modes` parameter, macroslip friction; Nan et al., Shock and Vibration 2020).
C99 generated from one variable spec per model, fixed-step RK4
with located switching events; `canInterpolateInputs` (input derivatives up to order 8),
`canHandleVariableCommunicationStepSize`, `canGetAndSetFMUstate`, `canSerializeFMUstate`.
The archive carries its C sources (`sources/`).

Experiment: {scenario.description}; start values are the FMU defaults (paper Table 1).
The load is the FMU's built-in one, f_w = Fw0 sin(3 int Omega dt) with its default Fw0 = 100 N/m
(integrated with the state: exact at any step). Inputs (`{MODEL_NAME}_in.csv`): `aeroLoad` [N/m] = 0
(added to the built-in load) and `rotorSpeed` [rpm], sampled at every communication point (step
{scenario.step!r} s).

Reference (`{MODEL_NAME}_ref.csv`): fmpy.simulate_fmu with `_in.csv`, communication step
{scenario.step!r} s from {scenario.start_time!r} s to {scenario.stop_time!r} s, the inputs set at each communication
point and held over the step (no input derivatives). Reproduce with
`python -m fmpy simulate {MODEL_NAME}.fmu --input-file {MODEL_NAME}_in.csv --output-interval {scenario.step!r}
--stop-time {scenario.stop_time!r}`.

Note: with its default parameters (tracked amplitude, describing-function contact) the response is
irregular and sensitive: a change of the step sizes by one ulp grows to ~1e-8 relative by
t = 0.3 s.

Generated by `make crosscheck` (harness/crosscheck/deliverables.py) from build/ShroudedBlade.fmu
(FMI 3.0: build/fmi3/ShroudedBlade.fmu); do not edit by hand.
"""


def validate_tree(root: Path) -> tuple[int, str]:
    """`python -m fmpy.cross_check.validate_vendor_repo <root>`: (exit code = number of problems, output)."""
    proc = subprocess.run(
        [sys.executable, "-m", "fmpy.cross_check.validate_vendor_repo", str(root)], capture_output=True, text=True
    )
    return proc.returncode, proc.stdout + proc.stderr


def vendor_repo_summary(rc: int, out: str, root: Path) -> str:
    """The validator's verdict as one Markdown line, with the tree named by its folder name (the
    validator prints the absolute path, which differs between checkouts)."""
    summary = [ln.strip() for ln in out.splitlines() if "problems found" in ln or "Validated" in ln]
    text = "; ".join(summary)
    for full in sorted({str(root), str(root.resolve())}, key=len, reverse=True):
        text = text.replace(full, root.name)
    return f"`python -m fmpy.cross_check.validate_vendor_repo {root.name}`: exit {rc}; {text}"


def check_result(result: np.ndarray, deliverables: Deliverables, stop_time: bool = True) -> float:
    """fmpy.util.validate_result of a result against the reference CSV: the fraction of samples
    outside the band (0 = pass; 1 also when the result ends before StopTime, unless `stop_time` is
    False). `result` needs `time` and the reference's variable names."""
    ref = read_csv(deliverables.ref_csv)
    opt = read_ref_opt_file(deliverables.ref_opt)
    return float(validate_result(result, ref, stop_time=opt["StopTime"] if stop_time else None))


def write_result(
    root: Path, deliverables: Deliverables, importer: str, importer_version: str, result: np.ndarray, how: str
) -> tuple[Path, float]:
    """File an importer's result under results/ with `passed` or `failed` from `check_result`."""
    version = deliverables.directory.parent.name
    safe = "".join(c if c.isalnum() or c in "-_." else "_" for c in importer)
    safe_ver = "".join(c if c.isalnum() or c in "-_." else "_" for c in importer_version.split(" ")[0])
    d = (
        Path(root)
        / "results"
        / deliverables.fmi
        / deliverables.kind
        / "linux64"
        / safe
        / safe_ver
        / TOOL
        / version
        / MODEL_NAME
    )
    if d.exists():
        shutil.rmtree(d)
    d.mkdir(parents=True)
    res = as_float_result(result, REF_VARIABLES)
    write_csv(d / f"{MODEL_NAME}_out.csv", res)
    _integer_columns(d / f"{MODEL_NAME}_out.csv", INTEGER_VARIABLES)
    rel_out = check_result(res, deliverables)
    values_out = check_result(res, deliverables, stop_time=False)
    (d / ("passed" if rel_out == 0 else "failed")).write_text("")
    note = ""
    if rel_out != 0 and values_out == 0:
        note = (
            f"\nThe values are inside the band everywhere (fraction outside = 0 when the stop-time test is "
            f"left out), but the last communication point {res['time'][-1]!r} s is short of StopTime: "
            f"the tool accumulates time (t += h), so validate_result rejects the run before comparing.\n"
        )
    (d / "README.md").write_text(
        f"# {MODEL_NAME} {version} imported with {importer} {importer_version}\n\n{how}\n\n"
        f"fmpy.util.validate_result against {MODEL_NAME}_ref.csv: {rel_out:g} "
        f"(fraction of samples outside the band; 1 also means 'stop time not reached')."
        f"\n{note}\nGenerated by `make crosscheck`.\n"
    )
    return d, rel_out, values_out


IMPORTER_IDS = {
    "fmpy": ("FMPy", "fmpy.simulate_fmu with the input table (inputs held over each step)"),
    "libcosim": (
        "libcosim",
        "libcosimpy: fixed-step execution, inputs set through an override manipulator before every step (held)",
    ),
    "ecos": ("Ecos", "ecospy: fixed-step simulation, inputs set with set_real before every step (held)"),
    "fmi4j": ("FMI4j", "crosscheck/java Fmi4jDriver: inputs set before every step (held)"),
}


#: who is filed for the other flavours: (FMI version, kind) -> importers (libcosim imports neither
#: FMI 2.0 model exchange nor FMI 3.0, Ecos no model exchange, FMI4j 0.38 no FMI 3.0: README)
FLAVOUR_IMPORTERS = {("2.0", "me"): ("fmpy", "fmi4j"), ("3.0", "cs"): ("fmpy", "ecos")}
ME_CHECK_REL_TOL = 1e-11  # fmpy's filed model-exchange run: CVode tighter than the reference
#: [s] the model-exchange folder's StopTime. The default response is sensitive: two integrations
#: that differ by 4e-6 (relative, in q) at 0.02 s (fmpy's model exchange applies the table's steps at
#: its own solver points; FMI4j's RK4 and the co-simulation FMU hold them exactly) are 2e-4 apart at
#: 0.12 s and 0.85 apart at 0.3 s, and the tracked amplitude then falls out of the band; up to 0.1 s
#: all three stay within 1.3e-4 (measured when the 2.0/me deliverables were made).
ME_STOP_TIME = 0.1


def _flavour_run(tool: str, dl: Deliverables, scenario: Scenario) -> tuple[str, str, str, np.ndarray]:
    """(importer, version, how, result with the reference's variables) of one importer on one flavour."""
    table = read_csv(dl.in_csv)
    if tool == "fmpy" and dl.kind == "me":
        res = me_reference(dl.fmu, scenario, table, ME_CHECK_REL_TOL, REF_VARIABLES)
        return (
            "FMPy",
            fmpy.__version__,
            f"fmpy.simulate_fmu, model exchange, CVode at RelTol {ME_CHECK_REL_TOL!r}, "
            "_in.csv interpolated linearly (steps)",
            res,
        )
    if tool == "fmpy":
        res = simulate_fmu(
            str(dl.fmu),
            start_time=scenario.start_time,
            stop_time=scenario.stop_time,
            output_interval=scenario.step,
            input=table,
            output=REF_VARIABLES,
        )
        return "FMPy", fmpy.__version__, "fmpy.simulate_fmu (FMI 3.0 co-simulation, inputs held over each step)", res
    plan = make_plan(scenario, 0)
    if tool == "fmi4j":
        r = xj.run(dl.fmu, scenario, plan, model_exchange=True)
        return "FMI4j", r.version, f"crosscheck/java Fmi4jMeDriver: {r.note}", r.result
    r = xe.run(dl.fmu, scenario, plan)
    return "Ecos", r.version, "ecospy (fmi4c): fixed-step simulation, inputs set before every step (held)", r.result


def _flavour_results(fmu: Path, scenario: Scenario, root: Path, fmi: str, kind: str) -> tuple[list[str], bool]:
    """Deliverables of one more flavour and its importers' filed results: Markdown lines, all passed."""
    if kind == "me":
        scenario = scenario.shortened(ME_STOP_TIME)
    dl = generate(fmu, scenario, root, fmi, kind)
    lines = [
        "",
        f"FMI {fmi} {kind} ({dl.directory.relative_to(Path(root).parent)}):",
        "",
        "| importer | version | validate_result (fraction outside band) | same, without the stop-time test | filed |",
        "|---|---|---|---|---|",
    ]
    ok = True
    for tool in FLAVOUR_IMPORTERS[(fmi, kind)]:
        try:
            name, version, how, result = _flavour_run(tool, dl, scenario)
        except Exception as exc:  # report, do not stop the others
            lines.append(f"| {tool} | - | FAILED: {type(exc).__name__}: {str(exc)[:300]} | - | - |")
            ok = False
            continue
        d, rel_out, values_out = write_result(root, dl, name, version, result, how)
        ok &= values_out == 0
        lines.append(f"| {name} | {version} | {rel_out:g} | {values_out:g} | {d.relative_to(Path(root).parent)} |")
    return lines, ok


def make_all(
    fmu: Path,
    scenario: Scenario,
    tools: tuple[str, ...],
    root: Path = DEFAULT_ROOT,
    rebuild: bool = True,
    fmu3: Path | None = None,
) -> tuple[str, bool]:
    """Regenerate the deliverables, file every importer's result, rebuild from sources, validate the
    tree; returns a Markdown section and whether everything passed."""
    shutil.rmtree(Path(root) / "fmus", ignore_errors=True)
    shutil.rmtree(Path(root) / "results", ignore_errors=True)
    scenario = deliverable_scenario(scenario)
    dl = generate(fmu, scenario, root)
    ok = True
    lines = [
        f"### Cross-check deliverables ({dl.directory.relative_to(Path(root).parent)})",
        "",
        "| importer | version | validate_result (fraction outside band) | same, without the stop-time test | filed |",
        "|---|---|---|---|---|",
    ]
    table = read_csv(dl.in_csv)
    plan = make_plan(scenario, 0)
    if not np.array_equal(plan.input_table()["aeroLoad"], table["aeroLoad"]):
        raise RuntimeError("the written _in.csv does not read back to the plan's inputs")
    runs = []
    for tool in tools:
        name, how = IMPORTER_IDS[tool]
        try:
            fn = {"fmpy": run_simulate_fmu, "libcosim": xl.run, "ecos": xe.run}.get(tool, xj.run)
            r = fn(dl.fmu, scenario, plan)
        except Exception as exc:  # report, do not stop the others
            lines.append(f"| {name} | - | FAILED: {type(exc).__name__}: {exc} | - | - |")
            ok = False
            continue
        runs.append(r)
        d, rel_out, values_out = write_result(root, dl, name, r.version, r.result, how)
        ok &= values_out == 0  # a run short of StopTime (accumulated time) is filed as failed, and explained
        lines.append(f"| {name} | {r.version} | {rel_out:g} | {values_out:g} | {d.relative_to(Path(root).parent)} |")
    for fmi, kind, flavour_fmu in (("2.0", "me", fmu), ("3.0", "cs", fmu3)):
        if flavour_fmu is None:
            continue
        more, flavour_ok = _flavour_results(Path(flavour_fmu), scenario, root, fmi, kind)
        lines += more
        ok &= flavour_ok
    rc, out = validate_tree(root)
    ok &= rc == 0
    lines += ["", vendor_repo_summary(rc, out, Path(root))]
    size = dl.ref_csv.stat().st_size
    lines.append(f"`{dl.ref_csv.name}`: {size / 1e6:.2f} MB, {len(read_csv(dl.ref_csv).dtype.names) - 1} variables.")
    if rebuild:
        with tempfile.TemporaryDirectory(prefix="sb-rebuilt-") as tmp:
            rebuilt = rebuild_from_sources(dl.fmu, Path(tmp) / f"{MODEL_NAME}.fmu")
            p8 = make_plan(scenario, 8)
            a = run_slave_loop(dl.fmu, scenario, p8)
            b = run_slave_loop(rebuilt, scenario, p8)
            diff, worst = max_rel_diff(b.result, a.result)
        ok &= diff <= 1e-10
        lines.append(
            f"Rebuilt from `sources/` with fmpy.build.build_platform_binary: max rel. diff to the shipped "
            f"binary {diff:.2e} ({worst})."
        )
    return "\n".join(lines), ok
