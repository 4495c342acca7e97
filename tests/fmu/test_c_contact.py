"""Tests of fmu_src/physics/contact.c (paper eq. 3-13, docs/model.md s.3, docs/model-notes.md s.4-5) via ctypes.

The reference is an independent Python version of the contact loop written here from the paper
(class `LoopCase`: the ten intervals of eq. 4 over the whole period, no half-wave symmetry; the
angles th1, th3 found by brentq where the stick pieces reach -N*, th2 = atan2(sqrt(B^2 - d^2), d);
the describing functions by scipy.integrate.quad with the breakpoints as `points`, epsrel 1e-13).
The C closed forms must match it to 1e-10 relative over B/d in (1, 50] down to B/d = 1 + 1e-6.
The only rewriting in the reference is exact: v - d = (B - d) - B (1 - cos theta) with
1 - cos t = 2 sin^2(t/2), which keeps the pieces accurate as B -> d+ (otherwise v - d would be the
difference of two nearly equal numbers and the reference itself would lose ~6 digits at 1 + 1e-6).
Quantities that vanish by symmetry (p_c, Coulomb f_k, full-stick f_c) have no scale of their own:
they are compared with 1e-10 * p_k, the normal stiffness of the same amplitude (their quadrature
residue is rounding of stiffness-sized pieces).
"""

from __future__ import annotations

import math
import sys
from dataclasses import dataclass

import numpy as np
import pytest
from scipy.integrate import quad
from scipy.optimize import brentq

from tests.support.cphysics import (
    COULOMB_DF,
    MACROSLIP_DF,
    MACROSLIP_TD,
    PROJECTION_CONSISTENT,
    PROJECTION_PAPER,
    REGIME_FULL_STICK,
    REGIME_OPEN,
    REGIME_STICK_SLIP,
    ContactParams,
    PhysicsLib,
)

TWO_PI = 2.0 * math.pi


def vers(t: float) -> float:
    """1 - cos t, accurate near t = 0 and t = 2 pi."""
    x = t if t <= math.pi else TWO_PI - t
    return 2.0 * math.sin(0.5 * x) ** 2


def opc(t: float) -> float:
    """1 + cos t, accurate near t = pi."""
    return 2.0 * math.sin(0.5 * (t - math.pi)) ** 2


