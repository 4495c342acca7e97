"""Validate the FMU against the independent Python reference and print a pass/fail table.

`python -m harness validate [--quick]` runs them (harness/cli/validate.py). Time-domain cases: the FMU runs with input derivatives up
to order 8; the reference (harness.reference.simulate) is fed `fmu_view(...)` of exactly the
inputs the FMU saw, with integration restarts at the communication points, and both are compared
on the communication grid, for every friction model, formulation, projection, gating setting and
amplitude mode, at constant speeds (3000, 5000 = resonance, 8000 rpm) and a 4000 -> 6000 rpm
run-up. Tolerances: tip displacement within 1e-6 of its amplitude over the whole run for
the describing-function models without switching (no gating, fixed B), 1e-4 with switching
instants (gating at |q| = d, tracked-B updates at period ends) and for the time-domain element. Harmonic-balance cases: gating off, tracked amplitude: the FMU's
periodic steady state (harness.analysis.steady_state) against the nearest harmonic-balance solution
(harness.analysis.harmonic_balance) that is stable and reachable by the tracked-amplitude update (the
reference's tracked map, harness.reference.tracked), amplitude and phase to
1e-4; where the reference says no root is reachable (the tracked-B period map has spectral radius
> 1) the FMU must not settle. Exit code 1 if any row fails.
"""

from __future__ import annotations

import csv
import io
import itertools
import math
from dataclasses import dataclass
from pathlib import Path
from typing import Any, Callable, Iterable

import numpy as np

from harness.files.atomic import atomic_write_text
from harness.analysis.harmonic_balance import harmonic_balance
from harness.analysis.steady_state import analyze
from harness.fmu.blade import BladeFMU, FMUError
from harness.model.excitation import AeroLoad, Constant, LinearRamp, Modulated, Piecewise, fmu_view
from harness.model.params import validate
from harness.reference.dynamics import simulate
from harness.reference.tracked import tracked_radii

TOL_DF = 1e-6  # describing-function models, no gating: smooth right-hand side
TOL_SWITCHING = 1e-4  # gating (K_eq, C_eq switch at |q| = d) and the time-domain element
TOL_HB = 1e-4  # steady-state amplitude vs harmonic balance (relative)
HB_RTOL = 1e-6  # steady-state detection tolerance for the HB cases (100x below TOL_HB)
KICK_PERIODS, KICK = 50, 4.0  # HB "kick" start: periods with KICK times the load
SOFT_PERIODS = 300  # HB "soft" start: periods over which the load amplitude ramps up from 0
TD_STEP = 2e-4  # communication step of the time-domain cases [s]
# FMU internal step for validation. The FMU's RK4 is 4th order (checked by the order row): at its
# default maxStep 1e-5 the stiffest cases (consistent formulation, gated contact, 0.1 s at 5000 rpm)
# reach ~2.6e-4, at 2.5e-6 ~1e-6, so the comparison measures the implementation, not the step.
MAX_STEP = 2.5e-6
SPEEDS = (3000.0, 5000.0, 8000.0)  # rpm; 5000 is the contact-free resonance (docs/model.md s.2)
HB_SPEEDS = (3000.0, 5000.0, 6000.0, 8000.0)  # rpm; contact branches at 6000-8000 (hardening)


@dataclass
class Row:
    scenario: str
    quantity: str
    error: float
    tolerance: float
    note: str = ""
    ok: bool | None = None  # set for yes/no checks without an error measure

    @property
    def passed(self) -> bool:
        return self.ok if self.ok is not None else bool(self.error <= self.tolerance)  # NaN fails


@dataclass
class Case:
    name: str
    options: dict[str, Any]
    speed: Piecewise
    stop_time: float
    kind: str = "time"  # "time", "order" (solver convergence order) or "hb"
    speed_rpm: float = math.nan

    def tolerance(self) -> float:
        # smooth right-hand side: a describing-function model with constant K_eq, C_eq (no gating,
        # fixed B). Tracked B jumps at located period ends, like gating switches at |q| = d.
        o = self.options
        smooth = o.get("frictionModel", 1) in (1, 2) and not o.get("gating", True) and o.get("amplitudeMode", 2) == 1
        return TOL_DF if smooth else TOL_SWITCHING


