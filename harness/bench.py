"""Benchmark the FMU and the harness and write bench/RESULTS.md (make bench).

Measured in one run on this machine: the FMU's internal step cost (the C benchmark
build/bench_step when it exists), the cost of one fmi2DoStep through the harness loop on fmpy
(small and large communication steps) against the FMU's own compute for the same work (time
spent inside fmi2DoStep), the same stepped-speed run through the Python reference as a ratio,
harmonic balance for all studies, the wall time of `reproduce` (the studies as periodic-orbit
branches) with its breakdown and the time spent in the FMI calls, and a 24-blade ring in the fmpy
master and in libcosim against the FMUs' own compute.
"""

from __future__ import annotations

import json
import math
import os
import platform
import re
import subprocess
import sys
import tempfile
import time
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any, Mapping

import fmpy
import numpy as np

from harness import reference as ref
from harness.analysis.cache import fmu_identity
from harness.analysis.curves import hb_curve
from harness.analysis.executor import Runner
from harness.files.atomic import atomic_write_text
from harness.analysis.periodic.branches import BranchSettings, trace_branches
from harness.analysis.periodic.period_map import ShootingSettings
from harness.bench_ring_orbits import SECTION as RING_ORBITS_SECTION
from harness.bench_ring_orbits import ring_orbits_cost
from harness.bench_ring_orbits import section as ring_orbits_section
from harness.bench_ring_orbits import with_before
from harness.fmu.blade import BladeFMU
from harness.fmu.build import BUILD_DIR, REPO_ROOT, build
from harness.model.excitation import AeroLoad, Stepped, fmu_view
from harness.studies.paper import SIZES, STUDIES, Size, base_params
from harness.system import ring_c, ring_libcosim
from harness.system.ring import Ring, run as ring_run
from harness.validation.reproduction import reproduce

BENCH_DIR = REPO_ROOT / "bench"

# the bench ring: 24 blades, EO 3, 5000 rpm, c = 298, F_w0 = 300, default contacts, 0.5 s.
# h = 2.5e-5 s for both masters: libcosim's held inputs need h <= 5e-5 s (docs/model.md s.8), and
# at 5e-5 s its 24-blade ring stays bounded but loses the travelling wave's symmetry (30 % spread)
RING_BENCH = dict(n=24, engine_order=3, fw0=300.0, blade={"c": 298.0}, step=2.5e-5, stop_time=0.5)


@dataclass(frozen=True)
class BenchSize:
    """How much each row of `make bench` measures. FULL is the benchmark; QUICK runs every row at
    tiny sizes (seconds, one repeat): a test that no row can break unseen, its numbers meaningless."""

    name: str
    repeats: int = 5  # best of, for the doStep and RK4 step costs
    sim_scale: float = 1.0  # on the simulated times of the doStep and reference rows
    ring: Mapping[str, Any] = field(default_factory=lambda: dict(RING_BENCH))
    ring_repeats: int = 3
    hb_values: int | None = None  # per study (None: all)
    hb_speeds: int | None = None  # of the default size's (None: all)
    jacobian_curves: int | None = None  # of JACOBIAN_CURVES (None: all)
    jacobian_range: tuple[float, float] = (3000.0, 12000.0)
    cli_repeats: int = 15
    ring_orbits: Mapping[str, Any] = field(default_factory=dict)  # ring_orbits_cost's sizes ({}: its defaults)
    reproduce: str | Size = "default"  # the reproduce row's size (`--size`)
    extras: bool = True  # reproduce's Fig. 2, 4/5, Campbell, iteration (fixed sizes: tens of seconds)
    step_args: tuple[str, ...] = ()  # for build/bench_step


def machine() -> dict[str, Any]:
    cpu = "unknown"
    try:
        with open("/proc/cpuinfo") as fh:
            for ln in fh:
                if ln.startswith("model name"):
                    cpu = ln.split(":", 1)[1].strip()
                    break
    except OSError:
        pass

    return {
        "nproc": os.cpu_count(),
        "cpu": cpu,
        "python": platform.python_version(),
        "fmpy": fmpy.__version__,
        "system": f"{platform.system()} {platform.release()}",
    }


def c_step_cost(args: tuple[str, ...] = ()) -> dict[str, Any]:
    """Run build/bench_step (the core engineer's C benchmark) if present; its output verbatim."""
    exe = BUILD_DIR / "bench_step"
    if not exe.is_file():
        try:
            build(("bench_step",))
        except Exception:
            pass
    if not exe.is_file():
        return {"available": False, "text": "build/bench_step not built (no such CMake target yet)"}
    proc = subprocess.run([str(exe), *args], capture_output=True, text=True, timeout=600)
    text = (proc.stdout + proc.stderr).strip()
    ns = [float(x) for x in re.findall(r"([0-9.]+(?:[eE][-+]?\d+)?)\s*ns", text)]
    return {"available": True, "text": text, "ns_values": ns}