@dataclass(frozen=True)
class LoopCase:
    """One contact configuration and amplitude B > d; kind: 'macroslip' or 'coulomb'."""

    B: float
    kn: float
    kdRatio: float
    mu: float
    gamma: float
    d: float
    kind: str = "macroslip"

    @property
    def kd(self) -> float:
        return self.kdRatio * self.kn

    @property
    def eps(self) -> float:
        return self.B - self.d

    @property
    def nstar(self) -> float:  # N* = mu k_n cos g (B - d)
        return self.mu * self.kn * math.cos(self.gamma) * self.eps

    @property
    def full_stick(self) -> bool:  # docs/model.md s.3
        return self.kind == "macroslip" and self.kd * math.tan(self.gamma) < self.mu * self.kn

    # --- eq. 3, eq. 4 pieces (theta is the phase; v = B cos theta, Delta_u = v sin g) ---
    def v_minus_d(self, t: float) -> float:
        return self.eps - self.B * vers(t)

    def v_plus_d(self, t: float) -> float:
        return -self.eps + self.B * opc(t)

    def normal_force(self, t: float) -> float:
        """Eq. 3 at phase t, contact pieces picked by sign (exact forms near the gap)."""
        cg = math.cos(self.gamma)
        vm, vp = self.v_minus_d(t), self.v_plus_d(t)
        if vm > 0:
            return self.kn * vm * cg
        if vp < 0:
            return self.kn * vp * cg
        return 0.0

    def piece1(self, t: float) -> float:  # k_d (Du - B sin g) + mu k_n cos g (v - d)
        sg, cg = math.sin(self.gamma), math.cos(self.gamma)
        return -self.kd * self.B * sg * vers(t) + self.mu * self.kn * cg * self.v_minus_d(t)

    def piece4(self, t: float) -> float:  # k_d (Du + d sin g)
        return self.kd * math.sin(self.gamma) * self.v_plus_d(t)

    def piece6(self, t: float) -> float:  # k_d (Du + B sin g) + mu k_n cos g (v + d)
        sg, cg = math.sin(self.gamma), math.cos(self.gamma)
        return self.kd * self.B * sg * opc(t) + self.mu * self.kn * cg * self.v_plus_d(t)

    def piece9(self, t: float) -> float:  # k_d (Du - d sin g)
        return self.kd * math.sin(self.gamma) * self.v_minus_d(t)

    def angles(self) -> tuple[float, float, float]:
        """(th1, th2, th3); th1, th3 as roots of piece + N* = 0 (stick reaches the slip limit)."""
        th2 = math.atan2(math.sqrt(self.eps * (self.B + self.d)), self.d)
        if self.kind == "coulomb":
            return 0.0, th2, math.pi - th2
        if self.full_stick:
            return math.nan, th2, math.nan
        ns = self.nstar
        kw = dict(xtol=1e-300, rtol=4 * np.finfo(float).eps, maxiter=500)
        th1 = 0.0 if ns == 0 else brentq(lambda t: self.piece1(t) + ns, 0.0, th2, **kw)
        th3 = math.pi - th2 if ns == 0 else brentq(lambda t: self.piece4(t) + ns, math.pi - th2, math.pi, **kw)
        return th1, th2, th3

    def breakpoints(self) -> list[float]:
        th1, th2, th3 = self.angles()
        if self.full_stick:
            pts = [th2, math.pi - th2, math.pi, math.pi + th2, TWO_PI - th2]
        else:
            pts = [th1, th2, math.pi - th2, th3, math.pi, math.pi + th1, math.pi + th2, TWO_PI - th2, math.pi + th3]
        return sorted({p for p in pts if 0.0 < p < TWO_PI})

    def friction(self, t: float, ang: tuple[float, float, float] | None = None) -> float:
        """Eq. 4 (ten intervals as printed), its Coulomb limit, or full stick F_f = (k_d tan g/k_n) F_n."""
        th1, th2, th3 = ang if ang is not None else self.angles()
        if self.full_stick:
            return self.kdRatio * math.tan(self.gamma) * self.normal_force(t)
        ns, pi = self.nstar, math.pi
        if self.kind == "coulomb":
            if t < th2 or pi - th2 <= t < pi:
                return -ns
            if pi <= t < pi + th2 or t >= TWO_PI - th2:
                return ns
            return 0.0
        if t < th1:
            return self.piece1(t)
        if t < th2:
            return -ns
        if t < pi - th2:
            return 0.0
        if t < th3:
            return self.piece4(t)
        if t < pi:
            return -ns
        if t < pi + th1:
            return self.piece6(t)
        if t < pi + th2:
            return ns
        if t < TWO_PI - th2:
            return 0.0
        if t < pi + th3:
            return self.piece9(t)
        return ns

    def state(self, t: float, ang: tuple[float, float, float]) -> int:
        """docs/model-notes.md s.4: 1 stick on intervals 1, 4, 6, 9; 2 slip on 2, 5, 7, 10; 0 open on 3, 8."""
        if self.full_stick:
            return 1
        th1, th2, th3 = ang
        pi = math.pi
        edges = [
            (th1, 1),
            (th2, 2),
            (pi - th2, 0),
            (th3, 1),
            (pi, 2),
            (pi + th1, 1),
            (pi + th2, 2),
            (TWO_PI - th2, 0),
            (pi + th3, 1),
        ]
        for edge, st in edges:
            if t < edge:
                return st
        return 2

    # --- describing functions by quadrature (docs/model.md s.3: per unit v) ---
    def integral(self, f, epsabs: float = 0.0) -> float:
        val, _ = quad(f, 0.0, TWO_PI, points=self.breakpoints(), epsabs=epsabs, epsrel=1e-13, limit=400)
        return val

    def quadrature(self) -> dict[str, float]:
        """fk, fcOmega (= f_c omega), pk and pc (should vanish), all by quad of the loop."""
        ang = self.angles()
        B = self.B
        pk = self.integral(lambda t: self.normal_force(t) * math.cos(t)) / (math.pi * B)
        # absolute floor for integrals that vanish by symmetry: 1e-13 of the p_k integral
        scale = abs(pk) * math.pi * B * 1e-13
        fk = self.integral(lambda t: self.friction(t, ang) * math.cos(t), scale) / (math.pi * B)
        fc_omega = -self.integral(lambda t: self.friction(t, ang) * math.sin(t), scale) / (math.pi * B)
        pc_omega = -self.integral(lambda t: self.normal_force(t) * math.sin(t), scale) / (math.pi * B)
        return dict(fk=fk, fcOmega=fc_omega, pk=pk, pcOmega=pc_omega)

    def dissipation(self) -> float:
        """Closed integral of F_f dv over one cycle: quad of F_f(theta) dv/dtheta, dv/dtheta = -B sin."""
        ang = self.angles()
        scale = self.nstar * self.B * 1e-13  # only matters in full stick, where the work is 0
        return self.integral(lambda t: self.friction(t, ang) * (-self.B * math.sin(t)), scale)