def _label(o: dict[str, Any]) -> str:
    fm = {1: "macroslipDF", 2: "coulombDF", 3: "jenkinsTD"}[o["frictionModel"]]
    parts = [fm, "printed" if o["formulation"] == 1 else "consistent"]
    if o["frictionModel"] != 3:
        parts += ["projPaper" if o["projection"] == 1 else "projConsistent", "gated" if o["gating"] else "ungated"]
    parts.append("fixedB" if o["amplitudeMode"] == 1 else "trackedB")
    return "/".join(parts)


def _option_sets(quick: bool) -> list[dict[str, Any]]:
    base = dict(frictionModel=1, formulation=1, projection=1, gating=True, amplitudeMode=2)
    if quick:  # one factor at a time around the paper's setting
        variants = [
            {},
            {"frictionModel": 2},
            {"frictionModel": 3},
            {"formulation": 2},
            {"projection": 2},
            {"gating": False},
            {"amplitudeMode": 1},
            {"gating": False, "amplitudeMode": 1},
        ]
        return [{**base, **v} for v in variants]
    out = []
    for fm, form, proj, gat, am in itertools.product((1, 2), (1, 2), (1, 2), (True, False), (1, 2)):
        out.append(dict(frictionModel=fm, formulation=form, projection=proj, gating=gat, amplitudeMode=am))
    for form, am in itertools.product((1, 2), (1, 2)):  # projection/gating do not apply to model 3
        out.append(dict(frictionModel=3, formulation=form, projection=1, gating=True, amplitudeMode=am))
    return out


def cases(quick: bool = False) -> list[Case]:
    """The validation matrix: time-domain cases and harmonic-balance cases."""
    stop = 0.05 if quick else 0.1
    speeds: list[tuple[str, Piecewise]] = [(f"{n:g}rpm", Constant(n)) for n in SPEEDS]
    speeds.append(("runup4000-6000", LinearRamp(4000.0, 6000.0, 0.0, stop)))
    if quick:
        speeds = [speeds[1], speeds[3]]
    out = [Case(f"{_label(o)}@{sn}", o, sp, stop) for o in _option_sets(quick) for sn, sp in speeds]
    stiff = dict(frictionModel=1, formulation=2, projection=1, gating=True, amplitudeMode=2)
    out.append(Case(f"{_label(stiff)}@5000rpm", stiff, Constant(5000.0), 0.1, kind="order"))
    hb = [
        (dict(frictionModel=fm, formulation=form, projection=proj, gating=False, amplitudeMode=2), n)
        for fm, form, proj in itertools.product((1, 2), (1, 2), (1, 2))
        for n in HB_SPEEDS
    ]
    if quick:  # open branch, unstable tracked map, contact branch
        hb = [(hb[0][0], 3000.0), (hb[0][0], 5000.0), (dict(hb[0][0], projection=2), 6000.0)]
    out += [Case(f"HB {_label(o)}@{n:g}rpm", o, Constant(n), 0.0, kind="hb", speed_rpm=n) for o, n in hb]
    return out


def _rel(a: np.ndarray, b: np.ndarray, mask: np.ndarray | None = None) -> float:
    scale = float(np.max(np.abs(b)))
    if mask is not None:
        a, b = a[mask], b[mask]
    if scale == 0.0:
        return float(np.max(np.abs(a)))
    return float(np.max(np.abs(a - b)) / scale)


def _fmu_and_reference(fmu, case: Case, step: float, max_step: float):
    p = validate(dict(case.options, maxStep=max_step))
    res = fmu.run(p, case.stop_time, step, speed_rpm=case.speed, derivative_order=8)
    grid = res["time"]
    aero = AeroLoad(p["Fw0"], p["engineOrder"], case.speed)
    aero_v, speed_v = fmu_view(aero, grid, 8), fmu_view(case.speed, grid, 8)
    ref = simulate(p, case.stop_time, aero_v, speed_v, t_eval=grid, breakpoints=grid)
    return p, res, ref, speed_v


