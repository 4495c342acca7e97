"""Starting states for the ring's shooting: runs from rest and sweeps, on the period map itself.

A seed is the state at load phase 0 after the ring has run for a while; Newton then finds the orbit
near it. Both kinds iterate the period map, x_{k+1} = P(x_k) (the co-simulation run period by
period, the master's extrapolation history carried in the state), so their states sit at load
phase 0, where the shooting's unknowns live:
- from rest: x_0 = 0 at one speed (for the tuned ring the travelling wave wherever that is stable);
- a sweep: up from rest at the lowest speed, the state carried from speed to speed, then back down
  (harness/system/ring_sweep.py's path, so the same multistable states are reached).
At each speed the iteration stops when the scaled change per period is below `settle` (after at
least `min_periods`) or after `max_periods`. From an exactly symmetric start (rest) the tuned ring's
iteration stays on the travelling wave, stable or not (the sweeps' runs leave an unstable one,
their rounding breaks the symmetry and the wave's multiplier above 1 grows it): the runs from rest
and the sweeps start from rest with blade 0 moved by `kick` [m] (asymmetric); the travelling-wave
seed starts from rest exactly.

The sweeps' own settled states (`settled_states`): harness/system/ring_sweep.py's sweep up and down
(the C loop run on with the state carried, its settle rule), and where it leaves each speed the
running ring is copied (fmi2GetFMUstate), advanced to the next load phase 0 and read as x, then put
back, so the sweep goes on undisturbed. The sweep runs at each speed on the period map's own grid
h = T / K aligned to the load (ring_sweep.align), so the points at load phase 0 are grid points
(CRing.phase tells how many steps ahead) and the history there is the map's: the state read is
exact, and a settled state's `change`, its scaled period residual |P(x) - x| / scale, is the
settle rule's own bound.
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from typing import Sequence

import numpy as np

from harness.system.ring import Ring
from harness.system.ring_c import CRing
from harness.system.ring_orbits.period_map import RingMapFailed, RingPeriodMap
from harness.system.ring_sweep import sweep as c_sweep


@dataclass
class Seed:
    origin: str  # "travelling wave", "rest", "sweep up", "sweep down", "C-loop sweep up", "C-loop sweep down"
    speed: float  # [rpm]
    x: np.ndarray
    change: float  # scaled change over the last period


KICK = 1e-7  # [m] blade 0's start displacement in the asymmetric starts (1/300 of the gap d)


def settle(
    pm: RingPeriodMap, x: np.ndarray, rpm: float, settle: float, max_periods: int, min_periods: int = 0
) -> tuple[np.ndarray, float]:
    """Iterates P at rpm from x until the scaled change per period is below `settle`."""
    change = np.inf
    for k in range(max_periods):
        Px = pm(x, rpm)[0]
        change = float(np.max(np.abs(Px - x) / pm.scales(Px, rpm)))
        x = Px
        if change < settle and k + 1 >= min_periods:
            break
    return x, change


def kicked(pm: RingPeriodMap, kick: float = KICK) -> np.ndarray:
    """Rest, with blade 0's first modal displacement at `kick` [m]."""
    x = np.zeros(pm.dim)
    x[0] = kick
    return x


def travelling_wave(
    pm: RingPeriodMap, speeds: Sequence[float], settle_tol: float = 1e-3, max_periods: int = 300
) -> list[Seed]:
    """From rest exactly (the tuned ring stays on its travelling wave)."""
    return _settled_from(pm, np.zeros(pm.dim), "travelling wave", speeds, settle_tol, max_periods)


def from_rest(
    pm: RingPeriodMap, speeds: Sequence[float], settle_tol: float = 1e-3, max_periods: int = 300, min_periods: int = 60
) -> list[Seed]:
    return _settled_from(pm, kicked(pm), "rest", speeds, settle_tol, max_periods, min_periods)


def _settled_from(
    pm: RingPeriodMap,
    x0: np.ndarray,
    label: str,
    speeds: Sequence[float],
    settle_tol: float,
    max_periods: int,
    *min_periods: int,
) -> list[Seed]:
    """A seed per speed: the map iterated from x0 until it settles (speeds where the map fails are left out)."""
    out = []
    for s in speeds:
        try:
            x, ch = settle(pm, x0, float(s), settle_tol, max_periods, *min_periods)
        except RingMapFailed:
            continue
        out.append(Seed(label, float(s), x, ch))
    return out


def sweep(
    pm: RingPeriodMap, speeds: Sequence[float], settle_tol: float = 1e-3, max_periods: int = 300, min_periods: int = 60
) -> list[Seed]:
    """Up from rest at the lowest speed, then down from the highest: a seed per speed and direction."""
    sp = sorted(float(s) for s in speeds)
    out = []
    x = kicked(pm)
    for origin, path in (("sweep up", sp), ("sweep down", sp[::-1][1:])):
        for k, s in enumerate(path):
            try:
                x, ch = settle(pm, x, s, settle_tol, max_periods, min_periods if k == 0 and origin == "sweep up" else 0)
            except RingMapFailed:
                x = kicked(pm)
                continue
            out.append(Seed(origin, s, x.copy(), ch))
    return out


class _AtPhaseZero:
    """on_settled hook of ring_sweep.sweep: the ring's state at the next load phase 0 per speed."""

    def __init__(self, pm: RingPeriodMap):
        self.pm = pm
        self.states: list[tuple[str, float, np.ndarray]] = []

    def __call__(self, cr: CRing, direction: str, rpm: float, spent: float) -> None:
        K = self.pm.s.steps_per_period
        ahead = (-cr.phase) % (2.0 * math.pi) * K / (2.0 * math.pi)  # steps to phase 0
        steps = round(ahead) % K
        if cr.setup.exactStep <= 0.0 or abs(ahead - round(ahead)) > 1e-6:
            raise RuntimeError(
                f"the sweep at {rpm:g} rpm is not on the load-aligned grid ({ahead:.9g} steps to phase 0)"
            )
        saved = cr.save()
        cr.advance(steps, rpm, finish=True)  # point k + steps pushed, not stepped: the state there
        self.states.append((direction, rpm, self.pm.read(cr)))
        cr.restore(saved)


def settled_states(
    pm: RingPeriodMap, ring: Ring, speeds: Sequence[float], rtol: float = 1e-4, periods: int = 5, max_time: float = 1.0
) -> list[Seed]:
    """The states of a C-loop sweep up and down `speeds` (ring_sweep.sweep, "both", its settle rule
    rtol / periods / max_time, pm's steps per period) at load phase 0 where it leaves each speed (see
    the module docstring); a state whose period map fails is left out."""
    hook = _AtPhaseZero(pm)
    c_sweep(
        ring,
        speeds,
        "both",
        rtol=rtol,
        periods=periods,
        max_time=max_time,
        steps_per_period=pm.s.steps_per_period,
        refine=False,
        on_settled=hook,
    )
    out = []
    for d, s, x in hook.states:
        try:
            res = float(pm.measures(x, s)[1])
        except RingMapFailed:
            continue
        out.append(Seed(f"C-loop sweep {d}", s, x, res))
    return out
