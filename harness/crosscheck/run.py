"""Cross-tool validation: the same FMU in independent FMI importers, compared with fmpy (`crosscheck`).

For each scenario (`harness.crosscheck.plan.SCENARIOS`: 5000 rpm, and a run-up) one input plan is
built and fed to every importer: fmpy (`simulate_fmu` with the input table: the reference), a
master loop over the project's FMI binding, libcosim (libcosimpy), Ecos (ecospy) and FMI4j (Java driver, Maven). Held inputs
are compared with fmpy's `simulate_fmu`; runs with input derivatives (order 8) with the binding loop
fed the same derivatives. A tool that passes its own communication points/step sizes (libcosim:
integer nanoseconds; Ecos: accumulated time, constant h) is also compared with the binding loop fed that
very (t_k, h_k) sequence, which isolates the FMU from the tool. The static checkers
(fmu-manipulation-toolbox, fmpy.validation) run on the archive. Prints the agreement table
(importer, version, inputs, max relative difference) and writes it to `crosscheck/agreement.md`;
`make crosscheck` also regenerates the cross-check deliverables. The wall times go to a file of their
own beside it (`crosscheck/agreement-timings.md`, not committed): they change from run to run, the
agreement does not, so a second `make crosscheck` leaves the checkout as it was.
"""

from __future__ import annotations

import fcntl
import math
import shutil
import sys
import tempfile
import time as _time
import traceback
from dataclasses import dataclass, field
from pathlib import Path
from typing import Callable

from harness.crosscheck import system_example as se
from harness.crosscheck.common import Run, max_rel_diff, rel_diffs
from harness.crosscheck.deliverables import make_all
from harness.crosscheck.importers import ecos as xe, fmi4j as xj, fmpy as xfmpy, libcosim as xl
from harness.crosscheck.plan import SCENARIOS, InputPlan, Scenario, make_plan
from harness.crosscheck.static import fmpy_validate, fmutool_check
from harness.fmu import build as _build
from harness.fmu.blade import fmu_path
from harness.fmu.build import REPO_ROOT
from harness.system.time_grid import ns_time_grid

AGREEMENT_FILE = REPO_ROOT / "crosscheck" / "agreement.md"
TIMINGS_SUFFIX = "-timings.md"  # agreement.md -> agreement-timings.md (ignored by git)
TOOLS = ("fmpy", "libcosim", "ecos", "fmi4j")
#: agreement target for a tool fed the same inputs, communication points and step sizes as fmpy
TOLERANCE = 1e-10
DERIVATIVE_ORDER = 8


@dataclass
class Row:
    run: Run
    diff: float = float("nan")  # max relative difference to the fmpy run with the same inputs
    worst: str = ""
    own_grid_diff: float | None = None  # to the binding loop fed the tool's own (t_k, h_k), where they differ
    compared_with: str = ""

    @property
    def ok(self) -> bool:
        if self.compared_with == "sensitivity":
            return True  # information: the size of a few-ulp perturbation of the step sizes
        if not self.run.ok:
            return False
        d = self.own_grid_diff if self.own_grid_diff is not None else self.diff
        return d <= TOLERANCE


@dataclass
class ScenarioReport:
    scenario: Scenario
    rows: list[Row] = field(default_factory=list)
    held_vs_taylor: float = float("nan")  # input reconstruction effect: held vs order-8 inputs (fmpy)
    sensitivity: float = float("nan")  # fmpy vs the binding loop with step sizes changed by a few ulps


def _attempt(importer: str, inputs: str, fn: Callable[[], Run]) -> Run:
    try:
        return fn()
    except Exception as exc:  # a tool failing is a result to report, not a crash of the whole check
        last = traceback.format_exception_only(type(exc), exc)[-1].strip()
        return Run(importer, "?", inputs, error=last)


