"""Located peaks and folds (harness.analysis.periodic.extrema) against independent values:
- the open-contact blade is linear: its amplitude over speed has a closed form (a 1-DOF forced
  response with the Galerkin constants of the independent Python reference), maximised by scipy;
- the base case's Jenkins peak against a 1-rpm scan of fixed-speed shooting (parabola through the
  three largest; within 0.05 rpm, 0.009 measured), and its lower fold against the lowest speed at which fixed-speed shooting still
  finds an orbit in contact (0.02-rpm scan).
"""

from __future__ import annotations

import math

import numpy as np
import pytest
from scipy.optimize import minimize_scalar

from harness.analysis.periodic.branches import BranchSettings, trace_branches
from harness.analysis.periodic.extrema import candidates
from harness.analysis.periodic.period_map import PeriodMap
from harness.analysis.periodic.shooting import newton
from harness.model.params import validate
from harness.reference.blade import galerkin


def _linear_peak(params: dict, fw0: float, eo: int) -> tuple[float, float]:
    """(speed [rpm], amplitude [m]) of the largest |G F / (K(Omega) - M w^2 + i C w)|, w = EO Omega."""
    g = galerkin(validate(params))

    def neg_amp(n: float) -> float:
        Om = 2 * math.pi * n / 60
        w = eo * Om
        return -g.loadGain * fw0 / abs(g.K0static + g.K0omega2 * Om * Om - g.M * w * w + 1j * g.C0 * w)

    r = minimize_scalar(neg_amp, bounds=(4000.0, 6000.0), method="bounded", options={"xatol": 1e-9})
    return float(r.x), -float(r.fun)


def test_open_contact_peak_equals_the_closed_form(fmu) -> None:
    params = {"d": 1.0, "Fw0": 100.0}  # the contact never closes: a linear blade
    pm = PeriodMap(fmu, params, "jenkins")
    branches, _ = trace_branches(fmu, params, "jenkins", (4500.0, 5500.0), BranchSettings(), pm)
    # the lightly damped resonance is narrower than the continuation's steps: a seed on its flank
    # may start a second trace of the same branch; each must locate the same peak
    peaks = [e for b in branches for e in b.located("peak")]
    assert peaks, [b.speeds for b in branches]
    n_ref, a_ref = _linear_peak({**pm.p, "d": 1.0}, 100.0, int(pm.p["engineOrder"]))
    for pk in peaks:  # shooting converges to 1e-10; the FMU's RK4 (maxStep 1e-5 s) is accurate to ~1e-9 here
        assert pk.speed == pytest.approx(n_ref, abs=0.005)  # measured 4e-4 rpm
        assert pk.amplitude == pytest.approx(a_ref, rel=2e-8)  # measured 2e-9
        assert pk.stable


@pytest.fixture(scope="module")
def base_jenkins(fmu):
    pm = PeriodMap(fmu, {}, "jenkins")
    branches, _ = trace_branches(fmu, {}, "jenkins", (5000.0, 9000.0), BranchSettings(), pm)
    return pm, branches


def test_base_case_jenkins_peak_within_0_05_rpm_of_a_fine_scan(base_jenkins) -> None:
    pm, branches = base_jenkins
    pk = max((e for b in branches for e in b.located("peak") if e.stable), key=lambda e: e.amplitude)
    speeds = np.arange(round(pk.speed) - 6.0, round(pk.speed) + 7.0, 1.0)
    amps = []
    for n in speeds:
        sol = newton(pm, pk.x, float(n))
        assert sol is not None, f"no orbit at {n} rpm from the peak's orbit"
        amps.append(sol.amplitude)
    amps = np.array(amps)
    k = int(np.argmax(amps))
    assert 0 < k < len(amps) - 1, "the scan's maximum is at its edge"
    c = np.polyfit(speeds[k - 1 : k + 2], amps[k - 1 : k + 2], 2)
    n_scan = -c[1] / (2 * c[0])
    assert abs(pk.speed - n_scan) <= 0.05, (pk.speed, n_scan)  # measured 0.009 rpm
    # the located peak is the maximum: no scanned orbit is larger (beyond Newton's 1e-10)
    assert pk.amplitude >= amps.max() * (1 - 1e-9)


def test_base_case_jenkins_lower_fold_within_0_1_rpm_of_a_fine_scan(base_jenkins) -> None:
    pm, branches = base_jenkins
    d = float(pm.p["d"])
    folds = [e for b in branches for e in b.located("fold") if e.speed < 7000.0]
    assert len(folds) == 1, folds
    fold = folds[0]

    def in_contact(n: float) -> bool:
        sol = newton(pm, fold.x, n)
        return sol is not None and sol.amplitude > d

    speeds = np.arange(fold.speed - 0.5, fold.speed + 0.5, 0.02)
    found = [n for n in speeds if in_contact(float(n))]
    assert found, "fixed-speed shooting finds no orbit in contact near the fold"
    assert abs(min(found) - fold.speed) <= 0.1, (min(found), fold.speed)
    assert not any(in_contact(float(n)) for n in speeds[speeds < fold.speed - 0.1])


def test_candidates_bracket_peaks_and_turning_points() -> None:
    from harness.analysis.periodic.continuation import Branch, BranchPoint

    def pt(n: float, a: float) -> BranchPoint:
        return BranchPoint(n, np.zeros(3), a, np.array([0.5]))

    # up to a peak at 2, a fold at 3 (the speed turns back), then down
    b = Branch("jenkins", [pt(1, 1.0), pt(2, 3.0), pt(3, 2.0), pt(2.5, 1.5), pt(2.0, 1.2)])
    assert candidates(b) == [(1, "peak"), (2, "fold")]


@pytest.mark.parametrize(
    "mu, said",
    [
        ([0.5, 0.3j], "stable"),
        ([2.26, 0.2], "unstable: fold (a real multiplier 2.26 > 1)"),
        ([-1.5, 0.1], "unstable: period doubling (a real multiplier -1.5 < -1)"),
        ([0.6 + 0.9j, 0.6 - 0.9j], "unstable: Neimark-Sacker (a complex pair of modulus 1.082 > 1)"),
        ([1.5, -1.2], "unstable: fold (a real multiplier 1.5 > 1); period doubling (a real multiplier -1.2 < -1)"),
    ],
)
def test_stability_is_said_with_its_reason(mu: list, said: str) -> None:
    from harness.analysis.periodic.shooting import describe

    assert describe(np.array(mu, dtype=complex)) == said