def compare_time(fmu, case: Case, step: float = TD_STEP, max_step: float = MAX_STEP) -> list[Row]:
    """FMU vs reference driven by the very inputs the FMU saw (fmu_view of order 8)."""
    if case.kind == "order":
        return solver_order(fmu, case, step)
    p, res, ref, speed_v = _fmu_and_reference(fmu, case, step, max_step)
    grid = res["time"]
    tol = case.tolerance()
    amp = float(np.max(np.abs(ref["tipDisplacement"])))
    rows = [
        Row(
            case.name,
            "tipDisplacement",
            _rel(res["tipDisplacement"], ref["tipDisplacement"]),
            tol,
            f"amplitude {amp * 1e3:.4g} mm",
        )
    ]
    rows.append(Row(case.name, "tipVelocity", _rel(res["tipVelocity"], ref["tipVelocity"]), tol))
    rows.append(Row(case.name, "dissipatedEnergy", _rel(res["dissipatedEnergy"], ref["dissipatedEnergy"]), tol))
    if p["amplitudeMode"] == 2:
        # B jumps at period ends psi = 2 pi k; a sample exactly at a period end may report the value
        # before or after the jump in either implementation: those samples are left out.
        cycles = (p["engineOrder"] * 2 * math.pi / 60 * speed_v.integral(grid)) / (2 * math.pi)
        away = np.abs(cycles - np.round(cycles)) > 1e-7
        rows.append(
            Row(
                case.name,
                "amplitude (tracked B)",
                _rel(res["amplitude"], ref["amplitude"], away),
                tol,
                f"{int(np.sum(~away))} samples at period ends left out",
            )
        )
    return rows


def solver_order(fmu, case: Case, step: float = TD_STEP) -> list[Row]:
    """Observed convergence order of the FMU's integrator: error vs the reference at maxStep 1e-5
    and 5e-6; RK4 with located events should give log2(e1/e2) = 4 (accepted: 3.5..4.5)."""
    errs = []
    for ms in (1e-5, 5e-6):
        _, res, ref, _ = _fmu_and_reference(fmu, case, step, ms)
        errs.append(_rel(res["tipDisplacement"], ref["tipDisplacement"]))
    order = math.log2(errs[0] / errs[1]) if errs[1] > 0 else math.nan
    return [
        Row(
            case.name,
            "RK4 order |p - 4|",
            abs(order - 4.0),
            0.5,
            f"order {order:.3f}: error {errs[0]:.3g} at maxStep 1e-5, {errs[1]:.3g} at 5e-6",
        )
    ]


def _steady_fmu(fmu, p: dict[str, Any], rpm: float, start: str, max_periods: int = 4000):
    """Run the FMU (gating off, tracked B) until harness.analysis.steady_state finds the periodic state.

    The first periods set where the run ends when branches coexist (only the final, nominal load
    matters for the steady state): start="soft" ramps the load amplitude from 0 over SOFT_PERIODS
    periods (the free vibration is hardly excited: follows the branch that grows from zero, e.g.
    an open branch just below the gap); start="kick" drives KICK_PERIODS periods with KICK times
    the load (reaches a contact branch that coexists with the open one)."""
    period = 60.0 / (rpm * p["engineOrder"])
    M = int(math.ceil(period / 1e-4))
    step = period / M  # an integer number of samples per period: no resampling in analyze
    speed = Constant(rpm)
    load = AeroLoad(p["Fw0"], p["engineOrder"], speed)
    if start == "soft":
        n = SOFT_PERIODS
        aero = Modulated(LinearRamp(0.0, 1.0, 0.0, n * period), load)
    else:
        n = KICK_PERIODS
        aero = AeroLoad(KICK * p["Fw0"], p["engineOrder"], speed)
    fmu.run(p, n * period, step, speed_rpm=speed, aero=aero, outputs=["tipDisplacement"])
    chunk, last = 200, None
    while True:
        res = fmu.run(None, (n + chunk) * period, step, speed_rpm=speed, outputs=["tipDisplacement"], reset=False)
        n += chunk
        data = res if last is None else np.concatenate([last, res[1:]])
        keep = data[-(100 * M + 1) :]  # the last 100 periods
        ss = analyze(keep["time"], keep["tipDisplacement"], period, rtol=HB_RTOL, min_periods=5)
        if ss.reached or n >= max_periods:
            return ss, n * period
        last = res


