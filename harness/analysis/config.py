"""Sweep configuration: what a sweep computes and how, validated completely before any work.

`SweepSettings` holds the numerical settings of every point (they enter the cache keys),
`SweepSpec` one response curve (parameters, coarse speed grid, directions, methods). `validate_spec`
checks everything (parameters through harness.model.params, speeds, methods, settings, the input Taylor
error) and raises `ConfigError` (a ParameterError: the CLI prints it as one line) naming the value.
"""

from __future__ import annotations

import math
from dataclasses import dataclass, replace
from typing import Any, Mapping, Sequence

import numpy as np

from harness.model import params as _params
from harness.fmu.blade import INPUT_FITS, SPEED_RANGE, input_error

MAX_RPM = SPEED_RANGE[1]  # highest rotorSpeed the FMU accepts [rpm]
DIRECTIONS = ("up", "down")
METHODS = ("time", "fixed", "hb")
ALGO_VERSION = 3  # bump when a change alters cached point results


class ConfigError(_params.ParameterError):
    """A sweep/study configuration value is not acceptable; the message names it."""


@dataclass(frozen=True)
class SweepSettings:
    """How each point is computed (all of it enters the cache key of a point)."""

    steps_per_period: int = 2  # communication steps per excitation period (analyze() works on any
    # whole number of raw samples per period, comparing the state (q, q') period to period)
    derivative_order: int = 8  # input derivative order set per step (0 = held inputs)
    input_fit: str = "chebyshev"  # load polynomial per step (harness.fmu.blade.step_inputs): at 2 steps per
    # period the degree-8 Chebyshev interpolant is within 6e-7 of the sine (Taylor: 8e-2)
    rtol: float = 1e-3  # steady-state tolerance: estimated relative distance from the periodic limit
    min_periods: int = 3  # converged periods needed
    chunk_periods: int = 400  # most periods simulated between two steady-state decisions
    max_time: float = 1.0  # cap of simulated time per plateau [s] (see `extend`)
    extend: float = 2.5  # a plateau / A(B) run still converging at its cap (fitted decay, rtol reached
    # in time by prediction) may go on to extend x cap: contact-free plateaus carried from a neighbour
    # need ~tau ln(0.3/rtol) = 1.3 s at rtol 1e-3 (tau = 2M/C0 = 0.22 s); irregular ones stop at the cap
    # grid refinement (time-domain sweeps)
    refine_levels: int = 4  # bisection rounds
    refine_tol: float = 0.08  # refine where |dA| > refine_tol * max A of the curve
    min_dn: float = 15.0  # smallest speed interval produced by bisection [rpm]
    agree_tol: float = 0.02  # chain repair stops when a recomputed point agrees within this
    # fixed point
    n_scan: int = 12  # B values scanned over (d, B_max]
    B_max: float | None = None  # [m]; None: 1.5 x the linear bound G Fw0 / (C0 omega)
    fixed_max_time: float = 0.6  # cap per A(B) evaluation [s] (contact damping settles it fast)

    def plateau_key(self) -> dict:
        return {
            k: getattr(self, k)
            for k in (
                "steps_per_period",
                "derivative_order",
                "input_fit",
                "rtol",
                "min_periods",
                "chunk_periods",
                "max_time",
                "extend",
            )
        }

    def fixed_key(self) -> dict:
        return {
            k: getattr(self, k)
            for k in (
                "steps_per_period",
                "derivative_order",
                "input_fit",
                "rtol",
                "min_periods",
                "chunk_periods",
                "fixed_max_time",
                "extend",
            )
        }


@dataclass(frozen=True)
class SweepSpec:
    """One response curve: a parameter set, a coarse speed grid, directions and methods."""

    params: Mapping[str, Any]
    speeds: Sequence[float]  # coarse grid [rpm]
    label: str = ""
    directions: Sequence[str] = DIRECTIONS
    methods: Sequence[str] = ("time", "hb")
    fixed_speeds: Sequence[float] | None = None  # speeds for `fixed` (default: `speeds`)
    hb_speeds: Sequence[float] | None = None  # speeds for `hb` (default: 200 over the range)
    settings: SweepSettings = SweepSettings()


def _num(
    name: str,
    value: Any,
    low: float | None = None,
    high: float | None = None,
    low_open: bool = False,
    integer: bool = False,
) -> float:
    try:
        v = float(value)
    except (TypeError, ValueError):
        raise ConfigError(f"{name} = {value!r} is not a number") from None
    if not math.isfinite(v):
        raise ConfigError(f"{name} = {value!r} is not finite")
    if integer and not v.is_integer():
        raise ConfigError(f"{name} = {value!r} must be an integer")
    if low is not None and (v < low or (low_open and v == low)):
        raise ConfigError(f"{name} = {value!r} must be {'>' if low_open else '>='} {low:g}")
    if high is not None and v > high:
        raise ConfigError(f"{name} = {value!r} must be <= {high:g}")
    return v


