"""Bifurcations of the ring's branches (harness/system/ring_orbits/crossings.py, continuation.py):
crossings detected beyond the multipliers' noise, located by bisection, and branch switching at a
pitchfork.

- detection: hand-made multiplier sequences (a real multiplier hovering within the noise band of
  +1, then leaving it) give exactly the crossings the hysteresis rule defines;
- switching: the tuned 4-blade ring at EO 2 (c = 298 N s/m2, Fw0 = 300 N/m, extrapolation order 2).
  Rotating it by one blade delays the load by half a period, which the sign change q -> -q undoes:
  R x = x with R moving blade i to i + 1 and negating its state (and the contacts' phi) is the
  travelling wave's symmetry (its asymmetry max |R x - x| / scale: rounding, <= 1e-9; measured
  1e-15). Traced from 5850 rpm over 5600-5900 rpm it loses stability going down through a real
  multiplier at +1 with the speed not turning; located by bisection (bracket <= ARC_TOL, the test
  function within 1e-2 of 0; measured 7e-5 at 5711.1 rpm). The orbits entered from it along the
  critical eigenvector must be genuine (period residual <= 1e-8; the shooting's tolerance is 1e-10)
  and break the symmetry (asymmetry above 1e-3; measured 3.4e-2): a pitchfork.
"""

from __future__ import annotations

import numpy as np

from harness.system.ring import Ring
from harness.system.ring_orbits.continuation import switch, trace
from harness.system.ring_orbits.crossings import ARC_TOL, NOISE, detect
from harness.system.ring_orbits.period_map import RingPeriodMap
from harness.system.ring_orbits.seeds import travelling_wave
from harness.system.ring_orbits.shooting import shoot

EO2 = Ring(n=4, engine_order=2, fw0=300.0, blade={"c": 298.0}, order=2)


def _mu(*real: float) -> np.ndarray:
    return np.array([complex(r) for r in real] + [0.3 + 0.4j, 0.3 - 0.4j])


def test_a_multiplier_hovering_at_one_is_no_crossing():
    h = 0.5 * NOISE
    hover = [_mu(0.9), _mu(1 + h), _mu(1 - h), _mu(1 + h), _mu(0.95)]
    assert detect(hover, "branch point") == []
    through = [_mu(0.9), _mu(1 + h), _mu(1 - h), _mu(1 + h), _mu(1.2), _mu(1 + h), _mu(0.8)]
    assert detect(through, "branch point") == [(0, 4), (4, 6)]
    # a second multiplier far above 1 does not hide the crossing of the first
    assert detect([_mu(3.0, 0.9), _mu(3.0, 1.1)], "branch point") == [(0, 1)]
    assert detect([_mu(3.0, 0.9), _mu(3.0, 1.1)], "Neimark-Sacker") == []


def _asymmetry(pm: RingPeriodMap, x: np.ndarray, speed: float) -> float:
    """max |R x - x| / scale, R: blade i -> i + 1 with q -> -q (and phi, the history's velocities and
    forces with it), the symmetry of the 4-blade ring at EO 2 (rotation by a blade = half a period's
    delay = the sign change)."""
    m2 = 2 * pm.m
    y, phi = x[: m2 * pm.n].reshape(pm.n, m2), pm.phi(x)
    past = np.vstack(pm.history(x))  # (2p, N)
    Rx = np.concatenate([-np.roll(y, 1, axis=0).ravel(), -np.roll(phi, 1), -np.roll(past, 1, axis=1).ravel()])
    return float(np.max(np.abs(Rx - x) / pm.scales(x, speed)))


def test_switching_at_a_pitchfork_finds_a_symmetry_broken_orbit():
    with RingPeriodMap(EO2) as pm:
        tw = travelling_wave(pm, [5850.0])[0]
        orb = shoot(pm, tw.x, tw.speed)
        assert orb is not None and _asymmetry(pm, orb.x, orb.speed) <= 1e-9, _asymmetry(pm, orb.x, orb.speed)
        br = trace(pm, orb, (5600.0, 5900.0))
        bps = [b for b in br.bifurcations if b.kind == "branch point" and b.vector is not None]
        assert bps, [(b.kind, b.speed) for b in br.bifurcations]
        assert any(b.located for b in bps), [(b.speed, b.bracket) for b in bps]
        found = []
        for b in bps:
            if b.located:  # bisected to ARC_TOL: a smooth crossing, the test function at its zero
                assert b.bracket <= ARC_TOL and abs(b.value) <= 1e-2, (b.speed, b.bracket, b.value)
            lo, hi = sorted((br.orbits[b.between[0]].speed, br.orbits[b.between[1]].speed))
            assert lo - 1e-6 <= b.speed <= hi + 1e-6, (b.speed, lo, hi)
            for g in switch(pm, br, b):
                new = shoot(pm, g.x, g.speed)
                if new is not None:
                    found.append(new)
        for o in found:
            assert o.residual <= 1e-8, o.residual
            assert pm.measures(o.x, o.speed)[1] <= 1e-8
        assert found
        spreads = [_asymmetry(pm, o.x, o.speed) for o in found]
        assert any(sp > 1e-3 for sp in spreads), spreads
