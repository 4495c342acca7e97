"""The contact's closed-form describing functions (harness.model.contact) against the reference's
quadrature of the loop (harness.reference.contact), and the loop's geometry.

Tolerances: the closed forms (eq. 7, 8 fixed, 10 rewritten with half-angle identities so that
nothing cancels as B -> d+) and the Gauss-Legendre quadrature of the piecewise loop (eq. 3/4,
evaluated with v - d = (B - d) - 2 B sin^2(theta/2)) agree to 1e-10 relative on B/d from 1 + 1e-6
to 50 (measured: closed forms within 4 ulp of a 60-digit evaluation of the printed formulas; the
quadrature within 5e-13, its breakpoints pi - theta2, theta3 carry absolute roundoff ~4e-16 on
pieces only ~1e-3 wide at B/d = 1 + 1e-6). Only a quantity that is 0 by symmetry (Coulomb f_k:
F_f is even about theta = pi/2 on [0, pi] while cos is odd; full-stick f_c: an elastic loop encloses
no area) has no relative scale: there the closed form must be exactly 0 and the quadrature's
roundoff is bounded by 1e-13 of the loop's force scale max|F_f| / B. The rewritten closed forms equal the printed ones
(evaluated literally) to 1e-12 where those are well conditioned (B/d >= 1.5). The energy identity is
checked against the exact area of the loop, which is a polygon in the (v, F_f) plane (every piece
of eq. 4 is affine in v), by the shoelace/trapezoid formula: exact up to roundoff.
"""

from __future__ import annotations

import itertools
import math
import warnings

import numpy as np
import pytest

from harness.model.contact import contact_consts, describing_function, loop_angles, regime
from harness.reference import contact as reference

KD = [0.608695652173913, 0.8235294117647058]
GAMMAS = [math.pi / k for k in (3, 4, 5, 6, 7)]
KNS = [1e5, 1e6, 1e7]
RATIOS = [1 + 1e-6, 1 + 1e-5, 1 + 1e-4, 1.001, 1.01, 1.1, 1.5, 2.0, 5.0, 10.0, 50.0]
OMEGA = 1570.8


def _params(kdr: float, gamma: float, kn: float) -> dict:
    return {"kdRatio": kdr, "gamma": gamma, "kn": kn}


@pytest.mark.parametrize("kdr,gamma,kn,model", list(itertools.product(KD, GAMMAS, KNS, (1, 2))))
def test_closed_form_matches_quadrature(kdr: float, gamma: float, kn: float, model: int) -> None:
    p = _params(kdr, gamma, kn)
    cc = contact_consts(p)
    d = cc.d
    for r in RATIOS:
        B = r * d
        a = describing_function(p, B, OMEGA, model, 1)
        b = reference.describing_function(p, B, OMEGA, model, 1)
        force_scale = max(cc.b, cc.a) * (B - d) / B  # max|F_f| / B: N* (slip) or k_d sin g (B - d) (full stick)
        for f in ("fk", "fcOmega", "pk"):
            x, y = getattr(a, f), getattr(b, f)
            zero_by_symmetry = (f == "fk" and model == 2) or (f == "fcOmega" and model == 1 and cc.full_stick)
            if zero_by_symmetry:
                assert x == 0.0 and abs(y) <= 1e-13 * force_scale, (f, r, x, y)
            else:
                assert y != 0.0 and abs(x - y) <= 1e-10 * abs(y), (f, r, x, y, abs(x - y) / abs(y))