# ---------------------------------------------------------------------------------------------------
D = 3e-5  # gap [m]
MU = 0.33
KD_PRINTED = 0.608695652173913  # 2(1-nu)/(2+nu), nu = 0.3 (paper)
KD_MINDLIN = 0.8235294117647058  # 2(1-nu)/(2-nu)
GAMMAS = [math.pi / 3, math.pi / 4, math.pi / 5, math.pi / 6, math.pi / 7]
KNS = [1e5, 1e6, 1e7]
RATIOS = sorted(set(np.round(1.0 + np.logspace(-6, math.log10(49.0), 38), 15)) | {1.001, 1.01})
OMEGA = 3 * 2 * math.pi * 5000 / 60  # EO 3 at 5000 rpm [rad/s]
RTOL = 1e-10


@pytest.fixture(scope="module")
def phys(physics_lib) -> PhysicsLib:
    return PhysicsLib(physics_lib)


def params(case: LoopCase) -> ContactParams:
    return ContactParams(case.kn, case.kdRatio, case.mu, case.gamma, case.d)


def compare(phys: PhysicsLib, case: LoopCase, errors: dict[str, float] | None = None, fk_floor: float = 0.0) -> None:
    """C closed forms vs the reference quadrature for one case (both projections). fk_floor: an
    absolute scale added to |f_k| in its tolerance where f_k is a near-cancellation of larger pieces."""
    model = COULOMB_DF if case.kind == "coulomb" else MACROSLIP_DF
    ref = case.quadrature()
    pk = ref["pk"]
    rc, df = phys.describe(params(case), case.B, model, PROJECTION_PAPER)
    assert rc == 0
    vals = df.as_dict()
    assert all(math.isfinite(v) for v in vals.values()), vals
    want = REGIME_FULL_STICK if case.full_stick else REGIME_STICK_SLIP
    assert df.regime == want
    errs = {"pk": abs(df.pk - pk) / abs(pk), "pc": abs(ref["pcOmega"]) / pk}
    if case.kind == "coulomb":
        errs["fk"] = abs(df.fk - ref["fk"]) / pk  # 0 by symmetry
        errs["fc"] = abs(df.fcOmega - ref["fcOmega"]) / ref["fcOmega"]
    elif case.full_stick:
        errs["fk"] = abs(df.fk - ref["fk"]) / abs(ref["fk"])
        errs["fc"] = abs(df.fcOmega - ref["fcOmega"]) / pk  # 0: no hysteresis in full stick
        assert df.fcOmega == 0.0
    else:
        errs["fk"] = abs(df.fk - ref["fk"]) / (abs(ref["fk"]) + fk_floor)
        errs["fc"] = abs(df.fcOmega - ref["fcOmega"]) / abs(ref["fcOmega"])
    th1, th2, th3 = case.angles()
    errs["th2"] = abs(df.theta2 - th2) / th2
    if not case.full_stick:
        errs["th1"] = abs(df.theta1 - th1) / max(th1, th2 * 1e-3)
        errs["th3"] = abs(df.theta3 - th3) / th3
    for name, e in errs.items():
        assert e <= RTOL, (name, e, case, vals, ref)
        if errors is not None:
            errors[name] = max(errors.get(name, 0.0), e)
    # projections (eq. 12-13 and the consistent one from eq. 18), from the reference values
    sg, cg = math.sin(case.gamma), math.cos(case.gamma)
    assert df.Keq == pytest.approx((ref["fk"] + pk) * sg, rel=RTOL, abs=RTOL * fk_floor)
    assert df.CeqOmega == pytest.approx(ref["fcOmega"] * sg, rel=RTOL, abs=RTOL * pk)
    rc, dfc = phys.describe(params(case), case.B, model, PROJECTION_CONSISTENT)
    assert rc == 0
    assert (dfc.fk, dfc.fcOmega, dfc.pk) == (df.fk, df.fcOmega, df.pk)
    assert dfc.Keq == pytest.approx(ref["fk"] * sg + pk * cg, rel=RTOL, abs=RTOL * fk_floor)
    assert dfc.CeqOmega == df.CeqOmega


