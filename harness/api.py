"""The public API of `harness` (re-exported there on first use): thin over the package's own
functions, checking every argument with a `ParameterError` that names the value, the accepted
range and the argument it came from. `python -m harness` / `harness` is the command line over the
same. Above the system layer: it imports model, fmu, analysis and system (docs/layers.md).
"""

from __future__ import annotations

import math
from pathlib import Path
from typing import Any, Sequence

import numpy as np
from fmpy import read_model_description

from harness.analysis.periodic.branches import orbits_at, trace_branches
from harness.analysis.periodic.continuation import Branch
from harness.analysis.periodic.period_map import MODELS, STATE_STARTS, PeriodMap
from harness.analysis.periodic.shooting import Orbit
from harness.fmu.blade import BladeFMU
from harness.fmu.build import fmu_file
from harness.fmu.slave import build_ring_fmus
from harness.model.params import ParameterError, input_range, validate
from harness.system import ring_c, ring_values
from harness.system.ring import Ring
from harness.system.ring import run as ring_run
from harness.system.ring_orbits.branches import RingBranches
from harness.system.ring_orbits.branches import ring_branches as trace_ring_branches
from harness.system.ring_orbits.period_map import RingShootingSettings
from harness.system.ring_orbits.seeds import SweepPath
from harness.version import version

__all__ = [
    "version",
    "fmu_path",
    "simulate",
    "periodic_orbits",
    "branch",
    "Ring",
    "run_ring",
    "ring_branches",
    "ParameterError",
    "RING_MASTERS",
]

RING_MASTERS = ("fmpy", "c")
"""The masters `run_ring` runs the ring with: its communication loop in Python ("fmpy", the readable
reference) or in C ("c", the same data flow)."""


def fmu_path(name: str = "ShroudedBlade") -> Path:
    """Path of one of the project's FMUs.

    Parameters
    ----------
    name : str
        "ShroudedBlade" (FMI 2.0 co-simulation and model exchange), "fmi3/ShroudedBlade" (FMI 3.0
        co-simulation), "Excitation", "BladeExternalContact" or "ShroudContact".

    Returns
    -------
    pathlib.Path
        Installed: the FMU that came with the package (harness/fmus/); in a checkout:
        `build/<name>.fmu`, built with CMake if out of date.

    Raises
    ------
    KeyError
        An unknown `name`.
    """
    return fmu_file(name)


def _error(message: str) -> Exception:
    return ParameterError(message)


def _finite(name: str, value: Any, where: str) -> float:
    """`value` as a float, or ParameterError naming it."""
    try:
        v = float(value)
    except (TypeError, ValueError):
        raise _error(f"{name} = {value!r} (from {where}) is not a number") from None
    if not math.isfinite(v):
        raise _error(f"{name} = {value!r} (from {where}) is not finite")
    return v


def _speed(speed: Any, where: str, low_open: bool, name: str = "speed_rpm") -> float:
    """A rotor speed [rpm] inside the FMU's rotorSpeed range (from its model description)."""
    lo, hi = input_range("rotorSpeed")
    v = _finite(name, speed, where)
    if (v <= lo if low_open else v < lo) or v > hi:
        raise _error(
            f"{name} = {speed!r} rpm (from {where}) is out of range; accepted: {'(' if low_open else '['}{lo:g},"
            f" {hi:g}] rpm (the FMU's rotorSpeed)"
        )
    return v


def _parameters(parameters: dict[str, Any], where: str) -> dict[str, Any]:
    """The parameters as given (names and values checked against the model description)."""
    validate(parameters, source=where)
    return dict(parameters)


def _model(model: str, where: str) -> None:
    if model not in MODELS:
        raise _error(f"model = {model!r} (from {where}(model=...)) is not one of {', '.join(MODELS)}")