MODES_SECTION = "## Cost per RK4 step vs the number of modes"


def modes_step_cost(repeats: int = 5, args: tuple[str, ...] = ()) -> dict[str, Any]:
    """`build/bench_step modes`: ns per internal RK4 step of the Jenkins element with m = 1..6 modes
    (docs/model.md s.2a), all configurations measured one after the other in one process."""
    exe = BUILD_DIR / "bench_step"
    if not exe.is_file():
        build(("bench_step",))
    rows: dict[str, dict[str, Any]] = {}
    for _ in range(repeats):  # the best of `repeats` runs per row (a shared machine)
        proc = subprocess.run([str(exe), "modes", *args], capture_output=True, text=True, timeout=600, check=True)
        for line in proc.stdout.splitlines():
            mm = re.match(r"(m = \d, \w+(?: \(default\))?)\s+([0-9.]+)\s+([0-9.]+)\s+([0-9.]+)$", line.strip())
            if mm and (mm.group(1) not in rows or float(mm.group(2)) < rows[mm.group(1)]["ns_per_step"]):
                rows[mm.group(1)] = {
                    "configuration": mm.group(1),
                    "ns_per_step": float(mm.group(2)),
                    "rhs_per_step": float(mm.group(3)),
                    "events_per_step": float(mm.group(4)),
                }
    return {"repeats": repeats, "rows": list(rows.values())}


def modes_section(d: dict[str, Any], machine_text: str, date: str) -> list[str]:
    base = next(r["ns_per_step"] for r in d["rows"] if r["configuration"] == "m = 1, consistent")
    L = [
        MODES_SECTION,
        "",
        f"`build/bench_step modes` ({machine_text}; {date}; `python -m harness bench --only-modes`): the Jenkins "
        "element, tracked B, 5000 rpm, communication step 1 ms, maxStep 1e-5 s, 1 s simulated, per row the best "
        f"of 3 x {d['repeats']} runs, the rows measured one after the other in each run (ratios side by side). "
        "m > 1 needs the "
        "consistent formulation; the stable step of the highest mode is maxStep <= 2 sqrt(2) / w_m "
        "(docs/model.md s.2a: 2.19e-5 s for m = 6 at 5000 rpm).",
        "",
        "| configuration | ns per RK4 step | / m = 1 consistent | rhs calls per step | events per step |",
        "|---|---|---|---|---|",
    ]
    for r in d["rows"]:
        L.append(
            f"| {r['configuration']} | {r['ns_per_step']:.1f} | {r['ns_per_step'] / base:.2f} | "
            f"{r['rhs_per_step']:.2f} | {r['events_per_step']:.5f} |"
        )
    return L + [""]


def update_modes_section(path: Path) -> None:
    """Measures the modes row and writes its section into an existing RESULTS.md (replacing it)."""
    m = machine()
    text = path.read_text() if path.is_file() else "# Benchmark results\n"
    machine_text = f"{m['nproc']} CPU(s), {m['cpu']}, {m['system']}, load average {os.getloadavg()[0]:.1f} at the start"
    sec = "\n".join(modes_section(modes_step_cost(), machine_text, time.strftime("%Y-%m-%d %H:%M")))
    atomic_write_text(path, replace_section(text, MODES_SECTION, sec))


def replace_section(text: str, heading: str, sec: str) -> str:
    """`text` with the section starting at `heading` (up to the next "## ") replaced by `sec`, or
    `sec` appended."""
    if heading in text:
        a = text.index(heading)
        b = text.find("\n## ", a + 1)
        return text[:a] + sec + ("\n" + text[b + 1 :] if b >= 0 else "")
    return text.rstrip("\n") + "\n\n" + sec


class _Timed:
    """Wraps the ctypes fmi2DoStep of a BladeFMU and accumulates the time spent inside it."""

    def __init__(self, fn):
        self.fn, self.total, self.calls = fn, 0.0, 0

    def __call__(self, *a):
        t = time.perf_counter()
        st = self.fn(*a)
        self.total += time.perf_counter() - t
        self.calls += 1
        return st


def _best(fn, repeats: int) -> tuple[float, float, Any]:
    """min wall and min CPU time over `repeats` calls of fn (the machine is shared: minima are the
    least disturbed runs); returns (wall, cpu, last result)."""
    walls, cpus, out = [], [], None
    for _ in range(repeats):
        t, c = time.perf_counter(), time.process_time()
        out = fn()
        walls.append(time.perf_counter() - t)
        cpus.append(time.process_time() - c)
    return min(walls), min(cpus), out