def run_scenario(
    fmu: Path, scenario: Scenario, tools: tuple[str, ...] = TOOLS, order: int = DERIVATIVE_ORDER
) -> ScenarioReport:
    """Run `scenario` in every tool of `tools`; rows hold the differences to fmpy."""
    report = ScenarioReport(scenario)
    plan = make_plan(scenario, order)
    held = plan.held()
    ref = xfmpy.run_simulate_fmu(fmu, scenario, held)
    if not ref.ok:
        raise RuntimeError(f"fmpy reference run failed: {ref.error}")
    report.rows.append(Row(ref, 0.0, "", None, "(reference)"))
    taylor_ref = xfmpy.run_slave_loop(fmu, scenario, plan)
    report.held_vs_taylor = rel_diffs(ref.result, taylor_ref.result)["tipDisplacement"]

    def add(run: Run, reference: Run, label: str, own: InputPlan | None = None) -> None:
        row = Row(run, compared_with=label)
        if run.ok:
            row.diff, row.worst = max_rel_diff(run.result, reference.result)
            if row.diff == 0:
                row.worst = ""
            if own is not None:
                same = xfmpy.run_slave_loop(fmu, scenario, own)
                row.own_grid_diff, _ = max_rel_diff(run.result, same.result)
        report.rows.append(row)

    if "fmpy" in tools:
        add(xfmpy.run_slave_loop(fmu, scenario, held), ref, "fmpy simulate_fmu, held")
        # the model's own sensitivity: h_k = step exactly instead of t_{k+1} - t_k (a few ulps apart)
        sens = xfmpy.run_slave_loop(fmu, scenario, held.with_time(held.time, scenario.step))
        sens.importer, sens.inputs = "FMI binding loop, h_k = h (ulp-perturbed steps)", "held"
        row = Row(sens, compared_with="sensitivity")
        row.diff, row.worst = max_rel_diff(sens.result, ref.result)
        report.sensitivity = row.diff
        report.rows.append(row)
        report.rows.append(Row(taylor_ref, 0.0, "", None, "(reference, order 8)"))
    if "libcosim" in tools:
        run = _attempt("libcosim (libcosimpy)", "held", lambda: xl.run(fmu, scenario, held))
        grid = ns_time_grid(scenario.start_time, scenario.step, held.n_steps)
        add(run, ref, "fmpy simulate_fmu, held", held.with_time(grid))
    if "ecos" in tools:
        run = _attempt("Ecos (ecospy)", "held", lambda: xe.run(fmu, scenario, held))
        grid = xe.accumulated_time_grid(scenario.start_time, scenario.step, held.n_steps)
        add(run, ref, "fmpy simulate_fmu, held", held.with_time(grid, scenario.step))
    if "fmi4j" in tools:
        run = _attempt("FMI4j (Java driver)", "held", lambda: xj.run(fmu, scenario, held))
        add(run, ref, "fmpy simulate_fmu, held")
        run = _attempt("FMI4j (Java driver)", f"taylor{order}", lambda: xj.run(fmu, scenario, plan, build_first=False))
        add(run, taylor_ref, f"FMI binding loop, order {order}")
    return report


def _fmt(x: float | None) -> str:
    if x is None:
        return "-"
    if isinstance(x, float) and math.isnan(x):
        return "n/a"
    return "0" if x == 0 else f"{x:.2e}"


def table(report: ScenarioReport) -> str:
    """Markdown agreement table of one scenario."""
    sc = report.scenario
    lines = [
        f"### {sc.name}: {sc.description}; {sc.stop_time:g} s, step {sc.step:g} s ({sc.n_steps()} steps)",
        "",
        "| importer | version | inputs | max rel. diff to fmpy | worst output | same (t_k, h_k) as the tool | status |",
        "|---|---|---|---|---|---|---|",
    ]
    for r in report.rows:
        run = r.run
        status = "reference" if r.compared_with.startswith("(reference") else ("ok" if r.ok else "FAIL")
        if r.compared_with == "sensitivity":
            status = "model sensitivity"
        if run.error:
            status = f"FAILED: {run.error}"
        lines.append(
            f"| {run.importer} | {run.version} | {run.inputs} | {_fmt(r.diff) if run.ok else '-'} | "
            f"{r.worst or '-'} | {_fmt(r.own_grid_diff)} | {status} |"
        )
    lines += [
        "",
        f"Held inputs vs inputs with derivatives to order {DERIVATIVE_ORDER} (fmpy, same FMU): "
        f"tipDisplacement differs by {_fmt(report.held_vs_taylor)} of its maximum: the input reconstruction, "
        "not the importer, is what a tool without fmi2SetRealInputDerivatives changes.",
    ]
    return "\n".join(lines)


#: one wall time: (section, what, seconds)
Timing = tuple[str, str, float]


def scenario_timings(report: ScenarioReport) -> list[Timing]:
    """The wall time of every run of a scenario (FMI4j: the driver's own, the JVM's start-up beside it)."""
    out = []
    for r in report.rows:
        what = f"{r.run.importer}, {r.run.inputs}"
        if "total_time" in r.run.extra:
            what += f" (JVM incl. start-up {r.run.extra['total_time']:.2f} s)"
        out.append((report.scenario.name, what, r.run.wall_time))
    return out


def timings_table(timings: list[Timing]) -> str:
    """Markdown table of the wall times (the file beside the agreement table, not committed)."""
    lines = [
        "# ShroudedBlade cross-check wall times",
        "",
        "Written by `python -m harness crosscheck` beside the agreement table; machine load changes them.",
        "",
        "| section | run | wall time [s] |",
        "|---|---|---|",
    ]
    lines += [f"| {sec} | {what} | {'-' if math.isnan(t) else f'{t:.3f}'} |" for sec, what, t in timings]
    return "\n".join(lines) + "\n"


def static_table(fmu: Path) -> tuple[str, bool, list[Timing]]:
    rows = [fmutool_check(fmu), fmpy_validate(fmu)]
    lines = ["| checker | version | result | messages |", "|---|---|---|---|"]
    for r in rows:
        msg = "; ".join(r.messages[-3:]) if not r.ok else "no error"
        lines.append(f"| {r.tool} | {r.version} | {'pass' if r.ok else 'FAIL'} | {msg} |")
    return "\n".join(lines), all(r.ok for r in rows), [("static checks", r.tool, r.wall_time) for r in rows]


