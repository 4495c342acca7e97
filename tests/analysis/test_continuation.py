"""Branches of periodic orbits by continuation (harness.analysis.periodic.branches / continuation), each
against an independent computation.

- Gating off, the fixed point B = A(B) is exactly the one-harmonic balance (the fixed-B ODE is
  linear, its orbit has no higher harmonic): every traced point equals an HB root
  (harness.analysis.harmonic_balance, Illinois on the closed-form residual: a second method) at its speed, 1e-7 of B (the FMU's
  RK4 at maxStep 2.5e-6 s is ~1e-10); every HB root on a speed grid lies on a traced branch
  (nothing missed, the folds of the multi-solution region passed); the stability of each point
  equals the reference's tracked-amplitude map radius (< 1 or > 1, away from |mu| = 1).
- Jenkins element, d = 0.06 mm, 3000..12000 rpm as in `make run`: the stable upper branch reaches
  ~7250 rpm. A continuation that stopped at the kink near 6776 rpm (an event appears) and
  re-started on the unstable side would miss 6780..7247 rpm; an orbit of that piece is checked by
  a 200-period FMU transient started on it, which must stay on it.
"""

from __future__ import annotations

import math

import numpy as np
import pytest

from harness.model.params import validate
from harness.analysis.periodic.branches import BranchSettings, trace_branches
from harness.analysis.periodic.period_map import PeriodMap, omega
from harness.analysis.periodic.shooting import shoot
from harness.analysis.harmonic_balance import harmonic_balance, linear_orbit
from harness.reference.tracked import tracked_map_radius
from tests.analysis.test_periodic import _period_end_states

FINE = {"maxStep": 2.5e-6}


@pytest.fixture(scope="module")
def ungated(fmu):
    p = dict(FINE, gating=False)
    branches, _ = trace_branches(fmu, p, "fixedPoint", (6000.0, 9000.0))
    return p, branches


def test_every_ungated_branch_point_is_a_harmonic_balance_root_with_its_stability(ungated):
    """The HB root condition at the point's B: the blade linearised at amplitude B (closed-form
    describing function and harmonic response) answers with amplitude B; the stability is
    the reference's tracked map's (points resolve folds more finely than HB's scan)."""
    p, branches = ungated
    pts = [q for b in branches for q in b.points if 6000.0 <= q.speed <= 9000.0]
    assert len(pts) > 20
    for q in pts:
        B = float(q.x[2])
        q0, v0 = linear_orbit(p, q.speed, B)
        A_lin = math.hypot(q0, v0 / omega(validate(p), q.speed))
        assert abs(A_lin - B) <= 1e-7 * B, (q.speed, B, A_lin)
        r = tracked_map_radius(p, q.speed, B)
        if abs(r - 1.0) > 0.02:  # clear of the stability boundary
            assert q.stable == (r < 1.0), (q.speed, B, r, q.multipliers)


def test_every_ungated_harmonic_balance_root_lies_on_a_branch(ungated):
    p, branches = ungated
    speeds = np.arange(6100.0, 9000.0, 100.0)
    n_multi = 0
    for n, sols in zip(speeds, harmonic_balance(p, speeds)):
        n_multi += len(sols) >= 3
        for s in sols:
            assert any(b.contains(n, s.B) for b in branches), (n, s.B)
    assert n_multi >= 3  # the grid crosses the multi-solution region (three roots, two folds)


def test_jenkins_stable_upper_branch_is_traced_past_the_kink(fmu):
    d = 6e-5
    branches, _ = trace_branches(fmu, {"d": d}, "jenkins", (3000.0, 12000.0))
    piece = [q for b in branches for q in b.points if q.stable and 7100.0 <= q.speed <= 7245.0 and q.amplitude > d]
    assert piece, "the stable upper branch between the kink and its fold is missing"
    q = piece[len(piece) // 2]
    pm = PeriodMap(fmu, {"d": d}, "jenkins")
    o = shoot(pm, q.x, q.speed)
    assert o is not None and o.stable
    assert abs(o.amplitude - q.amplitude) <= 1e-8 * q.amplitude
    r = _period_end_states(fmu, dict(o.start_values, d=d, frictionModel=3), q.speed, 200)
    assert np.max(np.abs(r["tipDisplacement"] - o.x[0])) <= 1e-6 * o.amplitude


@pytest.mark.parametrize("model,over", [("fixedPoint", {"d": 5e-5}), ("jenkins", {"m0": 0.02})])
def test_seeds_every_1000_rpm_find_the_branches_of_seeds_every_500(fmu, model, over):
    """make run seeds every 1000 rpm; with seeds every 500 rpm the same curves must have no orbit
    off those branches (these two curves differed before folds were resolved: a long step cut the
    tip of the lower fold near grazing, 5388 rpm at d = 0.05 mm, and only an extra seed found it)."""
    coarse, _ = trace_branches(fmu, over, model, (3000.0, 12000.0), BranchSettings(seed_step=1000.0))
    fine, _ = trace_branches(fmu, over, model, (3000.0, 12000.0), BranchSettings(seed_step=500.0))
    assert len(coarse) == len(fine)
    for b in fine:
        for q in b.points:
            if 3000.0 <= q.speed <= 12000.0:
                assert any(c.contains(q.speed, q.amplitude, 2e-3) for c in coarse), (q.speed, q.amplitude)