def _inside(fmu: Any, fn, repeats: int) -> tuple[float, int]:
    """min time spent inside fmi2DoStep over `repeats` calls of fn, and the number of doSteps."""
    best, calls = math.inf, 0
    for _ in range(repeats):
        timed = _Timed(fmu.stepper.doStep)
        fmu.stepper.doStep = timed
        try:
            fn()
        finally:
            fmu.stepper.doStep = timed.fn
        best, calls = min(best, timed.total), timed.calls
    return best, calls


def dostep_cost(fmu: Any, params: dict, repeats: int = 5, sim_scale: float = 1.0) -> dict[str, Any]:
    """Cost of one doStep of BladeFMU.run at 5000 rpm for three communication steps."""
    out = {}
    T = 60.0 / (5000.0 * params["engineOrder"])
    plain = {"outputs": ["tipDisplacement", "amplitude"]}
    for label, h, t_stop, kw in (
        ("h = maxStep = 1e-5 s (1 internal step)", 1e-5, 0.2, plain),
        ("h = T/8 = 0.5 ms (50 internal steps)", T / 8, 1.0, plain),
        ("h = T/4 = 1 ms (100 internal steps)", T / 4, 1.0, plain),
    ):
        fmu.run(params, 10 * h, h)  # warm-up

        def go():
            return fmu.run(params, t_stop * sim_scale, h, **kw)

        wall, cpu, r = _best(go, repeats)
        inside, n = _inside(fmu, go, repeats)
        out[label] = {
            "steps": n,
            "us_per_doStep": wall / n * 1e6,
            "cpu_us_per_doStep": cpu / n * 1e6,
            "us_inside_doStep": inside / n * 1e6,
            "ratio_wall": wall / inside,
            "ratio_cpu": cpu / inside,
            "sim_time": t_stop * sim_scale,
            "us_per_simulated_ms": wall / (t_stop * sim_scale) * 1e3,
        }
    return out


CLI_SECTION = "## Command line start-up"
# (row, command): ours through the installed console script, fmpy's CLI as its user runs it
CLI_COMMANDS = (
    ("harness --help", [str(Path(sys.executable).with_name("harness")), "--help"]),
    ("harness --version", [str(Path(sys.executable).with_name("harness")), "--version"]),
    ("python -m fmpy --help", [sys.executable, "-m", "fmpy", "--help"]),
)


def cli_start(repeats: int = 15) -> dict[str, Any]:
    """Wall time of each CLI_COMMANDS row, the rows run in turn `repeats` times (so a busy moment
    hits all of them): per row the best and the median [s], and the ratio to fmpy's --help."""
    times: dict[str, list[float]] = {name: [] for name, _ in CLI_COMMANDS}
    for _ in range(repeats):
        for name, cmd in CLI_COMMANDS:
            t = time.perf_counter()
            subprocess.run(cmd, capture_output=True, check=True, timeout=60)
            times[name].append(time.perf_counter() - t)
    fmpy_best = min(times["python -m fmpy --help"])
    return {
        "repeats": repeats,
        "load_average": os.getloadavg()[0],
        "rows": {
            k: {"best": min(v), "median": float(np.median(v)), "ratio_best": min(v) / fmpy_best}
            for k, v in times.items()
        },
    }


def _cli_section(c: dict[str, Any], date: str) -> list[str]:
    L = [
        CLI_SECTION,
        "",
        f"Wall time of the command, started as a new process (`python -m harness bench --only cli`, {date}, load "
        f"average {c['load_average']:.1f}): the rows run in turn, {c['repeats']} times; target <= 0.3 s. "
        "The top-level parser imports no command module (so none of numpy, scipy, fmpy).",
        "",
        "| command | best | median | best / fmpy's best |",
        "|---|---|---|---|",
    ]
    for k, v in c["rows"].items():
        L.append(f"| `{k}` | {v['best']:.3f} s | {v['median']:.3f} s | {v['ratio_best']:.2f} |")
    return L + [""]


RING_SECTION = "## The bladed-disk ring"


def _timed(f, *a, **kw) -> tuple[Any, float, float]:
    t, c = time.perf_counter(), time.process_time()
    out = f(*a, **kw)
    return out, time.perf_counter() - t, time.process_time() - c


def _row(wall: float, cpu: float, inside: float, doSteps: int, q: np.ndarray) -> dict[str, Any]:
    return {
        "doSteps": doSteps,
        "wall": wall,
        "cpu": cpu,
        "inside_doStep": inside,
        "ratio_wall": wall / inside,
        "ratio_cpu": cpu / inside,
        "finite": bool(np.all(np.isfinite(q))),
        "max_q": float(np.abs(q).max()),
    }


def _fastest(repeats: int, f, *a, **kw) -> tuple[Any, float, float]:
    """f's result and its least wall and CPU time over `repeats` runs (the machine is shared)."""
    runs = [_timed(f, *a, **kw) for _ in range(repeats)]
    return runs[0][0], min(r[1] for r in runs), min(r[2] for r in runs)