def _printed(p: dict, B: float, model: int) -> tuple[float, float, float]:
    """f_k, f_c omega, p_k evaluated literally as printed: eq. 5 angles by arccos, eq. 7, eq. 8 with the
    docs/model.md fix (4 cos theta1), eq. 10; Coulomb f_c omega = 4 N* (1 - d/B) / (pi B) (model-notes s.5)."""
    cc = contact_consts(p)
    kd, kn, mu, d, g = cc.kd, cc.kn, cc.mu, cc.d, cc.gamma
    sg, cg, kdt, mkn = math.sin(g), math.cos(g), kd * math.tan(g), mu * kn
    t2 = math.acos(d / B)
    Ns = mu * kn * cg * (B - d)
    pk = kn * cg * (2 * B * t2 + B * math.sin(2 * t2) - 4 * d * math.sin(t2)) / (math.pi * B)
    if model == 2:
        return 0.0, 4 * Ns * (1 - d / B) / (math.pi * B), pk
    t1 = math.acos((kdt * B + 2 * mkn * d - mkn * B) / (kdt * B + mkn * B))
    t3 = math.acos(-(d * kdt + mkn * (B - d)) / (B * kdt))
    fk = (
        2
        / (math.pi * B)
        * (
            0.25 * B * kd * sg * (2 * t1 + math.sin(2 * t1) - 4 * math.sin(t1))
            + 0.25 * mu * kn * cg * (2 * B * t1 + B * math.sin(2 * t1) - 4 * d * math.sin(t1))
            - Ns * (math.sin(t2) - math.sin(t1) - math.sin(t3))
            + 0.25
            * kd
            * sg
            * (
                2 * B * (t2 + t3 - math.pi)
                + B * (math.sin(2 * t3) + math.sin(2 * t2))
                + 4 * d * (math.sin(t3) - math.sin(t2))
            )
        )
    )
    fcw = (
        -2
        / (math.pi * B)
        * (
            0.25 * B * kd * sg * (4 * math.cos(t1) - math.cos(2 * t1) - 3)
            + 0.25 * mu * kn * cg * (B + 4 * d * math.cos(t1) - B * math.cos(2 * t1) - 4 * d)
            + Ns * (math.cos(t2) - math.cos(t1))
            + 0.25
            * kd
            * sg
            * (B * math.cos(2 * t2) - B * math.cos(2 * t3) - 4 * d * math.cos(t3) - 4 * d * math.cos(t2))
            - Ns * (1 + math.cos(t3))
        )
    )
    return fk, fcw, pk


@pytest.mark.parametrize("kdr,gamma,model", [(k, g, m) for k, g, m in itertools.product(KD, GAMMAS[:4], (1, 2))])
def test_stable_closed_forms_equal_the_printed_ones(kdr: float, gamma: float, model: int) -> None:
    """The cancellation-free rewriting is an identity: equal to eq. 7/8/10 as printed (1e-12) where the
    printed brackets are well conditioned (B/d >= 1.5; at 1 + 1e-6 they lose ~4 digits in f_c)."""
    p = _params(kdr, gamma, 1e7)
    for r in (1.5, 2.0, 5.0, 50.0):
        B = r * 3e-5
        df = describing_function(p, B, OMEGA, model)
        for f, ref in zip(("fk", "fcOmega", "pk"), _printed(p, B, model)):
            assert getattr(df, f) == pytest.approx(ref, rel=1e-12, abs=0.0 if ref else 1e-30), (f, r)


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
            verts.append((v, float(reference.loop_friction(cc, B, th - eps * (th - brk[k - 1]), model))))
        if k < len(brk) - 1:
            verts.append((v, float(reference.loop_friction(cc, B, th + eps * (brk[k + 1] - th), model))))
    # within each interval F_f is affine in v, so the trapezoid rule on its end values is exact;
    # the eps-shifted evaluation points cost O(eps) relative error
    area = 0.0
    for (v0, f0), (v1, f1) in zip(verts[:-1], verts[1:]):
        area += 0.5 * (f0 + f1) * (v1 - v0)
    return area