def grid_errors(phys: PhysicsLib, gamma: float, kd: float, kind: str = "macroslip") -> dict[str, float]:
    errors: dict[str, float] = {}
    for kn in KNS:
        for ratio in RATIOS:
            compare(phys, LoopCase(B=D * ratio, kn=kn, kdRatio=kd, mu=MU, gamma=gamma, d=D, kind=kind), errors)
    return errors


@pytest.mark.parametrize("kd", [KD_PRINTED, KD_MINDLIN])
@pytest.mark.parametrize("gamma", GAMMAS)
def test_closed_forms_vs_quadrature_grid(phys: PhysicsLib, gamma: float, kd: float) -> None:
    """f_k (eq. 7), f_c (eq. 8 fixed), p_k (eq. 10) = quadrature of eq. 3/4, B/d in (1, 50]."""
    grid_errors(phys, gamma, kd)


@pytest.mark.parametrize("gamma", GAMMAS)
def test_coulomb_vs_quadrature_grid(phys: PhysicsLib, gamma: float) -> None:
    """Coulomb DF (theta1 = 0, theta3 = pi - theta2) vs quadrature, and vs f_c = 4 N* (1 - d/B)/(pi B omega)."""
    grid_errors(phys, gamma, KD_PRINTED, "coulomb")
    for ratio in RATIOS:
        case = LoopCase(B=D * ratio, kn=1e7, kdRatio=KD_PRINTED, mu=MU, gamma=gamma, d=D, kind="coulomb")
        ref = case.quadrature()
        assert ref["fcOmega"] == pytest.approx(4 * case.nstar * (1 - D / case.B) / (math.pi * case.B), rel=RTOL)
        assert abs(ref["fk"]) <= RTOL * ref["pk"]


def test_printed_kd_at_pi_over_7_is_full_stick(phys: PhysicsLib) -> None:
    cp = ContactParams(1e7, KD_PRINTED, MU, math.pi / 7, D)
    assert KD_PRINTED * math.tan(math.pi / 7) < MU
    assert phys.regime(cp, 2 * D) == REGIME_FULL_STICK
    assert phys.regime(cp, 2 * D, COULOMB_DF) == REGIME_STICK_SLIP  # Coulomb never sticks
    assert phys.regime(ContactParams(1e7, KD_MINDLIN, MU, math.pi / 7, D), 2 * D) == REGIME_STICK_SLIP


@pytest.mark.parametrize("gamma", GAMMAS)
@pytest.mark.parametrize("rel", [1e-4, 1e-7])
def test_regime_boundary_both_sides(phys: PhysicsLib, gamma: float, rel: float) -> None:
    """k_d tan g = mu k_n: just above is the paper's loop (th1 -> th2, th3 -> pi), just below full stick.
    Both sides agree with their own quadrature; f_c jumps to 0 (the loop at a = b still has area)."""
    kd_b = MU / math.tan(gamma)
    for ratio in (1.0 + 1e-6, 1.01, 1.5, 10.0):
        above = LoopCase(B=D * ratio, kn=1e6, kdRatio=kd_b * (1 + rel), mu=MU, gamma=gamma, d=D)
        below = LoopCase(B=D * ratio, kn=1e6, kdRatio=kd_b * (1 - rel), mu=MU, gamma=gamma, d=D)
        assert not above.full_stick and below.full_stick
        compare(phys, above)
        compare(phys, below)
        _, dfa = phys.describe(params(above), above.B)
        assert dfa.theta1 == pytest.approx(dfa.theta2, rel=10 * math.sqrt(rel))
        assert dfa.theta3 == pytest.approx(math.pi, rel=10 * math.sqrt(rel))
        assert dfa.fcOmega > 0


