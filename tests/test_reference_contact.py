"""Reference contact model (harness.reference_contact): closed forms against quadrature and geometry.

Tolerances: closed forms vs adaptive quadrature (scipy quad, epsrel 2e-14, split at every loop
breakpoint) agree to 1e-10 relative for B/d >= 1.01. Closer to the gap the closed forms lose digits
by cancellation (terms ~ k_n B summing to ~ k_n (B-d)^2 / B), so there we compare with an absolute
tolerance of 1e-10 k_n (the natural scale of f_k, p_k, f_c omega). The energy identity is checked
against the exact area of the loop, which is a polygon in the (v, F_f) plane (every piece of eq. 4
is affine in v), by the shoelace/trapezoid formula: exact up to roundoff.
"""
from __future__ import annotations

import itertools
import math
import warnings

import numpy as np
import pytest

from harness.reference_contact import (contact_consts, describing_function, loop_angles, loop_friction, loop_state,
                                       normal_force, regime)

KD = [0.608695652173913, 0.8235294117647058]
GAMMAS = [math.pi / k for k in (3, 4, 5, 6, 7)]
KNS = [1e5, 1e6, 1e7]
RATIOS = [1.01, 1.1, 1.5, 2.0, 5.0, 10.0, 50.0]
OMEGA = 1570.8


def _params(kdr: float, gamma: float, kn: float) -> dict:
    return {"kdRatio": kdr, "gamma": gamma, "kn": kn}


@pytest.mark.parametrize("kdr,gamma,kn,model", list(itertools.product(KD, GAMMAS, KNS, (1, 2))))
def test_closed_form_matches_quadrature(kdr: float, gamma: float, kn: float, model: int) -> None:
    p = _params(kdr, gamma, kn)
    d = 3e-5
    for r in RATIOS:
        a = describing_function(p, r * d, OMEGA, model, 1, "closed")
        b = describing_function(p, r * d, OMEGA, model, 1, "quadrature")
        for f in ("fk", "fcOmega", "pk"):
            x, y = getattr(a, f), getattr(b, f)
            assert abs(x - y) <= 1e-10 * abs(y) + 1e-16 * kn, (f, r, x, y)
    for r in (1 + 1e-6, 1 + 1e-4, 1.001):
        a = describing_function(p, r * d, OMEGA, model, 1, "closed")
        b = describing_function(p, r * d, OMEGA, model, 1, "quadrature")
        for f in ("fk", "fcOmega", "pk"):
            assert abs(getattr(a, f) - getattr(b, f)) <= 1e-10 * kn


def _loop_area(p: dict, B: float, model: int) -> float:
    """Closed integral of F_f dv: the loop is a polygon in (v, F_f); trapezoids between vertices
    (both one-sided values at every breakpoint) are exact."""
    cc = contact_consts(p)
    t1, t2, t3 = loop_angles(cc, B, model)
    pi = math.pi
    brk = sorted({0.0, t1, t2, pi - t2, t3, pi, pi + t1, pi + t2, 2 * pi - t2, pi + t3, 2 * pi})
    eps = 1e-13
    verts = []
    for k, th in enumerate(brk):
        v = B * math.cos(th)
        if k > 0:
            verts.append((v, float(loop_friction(cc, B, th - eps * (th - brk[k - 1]), model))))
        if k < len(brk) - 1:
            verts.append((v, float(loop_friction(cc, B, th + eps * (brk[k + 1] - th), model))))
    # within each interval F_f is affine in v, so the trapezoid rule on its end values is exact;
    # the eps-shifted evaluation points cost O(eps) relative error
    area = 0.0
    for (v0, f0), (v1, f1) in zip(verts[:-1], verts[1:]):
        area += 0.5 * (f0 + f1) * (v1 - v0)
    return area


@pytest.mark.parametrize("kdr,gamma,model", [(KD[0], math.pi / 3, 1), (KD[1], math.pi / 7, 1), (KD[0], math.pi / 5, 1),
                                             (KD[0], math.pi / 3, 2), (KD[1], math.pi / 4, 2)])
@pytest.mark.parametrize("r", [1.05, 1.5, 4.0, 50.0])
def test_energy_identity(kdr: float, gamma: float, model: int, r: float) -> None:
    """closed integral of F_f dv = pi omega B^2 f_c (MODEL.md s.3), the loop run in the direction of
    increasing theta (the direction of motion); it is the work done against friction, > 0."""
    p = _params(kdr, gamma, 1e7)
    B = r * 3e-5
    area = _loop_area(p, B, model)
    df = describing_function(p, B, OMEGA, model)
    assert area == pytest.approx(math.pi * OMEGA * B * B * df.fc, rel=1e-9)
    assert area > 0


