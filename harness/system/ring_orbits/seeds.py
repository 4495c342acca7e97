"""Starting states for the ring's shooting: runs from rest and sweeps, on the period map itself.

A seed is the state at load phase 0 after the ring has run for a while; Newton then finds the orbit
near it. Both kinds iterate the period map, x_{k+1} = P(x_k) (the co-simulation run period by
period, the master's extrapolation history carried in the state), so their states sit at load
phase 0, where the shooting's unknowns live:
- from rest: x_0 = 0 at one speed (for the tuned ring the travelling wave wherever that is stable);
- a sweep: up from rest at the lowest speed, the state carried from speed to speed, then back down
  (harness/system/ring_sweep.py's path, so the same multistable states are reached);
- random starts: blade i at a_i cos(phi_i) with velocity -a_i omega sin(phi_i), a_i uniform in
  RANDOM_AMPLITUDES times a scale (the largest response the other seeds reached), phi_i uniform, the
  contacts' forces and the master's history zero, from numpy's default_rng([RANDOM_SEED, round(100 rpm)])
  (a speed's starts do not depend on the grid). Rest and sweeps reach the states whose basin holds
  rest or the neighbouring speed's state; a stable state whose basin holds neither (on the tuned study
  ring a family of asymmetric states at 6760-7240 rpm) is reached only from elsewhere.
At each speed the iteration stops when the scaled change per period is below `settle` (after at
least `min_periods`) or after `max_periods`. From an exactly symmetric start (rest) the tuned ring's
iteration stays on the travelling wave, stable or not (the sweeps' runs leave an unstable one,
their rounding breaks the symmetry and the wave's multiplier above 1 grows it): the runs from rest
and the sweeps start from rest with blade 0 moved by `kick` [m] (asymmetric); the travelling-wave
seed starts from rest exactly.

The sweeps' own settled states (`settled_states`): harness/system/ring_sweep.py's sweep up and down
(the C loop run on with the state carried, its settle rule; with its peak's refinement, whose speeds
count too), and where it leaves each speed the running ring is copied (fmi2GetFMUstate), advanced to
the next load phase 0 and read as x, then put back, so the sweep goes on undisturbed. The sweep runs
at each speed on the period map's own grid h = T / K aligned to the load (ring_sweep.align), so the
points at load phase 0 are grid points (the load phase psi the sweep passes, CRing.phase, tells how
many steps ahead) and the history there is the map's: the state is read exactly, and a seed's
`change`, its scaled period residual |P(x) - x| / scale, is small only if the state has settled.
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
    origin: str  # "travelling wave", "rest", "sweep up/down", "C-loop sweep up/down", "C-loop refinement up/down"
    speed: float  # [rpm]
    x: np.ndarray
    change: float  # scaled change over the last period


KICK = 1e-7  # [m] blade 0's start displacement in the asymmetric starts (1/300 of the gap d)
RANDOM_STARTS = 3  # per speed, 100 rpm apart (branches.RANDOM_SPACING): on the tuned study ring over
# 5000-7500 rpm the engine's missed stable states 49 -> 30 of 263 for 23 % more periods
# (docs/findings/ring-completeness.md)
RANDOM_AMPLITUDES = (0.2, 1.5)  # a random start's blade amplitudes, multiples of the scale
RANDOM_SEED = 2  # the completeness check draws its starts from another generator (seed 1)


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


def settle_all(
    pm: RingPeriodMap,
    starts: Sequence[tuple[np.ndarray, float]],
    settle_tol: float,
    max_periods: int,
    min_periods: int = 0,
) -> list[tuple[np.ndarray, float] | None]:
    """`settle` of every (x0, rpm) in `starts`, run side by side: each period of the runs not yet
    settled is one batch of the map's images (its threads). Each run's numbers are those of `settle`
    alone (an image is a function of x only); None for a run whose map fails."""
    x = [np.asarray(x0, dtype=float) for x0, _ in starts]
    done: list[tuple[np.ndarray, float] | None] = [(xi, np.inf) for xi in x] if max_periods < 1 else [None] * len(x)
    live = list(range(len(starts)))
    for k in range(max_periods):
        if not live:
            break
        images = _images(pm, [(x[i], float(starts[i][1])) for i in live])
        still = []
        for i, Px in zip(live, images):
            if Px is None:  # failed: left out, as `_settled_from` leaves it
                continue
            rpm = float(starts[i][1])
            change = float(np.max(np.abs(Px - x[i]) / pm.scales(Px, rpm)))
            x[i] = Px
            if (change < settle_tol and k + 1 >= min_periods) or k + 1 == max_periods:
                done[i] = (Px, change)
            else:
                still.append(i)
        live = still
    return done


def _images(pm: RingPeriodMap, points: list[tuple[np.ndarray, float]]) -> list[np.ndarray | None]:
    """pm.images of the points; where one fails, each in turn (the images before it are known: no
    period twice), None for those that fail."""
    try:
        return list(pm.images(points))
    except RingMapFailed:
        out: list[np.ndarray | None] = []
        for x, rpm in points:
            try:
                out.append(pm(x, rpm)[0])
            except RingMapFailed:
                out.append(None)
        return out


def travelling_wave(
    pm: RingPeriodMap, speeds: Sequence[float], settle_tol: float = 1e-3, max_periods: int = 300
) -> list[Seed]:
    """From rest exactly (the tuned ring stays on its travelling wave)."""
    return _settled_from(pm, np.zeros(pm.dim), "travelling wave", speeds, settle_tol, max_periods)


def from_rest(
    pm: RingPeriodMap, speeds: Sequence[float], settle_tol: float = 1e-3, max_periods: int = 300, min_periods: int = 60
) -> list[Seed]:
    return _settled_from(pm, kicked(pm), "rest", speeds, settle_tol, max_periods, min_periods)


def random_state(
    pm: RingPeriodMap, speed: float, rng: np.random.Generator, scale: float, amplitudes: tuple[float, float]
) -> np.ndarray:
    """A random start at `speed` [rpm] (module docstring), blade amplitudes uniform in amplitudes x scale [m]."""
    a = scale * rng.uniform(*amplitudes, pm.n)
    phi = rng.uniform(0.0, 2.0 * math.pi, pm.n)
    w = pm.omega(speed)
    q = np.zeros((pm.n, pm.m))
    v = np.zeros((pm.n, pm.m))
    q[:, 0], v[:, 0] = a * np.cos(phi), -a * w * np.sin(phi)
    return pm.state(q, v, np.zeros(pm.n))


def random_starts(
    pm: RingPeriodMap,
    speeds: Sequence[float],
    scale: float,
    settle_tol: float = 1e-3,
    max_periods: int = 300,
    min_periods: int = 60,
    per_speed: int = RANDOM_STARTS,
) -> list[Seed]:
    """`per_speed` random starts per speed (module docstring), each settled as a run from rest."""
    runs = []
    for s in speeds:
        rng = np.random.default_rng([RANDOM_SEED, round(100 * float(s))])
        runs += [(random_state(pm, float(s), rng, scale, RANDOM_AMPLITUDES), float(s)) for _ in range(per_speed)]
    labels = [f"random {k}" for _ in speeds for k in range(per_speed)]
    return _seeds(labels, runs, settle_all(pm, runs, settle_tol, max_periods, min_periods))


def _settled_from(
    pm: RingPeriodMap,
    x0: np.ndarray,
    label: str,
    speeds: Sequence[float],
    settle_tol: float,
    max_periods: int,
    *min_periods: int,
) -> list[Seed]:
    """A seed per speed: the map iterated from x0 until it settles (speeds where the map fails are left
    out), the speeds' runs side by side (`settle_all`)."""
    runs = [(x0, float(s)) for s in speeds]
    return _seeds([label] * len(runs), runs, settle_all(pm, runs, settle_tol, max_periods, *min_periods))


