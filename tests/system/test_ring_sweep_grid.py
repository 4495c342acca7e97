"""The speed sweep's grid (harness/system/ring_sweep.py): at each speed the C loop steps on the period
map's exact grid h = T / K aligned to the load phase, so that its discrete system there is the period
map's (harness/system/ring_orbits/period_map.py). The load phase psi is tracked here on its own
(psi' = omega at each speed, from the ring's time where the sweep leaves each speed), not read from
CRing.phase nor from the phase the sweep passes its hook.

- a sweep up and down (the 4-blade ring at 5600, 6000, 6400 rpm): where it leaves each speed, the next
  load phase 0 is a grid point (within 1e-6 of a step); the period map of the sweep's state there
  equals the sweep's own state one period later within MAP_TOL of the scale (the same discrete
  system; not to zero because the blades integrate psi with their state and its rounding grows with
  the time run, while the map starts from psi = 0: measured 1.2e-11 at t = 0.075 s, 2.6e-10 at
  t = 0.33 s), and the settled state is a fixed point of the map within the settle rule's 1e-4
  (measured 2.6e-6..1.3e-5). On the earlier grid of whole nanoseconds the phase-0 point falls
  between grid points and the map misses the next period;
- from a phase off the grid (37 steps of 0.7 T / K at 5600 rpm), `align` at 6000 rpm makes one partial step onto
  the grid and the same identity holds (measured 3.2e-13); without the partial step (delta = 0) the grid is off the
  load's phase by a fraction of a step and it does not.
"""

from __future__ import annotations

import math
from dataclasses import replace

import numpy as np

from harness.system.ring import Ring
from harness.system.ring_c import CRing
from harness.system.ring_orbits.period_map import RingPeriodMap
from harness.system.ring_sweep import align, exact_step, period_step, sweep

SMALL = Ring(n=4, engine_order=3, fw0=300.0, blade={"c": 298.0}, order=2)
K = 160
MAP_TOL = 1e-9  # measured 3.2e-13 (t = 0.03 s)..2.6e-10 (t = 0.33 s): psi's rounding in the blades
SETTLE_RTOL = 1e-4  # the sweep's settle rule


def steps_to_phase_zero(psi: float) -> float:
    return (-psi) % (2.0 * math.pi) / (2.0 * math.pi / K)


def here_and_one_period_on(cr: CRing, pm: RingPeriodMap, steps: int, rpm: float) -> tuple[np.ndarray, np.ndarray]:
    """The ring's state (with its history) `steps` points on and K points after that; cr is left as it was."""
    saved = cr.save()
    cr.advance(steps, rpm)
    mid = cr.save()
    cr.advance(0, rpm, finish=True)
    x0 = pm.read(cr)
    cr.restore(mid)
    cr.advance(K, rpm)
    cr.advance(0, rpm, finish=True)
    x1 = pm.read(cr)
    cr.restore(saved)
    return x0, x1


def scaled(pm: RingPeriodMap, a: np.ndarray, b: np.ndarray, rpm: float) -> float:
    return float(np.max(np.abs(a - b) / pm.scales(b, rpm)))


def test_sweep_runs_the_period_maps_system():
    states = []
    with RingPeriodMap(SMALL) as pm:
        psi, t = [0.0], [0.0]

        def hook(cr: CRing, d: str, rpm: float, _: float) -> None:
            psi[0] = (psi[0] + pm.omega(rpm) * (cr.time(cr.k) - t[0])) % (2.0 * math.pi)  # since the last speed
            t[0] = cr.time(cr.k)
            ahead = steps_to_phase_zero(psi[0])
            states.append((d, rpm, ahead, *here_and_one_period_on(cr, pm, round(ahead) % K, rpm)))

        sw = sweep(SMALL, [5600.0, 6000.0, 6400.0], "both", refine=False, rtol=SETTLE_RTOL, on_settled=hook)
        assert all(s.all() for s in sw.settled.values())
        assert len(states) == 6
        for d, rpm, ahead, x0, x1 in states:
            assert abs(ahead - round(ahead)) <= 1e-6, (d, rpm, ahead)
            Px0 = pm(x0, rpm)[0]
            assert scaled(pm, Px0, x1, rpm) <= MAP_TOL, (d, rpm, scaled(pm, Px0, x1, rpm))
            assert scaled(pm, Px0, x0, rpm) <= SETTLE_RTOL, (d, rpm, scaled(pm, Px0, x0, rpm))


def test_align_steps_onto_the_load_phase_grid():
    first, rpm = 5600.0, 6000.0
    h0 = period_step(SMALL, first, K)
    with RingPeriodMap(SMALL) as pm, CRing(replace(SMALL, speed=first, step=h0, stop_time=h0)) as cr:
        cr.exact_grid(0.7 * exact_step(SMALL, first, K), 0.0)  # 37 steps: 25.9 slots of 2 pi / K
        cr.advance(37, first)
        psi = pm.omega(first) * cr.time(cr.k)
        assert abs(steps_to_phase_zero(psi) - round(steps_to_phase_zero(psi))) > 0.05  # off the 6000 rpm grid
        t_change = cr.time(cr.k)
        align(cr, rpm, K)
        cr.advance(2 * K, rpm)
        psi += pm.omega(rpm) * (cr.time(cr.k) - t_change)
        ahead = steps_to_phase_zero(psi)
        assert abs(ahead - round(ahead)) <= 1e-6, ahead
        x0, x1 = here_and_one_period_on(cr, pm, round(ahead) % K, rpm)
        assert scaled(pm, pm(x0, rpm)[0], x1, rpm) <= MAP_TOL