def test_fc_fix_of_eq8_matters() -> None:
    """The printed eq. 8 (cos theta1 instead of 4 cos theta1) fails the energy identity."""
    p = _params(KD[0], math.pi / 3, 1e7)
    cc = contact_consts(p)
    B = 2 * 3e-5
    t1, t2, t3 = loop_angles(cc, B)
    sg, cg = math.sin(cc.gamma), math.cos(cc.gamma)
    kd, kn, mu, d = cc.kd, cc.kn, cc.mu, cc.d
    Ns = mu * kn * cg * (B - d)
    printed = -2.0 / (math.pi * B) * (
        0.25 * B * kd * sg * (math.cos(t1) - math.cos(2 * t1) - 3)
        + 0.25 * mu * kn * cg * (B + 4 * d * math.cos(t1) - B * math.cos(2 * t1) - 4 * d)
        + Ns * (math.cos(t2) - math.cos(t1))
        + 0.25 * kd * sg * (B * math.cos(2 * t2) - B * math.cos(2 * t3) - 4 * d * math.cos(t3) - 4 * d * math.cos(t2))
        - Ns * (1 + math.cos(t3)))
    area = _loop_area(p, B, 1)
    assert abs(math.pi * B * B * printed - area) > 0.01 * area
    assert math.pi * B * B * describing_function(p, B, OMEGA).fcOmega == pytest.approx(area, rel=1e-10)


def test_regime_boundary() -> None:
    """Full stick iff k_d tan g < mu k_n: gamma* = atan(mu / kdRatio). At gamma* the eq.-5 angles
    degenerate continuously (theta1 -> theta2, theta3 -> pi) but the paper's loop still encloses an
    area there (it starts each stroke at +-N* and jumps N* -> 0 at separation), while MODEL.md's
    full-stick regime is elastic (f_c = 0, f_k = (k_d tan g / k_n) p_k): the describing function
    jumps across gamma*. We check both sides against their own definitions and record the jump."""
    for kdr in KD:
        gs = math.atan(0.33 / kdr)
        below, above = _params(kdr, gs * (1 - 1e-9), 1e7), _params(kdr, gs * (1 + 1e-9), 1e7)
        assert regime(below, 6e-5) == 2 and regime(above, 6e-5) == 1
        assert regime(above, 6e-5, model=2) == 1 and regime(below, 6e-5, model=2) == 1
        assert regime(above, 3e-5) == 0 and regime(above, 2e-5) == 0
        t1, t2, t3 = loop_angles(above, 6e-5)
        assert abs(t1 - t2) < 1e-6 and abs(t3 - math.pi) < 1e-4
        a, b = describing_function(above, 6e-5, OMEGA), describing_function(below, 6e-5, OMEGA)
        assert b.fcOmega == 0.0 and b.fk == pytest.approx(0.33 * b.pk, rel=1e-8)  # k_d tan g* = mu k_n
        # paper loop at the boundary: two stick lines of slope 2a and a, jumps at separation;
        # its area is N* (B + d) (trapezoid of the parallelogram-like loop): f_c omega > 0
        cc = contact_consts(above)
        Ns = cc.mu * cc.kn * math.cos(cc.gamma) * (6e-5 - cc.d)
        assert math.pi * 6e-5 ** 2 * a.fcOmega == pytest.approx(_loop_area(above, 6e-5, 1), rel=1e-9)
        assert a.fcOmega > 0.05 * a.pk and Ns > 0
    # the printed kdRatio puts pi/7 in full stick, Mindlin's value does not (MODEL.md s.3)
    assert regime(_params(KD[0], math.pi / 7, 1e7), 6e-5) == 2
    assert regime(_params(KD[1], math.pi / 7, 1e7), 6e-5) == 1


def test_full_stick_never_evaluates_arccos_outside() -> None:
    p = _params(KD[0], math.pi / 7, 1e7)
    with warnings.catch_warnings():
        warnings.simplefilter("error")
        df = describing_function(p, np.geomspace(3.0000001e-5, 1e-2, 200), OMEGA)
    assert np.all(np.isfinite(df.fk)) and np.all(df.fc == 0.0)
    cc = contact_consts(p)
    assert np.allclose(df.fk, cc.kd * math.tan(cc.gamma) / cc.kn * df.pk, rtol=1e-14)


def test_open_and_continuity_at_gap() -> None:
    p = {}
    d = 3e-5
    df = describing_function(p, np.array([0.5 * d, d]), OMEGA)
    assert np.all(df.fk == 0) and np.all(df.fc == 0) and np.all(df.pk == 0) and np.all(df.regime == 0)
    near = describing_function(p, d * (1 + 1e-8), OMEGA)
    assert abs(near.Keq) < 1e-6 * 1e7 and abs(near.CeqOmega) < 1e-6 * 1e7


