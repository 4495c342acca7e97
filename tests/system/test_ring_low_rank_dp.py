"""The ring's "low-rank" DP (harness/system/ring_orbits/derivative.py) against the full forward
differences (one period per unknown), on 4-blade rings of the study's blades (EO 3, c = 298 N s/m2,
extrapolation order 2): the tuned ring (Fw0 = 300 N/m; at 8000 rpm two of its contacts stick at
phase 0), a looser one (Fw0 = 100 N/m; its travelling wave at 6000 rpm is unstable, |mu| 3.9) and a
mistuned one (EI scattered by +-2 %), and the EO 2 ring whose travelling wave loses stability at a
pitchfork near 5711 rpm.

Checks and tolerances (DP differences in the scaled unknowns, S^-1 DP S, relative to the full DP's
largest singular value; multipliers: every full multiplier's distance to the nearest low-rank one):
- at orbits (stable and unstable, tuned, loose and mistuned, with sticking contacts) with the basis
  of two DPs taken 50 and 100 rpm below on the same branch: DP within DP_TOL of the full one
  (measured max 3.6e-6), multipliers within MU_TOL (measured max 6.5e-7);
- at the orbit whose full DP gave the basis the check passes (a low-rank DP, not the fallbacks);
- a stale basis is detected and falls back: one from another ring (EO 2) and one from 6000 rpm,
  where every contact was open at phase 0 (no phi acted), used at 8000 rpm where two stick: the DP still equals the full one;
  with the check switched off the first gives a DP off by more than 100 DP_TOL (so the check is what
  keeps it right);
- a branch traced with "low-rank" (EO 2 ring, 5600-5900 rpm) has the same largest stable state
  (amplitude within 1e-6, speed within 0.5 rpm: the located peak's tolerance) and the same
  bifurcation kinds, the branch point within 0.5 rpm (measured: 2e-9 relative, 1e-8 rpm, 5e-5 rpm;
  52.6 periods per point instead of 66.4), with low-rank DPs among its DPs;
- a low-rank DP is kept in the map's memo and found again at its point without a period;
- invalid `dp` values are refused naming the value and the accepted ones.
"""

from __future__ import annotations

import numpy as np
import pytest

from harness.analysis.periodic.continuation import BranchProblem
from harness.analysis.periodic.shooting import multipliers
from harness.studies.mistuning import mistuned
from harness.system.ring import Ring
from harness.system.ring_orbits import derivative
from harness.system.ring_orbits.continuation import trace
from harness.system.ring_orbits.derivative import forward_differences
from harness.system.ring_orbits.period_map import RingPeriodMap, RingShootingSettings
from harness.system.ring_orbits.seeds import from_rest, travelling_wave
from harness.system.ring_orbits.shooting import jacobians, monodromy, shoot

DP_TOL = 3e-5  # measured max 3.6e-6 (the forward differences' own spread: 1.9e-6 against central ones)
MU_TOL = 1e-5  # measured max 6.5e-7
LOW = RingShootingSettings(dp="low-rank")
TUNED = Ring(n=4, engine_order=3, fw0=300.0, blade={"c": 298.0}, order=2)
LOOSE = Ring(n=4, engine_order=3, fw0=100.0, blade={"c": 298.0}, order=2)
MISTUNED = mistuned(TUNED, "EI", (1.0, 1.02, 0.98, 1.01))
EO2 = Ring(n=4, engine_order=2, fw0=300.0, blade={"c": 298.0}, order=2)


def _orbit(pm: RingPeriodMap, seed: str, rpm: float):
    sd = (travelling_wave if seed == "wave" else from_rest)(pm, [rpm])[0]
    o = shoot(pm, sd.x, rpm)
    assert o is not None, (seed, rpm)
    return o


def _full(pm: RingPeriodMap, o) -> tuple[np.ndarray, np.ndarray]:
    Px = pm(o.x, o.speed)[0]
    return forward_differences(pm, o.x, o.speed, Px)[0], Px


