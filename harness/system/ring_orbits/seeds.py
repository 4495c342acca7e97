"""Starting states for the ring's shooting: runs from rest and sweeps, on the period map itself.

A seed is the state at load phase 0 after the ring has run for a while; Newton then finds the orbit
near it. Both kinds iterate the period map, x_{k+1} = P(x_k) (the co-simulation run period by
period, its extrapolation history restarted at every period start), so their states sit at load
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
"""
from __future__ import annotations

from dataclasses import dataclass
from typing import Sequence

import numpy as np

from harness.system.ring_orbits.period_map import RingMapFailed, RingPeriodMap


@dataclass
class Seed:
    origin: str  # "rest", "sweep up", "sweep down"
    speed: float  # [rpm]
    x: np.ndarray
    change: float  # scaled change over the last period


KICK = 1e-7  # [m] blade 0's start displacement in the asymmetric starts (1/300 of the gap d)


def settle(pm: RingPeriodMap, x: np.ndarray, rpm: float, settle: float, max_periods: int, min_periods: int = 0
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


def travelling_wave(pm: RingPeriodMap, speeds: Sequence[float], settle_tol: float = 1e-3, max_periods: int = 300
                    ) -> list[Seed]:
    """From rest exactly (the tuned ring stays on its travelling wave)."""
    out = []
    for s in speeds:
        try:
            x, ch = settle(pm, np.zeros(pm.dim), float(s), settle_tol, max_periods)
        except RingMapFailed:
            continue
        out.append(Seed("travelling wave", float(s), x, ch))
    return out


def from_rest(pm: RingPeriodMap, speeds: Sequence[float], settle_tol: float = 1e-3, max_periods: int = 300,
              min_periods: int = 60) -> list[Seed]:
    out = []
    for s in speeds:
        try:
            x, ch = settle(pm, kicked(pm), float(s), settle_tol, max_periods, min_periods)
        except RingMapFailed:
            continue
        out.append(Seed("rest", float(s), x, ch))
    return out


def sweep(pm: RingPeriodMap, speeds: Sequence[float], settle_tol: float = 1e-3, max_periods: int = 300,
          min_periods: int = 60) -> list[Seed]:
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