def test_coulomb_is_the_stiff_tangential_limit() -> None:
    """k_d -> infinity: theta1 -> 0, theta3 -> pi - theta2 and the macroslip DF tends to Coulomb's."""
    for r in (1.2, 3.0, 20.0):
        B = r * 3e-5
        coul = describing_function(_params(KD[0], math.pi / 3, 1e7), B, OMEGA, 2)
        errs = []
        for kdr in (1e3, 1e5, 1e7):
            stiff = describing_function(_params(kdr, math.pi / 3, 1e7), B, OMEGA, 1)
            errs.append(max(abs(stiff.fcOmega - coul.fcOmega), abs(stiff.fk)) / coul.pk)
            assert stiff.pk == coul.pk
        # the stick arcs shrink like theta1 ~ k_d^(-1/2): the error falls ~10x per 100x in k_d
        assert errs[-1] < 1e-3 and errs[1] < 0.2 * errs[0] and errs[2] < 0.2 * errs[1]


def test_projection() -> None:
    p = {}
    B = 5e-5
    a, b = describing_function(p, B, OMEGA, 1, 1), describing_function(p, B, OMEGA, 1, 2)
    sg, cg = math.sin(math.pi / 3), math.cos(math.pi / 3)
    assert a.Keq == pytest.approx((a.fk + a.pk) * sg, rel=1e-15)
    assert b.Keq == pytest.approx(b.fk * sg + b.pk * cg, rel=1e-15)
    assert a.Ceq == b.Ceq == pytest.approx(a.fc * sg, rel=1e-15)
    assert a.Ceq == pytest.approx(a.CeqOmega / OMEGA, rel=1e-15)


def test_normal_force_eq3() -> None:
    p = {}
    v = np.array([-1e-4, -3e-5, 0.0, 2e-5, 3e-5, 1e-4])
    cg = math.cos(math.pi / 3)
    expect = np.array([1e7 * (-1e-4 + 3e-5) * cg, 0, 0, 0, 0, 1e7 * (1e-4 - 3e-5) * cg])
    assert np.allclose(normal_force(p, v), expect, rtol=1e-15, atol=0)


@pytest.mark.parametrize("model", [1, 2])
def test_loop_closes_and_is_continuous_except_separation(model: int) -> None:
    """F_f is continuous along the loop except the jumps N* -> 0 at theta2 and pi + theta2."""
    p = {}
    cc = contact_consts(p)
    B = 6e-5
    t1, t2, t3 = loop_angles(cc, B, model)
    pi = math.pi
    Ns = cc.mu * cc.kn * math.cos(cc.gamma) * (B - cc.d)
    jumps = {t2: (-Ns, 0.0), pi + t2: (Ns, 0.0)}
    if model == 2:  # Coulomb: contact starts sliding at full N* (no stick arc after impact)
        jumps.update({pi - t2: (0.0, -Ns), 2 * pi - t2: (0.0, Ns), pi: (-Ns, Ns)})
    for th in sorted({t1, pi - t2, t3, pi, pi + t1, 2 * pi - t2, pi + t3} - {0.0} - set(jumps)):
        lo, hi = loop_friction(cc, B, th - 1e-12, model), loop_friction(cc, B, th + 1e-12, model)
        assert abs(lo - hi) <= 1e-6 * Ns, th
    for th, (before, after) in jumps.items():
        assert abs(loop_friction(cc, B, th - 1e-12, model) - before) <= 1e-6 * Ns
        assert abs(loop_friction(cc, B, th + 1e-12, model) - after) <= 1e-6 * Ns
    closing = (float(loop_friction(cc, B, 2 * pi - 1e-13, model)), float(loop_friction(cc, B, 0.0, model)))
    assert closing[0] == pytest.approx(Ns, rel=1e-9)  # sliding up at full N* before the reversal
    assert closing[1] == pytest.approx(Ns if model == 1 else -Ns, rel=1e-9)  # Coulomb reverses at once


def test_loop_state_intervals() -> None:
    p = {}
    cc = contact_consts(p)
    B = 6e-5
    t1, t2, t3 = loop_angles(cc, B)
    pi = math.pi
    mids = [0.5 * (a + b) for a, b in zip([0, t1, t2, pi - t2, t3, pi, pi + t1, pi + t2, 2 * pi - t2, pi + t3],
                                          [t1, t2, pi - t2, t3, pi, pi + t1, pi + t2, 2 * pi - t2, pi + t3, 2 * pi])]
    assert list(loop_state(cc, B, np.array(mids))) == [1, 2, 0, 1, 2, 1, 2, 0, 1, 2]
    assert list(loop_state(cc, B, np.array(mids), 2)) == [2, 2, 0, 2, 2, 2, 2, 0, 2, 2]  # Coulomb: no stick
    assert loop_state(_params(KD[0], math.pi / 7, 1e7), B, 1.0) == 1  # full stick
    assert loop_state(cc, 2e-5, 1.0) == 0