def _differences(pm: RingPeriodMap, o, J: np.ndarray, Jf: np.ndarray) -> tuple[float, float]:
    """(scaled DP difference over the full DP's largest singular value, largest distance of a full
    multiplier to the nearest low-rank one)."""
    sc = pm.scales(o.x, o.speed)
    D, Df = (A * sc[None, :] / sc[:, None] for A in (J, Jf))
    mu, mf = multipliers(J), multipliers(Jf)
    return float(np.linalg.norm(D - Df, 2) / np.linalg.norm(Df, 2)), float(max(np.min(np.abs(mu - m)) for m in mf))


@pytest.mark.parametrize(
    "ring, seed, rpm",
    [
        (TUNED, "rest", 6000.0),  # stable
        (TUNED, "rest", 8000.0),  # two contacts sticking
        (LOOSE, "wave", 6200.0),  # unstable, |mu| 4.2
        (MISTUNED, "rest", 6000.0),
        (EO2, "wave", 5650.0),  # unstable: below the pitchfork
    ],
)
def test_low_rank_dp_equals_the_full_one(ring, seed, rpm):
    with RingPeriodMap(ring, LOW) as pm:
        lr = pm.low_rank
        olds = [_orbit(pm, seed, rpm - d) for d in (100.0, 50.0)]
        o = _orbit(pm, seed, rpm)
        lr.forget()
        for old in olds:  # the basis: the full DPs 100 and 50 rpm below
            lr.learn(_full(pm, old)[0], old.x, old.speed)
        Jf, Px = _full(pm, o)
        J = lr(o.x, o.speed, Px)[0]
        assert lr.outcome in ("low-rank", "acting"), (lr.outcome, lr.worst)
        err, dmu = _differences(pm, o, J, Jf)
        print(
            f"{ring.engine_order} {ring.fw0} {seed} {rpm}: {lr.outcome} {lr.directions} periods, worst probe "
            f"{lr.worst:.1e}, DP {err:.1e}, multipliers {dmu:.1e}, |mu| {np.abs(multipliers(Jf)).max():.3f}"
        )
        assert err <= DP_TOL and dmu <= MU_TOL, (err, dmu)
        # at the orbit of the basis' last full DP the check passes: a low-rank DP
        lr.forget()
        lr.learn(Jf, o.x, o.speed)
        J = lr(o.x, o.speed, Px)[0]
        assert lr.outcome == "low-rank", (lr.outcome, lr.worst)
        err, dmu = _differences(pm, o, J, Jf)
        assert err <= DP_TOL and dmu <= MU_TOL, (err, dmu)


def test_a_stale_basis_is_detected():
    with RingPeriodMap(EO2) as other:
        o2 = _orbit(other, "wave", 6000.0)
        J2 = _full(other, o2)[0]
    with RingPeriodMap(TUNED, LOW) as pm:
        lr = pm.low_rank
        o = _orbit(pm, "rest", 6000.0)
        Jf, Px = _full(pm, o)
        # another ring's basis (the same unknowns): it misses the row space
        lr.forget()
        lr.learn(J2, o2.x, o2.speed)
        J = lr(o.x, o.speed, Px)[0]
        assert lr.outcome != "low-rank", (lr.outcome, lr.worst)
        assert _differences(pm, o, J, Jf)[0] <= DP_TOL
        # the same with the check switched off: far off
        lr.forget()
        lr.learn(J2, o2.x, o2.speed)
        with pytest.MonkeyPatch.context() as mp:
            mp.setattr(derivative, "CHECK_RTOL", np.inf)
            J = lr(o.x, o.speed, Px)[0]
        assert _differences(pm, o, J, Jf)[0] > 100 * DP_TOL
        # every contact open at 6000 rpm (no phi acts), two sticking at 8000 rpm (their phi acts)
        J6 = Jf
        stick = _orbit(pm, "rest", 8000.0)
        Jf, Px = _full(pm, stick)
        k0 = 2 * pm.m * pm.n
        sc = pm.scales(stick.x, stick.speed)
        Df = Jf * sc[None, :] / sc[:, None]
        phi_cols = np.linalg.norm(Df[:, k0 : k0 + pm.n], axis=0) / np.linalg.norm(Df, 2)
        assert np.max(phi_cols) > 1e-3, phi_cols  # a sticking contact's phi acts
        lr.forget()
        lr.learn(J6, o.x, o.speed)
        assert not np.any(lr.acting[k0 : k0 + pm.n])
        J = lr(stick.x, stick.speed, Px)[0]
        assert _differences(pm, stick, J, Jf)[0] <= DP_TOL
        assert lr.outcome == "failed check", (lr.outcome, lr.worst)