def simulate(
    stop_time: float = 0.3,
    *,
    speed_rpm: float = 5000.0,
    step: float = 1e-4,
    outputs: Sequence[str] | None = None,
    fmu: str | Path | None = None,
    **parameters: Any,
) -> np.ndarray:
    """Run the blade FMU from rest at constant speed under its aerodynamic load Fw0 sin(EO * phase).

    As `harness simulate` without the files.

    Parameters
    ----------
    stop_time : float
        End of the run [s].
    speed_rpm : float
        Rotor speed [rpm], inside the FMU's rotorSpeed range.
    step : float
        Communication step [s], 0 < step <= stop_time.
    outputs : sequence of str, optional
        The FMU outputs to record (default: all of them).
    fmu : str or pathlib.Path, optional
        Another FMU file (default `fmu_path()`).
    **parameters
        FMU parameters by name, Fw0 among them (e.g. ``d=4e-5, gating=False``).

    Returns
    -------
    numpy.ndarray
        A record array with 'time' [s] and the outputs at every communication point.

    Raises
    ------
    ParameterError
        A value out of its range or an unknown parameter name, naming the argument it came from.
    """
    where = "harness.simulate"
    params = _parameters(parameters, f"{where}(**parameters)")
    v = _speed(speed_rpm, f"{where}(speed_rpm=...)", low_open=False)
    t = _finite("stop_time", stop_time, f"{where}(stop_time=...)")
    h = _finite("step", step, f"{where}(step=...)")
    if not 0 < h <= t:
        raise _error(f"step = {step!r} s (from {where}(step=...)) is out of range; accepted: (0, stop_time = {t:g}] s")
    with BladeFMU(fmu) as blade:
        return blade.run(params, t, h, speed_rpm=v, outputs=outputs)


def periodic_orbits(
    speed_rpm: float, model: str = "fixedPoint", *, fmu: str | Path | None = None, **parameters: Any
) -> list[Orbit]:
    """Every periodic orbit of the blade FMU found at one speed, by shooting.

    As `harness periodic --speed SPEED --model MODEL`.

    Parameters
    ----------
    speed_rpm : float
        Rotor speed [rpm], inside the FMU's rotorSpeed range (above its lower end).
    model : str
        The contact model: "fixedB" (the describing function at a fixed amplitude, parameter B),
        "fixedPoint" (the paper's B = A(B)), "jenkins" (the time-domain macroslip element) or
        "coulomb".
    fmu : str or pathlib.Path, optional
        Another FMU file (default `fmu_path()`).
    **parameters
        FMU parameters by name (not the state on the orbit: that is what shooting solves for).

    Returns
    -------
    list of Orbit
        Sorted by amplitude, each with its Floquet multipliers and stability (`.amplitude` [m],
        `.stable`, `.label`, `.multipliers`, `.as_dict()`).

    Raises
    ------
    ParameterError
        A value out of its range, an unknown model or parameter, or a state start value.
    """
    where = "harness.periodic_orbits"
    v = _speed(speed_rpm, f"{where}(speed_rpm=...)", low_open=True)
    _model(model, where)
    state = [k for k in parameters if k in STATE_STARTS]
    if state:
        raise _error(
            f"{state[0]} (from {where}(**parameters)): the state on the orbit is what shooting solves"
            " for; give parameters only"
        )
    params = _parameters(parameters, f"{where}(**parameters)")
    with BladeFMU(fmu) as blade:
        return orbits_at(PeriodMap(blade, params, model), v)


def branch(
    speed_range_rpm: tuple[float, float], model: str = "fixedPoint", *, fmu: str | Path | None = None, **parameters: Any
) -> list[Branch]:
    """The branches of periodic orbits of the blade FMU over a speed range.

    Traced by pseudo-arclength continuation from the orbits found at seed speeds 500 rpm apart, as
    the studies of `harness reproduce`.

    Parameters
    ----------
    speed_range_rpm : (float, float)
        (low, high) [rpm], low < high, both inside the FMU's rotorSpeed range.
    model : str
        The contact model, as in `periodic_orbits`.
    fmu : str or pathlib.Path, optional
        Another FMU file (default `fmu_path()`).
    **parameters
        FMU parameters by name.

    Returns
    -------
    list of Branch
        Each branch's `.points` (speed, amplitude, stability), its located peaks and folds
        (`.extrema`) and why it ended (`.end_reasons`).

    Raises
    ------
    ParameterError
        A bad range, model or parameter, naming the value and the accepted range.
    """
    where = "harness.branch"
    _model(model, where)
    try:
        lo, hi = speed_range_rpm
    except (TypeError, ValueError):
        raise _error(
            f"speed_range_rpm = {speed_range_rpm!r} (from {where}(speed_range_rpm=...)) is not a pair (low, high)"
            " of speeds [rpm]"
        ) from None
    lo = _speed(lo, f"{where}(speed_range_rpm=(low, ...))", low_open=True, name="low")
    hi = _speed(hi, f"{where}(speed_range_rpm=(..., high))", low_open=True, name="high")
    if not lo < hi:
        raise _error(
            f"speed_range_rpm = {speed_range_rpm!r} rpm (from {where}(speed_range_rpm=...)): low must be < high"
        )
    params = _parameters(parameters, f"{where}(**parameters)")
    with BladeFMU(fmu) as blade:
        return trace_branches(blade, params, model, (lo, hi))[0]