@pytest.mark.parametrize("kd", [1e2, 1e4, 1e6])
def test_macroslip_tends_to_coulomb(phys: PhysicsLib, kd: float) -> None:
    """k_d -> infinity: the macroslip DF approaches the Coulomb DF (difference O(b/a)).
    Here f_k ~ N* sqrt(b/a)/B is what remains of pieces of size N* sin(th2)/B that cancel, so the
    quadrature reference is only good to 1e-13 of those pieces: f_k gets that absolute floor."""
    for ratio in (1.0 + 1e-6, 1.01, 2.0, 50.0):
        case = LoopCase(B=D * ratio, kn=1e7, kdRatio=kd, mu=MU, gamma=math.pi / 3, d=D)
        th2 = case.angles()[1]
        compare(phys, case, fk_floor=2 * case.nstar * math.sin(th2) / (math.pi * case.B))
        _, m = phys.describe(params(case), case.B, MACROSLIP_DF)
        _, c = phys.describe(params(case), case.B, COULOMB_DF)
        b_over_a = MU / (kd * math.tan(math.pi / 3))
        assert abs(m.fcOmega - c.fcOmega) <= 2 * b_over_a * c.fcOmega
        assert abs(m.fk) <= 10 * math.sqrt(b_over_a) * m.pk


@pytest.mark.parametrize("kind", ["macroslip", "coulomb"])
@pytest.mark.parametrize("gamma", [math.pi / 3, math.pi / 7])
def test_loop_pointwise_and_state(phys: PhysicsLib, kind: str, gamma: float) -> None:
    """contactLoopFriction / contactLoopState against the reference loop, phase by phase."""
    model = COULOMB_DF if kind == "coulomb" else MACROSLIP_DF
    for kd in (KD_PRINTED, KD_MINDLIN):
        for ratio in (1.0 + 1e-6, 1.001, 1.01, 1.3, 2.0, 5.0, 50.0):
            case = LoopCase(B=D * ratio, kn=1e7, kdRatio=kd, mu=MU, gamma=gamma, d=D, kind=kind)
            ang = case.angles()
            bps = case.breakpoints()
            th2 = ang[1]
            thetas = list(np.linspace(0, 2 * math.pi, 721)[:-1])
            for bp in bps + [0.0]:
                thetas += [bp + s * th2 * f for s in (-1, 1) for f in (1e-6, 1e-3, 0.3)]
            scale = max(case.nstar, case.kd * math.sin(gamma) * case.eps)
            cp = params(case)
            for t in thetas:
                t = t % (2 * math.pi)
                if min(abs(t - bp) for bp in bps + [0.0, 2 * math.pi]) < 1e-12:
                    continue
                want = case.friction(t, ang)
                got = phys.loop_friction(cp, case.B, t, model)
                assert abs(got - want) <= 1e-11 * scale, (t, got, want, case)
                assert phys.loop_state(cp, case.B, t, model) == case.state(t, ang), (t, case)
                # the phase is taken modulo 2 pi
                assert phys.loop_friction(cp, case.B, t - 4 * math.pi, model) == pytest.approx(got, abs=1e-9 * scale)


@pytest.mark.parametrize("gamma", GAMMAS)
def test_energy_identity(phys: PhysicsLib, gamma: float) -> None:
    """Closed integral of F_f dv over one cycle (quadrature in theta) = pi omega B^2 f_c, and > 0."""
    for kind, kd in (("macroslip", KD_PRINTED), ("macroslip", KD_MINDLIN), ("coulomb", KD_PRINTED)):
        model = COULOMB_DF if kind == "coulomb" else MACROSLIP_DF
        for ratio in (1.0 + 1e-6, 1.001, 1.01, 1.2, 3.0, 50.0):
            case = LoopCase(B=D * ratio, kn=1e6, kdRatio=kd, mu=MU, gamma=gamma, d=D, kind=kind)
            rc, df = phys.describe(params(case), case.B, model)
            assert rc == 0
            fc = df.fcOmega / OMEGA
            work = case.dissipation()
            if case.full_stick:
                assert fc == 0.0 and abs(work) <= 1e-10 * case.kn * case.eps**2
            else:
                assert work > 0
                assert work == pytest.approx(math.pi * OMEGA * case.B**2 * fc, rel=RTOL)