@pytest.mark.parametrize(
    "kdr,gamma,model",
    [
        (KD[0], math.pi / 3, 1),
        (KD[1], math.pi / 7, 1),
        (KD[0], math.pi / 5, 1),
        (KD[0], math.pi / 3, 2),
        (KD[1], math.pi / 4, 2),
    ],
)
@pytest.mark.parametrize("r", [1.05, 1.5, 4.0, 50.0])
def test_energy_identity(kdr: float, gamma: float, model: int, r: float) -> None:
    """closed integral of F_f dv = pi omega B^2 f_c (docs/model.md s.3), the loop run in the direction of
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
    printed = (
        -2.0
        / (math.pi * B)
        * (
            0.25 * B * kd * sg * (math.cos(t1) - math.cos(2 * t1) - 3)
            + 0.25 * mu * kn * cg * (B + 4 * d * math.cos(t1) - B * math.cos(2 * t1) - 4 * d)
            + Ns * (math.cos(t2) - math.cos(t1))
            + 0.25
            * kd
            * sg
            * (B * math.cos(2 * t2) - B * math.cos(2 * t3) - 4 * d * math.cos(t3) - 4 * d * math.cos(t2))
            - Ns * (1 + math.cos(t3))
        )
    )
    area = _loop_area(p, B, 1)
    assert abs(math.pi * B * B * printed - area) > 0.01 * area
    assert math.pi * B * B * describing_function(p, B, OMEGA).fcOmega == pytest.approx(area, rel=1e-10)


def test_regime_boundary() -> None:
    """Full stick iff k_d tan g < mu k_n: gamma* = atan(mu / kdRatio). At gamma* the eq.-5 angles
    degenerate continuously (theta1 -> theta2, theta3 -> pi) but the paper's loop still encloses an
    area there (it starts each stroke at +-N* and jumps N* -> 0 at separation), while docs/model.md's
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
        # its area is N* (B - d): per half cycle (int F_f dv) the first stick line (slope 2a, +N* to -N*)
        # contributes nothing, the slip arcs are empty (theta1 = theta2, theta3 = pi) and the stick line
        # a (v + d), from 0 at v = -d to -N* at v = -B, gives N* (B - d) / 2: f_c omega > 0
        cc = contact_consts(above)
        Ns = cc.mu * cc.kn * math.cos(cc.gamma) * (6e-5 - cc.d)
        assert math.pi * 6e-5**2 * a.fcOmega == pytest.approx(_loop_area(above, 6e-5, 1), rel=1e-9)
        assert math.pi * 6e-5**2 * a.fcOmega == pytest.approx(Ns * (6e-5 - cc.d), rel=1e-7)  # gamma* (1 + 1e-9)
        assert a.fcOmega > 0.05 * a.pk and Ns > 0
    # the printed kdRatio puts pi/7 in full stick, Mindlin's value does not (docs/model.md s.3)
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
    assert np.allclose(reference.normal_force(p, v), expect, rtol=1e-15, atol=0)


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
        lo, hi = reference.loop_friction(cc, B, th - 1e-12, model), reference.loop_friction(cc, B, th + 1e-12, model)
        assert abs(lo - hi) <= 1e-6 * Ns, th
    for th, (before, after) in jumps.items():
        assert abs(reference.loop_friction(cc, B, th - 1e-12, model) - before) <= 1e-6 * Ns
        assert abs(reference.loop_friction(cc, B, th + 1e-12, model) - after) <= 1e-6 * Ns
    closing = (
        float(reference.loop_friction(cc, B, 2 * pi - 1e-13, model)),
        float(reference.loop_friction(cc, B, 0.0, model)),
    )
    assert closing[0] == pytest.approx(Ns, rel=1e-9)  # sliding up at full N* before the reversal
    assert closing[1] == pytest.approx(Ns if model == 1 else -Ns, rel=1e-9)  # Coulomb reverses at once


def test_loop_state_intervals() -> None:
    p = {}
    cc = contact_consts(p)
    B = 6e-5
    t1, t2, t3 = loop_angles(cc, B)
    pi = math.pi
    mids = [
        0.5 * (a + b)
        for a, b in zip(
            [0, t1, t2, pi - t2, t3, pi, pi + t1, pi + t2, 2 * pi - t2, pi + t3],
            [t1, t2, pi - t2, t3, pi, pi + t1, pi + t2, 2 * pi - t2, pi + t3, 2 * pi],
        )
    ]
    assert list(reference.loop_state(cc, B, np.array(mids))) == [1, 2, 0, 1, 2, 1, 2, 0, 1, 2]
    assert list(reference.loop_state(cc, B, np.array(mids), 2)) == [2, 2, 0, 2, 2, 2, 2, 0, 2, 2]  # Coulomb: no stick
    assert reference.loop_state(_params(KD[0], math.pi / 7, 1e7), B, 1.0) == 1  # full stick
    assert reference.loop_state(cc, 2e-5, 1.0) == 0


@pytest.mark.parametrize("model", [1, 2])
def test_loop_angles_by_root_finding_equal_the_half_angle_forms(model: int) -> None:
    """The reference finds the eq.-5 angles by brentq on the loop's switching conditions; the product
    writes them in closed (half-angle) form. Both to roundoff: 1e-12 relative (the angles are
    ~1e-3 rad at B/d = 1 + 1e-6, where brentq's rtol 4 eps leaves ~1e-15 of them)."""
    for kdr, gamma, kn in itertools.product(KD, GAMMAS, KNS):
        cc = contact_consts(_params(kdr, gamma, kn))
        B = cc.d * np.array(RATIOS)
        for x, y in zip(loop_angles(cc, B, model), reference.loop_angles(cc, B, model)):
            np.testing.assert_allclose(y, x, rtol=1e-12, atol=0)