def ring_cost(repeats: int = 3, setup: Mapping[str, Any] = RING_BENCH) -> dict[str, Any]:
    """The 24-blade ring (RING_BENCH) on the blades' built-in load in the fmpy master (feedthrough,
    linear extrapolation; and libcosim's data flow, held inputs), in libcosim, and in our C loop:
    wall of each whole run (instantiating the FMUs included) against the FMUs' own
    compute, the time inside fmi2DoStep of all FMUs, measured in C around each call
    (harness/system/ring_c.py, time_dosteps) for each data flow. libcosim's trajectory is checked to
    equal the C loop's in its data flow bit for bit, so that run's inside time is libcosim's compute.
    Least time of `repeats` runs for the C loop, the inside times and libcosim (one run of the fmpy
    master, 25 s or more); the load average before and after says how shared the machine was."""
    out: dict[str, Any] = {
        "setup": {k: (dict(v) if isinstance(v, dict) else v) for k, v in setup.items()},
        "machine": machine(),
        "date": time.strftime("%Y-%m-%d %H:%M"),
        "repeats": repeats,
        "load_before": os.getloadavg()[0],
    }
    ft = Ring(**setup, order=1)
    lc_flow = Ring(**setup, order=0, coupling="libcosim")
    ring_c.run(Ring(**{**setup, "stop_time": 10 * setup["step"]}))  # build, load once
    n = 2 * ft.n * ft.n_steps
    inside = {
        k: min(float(ring_c.run(r, time_dosteps=True)["inside_doStep"]) for _ in range(repeats))
        for k, r in (("ft", ft), ("lc", lc_flow))
    }
    g: dict[str, Any] = {"fmus": n // ft.n_steps}
    c_ft, wall, cpu = _fastest(repeats, ring_c.run, ft)
    g["C loop"] = _row(wall, cpu, inside["ft"], n, c_ft["q"])
    c_lc = ring_c.run(lc_flow)
    r, wall, cpu = _timed(ring_run, ft)  # the Python loop: 25 s a run
    g["fmpy feedthrough"] = _row(wall, cpu, inside["ft"], n, r["q"])
    g["C loop"]["deviation_from_fmpy"] = float(np.abs(c_ft["q"] - r["q"]).max() / np.abs(r["q"]).max())
    r, wall, cpu = _timed(ring_run, lc_flow)
    g["fmpy libcosim data flow"] = _row(wall, cpu, inside["lc"], n, r["q"])
    lc, wall, cpu = _fastest(repeats, ring_libcosim.run, Ring(**setup, order=0))
    g["libcosim"] = {
        **_row(wall, cpu, inside["lc"], n, lc["q"]),
        "step_wall": float(lc["step_wall"]),
        "ratio_step_wall": float(lc["step_wall"]) / inside["lc"],
        "equals_fmpy_libcosim_data_flow": bool(np.array_equal(lc["q"], c_lc["q"])),
    }
    out["builtin"] = g
    out["load_after"] = os.getloadavg()[0]
    return out


def reference_ratio(fmu: Any, params: dict, sim_scale: float = 1.0) -> dict[str, Any]:
    """The same stepped-speed run (3 plateaus x 0.1 s, 4500/5000/5500 rpm, kn = 1e6, B fixed at 2 d)
    through the FMU and through the Python reference (DOP853 with located events), fed
    the same piecewise Taylor input."""
    # kn = 1e6 and B fixed at 2 d (paper's formulation): a regular response, so the two codes can
    # agree point by point; at kn = 1e7 the contact response is sensitive (nearby trajectories
    # separate exponentially), which says nothing about either code
    params = dict(params, amplitudeMode=1, B=2 * params["d"], kn=1e6)
    T = 0.1 * sim_scale
    speed = Stepped([4500.0, 5000.0, 5500.0], [T, T, T])
    aero = AeroLoad(params["Fw0"], params["engineOrder"], speed)
    h = 60.0 / (5500.0 * params["engineOrder"]) / 8
    t = time.perf_counter()
    r = fmu.run(params, 3 * T, h, aero=aero, speed_rpm=speed, outputs=["tipDisplacement"])
    w_fmu = time.perf_counter() - t
    grid = r["time"]
    t = time.perf_counter()
    rr = ref.simulate(params, 3 * T, fmu_view(aero, grid, 8), fmu_view(speed, grid, 8), grid, breakpoints=grid)
    w_ref = time.perf_counter() - t
    dev = float(np.max(np.abs(rr["tipDisplacement"] - r["tipDisplacement"])) / np.max(np.abs(r["tipDisplacement"])))
    return {
        "sim_time": 3 * T,
        "wall_fmu": w_fmu,
        "wall_reference": w_ref,
        "ratio": w_ref / w_fmu,
        "max_rel_deviation": dev,
    }


def hb_all(values: int | None = None, speeds: int | None = None) -> dict[str, Any]:
    """Harmonic balance of every study's curves (the first `values` of each, at the first `speeds`
    of the default size's speeds; None: all)."""
    base = base_params()
    grid = SIZES["default"].hb_speeds[:speeds]
    hb_curve(base, grid[:5])  # warm-up
    t = time.perf_counter()
    n = 0
    for st in STUDIES.values():
        for v in st.values[:values]:
            n += len(hb_curve(dict(base, **{st.param: v}), grid))
    return {
        "curves": sum(len(s.values[:values]) for s in STUDIES.values()),
        "speeds_per_curve": len(grid),
        "solutions": n,
        "wall": time.perf_counter() - t,
    }


# representative curves: (model, parameters over the base case)
JACOBIAN_CURVES = (
    ("fixedPoint", {}),
    ("jenkins", {}),
    ("coulomb", {}),
    ("fixedPoint", {"d": 6e-5}),
    ("jenkins", {"kn": 1e5}),
    ("fixedPoint", {"gamma": math.pi / 7}),
)


def branch_jacobians(
    fmu: Any, curves: int | None = None, speed_range: tuple[float, float] = (3000.0, 12000.0)
) -> dict[str, Any]:
    """Branches of JACOBIAN_CURVES over 3000..12000 rpm (seeds every 1000 rpm, as `make run`),
    one process, with DP from the FMU's sensitivities (4 steps per period) vs by finite
    differences (the former path: Broyden in Newton, central monodromy, 8 steps per period)."""
    out = {}
    for label, sh in (
        ("sensitivities", ShootingSettings()),
        ("finite differences", ShootingSettings(sensitivities=False, steps_per_period=8)),
    ):
        wall = cpu = fmi = 0.0
        periods = points = 0
        for model, extra in JACOBIAN_CURVES[:curves]:
            t, c = time.perf_counter(), time.process_time()
            branches, st = trace_branches(
                fmu, dict(base_params(), **extra), model, speed_range, BranchSettings(seed_step=1000.0, shooting=sh)
            )
            wall += time.perf_counter() - t
            cpu += time.process_time() - c
            fmi += st.fmi_s
            periods += st.evaluations
            points += sum(len(b.points) for b in branches)
        out[label] = {"wall": wall, "cpu": cpu, "fmi": fmi, "periods": periods, "points": points}
    return out


def reproduce_cold(size: str | Size, workers: int | None, extras: bool = True) -> dict[str, Any]:
    """`reproduce` as `make run` does it: the studies as periodic-orbit branches, plus extras."""
    with tempfile.TemporaryDirectory() as tmp:
        t = time.perf_counter()
        with Runner(workers=workers, progress=False) as runner:
            rep = reproduce(Path(tmp) / "results", size, runner=runner, extras=extras)
        wall = time.perf_counter() - t
    tim = {k: (math.nan if v is None else v) for k, v in rep.summary.as_dict()["timing"].items()}
    return {
        "size": size if isinstance(size, str) else size.name,
        "wall": wall,
        "workers": workers or os.cpu_count(),
        **tim,
    }


def write_results(path: Path, data: dict[str, Any]) -> None:
    m = data["machine"]
    L = [
        "# Benchmark results",
        "",
        f"Machine: {m['nproc']} CPU(s), {m['cpu']}, {m['system']}, Python {m['python']}, fmpy {m['fmpy']}.",
        f"Measured by `make bench` (`python -m harness bench`) on {data['date']}; every number below comes from "
        "that single run"
        + (
            ""
            if data.get("ring", {}).get("date", data["date"]) == data["date"]
            else " but the ring section's, measured separately (its date and machine stated there)"
        )
        + ".",
        "",
    ]
    c = data.get("c_step", {})
    L += ["## FMU internal step cost (C benchmark `build/bench_step`)", ""]
    L += ["```", c.get("text", ""), "```", ""] if c.get("available") else [c.get("text", "not measured"), ""]
    if "modes" in data:
        L += modes_section(data["modes"], f"{m['nproc']} CPU(s), {m['cpu']}, {m['system']}", data["date"])
    if "dostep" in data:
        L += [
            "## Cost of one fmi2DoStep through the harness loop (fmpy/ctypes)",
            "",
            "BladeFMU.run at 5000 rpm, outputs sampled every step (first three rows: fmi2SetReal, "
            "fmi2SetRealInputDerivatives, fmi2DoStep, fmi2GetReal per step); the last row is the sweeps' "
            "configuration (fmi2SetRealInputDerivatives and fmi2DoStep per step, fmi2GetReal once per "
            "period); minimum over 5 repeats.",
            "",
            "| communication step | doSteps | us per doStep (wall) | (CPU) | us inside fmi2DoStep | wall / inside | CPU / inside |",
            "|---|---|---|---|---|---|---|",
        ]
        for k, v in data["dostep"].items():
            L.append(
                f"| {k} | {v['steps']} | {v['us_per_doStep']:.2f} | {v['cpu_us_per_doStep']:.2f} | "
                f"{v['us_inside_doStep']:.2f} | {v['ratio_wall']:.2f} | {v['ratio_cpu']:.2f} |"
            )
        L.append("")
    if "reference" in data:
        r = data["reference"]
        L += [
            "## The same run through the Python reference",
            "",
            f"Stepped speed 4500/5000/5500 rpm, kn = 1e6 N/m, B fixed at 2 d, {r['sim_time']} s simulated, "
            f"same piecewise Taylor input: FMU "
            f"{r['wall_fmu']:.3f} s, reference {r['wall_reference']:.2f} s: **reference / FMU = {r['ratio']:.0f}x** "
            f"(max deviation {r['max_rel_deviation']:.1e} of the peak).",
            "",
        ]
    if "hb" in data:
        h = data["hb"]
        L += [
            "## Harmonic balance for all studies (target <= 1 s)",
            "",
            f"{h['curves']} curves x {h['speeds_per_curve']} speeds ({h['solutions']} solutions, every branch with "
            f"stability), one process: **{h['wall']:.3f} s**.",
            "",
        ]
    if "jacobians" in data:
        j = data["jacobians"]
        L += [
            "## Branches: the Jacobian from the FMU's sensitivities vs by finite differences",
            "",
            f"{len(JACOBIAN_CURVES)} representative curves (fixed point, Jenkins element, Coulomb, d = 0.06 mm, "
            "kn = 1e5 N/m with the Jenkins element, gamma = pi/7), 3000..12000 rpm, seeds every 1000 rpm, one "
            "process; finite differences = the former path (Broyden-updated forward differences in Newton, "
            "central ones for the monodromy, 8 steps per period).",
            "",
            "| Jacobian | periods | branch points | wall | CPU | in the FMI calls | CPU / FMI |",
            "|---|---|---|---|---|---|---|",
        ]
        for k, v in j.items():
            L.append(
                f"| {k} | {v['periods']} | {v['points']} | {v['wall']:.2f} s | {v['cpu']:.2f} s | "
                f"{v['fmi']:.2f} s | {v['cpu'] / v['fmi']:.2f} |"
            )
        a, b = j.get("sensitivities"), j.get("finite differences")
        if a and b:
            L += [
                "",
                f"Sensitivities: **{b['wall'] / a['wall']:.2f}x less wall time**, "
                f"{b['periods'] / a['periods']:.2f}x fewer periods.",
                "",
            ]
    if "ring" in data:
        L += _ring_section(data["ring"], data.get("date", ""))
    if "cli" in data:
        L += _cli_section(data["cli"], data.get("date", ""))
    if "reproduce" in data:
        r = data["reproduce"]
        nan = math.nan
        fmi, worker = r.get("branches_fmi_s", nan), r.get("branches_worker_s", nan)
        L += [
            "## `make run` (`reproduce`): the studies as periodic-orbit branches",
            "",
            f"Size `{r['size']}`, all studies{' and extras' if math.isfinite(r.get('extras_wall', nan)) else ''}, "
            f"{r.get('workers')} worker processes: "
            f"**{r['wall']:.1f} s wall**.",
            "",
            f"- branches: {r.get('curves', 0):.0f} curves (fixed point B = A(B) and Jenkins element for every "
            f"study value, Coulomb fixed point for kn and angle), {r.get('branches_evaluations', 0):.0f} periods = "
            f"{r.get('branches_simulated_s', 0):.0f} s of blade time: {r.get('branches_wall', nan):.1f} s wall; "
            f"time in the FMI calls (ctypes included) {fmi:.1f} s of {worker:.1f} s worker time: "
            f"**worker time / FMI time = {worker / fmi:.2f}**, wall x workers / FMI time = "
            f"{r.get('branches_wall', nan) * r.get('workers', 1) / fmi:.2f}",
            f"- harmonic balance: {r.get('hb_wall', nan):.2f} s",
            f"- Fig. 2, 4/5, Campbell, the paper's iteration: {r.get('extras_wall', nan):.1f} s",
            "",
        ]
    atomic_write_text(path, "\n".join(L))


def _ring_section(g: dict[str, Any], run_date: str) -> list[str]:
    st = g["setup"]
    if "builtin" not in g:  # results written before the built-in load: nothing to compare
        return []
    m = g.get("machine", {})
    when = (
        ""
        if g.get("date") == run_date
        else f" Measured in a separate run (`python -m harness bench --only ring`) on {g.get('date')}, "
        f"{m.get('nproc')} CPU(s), {m.get('cpu')}, Python {m.get('python')}, fmpy {m.get('fmpy')}; "
        "every row of this table comes from that one run."
    )
    if "load_before" in g:
        when += (
            f" The machine was shared (load average {g['load_before']:.1f} before, {g['load_after']:.1f} after, "
            f"on {m.get('nproc')} CPUs): C loop, inside times and libcosim are the least of {g['repeats']} runs, "
            "the fmpy master one run."
        )
    L = [
        f"{RING_SECTION} ({st['n']} blades): the masters vs the FMUs' own compute (goal <= 2x for libcosim)",
        "",
        f"{st['n']} blades + {st['n']} shroud contacts, the blades making their load (built-in load, "
        f"{g['builtin']['fmus']} FMUs). EO {st['engine_order']}, 5000 rpm, "
        f"c = {st['blade']['c']:g} N s/m2, F_w0 = {st['fw0']:g} N/m, default contacts (k_n = 1e7), "
        f"{st['stop_time']:g} s at h = {st['step']:g} s in every master. Wall = the whole run (instantiating the "
        "FMUs included); inside = the time inside fmi2DoStep of all FMUs, measured in C around each call by the C "
        "loop (harness/system/ring_c.py) in the same data flow: feedthrough with linear extrapolation, or "
        "libcosim's (held inputs, the forces of the contacts' previous step). libcosim steps the FMUs on its own "
        "worker threads (CPU counts all threads)." + when,
        "",
        "| master | doSteps | wall | CPU | inside fmi2DoStep | wall / inside | CPU / inside | max abs q |",
        "|---|---|---|---|---|---|---|---|",
    ]
    labels = {
        "fmpy feedthrough": "fmpy master (feedthrough, linear extrapolation)",
        "fmpy libcosim data flow": "fmpy master (libcosim's data flow, held inputs)",
        "libcosim": "libcosim (fixed step, held inputs)",
        "C loop": "our C loop (feedthrough, linear extrapolation)",
    }
    for k, label in labels.items():
        v = g["builtin"][k]
        L.append(
            f"| {label} | {v['doSteps']} | {v['wall']:.2f} s | {v['cpu']:.2f} s | "
            f"{v['inside_doStep']:.2f} s | **{v['ratio_wall']:.2f}** | {v['ratio_cpu']:.2f} | "
            f"{v['max_q']:.3g} m{'' if v['finite'] else ' (NOT finite)'} |"
        )
    lc, cl = g["builtin"]["libcosim"], g["builtin"]["C loop"]
    L += [
        "",
        f"libcosim: wall / FMU compute = **{lc['ratio_wall']:.2f}x**; goal <= 2x "
        f"{'met' if lc['ratio_wall'] <= 2 else 'not met'}; its stepping alone (CosimExecution.step, loading and "
        f"initialization left out) {lc['step_wall']:.2f} s = {lc['ratio_step_wall']:.2f}x. "
        f"libcosim's trajectory equals the C loop's in its data flow bit for bit: "
        f"{'yes' if lc['equals_fmpy_libcosim_data_flow'] else 'NO'}. One doStep costs "
        f"{lc['inside_doStep'] / lc['doSteps'] * 1e6:.2f} us inside the FMU, so a master's per-step data handling "
        "decides. Our C loop makes the fmpy master's calls without Python between them (q within "
        f"{cl['deviation_from_fmpy']:.1e} of the fmpy master): **{cl['ratio_wall']:.2f}x**.",
        "",
    ]
    return L


# `--quick`: every row once at tiny sizes (tests/project/test_bench_quick.py runs it in `make test`)
TINY_REPRODUCE = Size(
    "tiny",
    hb_speeds=(3000.0, 3500.0, 4000.0),
    values={"gap": (2e-5,), "mass": (0.02,), "angle": (math.pi / 3,), "kn": (1e5,)},
    fig45_time=0.05,
    coulomb=False,
    iteration_steps=2,
    speed_range=(3000.0, 4000.0),
    seed_step=1000.0,
    modes=(),
    campbell_modes=0,
)
QUICK = BenchSize(
    "quick",
    repeats=1,
    sim_scale=0.02,
    ring={**RING_BENCH, "n": 4, "stop_time": 0.005},
    ring_repeats=1,
    hb_values=1,
    hb_speeds=3,
    jacobian_curves=2,
    jacobian_range=(8000.0, 9000.0),
    cli_repeats=1,
    ring_orbits=dict(repeats=1, band=(5800.0, 6400.0), seed_points=2, points=1),
    reproduce=TINY_REPRODUCE,
    extras=False,
    step_args=("quick",),
)


def run_bench(
    output_file: Path | str = BENCH_DIR / "RESULTS.md",
    size: str = "default",
    workers: int | None = None,
    skip_reproduce: bool = False,
    only: str | None = None,
    only_modes: bool = False,
    quick: bool = False,
) -> int:
    """Measure every section (or `only` one: "ring", "ring-orbits" or "cli"; or `only_modes`: the cost per RK4 step vs the
    number of modes) and write `output_file` (Markdown) and its .json beside it. `quick`: every row
    at the QUICK size, never written over bench/RESULTS.md (into a temporary directory instead)."""
    out = Path(output_file)
    if quick:
        if only or only_modes:
            raise ValueError("--quick runs every row: not with --only or --only-modes")
        if out.resolve() == (BENCH_DIR / "RESULTS.md").resolve():  # never over the measured results
            with tempfile.TemporaryDirectory() as tmp:
                return measure(Path(tmp) / "RESULTS.md", QUICK, workers, skip_reproduce)
        return measure(out, QUICK, workers, skip_reproduce)
    if only_modes:
        update_modes_section(out)
        print(out.read_text())
        return 0
    if only is not None:  # that section and its .json entry replaced, the rest kept
        old = out.with_suffix(".json")
        data = json.loads(old.read_text()) if old.is_file() else {"machine": machine(), "date": ""}
        if only == "ring":
            print("24-blade ring ...", flush=True)
            data["ring"] = ring_cost()
            heading, section = RING_SECTION, _ring_section(data["ring"], data["date"])
        elif only == "ring-orbits":
            load = os.getloadavg()[0]
            print("the ring's periodic steady states ...", flush=True)
            now = time.strftime("%Y-%m-%d %H:%M")
            data["ring_orbits"] = with_before(ring_orbits_cost(), data.get("ring_orbits"), now, out)
            heading = RING_ORBITS_SECTION
            section = ring_orbits_section(
                data["ring_orbits"],
                _machine_text(data.get("machine") or machine(), load),
                now,
            )
        else:
            print("command line start-up ...", flush=True)
            data["cli"] = cli_start()
            heading, section = CLI_SECTION, _cli_section(data["cli"], time.strftime("%Y-%m-%d %H:%M"))
        text = out.read_text() if out.is_file() else "# Benchmark results\n"
        atomic_write_text(out, replace_section(text, heading, "\n".join(section)))
        atomic_write_text(old, json.dumps(data, indent=1, default=str))
        print(out.read_text())
        return 0
    return measure(out, BenchSize("full", reproduce=size), workers, skip_reproduce)


def measure(out: Path, size: BenchSize, workers: int | None, skip_reproduce: bool) -> int:
    """Every row at `size`, written to `out` (.md and .json) and printed."""
    path, _ = fmu_identity(None)
    data: dict[str, Any] = {"machine": machine(), "date": time.strftime("%Y-%m-%d %H:%M")}
    print("C step benchmark ...", flush=True)
    data["c_step"] = c_step_cost(size.step_args)
    print("C step benchmark vs the number of modes ...", flush=True)
    data["modes"] = modes_step_cost(size.repeats, size.step_args)
    p = base_params()
    with BladeFMU(path) as fmu:
        print("doStep cost ...", flush=True)
        data["dostep"] = dostep_cost(fmu, p, size.repeats, size.sim_scale)
        print("reference ratio ...", flush=True)
        data["reference"] = reference_ratio(fmu, p, size.sim_scale)
        print("branch Jacobians: sensitivities vs finite differences ...", flush=True)
        data["jacobians"] = branch_jacobians(fmu, size.jacobian_curves, size.jacobian_range)
    print("harmonic balance ...", flush=True)
    data["hb"] = hb_all(size.hb_values, size.hb_speeds)
    print(f"{size.ring['n']}-blade ring: fmpy master and libcosim ...", flush=True)
    data["ring"] = ring_cost(size.ring_repeats, size.ring)
    print("command line start-up ...", flush=True)
    data["cli"] = cli_start(size.cli_repeats)
    print("the ring's periodic steady states ...", flush=True)
    load = os.getloadavg()[0]
    data["ring_orbits"] = ring_orbits_cost(**size.ring_orbits)
    if not skip_reproduce:
        name = size.reproduce if isinstance(size.reproduce, str) else size.reproduce.name
        print(f"reproduce --size {name} (branches) ...", flush=True)
        data["reproduce"] = reproduce_cold(size.reproduce, workers, size.extras)
    write_results(out, data)
    sec = "\n".join(ring_orbits_section(data["ring_orbits"], _machine_text(data["machine"], load), data["date"]))
    atomic_write_text(out, replace_section(out.read_text(), RING_ORBITS_SECTION, sec))
    atomic_write_text(out.with_suffix(".json"), json.dumps(data, indent=1, default=str))
    print(out.read_text())
    return 0


def _machine_text(m: dict[str, Any], load: float) -> str:
    return f"{m['nproc']} CPU(s), {m['cpu']}, {m['system']}, load average {load:.1f} at the start"