def _check_speeds(name: str, speeds: Any, label: str, at_least: int = 1) -> tuple[float, ...]:
    try:
        vals = [float(s) for s in speeds]
    except (TypeError, ValueError):
        raise ConfigError(f"{label}{name} = {speeds!r} must be a list of speeds in rpm") from None
    for s in vals:
        if not math.isfinite(s) or not 0 < s <= MAX_RPM:
            raise ConfigError(f"{label}{name} contains {s!r} rpm: every speed must be in (0, {MAX_RPM:g}] rpm")
    out = tuple(sorted(set(vals)))
    if len(out) < at_least:
        raise ConfigError(f"{label}{name} has {len(out)} distinct speed(s); a sweep needs at least {at_least}")
    return out


def validate_settings(s: SweepSettings) -> SweepSettings:
    # >= 2: one step per period leaves a load error of 3e-4 (Chebyshev) whose 3rd harmonic can hit
    # the first bending mode (1550 rpm: 1.6 % of the response); at 2 steps it is 6e-7
    _num("steps_per_period", s.steps_per_period, 2, 4096, integer=True)
    _num("derivative_order", s.derivative_order, 0, 8, integer=True)
    _num("rtol", s.rtol, 0, 0.1, low_open=True)
    _num("min_periods", s.min_periods, 1, 1000, integer=True)
    _num("chunk_periods", s.chunk_periods, 1, 100000, integer=True)
    _num("max_time", s.max_time, 0, 1e4, low_open=True)
    _num("extend", s.extend, 1, 100)
    _num("refine_levels", s.refine_levels, 0, 20, integer=True)
    _num("refine_tol", s.refine_tol, 0, 1, low_open=True)
    _num("min_dn", s.min_dn, 0, MAX_RPM, low_open=True)
    _num("agree_tol", s.agree_tol, 0, 1, low_open=True)
    _num("n_scan", s.n_scan, 3, 10000, integer=True)
    _num("fixed_max_time", s.fixed_max_time, 0, 1e4, low_open=True)
    if s.B_max is not None:
        _num("B_max", s.B_max, 0, 1.0, low_open=True)
    if s.input_fit not in INPUT_FITS:
        raise ConfigError(f"input_fit = {s.input_fit!r}: choose from {', '.join(INPUT_FITS)}")
    # The load over a step is a polynomial of the derivative order (harness.fmu.blade.input_error): order
    # 8 Taylor 1.6e-4 at 4 steps per period, 2e-3 at 3; order 8 Chebyshev 6e-7 at 2, 3e-4 at 1.
    err = input_error(2 * math.pi / s.steps_per_period, int(s.derivative_order), s.input_fit)
    if err > 1e-3:
        raise ConfigError(
            f"steps_per_period = {s.steps_per_period} with derivative_order = "
            f"{s.derivative_order} ({s.input_fit}) misrepresents the load (error {err:.2g} > 1e-3): "
            "use more steps per period or derivative order 8"
        )
    return s


def validate_spec(spec: SweepSpec) -> SweepSpec:
    """Check everything before any work starts; returns a normalised copy. Raises ConfigError or
    ParameterError naming the bad value."""
    label = f"{spec.label}: " if spec.label else ""
    p = _params.validate(spec.params, source=spec.label or "sweep configuration")
    if p["engineOrder"] < 1:
        raise ConfigError(f"{label}engineOrder = {p['engineOrder']} must be >= 1")
    methods = tuple(spec.methods)
    for m in methods:
        if m not in METHODS:
            raise ConfigError(f"{label}method {m!r} is unknown; choose from {', '.join(METHODS)}")
    if not methods:
        raise ConfigError(f"{label}no method given; choose from {', '.join(METHODS)}")
    dirs = tuple(spec.directions)
    for d in dirs:
        if d not in DIRECTIONS:
            raise ConfigError(f"{label}direction {d!r} is unknown; choose from up, down")
    if "time" in methods and not dirs:
        raise ConfigError(f"{label}a time-domain sweep needs a direction (up, down)")
    speeds = _check_speeds("speeds", spec.speeds, label, at_least=2 if "time" in methods else 1)
    fixed = None if spec.fixed_speeds is None else _check_speeds("fixed_speeds", spec.fixed_speeds, label)
    hb = None if spec.hb_speeds is None else _check_speeds("hb_speeds", spec.hb_speeds, label)
    settings = validate_settings(spec.settings)
    return replace(
        spec,
        params=p,
        speeds=speeds,
        directions=dirs,
        methods=methods,
        fixed_speeds=fixed,
        hb_speeds=hb,
        settings=settings,
    )


def parse_speed_range(text: str) -> tuple[float, ...]:
    """'2000:10000:250' (start:stop:step, stop included) or '3000,5000,7000' -> speeds [rpm]."""
    try:
        if ":" in text:
            a, b, c = (float(x) for x in text.split(":"))
            if not (c > 0 and b >= a):
                raise ValueError
            n = int(math.floor((b - a) / c + 1e-9))
            return tuple(a + c * np.arange(n + 1))
        return tuple(float(x) for x in text.split(",") if x.strip())
    except ValueError:
        raise ConfigError(
            f"speed range {text!r}: use start:stop:step (e.g. 2000:10000:250) or a "
            "comma list (e.g. 3000,5000,7000), in rpm"
        ) from None