def system_section(fmu: Path, stop_time: float | None) -> tuple[str, bool, list[Timing]]:
    """The system example (Excitation FMU + two blades) in the binding master and in libcosim."""
    system = se.System() if stop_time is None else se.System(stop_time=stop_time)
    exc = se.build_excitation_fmu()
    t0 = _time.perf_counter()
    a = se.run_binding(fmu, exc, system)
    t1 = _time.perf_counter()
    b = se.run_libcosim(fmu, exc, system)
    t2 = _time.perf_counter()
    d, worst = max_rel_diff(b, a)
    blades = ", ".join(f"{k} {dict(v) or 'Table 1'}" for k, v in system.blades.items())
    lines = [
        f"### System example: Excitation FMU (run-up {system.excitation['n0']:g} -> {system.excitation['n1']:g} rpm) "
        f"driving two blades ({blades}); {system.stop_time:g} s, step {system.step:g} s",
        "",
        "| master | recorded variables | max rel. diff to the binding master |",
        "|---|---|---|",
        f"| FMI binding loop | {len(a.dtype.names) - 1} | (reference) |",
        f"| libcosim (libcosimpy) | {len(b.dtype.names) - 1} | {_fmt(d)}{' (' + worst + ')' if d else ''} |",
    ]
    timings = [("system example", "FMI binding loop", t1 - t0), ("system example", "libcosim", t2 - t1)]
    return "\n".join(lines), d <= TOLERANCE, timings


def snapshot(fmu: Path, directory: Path) -> Path:
    """Copy the FMU to `directory` (under the build lock when it is build/ShroudedBlade.fmu): other
    processes may rebuild build/ while the cross-check runs, and CMake rewrites the archive in place."""
    out = Path(directory) / fmu.name
    lock_file = _build.BUILD_DIR / ".build.lock"
    if Path(fmu).resolve() == _build.FMU_PATH.resolve() and lock_file.parent.is_dir():
        with open(lock_file, "w") as lock:
            fcntl.flock(lock, fcntl.LOCK_EX)
            shutil.copyfile(fmu, out)
    else:
        shutil.copyfile(fmu, out)
    return out


def crosscheck(
    fmu: Path | None = None,
    scenario: str = "all",
    stop_time: float | None = None,
    tools: str = ",".join(TOOLS),
    deliverables: bool = False,
    output_file: Path = AGREEMENT_FILE,
) -> int:
    """Every scenario (or one) in the importers `tools` (comma-separated), the system example, the
    static checks and, with `deliverables`, the committed deliverables; the agreement table into
    `output_file`. Exit code: 0 all agree, 1 a disagreement, 2 an unknown tool."""
    with tempfile.TemporaryDirectory(prefix="sb-crosscheck-") as tmp:
        copy = snapshot(Path(fmu) if fmu else fmu_path(build=True), Path(tmp))
        return _run(copy, scenario, stop_time, tools, deliverables, Path(output_file))


def _run(
    fmu: Path, scenario: str, stop_time: float | None, tool_list: str, deliverables: bool, output_file: Path
) -> int:
    tools = tuple(t.strip() for t in tool_list.split(",") if t.strip())
    unknown = set(tools) - set(TOOLS)
    if unknown:
        print(f"error: unknown tool(s) {', '.join(sorted(unknown))}; known: {', '.join(TOOLS)}", file=sys.stderr)
        return 2
    names = sorted(SCENARIOS) if scenario == "all" else [scenario]
    ok = True
    timings: list[Timing] = []
    parts = [
        "# ShroudedBlade cross-tool agreement",
        "",
        "Generated by `python -m harness crosscheck` (`make crosscheck`); see docs/crosscheck.md.",
        "",
    ]
    for name in names:
        sc = SCENARIOS[name]
        if stop_time is not None:
            sc = sc.shortened(stop_time)
        rep = run_scenario(fmu, sc, tools)
        timings += scenario_timings(rep)
        text = table(rep)
        print(text + "\n", flush=True)
        parts += [text, ""]
        ok &= all(r.ok or r.compared_with.startswith("(reference") for r in rep.rows)
    if "libcosim" in tools and "fmpy" in tools:
        text, sys_ok, sys_times = system_section(fmu, stop_time)
        timings += sys_times
        print(text + "\n")
        parts += [text, ""]
        ok &= sys_ok
    st, st_ok, st_times = static_table(fmu)
    timings += st_times
    print(st + "\n")
    parts += ["### Static checks", "", st, ""]
    ok &= st_ok
    if deliverables:
        _build.build(("fmu3",))  # the FMI 3.0 FMU of the same sources (fmus/3.0/cs)
        text, d_ok = make_all(fmu, SCENARIOS["steady"], tools, fmu3=_build.FMU3_PATH)
        print(text + "\n")
        parts += [text, ""]
        ok &= d_ok
    output_file.parent.mkdir(parents=True, exist_ok=True)
    output_file.write_text("\n".join(parts))
    timings_file = output_file.with_name(output_file.stem + TIMINGS_SUFFIX)
    timings_file.write_text(timings_table(timings))
    print(timings_table(timings))
    print(f"wrote {output_file} and {timings_file.name} (wall times, not committed)")
    return 0 if ok else 1
