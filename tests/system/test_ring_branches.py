"""Bifurcations of the ring's branches (harness/system/ring_orbits/crossings.py, continuation.py):
crossings detected beyond the multipliers' noise, located by Brent's method, and branch switching
at a pitchfork; the reuse of DPs and the quasi-Newton corrector the continuation's speed rests on.

- detection: hand-made multiplier sequences (a real multiplier hovering within the noise band of
  +1, then leaving it) give exactly the crossings the hysteresis rule defines;
- switching: the tuned 4-blade ring at EO 2 (c = 298 N s/m2, Fw0 = 300 N/m, extrapolation order 2).
  Rotating it by one blade delays the load by half a period, which the sign change q -> -q undoes:
  R x = x with R moving blade i to i + 1 and negating its state (and the contacts' phi) is the
  travelling wave's symmetry (its asymmetry max |R x - x| / scale: rounding, <= 1e-9; measured
  1e-15). Traced from 5850 rpm over 5600-5900 rpm it loses stability going down through a real
  multiplier at +1 with the speed not turning; located (bracket <= ARC_TOL, the test function within
  1e-2 of 0; measured 4.5e-7 at 5711.09 rpm) where a plain bisection written here puts it. The orbits
  entered from it along the critical eigenvector must be genuine (period residual <= 1e-8; the
  shooting's tolerance is 1e-10) and break the symmetry (asymmetry above 1e-3; measured 3.4e-2): a
  pitchfork.
- reuse: a DP is reused only at the point it was taken (the memo), and the corrector quasi-Newton
  from a reused (or a deliberately wrong) Jacobian ends where Newton with fresh ones does, or fails;
  with a fresh start it ignores the Jacobian given (bit for bit the same from a wrong one).
"""

from __future__ import annotations

import numpy as np
import pytest

from harness.analysis.periodic.continuation import SPEED_SCALE, BranchProblem, correct
from harness.analysis.periodic.shooting import multipliers
from harness.system.ring import Ring
from harness.system.ring_orbits.continuation import RING_CONTINUATION, switch, trace
from harness.system.ring_orbits.crossings import ARC_TOL, JUMP, NOISE, critical_value, detect, estimator
from harness.system.ring_orbits.period_map import RingPeriodMap
from harness.system.ring_orbits.seeds import travelling_wave
from harness.system.ring_orbits.shooting import jacobians, monodromy, shoot

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


@pytest.fixture(scope="module")
def pitchfork():
    """The EO 2 ring's travelling wave traced from 5850 rpm over 5600-5900 rpm: (map, branch)."""
    with RingPeriodMap(EO2) as pm:
        tw = travelling_wave(pm, [5850.0])[0]
        orb = shoot(pm, tw.x, tw.speed)
        assert orb is not None and _asymmetry(pm, orb.x, orb.speed) <= 1e-9, _asymmetry(pm, orb.x, orb.speed)
        yield pm, trace(pm, orb, (5600.0, 5900.0))


def test_switching_at_a_pitchfork_finds_a_symmetry_broken_orbit(pitchfork):
    pm, br = pitchfork
    bps = [b for b in br.bifurcations if b.kind == "branch point" and b.vector is not None]
    assert bps, [(b.kind, b.speed) for b in br.bifurcations]
    assert any(b.located for b in bps), [(b.speed, b.bracket) for b in bps]
    found = []
    for b in bps:
        if b.located:  # located to ARC_TOL: a smooth crossing, the test function at its zero
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


def _bisected(pm: RingPeriodMap, a, b, kind: str) -> float:
    """The speed [rpm] of the crossing of `kind` between branch points a and b by plain bisection of
    the chord fraction on the sign of the test function, each fraction solved by the corrector with
    a fresh Jacobian per iteration and its multipliers from a fresh DP, to a bracket of ARC_TOL / 4."""
    prob = BranchProblem(pm, pm.scales(a.x, a.speed))
    prob.memo = None
    za, zb = prob.to_z(a.x, a.speed), prob.to_z(b.x, b.speed)
    chord = zb - za
    length = float(np.linalg.norm(chord))
    Hz, Px, _ = prob.H(za)
    Jz = prob.jac(za, Hz, Px)[0]
    lo, hi, glo, speed = 0.0, 1.0, critical_value(a.multipliers, kind), a.speed
    while (hi - lo) * length > 0.25 * ARC_TOL:
        f = 0.5 * (lo + hi)
        z, Hz, Px, _, _ = correct(prob, za + f * chord, chord / length, Jz, RING_CONTINUATION, quasi=False)
        g = critical_value(multipliers(prob.jac(z, Hz, Px)[1]), kind)
        lo, hi, glo = (f, hi, g) if g * glo > 0.0 else (lo, f, glo)
        speed = prob.from_z(z)[1]
    return speed


def test_located_crossing_agrees_with_plain_bisection(pitchfork):
    """Every smooth crossing located by Brent's method (crossings.locate) lies where a plain
    bisection (to a quarter of the tolerance) puts it: within the two brackets, (1 + 1/4) ARC_TOL of
    scaled arc, at most 0.125 rpm (measured: 0.0045 rpm at 5711.09 rpm)."""
    pm, br = pitchfork
    smooth = [b for b in br.bifurcations if b.kind != "fold" and b.located and not abs(b.value) > JUMP]
    assert smooth, [(b.kind, b.speed, b.located, b.value) for b in br.bifurcations]
    for b in smooth:
        ref = _bisected(pm, br.orbits[b.index - 1], br.orbits[b.index], b.kind)
        assert abs(b.speed - ref) <= 1.25 * ARC_TOL * SPEED_SCALE, (b.speed, ref)