def _ring_speed(speed: Any, where: str, name: str = "speed") -> None:
    """A ring speed [rpm] inside BladeExternalContact's rotorSpeed range (its model description)."""
    md = read_model_description(str(build_ring_fmus()[0]))
    rs = next(v for v in md.modelVariables if v.name == "rotorSpeed")
    lo, hi = float(rs.min), float(rs.max)
    v = _finite(name, speed, where)
    if not lo < v <= hi:
        raise _error(
            f"{name} = {speed!r} rpm (from {where}) is out of range; accepted: ({lo:g}, {hi:g}] rpm"
            " (BladeExternalContact's rotorSpeed)"
        )


def run_ring(ring: Ring, master: str = "c") -> dict[str, np.ndarray]:
    """Run the bladed-disk ring from rest.

    As `harness ring`.

    Parameters
    ----------
    ring : Ring
        n blades coupled by n shroud contacts, each blade loaded by its built-in travelling-wave
        load; its speed, step and stop time set the run.
    master : str
        One of RING_MASTERS: "c" (the communication loop in C) or "fmpy" (the same data flow in
        Python).

    Returns
    -------
    dict of str to numpy.ndarray
        "time" [s] and, per blade (columns), "q", "v", the energies "E" and "W", the contact forces
        "contactForce", "forceA", "forceB", the contacts' dissipated energy "Ec" and "state", at
        every communication point.

    Raises
    ------
    ParameterError
        A bad blade count, parameter, step, stop time, speed or master.
    RingDiverged
        A blade's |q| passed `ring.q_limit` (the Jacobi coupling blew up).
    """
    where = "harness.run_ring"
    if master not in RING_MASTERS:
        raise _error(f"master = {master!r} (from {where}(master=...)) is not one of {', '.join(RING_MASTERS)}")
    _check_ring(ring, where)
    t = _finite("stop_time", ring.stop_time, f"{where}(ring=Ring(stop_time=...))")
    h = _finite("step", ring.step, f"{where}(ring=Ring(step=...))")
    if not 0 < h <= t:
        raise _error(
            f"step = {ring.step!r} s (from {where}(ring=Ring(step=...))) is out of range; accepted:"
            f" (0, stop_time = {t:g}] s"
        )
    _ring_speed(ring.speed, f"{where}(ring=Ring(speed=...))")
    if master == "c":
        return ring_c.run(ring)
    return ring_run(ring)


def _check_ring(ring: Ring, where: str) -> None:
    """n and the FMU parameters of `ring` (as run_ring)."""
    nmax = ring_values.max_blades()
    if not (isinstance(ring.n, int) and not isinstance(ring.n, bool) and 2 <= ring.n <= nmax):
        raise _error(
            f"n = {ring.n!r} (from {where}(ring=Ring(n=...))) is out of range; accepted: [2, {nmax}] blades"
            " (the blade FMU's bladeCount)"
        )
    var = ring_values.settable()
    for kind, values in (("blade", ring.blade), ("contact", ring.contact)):
        for name, value in values.items():
            if name not in var[kind]:
                raise _error(
                    f"{name} (from {where}(ring=Ring({kind}=...))) is not a parameter of the {kind} FMU;"
                    f" known: {', '.join(sorted(var[kind]))}"
                )
            ring_values.typed(name, value, *var[kind][name], origin=f"{where}(ring=Ring({kind}=...))")