def test_open_regime_and_continuity(phys: PhysicsLib) -> None:
    """B <= d: regime open, everything 0; B -> d+: p_k ~ (4/3)(k_n cos g/pi)(2 delta)^(3/2),
    f_k ~ delta^(3/2), f_c ~ delta^2, so the DF tends to 0 continuously."""
    cp = ContactParams(1e7, KD_PRINTED, MU, math.pi / 3, D)
    for B in (0.0, 1e-9, D / 2, D * (1 - 1e-15), D):
        rc, df = phys.describe(cp, B)
        assert rc == 0 and df.regime == REGIME_OPEN
        assert all(v == 0 for v in df.as_dict().values())
        assert phys.loop_friction(cp, B, 1.0) == 0.0 and phys.loop_state(cp, B, 0.1) == 0
    cg = math.cos(math.pi / 3)
    prev = None
    for delta in (1e-3, 1e-6, 1e-9, 1e-12):
        rc, df = phys.describe(cp, D * (1 + delta))
        assert rc == 0 and df.regime == REGIME_STICK_SLIP
        asym = (4 / 3) * 1e7 * cg / math.pi * (2 * delta) ** 1.5
        assert df.pk == pytest.approx(asym, rel=5 * delta)
        assert 0 < df.fk < df.pk and 0 < df.fcOmega <= 1e7 * delta**2
        if prev is not None:
            assert df.pk < prev.pk and df.fk < prev.fk and df.fcOmega < prev.fcOmega
        prev = df


def test_normal_force_eq3(phys: PhysicsLib) -> None:
    cp = ContactParams(1e7, KD_PRINTED, MU, math.pi / 4, D)
    cg = math.cos(math.pi / 4)
    for v in np.linspace(-3 * D, 3 * D, 61):
        want = 1e7 * (v - D) * cg if v > D else (1e7 * (v + D) * cg if v < -D else 0.0)
        assert phys.normal_force(cp, v) == pytest.approx(want, rel=1e-14, abs=1e-300)
    assert math.isnan(phys.normal_force(cp, math.nan))
    assert math.isnan(phys.normal_force(ContactParams(-1.0, KD_PRINTED, MU, 1.0, D), 0.0))


def test_time_domain_model_reports_macroslip_df(phys: PhysicsLib) -> None:
    cp = ContactParams(1e7, KD_PRINTED, MU, math.pi / 3, D)
    for B in (3.1e-5, 6e-5, 1e-3):
        assert phys.describe(cp, B, MACROSLIP_TD)[1].as_dict() == phys.describe(cp, B, MACROSLIP_DF)[1].as_dict()


def test_degenerate_parameters_are_finite(phys: PhysicsLib) -> None:
    """Edges of the parameter box (kn, kdRatio, mu = 0, gamma = 0 or pi/2, d = 0, huge B) never give NaN."""
    half_pi = 1.5707963267948966
    cases = [
        (0.0, KD_PRINTED, MU, 1.0, D),
        (1e7, 0.0, MU, 1.0, D),
        (1e7, KD_PRINTED, 0.0, 1.0, D),
        (1e7, KD_PRINTED, MU, 0.0, D),
        (1e7, KD_PRINTED, MU, half_pi, D),
        (1e7, KD_PRINTED, MU, 1.0, 0.0),
        (1e7, 0.0, 0.0, 0.0, 0.0),
        (1e12, 1e9, 1e3, 0.5, 1e-9),
    ]
    for fields in cases:
        cp = ContactParams(*fields)
        assert phys.params_valid(cp)
        for B in (0.0, fields[4] * (1 + 1e-14) + 1e-300, 2 * fields[4] + 1e-9, 1.0, 1e3):
            for model in (MACROSLIP_DF, COULOMB_DF, MACROSLIP_TD):
                for proj in (PROJECTION_PAPER, PROJECTION_CONSISTENT):
                    rc, df = phys.describe(cp, B, model, proj)
                    assert rc == 0, (fields, B, model)
                    assert all(math.isfinite(v) for v in df.as_dict().values()), (fields, B, df.as_dict())
                for t in np.linspace(0, 2 * math.pi, 13):
                    assert math.isfinite(phys.loop_friction(cp, B, t, model))
    # mu = 0: no friction at all
    rc, df = phys.describe(ContactParams(1e7, KD_PRINTED, 0.0, 1.0, D), 2 * D)
    assert df.fk == 0 and df.fcOmega == 0 and df.pk > 0