def test_a_dp_is_reused_only_at_its_own_point(pitchfork):
    """The map's memo of DPs (continuation.JacobianMemo) gives a branch problem in other scaled
    coordinates the DP taken at the same point (a fresh one there agrees to 3e-8 of its largest
    entry: the rounding of the round trip; measured 3.2e-9) and nothing at a point 1e-9 (relative)
    away."""
    pm, br = pitchfork
    o = br.orbits[len(br.orbits) // 2]
    memo = jacobians(pm)
    DP = monodromy(pm, o.x, o.speed)
    prob = BranchProblem(pm, 3.0 * pm.scales(o.x, o.speed))
    z = prob.to_z(o.x, o.speed)
    Hz, Px, _ = prob.H(z)
    e = pm.evaluations
    Jz, DPm = prob.jac(z, Hz, Px)
    assert pm.evaluations - e <= 1  # at most the speed column (dP/dn) was taken
    prob.memo = None
    Jf, DPf = prob.jac(z, Hz, Px)
    assert np.max(np.abs(DPm - DPf)) <= 3e-8 * np.max(np.abs(DPf)), np.max(np.abs(DPm - DPf))
    assert np.max(np.abs(Jz - Jf)) <= 3e-8 * np.max(np.abs(Jf)), np.max(np.abs(Jz - Jf))
    assert np.array_equal(memo.get(o.x, o.speed)[0], DP)
    assert memo.get(o.x * (1.0 + 1e-9), o.speed) is None and memo.get(o.x, o.speed * (1.0 + 1e-9)) is None


def test_broyden_corrector_reaches_full_newtons_point(pitchfork):
    """The continuation's corrector, quasi-Newton from the last point's Jacobian (one period per
    iteration), ends where Newton with a fresh Jacobian per iteration does (both to the corrector's
    tolerance 1e-9 of scaled residual: the points agree to 1e-8 of scaled arc, measured 1.3e-9); from a
    deliberately wrong Jacobian (a column doubled, the speed column reversed) it either fails (the
    step is refused and halved) or ends on the same point: it accepts a point only on its residual,
    evaluated afresh (re-run here with the map's cache cleared: at most 1e-9)."""
    pm, br = pitchfork
    for o in br.orbits[:: max(1, len(br.orbits) // 4)]:
        prob = BranchProblem(pm, pm.scales(o.x, o.speed))
        z = prob.to_z(o.x, o.speed)
        Hz, Px, _ = prob.H(z)
        Jz = prob.jac(z, Hz, Px)[0]
        _, _, Vt = np.linalg.svd(Jz)
        t = Vt[-1] / np.linalg.norm(Vt[-1])
        zp = z + 0.02 * t
        quasi = correct(prob, zp, t, Jz, RING_CONTINUATION, quasi=True)
        full = correct(prob, zp, t, Jz, RING_CONTINUATION, quasi=False)
        assert quasi is not None and full is not None
        assert np.max(np.abs(quasi[0] - full[0])) <= 1e-8, np.max(np.abs(quasi[0] - full[0]))
        for column, factor in ((0, 2.0), (-1, -1.0)):
            J = Jz.copy()
            J[:, column] *= factor
            done = correct(prob, zp, t, J, RING_CONTINUATION, quasi=True)
            if done is None:
                continue
            assert np.max(np.abs(done[0] - full[0])) <= 1e-8, np.max(np.abs(done[0] - full[0]))
            pm.seen.clear()
            assert np.max(np.abs(prob.H(done[0])[0])) <= 1e-9
        # fresh_start (the crossings' second try): the Jacobian given is not used, a fresh one at zp
        # is: from the right one and from a wrong one the same iterates bit for bit (no memo: both
        # take it by finite differences), ending on Newton's point
        wrong = Jz.copy()
        wrong[:, 0] *= 2.0
        prob.memo = None
        fresh = [correct(prob, zp, t, J, RING_CONTINUATION, quasi=True, fresh_start=True) for J in (Jz, wrong)]
        assert fresh[0] is not None and fresh[1] is not None
        assert np.array_equal(fresh[0][0], fresh[1][0]) and fresh[0][4] == fresh[1][4]
        assert np.max(np.abs(fresh[0][0] - full[0])) <= 1e-8, np.max(np.abs(fresh[0][0] - full[0]))


def test_estimated_test_function_is_the_multipliers_to_first_order(pitchfork):
    """crossings.estimator (k directional derivatives instead of a DP): at the orbit whose DP it was
    built from it gives that orbit's test function within 1e-5 (the finite differences; measured
    5e-7); at the next point of the branch, where a multiplier of the kind is within 0.5 of the
    circle at both, within half the test function's change between the two (second order in the
    change of DP; measured 23 % over a step of 83 rpm through the pitchfork), and the
    Neimark-Sacker pair's within 1e-6 (measured 7e-10)."""
    pm, br = pitchfork
    checked = 0
    for a, b in zip(br.orbits[:-1], br.orbits[1:]):
        for kind in ("branch point", "Neimark-Sacker"):
            ga, gb = critical_value(a.multipliers, kind), critical_value(b.multipliers, kind)
            if not (np.isfinite(ga) and np.isfinite(gb)) or max(abs(ga), abs(gb)) > 0.5:
                continue  # no multiplier of the kind near the circle at both: another one may be the critical one
            est = estimator(pm, monodromy(pm, a.x, a.speed), kind)
            assert abs(est(a.x, pm(a.x, a.speed)[0], a.speed) - ga) <= 1e-5
            err = abs(est(b.x, pm(b.x, b.speed)[0], b.speed) - gb)
            assert err <= (0.5 * abs(gb - ga) if kind == "branch point" else 1e-6), (kind, a.speed, err, gb - ga)
            checked += 1
    assert checked >= 3