def ring_branches(
    ring: Ring,
    speed_range_rpm: tuple[float, float],
    seed_points: int | None = None,
    steps_per_period: int = 160,
    sweep_seeds_rpm: Sequence[float] | None = None,
) -> RingBranches:
    """The periodic steady states of the bladed-disk ring over a speed band.

    Every branch of periodic orbits of the co-simulation the sweeps run (the C loop, h = T /
    steps_per_period), traced by shooting and pseudo-arclength continuation in speed from every seed
    (the travelling wave of a tuned ring, runs from rest and a sweep of the period map up and down at
    `seed_points` speeds, the states of a C-loop sweep up and down at most 100 rpm apart where
    it leaves each speed, and 3 random starts per speed at most 100 rpm apart, seeded, so a run is
    repeatable), with branch switching at branch points and branches merged up to the ring's symmetries.

    Parameters
    ----------
    ring : harness.Ring
        The ring (its blades, contacts, load Fw0, engine order, extrapolation order); its speed,
        step and stop time are not used. Built-in load and the Jenkins contact (frictionModel 3).
    speed_range_rpm : (float, float)
        The band [rpm], FROM < TO inside BladeExternalContact's rotorSpeed range.
    seed_points : int, optional
        Speeds of the seeds across the band, 2..200 (default: at most 300 rpm apart, at least 4).
    steps_per_period : int, optional
        Communication steps per excitation period, 8..100000 (default 160, as the sweeps).
    sweep_seeds_rpm : sequence of float, optional
        The speeds [rpm] of a further C-loop sweep up and down (increasing, at least 2, each a ring
        speed; they may reach beyond the band) whose peak is located: the state at every speed it
        settles at inside the band, its peak refinement's included, is a seed first (what the
        mistuning study passes: its own sweep). Default: none.

    Returns
    -------
    RingBranches
        `.branches` (each with per-point `speeds`, per-blade `amplitudes` [m], `stable`, the
        multipliers and period residuals of its orbits, `bifurcations`), the largest stable steady
        state `.peak_stable_amplitude` [m] at `.peak_stable_speed` [rpm] on blade
        `.peak_stable_blade`, and `.as_dict()` (what `harness ring --branches --json` prints).

    Raises
    ------
    ParameterError
        A bad ring, band, seed count or step count, naming the value and the accepted range.
    """
    where = "harness.ring_branches"
    _check_ring(ring, where)
    try:
        lo, hi = (float(v) for v in speed_range_rpm)
    except (TypeError, ValueError):
        raise _error(
            f"speed_range_rpm = {speed_range_rpm!r} (from {where}(speed_range_rpm=...)): need two speeds FROM, TO [rpm]"
        ) from None
    _ring_speed(lo, f"{where}(speed_range_rpm=(FROM, ...))", "FROM")
    _ring_speed(hi, f"{where}(speed_range_rpm=(..., TO))", "TO")
    if not lo < hi:
        raise _error(
            f"speed_range_rpm = {speed_range_rpm!r} (from {where}(speed_range_rpm=...)): FROM must be below TO"
        )
    for name, v, a, b in (("seed_points", seed_points, 2, 200), ("steps_per_period", steps_per_period, 8, 100000)):
        if v is None and name == "seed_points":
            continue
        if not (isinstance(v, int) and not isinstance(v, bool) and a <= v <= b):
            raise _error(
                f"{name} = {v!r} (from {where}({name}=...)) is out of range; accepted: whole numbers in [{a}, {b}]"
            )
    sweeps: tuple[SweepPath, ...] = ()
    if sweep_seeds_rpm is not None:
        arg = f"{where}(sweep_seeds_rpm=...)"
        try:
            sp = [float(rpm) for rpm in sweep_seeds_rpm]
        except (TypeError, ValueError):
            raise _error(f"sweep_seeds_rpm = {sweep_seeds_rpm!r} (from {arg}): need speeds [rpm]") from None
        for rpm in sp:
            _ring_speed(rpm, arg, "sweep_seeds_rpm")
        if len(sp) < 2 or any(b <= a for a, b in zip(sp, sp[1:])):
            raise _error(f"sweep_seeds_rpm = {sp!r} (from {arg}): need at least 2 speeds, increasing")
        sweeps = (SweepPath(tuple(sp), refine=True),)
    return trace_ring_branches(
        ring,
        (lo, hi),
        points=seed_points,
        settings=RingShootingSettings(steps_per_period=steps_per_period),
        sweeps=sweeps,
    )