BAD_PARAMS = [
    (-1.0, KD_PRINTED, MU, 1.0, D),
    (1e7, -0.1, MU, 1.0, D),
    (1e7, KD_PRINTED, -0.1, 1.0, D),
    (1e7, KD_PRINTED, MU, -0.1, D),
    (1e7, KD_PRINTED, MU, 1.6, D),
    (1e7, KD_PRINTED, MU, 1.0, -1e-6),
]
BAD_PARAMS += [
    tuple(bad if i == j else f for j, f in enumerate((1e7, KD_PRINTED, MU, 1.0, D)))
    for i in range(5)
    for bad in (math.nan, math.inf, -math.inf)
]


@pytest.mark.parametrize("fields", BAD_PARAMS)
def test_invalid_params(phys: PhysicsLib, fields: tuple[float, ...]) -> None:
    cp = ContactParams(*fields)
    assert not phys.params_valid(cp)
    for B in (0.0, 6e-5):
        rc, df = phys.describe(cp, B)
        assert rc != 0 and all(v == 0 for v in df.as_dict().values())
        assert math.isnan(phys.loop_friction(cp, B, 1.0))
        assert phys.loop_state(cp, B, 1.0) == 0 and phys.regime(cp, B) == REGIME_OPEN


def test_invalid_arguments(phys: PhysicsLib) -> None:
    cp = ContactParams(1e7, KD_PRINTED, MU, 1.0, D)
    for B in (math.nan, math.inf, -math.inf, -1e-5, -0.0 - 1e-300):
        rc, df = phys.describe(cp, B)
        assert rc != 0 and all(v == 0 for v in df.as_dict().values())
        assert math.isnan(phys.loop_friction(cp, B, 0.5)) and phys.loop_state(cp, B, 0.5) == 0
        assert phys.regime(cp, B) == REGIME_OPEN
    for model in (0, 4, -1):
        assert phys.describe(cp, 6e-5, model)[0] != 0
        assert math.isnan(phys.loop_friction(cp, 6e-5, 0.5, model))
    for proj in (0, 3):
        assert phys.describe(cp, 6e-5, MACROSLIP_DF, proj)[0] != 0
    for t in (math.nan, math.inf):
        assert math.isnan(phys.loop_friction(cp, 6e-5, t)) and phys.loop_state(cp, 6e-5, t) == 0
    assert phys.lib.contactDescribe(None, MACROSLIP_DF, PROJECTION_PAPER, 6e-5, None) != 0
    assert phys.lib.contactDescribe(cp, MACROSLIP_DF, PROJECTION_PAPER, 6e-5, None) != 0
    assert phys.lib.contactRegime(None, 6e-5) == REGIME_OPEN


if __name__ == "__main__":  # report the worst errors over the grid: python tests/fmu/test_c_contact.py LIB
    lib = PhysicsLib(sys.argv[1])
    worst: dict[str, float] = {}
    for g in GAMMAS:
        for k in (KD_PRINTED, KD_MINDLIN):
            for name, e in grid_errors(lib, g, k).items():
                worst[f"macroslip {name}"] = max(worst.get(f"macroslip {name}", 0.0), e)
        for name, e in grid_errors(lib, g, KD_PRINTED, "coulomb").items():
            worst[f"coulomb {name}"] = max(worst.get(f"coulomb {name}", 0.0), e)
    for name, e in sorted(worst.items()):
        print(f"{name:16s} {e:.3e}")