def test_a_branch_traced_low_rank_is_the_full_ones():
    out = {}
    for mode in ("full", "low-rank"):
        with RingPeriodMap(EO2, RingShootingSettings(dp=mode)) as pm:
            o = _orbit(pm, "wave", 5850.0)
            e0 = pm.evaluations
            br = trace(pm, o, (5600.0, 5900.0))
            st = br.stable
            amp = br.amplitudes.max(axis=1)
            peaks = [p for p in br.peaks if p.stable] + [o for o, s in zip(br.orbits, st) if s]
            top = max(peaks, key=lambda p: p.amplitude)
            out[mode] = (
                top.amplitude,
                top.speed,
                [(b.kind, b.speed) for b in br.bifurcations],
                (pm.evaluations - e0) / len(br.orbits),
                pm.low_rank.counts if pm.low_rank else None,
            )
            print(mode, out[mode], len(br.orbits), amp.max())
    (af, nf, bf, _, _), (al, nl, bl, _, counts) = out["full"], out["low-rank"]
    assert abs(al - af) <= 1e-6 * af and abs(nl - nf) <= 0.5, (af, nf, al, nl)
    assert [k for k, _ in bl] == [k for k, _ in bf], (bf, bl)
    assert all(abs(a - b) <= 0.5 for (_, a), (_, b) in zip(bf, bl)), (bf, bl)
    assert counts["low-rank"] > 0


def test_the_memo_keeps_a_low_rank_dp():
    """The continuation's Jacobian taken low-rank is found again at its point (no period), by the
    continuation and by the monodromy alike."""
    with RingPeriodMap(TUNED, LOW) as pm:
        o = _orbit(pm, "rest", 6000.0)
        jacobians(pm).items.clear()  # (the shooting's monodromy is kept there)
        prob = BranchProblem(pm, pm.scales(o.x, o.speed))
        z = prob.to_z(o.x, o.speed)
        Hz, Px, _ = prob.H(z)
        e0 = pm.evaluations
        Jz, DP = prob.jac(z, Hz, Px)
        assert pm.low_rank.outcome == "low-rank" and pm.evaluations > e0
        e0 = pm.evaluations
        Jz2, DP2 = prob.jac(z, Hz, Px)
        x, n = prob.from_z(z)
        assert pm.evaluations == e0
        assert np.array_equal(DP2, DP) and np.array_equal(Jz2, Jz)
        assert np.array_equal(monodromy(pm, x, n), DP) and pm.evaluations == e0


@pytest.mark.parametrize("bad", ["lowrank", "", "FULL", None, 1])
def test_invalid_dp_is_refused(bad):
    with pytest.raises(ValueError) as e:
        RingShootingSettings(dp=bad).check()
    text = str(e.value)
    assert repr(bad) in text and "'full'" in text and "'low-rank'" in text, text


def test_the_default_takes_the_full_differences():
    assert RingShootingSettings().dp == "full"
    with RingPeriodMap(TUNED) as pm:
        assert pm.low_rank is None and pm.state_jacobian(np.zeros(pm.dim), 6000.0, np.zeros(pm.dim)) is None