def compare_hb(fmu, case: Case) -> list[Row]:
    """The FMU's periodic steady state vs the harmonic balance (gating off, tracked B): two methods of
    the product, time integration and the frequency domain (harness.analysis.harmonic_balance).

    The reference gives the spectral radius of the tracked-amplitude period map at each HB root
    (harness.reference.tracked): a root is reachable by the FMU if it is stable and that radius is < 1.
    Two starts (soft, kick); each one that settles is compared with the nearest reachable root.
    Where no root is reachable the FMU must not settle (the B update overshoots: the period-to-period oscillation
    of docs/model.md s.4). A reachable root that no start settles on fails."""
    p = validate(case.options)
    sols = harmonic_balance(p, case.speed_rpm)
    radius = dict(zip((s.B for s in sols), tracked_radii(p, sols)))
    reachable = [s for s in sols if s.stable and radius[s.B] < 1.0]
    runs = {start: _steady_fmu(fmu, p, case.speed_rpm, start) for start in ("soft", "kick")}
    settled = {k: v for k, v in runs.items() if v[0].reached}
    if not reachable:
        radii = ", ".join(f"{radius[s.B]:.3g}" for s in sols if s.stable)
        note = f"reference: tracked-B map unstable at every stable HB root (radius {radii}); FMU " + (
            f"settled ({', '.join(settled)} start)"
            if settled
            else f"did not settle in {max(t for _, t in runs.values()):.3g} s"
        )
        return [Row(case.name, "no steady state (as predicted)", math.nan, math.nan, note, ok=not settled)]
    if not settled:
        ss, t_end = runs["soft"]
        return [
            Row(
                case.name,
                "steady amplitude vs HB",
                math.nan,
                TOL_HB,
                f"FMU did not settle in {t_end:.3g} s from either start: {ss.message}",
            )
        ]
    rows = []
    for start, (ss, _) in settled.items():
        best = min(reachable, key=lambda s: abs(s.B - ss.harmonic_amplitude))
        err_b = abs(ss.harmonic_amplitude - best.B) / best.B
        dph = abs((ss.phase - best.phase + math.pi) % (2 * math.pi) - math.pi)
        branch = "open branch" if best.open else "contact branch"
        note = (
            f"{start} start: B_fmu {ss.harmonic_amplitude * 1e3:.6g} mm, B_hb {best.B * 1e3:.6g} mm"
            f" ({branch}, tracked radius {radius[best.B]:.3g}, {len(sols)} HB root(s))"
        )
        rows += [
            Row(case.name, f"steady amplitude vs HB ({start})", err_b, TOL_HB, note),
            Row(case.name, f"steady phase vs HB ({start}) [rad]", dph, TOL_HB),
        ]
    return rows


def run_validation(
    case_list: Iterable[Case], fmu_path=None, on_row: Callable[[Row], None] | None = None, max_step: float = MAX_STEP
) -> list[Row]:
    rows: list[Row] = []
    with BladeFMU(fmu_path) as fmu:
        for case in case_list:
            try:
                new = compare_hb(fmu, case) if case.kind == "hb" else compare_time(fmu, case, max_step=max_step)
            except FMUError as exc:
                new = [Row(case.name, "run", math.nan, 0.0, f"FMU error: {exc}")]
            for r in new:
                rows.append(r)
                if on_row:
                    on_row(r)
    return rows


HEADER = f"{'scenario':<58} {'quantity':<30} {'max error':>10} {'tolerance':>9}  result"


def format_row(r: Row) -> str:
    err = "-" if r.ok is not None else f"{r.error:.3g}"
    tol = "-" if r.ok is not None else f"{r.tolerance:.0e}"
    return (
        f"{r.scenario:<58} {r.quantity:<30} {err:>10} {tol:>9}  "
        f"{'pass' if r.passed else 'FAIL'}{'  ' + r.note if r.note else ''}"
    )


def write_table(path: str | Path, rows: Iterable[Row]) -> None:
    """The rows as CSV (scenario, quantity, max_error, tolerance, passed, note), atomically: never a
    half-written table."""
    buf = io.StringIO(newline="")
    w = csv.writer(buf)
    w.writerow(["scenario", "quantity", "max_error", "tolerance", "passed", "note"])
    for r in rows:
        w.writerow([r.scenario, r.quantity, f"{r.error:.6g}", f"{r.tolerance:g}", r.passed, r.note])
    atomic_write_text(path, buf.getvalue())