def _seeds(
    labels: list[str], runs: list[tuple[np.ndarray, float]], settled: list[tuple[np.ndarray, float] | None]
) -> list[Seed]:
    return [Seed(lb, s, r[0], r[1]) for lb, (_, s), r in zip(labels, runs, settled) if r is not None]


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

    def __call__(self, cr: CRing, direction: str, rpm: float, psi: float) -> None:
        K = self.pm.s.steps_per_period
        ahead = (-psi) % (2.0 * math.pi) * K / (2.0 * math.pi)  # steps to phase 0
        steps = round(ahead) % K
        if cr.setup.exactStep <= 0.0 or abs(ahead - round(ahead)) > 1e-6:
            raise RuntimeError(f"the sweep at {rpm:g} rpm is off the load-aligned grid ({ahead:.9g} steps to phase 0)")
        saved = cr.save()
        cr.advance(steps, rpm, finish=True, records=("q",))  # point k + steps pushed, not stepped: the state there
        self.states.append((direction, rpm, self.pm.read(cr)))
        cr.restore(saved)


@dataclass(frozen=True)
class SweepPath:
    """A C-loop sweep up and down `speeds` [rpm] (ring_sweep.sweep, "both") whose settled states are
    seeds: its settle rule (rtol, periods, max_time [s]) and, with `refine`, its located peak
    (speed_tol [rpm]), whose refinement's states are seeds too. The mistuning study passes its own
    sweep's, so that the state of every speed it settled at, its located peak's included, is a seed."""

    speeds: tuple[float, ...]
    rtol: float = 1e-4
    periods: int = 5
    max_time: float = 1.0
    refine: bool = False
    speed_tol: float = 1.0


def settled_states(pm: RingPeriodMap, ring: Ring, path: SweepPath) -> list[Seed]:
    """The states of the C-loop sweep `path` (at pm's steps per period) at load phase 0 where it
    leaves each speed, the refinement's speeds too (see the module docstring; origin "C-loop sweep
    up/down", "C-loop refinement up/down"); a state whose period map fails is left out."""
    hook = _AtPhaseZero(pm)
    sw = c_sweep(
        ring,
        path.speeds,
        "both",
        rtol=path.rtol,
        periods=path.periods,
        max_time=path.max_time,
        steps_per_period=pm.s.steps_per_period,
        refine=path.refine,
        speed_tol=path.speed_tol,
        on_settled=hook,
    )
    main = sum(len(a) for a in sw.amplitudes_m.values())  # the sweep's own speeds come first, then the refinement
    out = []
    for i, (d, s, x) in enumerate(hook.states):
        try:
            res = float(pm.measures(x, s)[1])
        except RingMapFailed:
            continue
        out.append(Seed(f"C-loop {'sweep' if i < main else 'refinement'} {d}", s, x, res))
    return out
