"""Independent Python reference of the ShroudContact element (docs/model.md s.8): the macroslip
contact between two shrouds driven by a prescribed relative displacement u(t) = q_A - q_B.

Written from docs/model.md s.8 and docs/model-notes.md s.2, not from the C (which tracks the slider
position w, finds events as polynomial roots and integrates the friction energy in closed form).
Here the state is the friction force F_f itself: in stick F_f = F_0 + a (u - u_0) (a = k_d sin g);
in slip F_f = s mu |F_n| = s b (sigma u - d) (b = mu k_n cos g); open F_f = 0. Events are found on
the analytic motion by scanning a grid and brentq; the friction energy is the quadrature (scipy
quad) of F_f w' with w' = sin(g) u' - F_f' / k_d over each slip piece. The describing-function
variant (frictionModel 1, 2) is F_c = K_eq u + C_eq u' while |u| > d (gating), with K_eq, C_eq from
harness.reference.contact and its energy the quadrature of C_eq u'^2 over the gate-on pieces.
Force on the contact coordinate F_c = F_n cos g + F_f sin g (eq. 14); side A gets -F_c, B +F_c.
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from typing import Any, Callable, Mapping

import numpy as np
from scipy.integrate import quad
from scipy.optimize import brentq

from harness.model.contact import MACROSLIP_TD, STATE_OPEN, STATE_SLIP, STATE_STICK
from harness.reference.contact import contact_consts, describing_function

Fn = Callable[[float], float]


@dataclass(frozen=True)
class Motion:
    """A prescribed relative motion: u(t) [m] and du/dt [m/s], scalar callables."""

    u: Fn
    du: Fn


@dataclass
class _Piece:
    """One mode between two events: [t0, t1], mode, side sigma, slip direction s, F_f and u at t0."""

    t0: float
    t1: float
    mode: int
    side: int
    s: int
    F0: float
    u0: float
    E0: float  # friction energy at t0 [J]


def _first_crossing(g: Fn, t0: float, t1: float, dt: float, tiny: float) -> float | None:
    """First t in (t0, t1] where g(t) < -tiny (grid scan with spacing <= dt, then brentq); None if
    the grid sees none."""
    n = max(1, int(math.ceil((t1 - t0) / dt)))
    ts = np.linspace(t0, t1, n + 1)
    prev = t0
    for t in ts[1:]:
        if g(t) < -tiny:
            if g(prev) < -tiny:  # already negative at the piece start (a reversal)
                return prev
            return brentq(lambda x: g(x) + tiny, prev, t, xtol=1e-16, rtol=4 * np.finfo(float).eps)
        prev = t
    return None


class JenkinsPair:
    """The time-domain element (frictionModel 3) on a motion, from rest with the spring unloaded, or
    with the friction force F0 [N] at the start (in contact there; the caller keeps it in the cone)."""

    def __init__(self, params: Mapping[str, Any], F0: float = 0.0):
        self.cc = contact_consts(params)
        self.F_start = F0
        self.sg, self.cg = math.sin(self.cc.gamma), math.cos(self.cc.gamma)
        self.a = self.cc.kd * self.sg  # F_f per unit u in stick [N/m]
        self.b = self.cc.mu * self.cc.kn * self.cg  # friction limit per unit sigma u - d [N/m]

    def _friction(self, p: _Piece, u: float) -> float:
        if p.mode == STATE_STICK:
            return p.F0 + self.a * (u - p.u0)
        if p.mode == STATE_SLIP:
            return p.s * self.b * (p.side * u - self.cc.d)
        return 0.0

    def _power(self, m: Motion, p: _Piece, t: float) -> float:
        """F_f w' in slip: w' = sin g u' - F_f'/k_d, F_f' = s b sigma u'."""
        du = m.du(t)
        Ff = self._friction(p, m.u(t))
        return Ff * (self.sg * du - p.s * self.b * p.side * du / self.cc.kd)

    def pieces(self, m: Motion, t_end: float, dt_scan: float) -> list[_Piece]:
        """The mode pieces over [0, t_end]."""
        cc, u0 = self.cc, m.u(0.0)
        side = 1 if u0 >= 0 else -1
        closed = abs(u0) > cc.d
        s0 = (1 if self.F_start > 0 else -1) if closed and self.F_start != 0.0 else side
        p = _Piece(
            0.0, t_end, STATE_STICK if closed else STATE_OPEN, side, s0, self.F_start if closed else 0.0, u0, 0.0
        )
        out = []
        scale = self.b * cc.d + self.a * cc.d + 1e-300
        for _ in range(100000):
            cands: list[tuple[float, str]] = []
            if p.mode == STATE_OPEN:
                fs = [("enter+", lambda t: cc.d - m.u(t)), ("enter-", lambda t: cc.d + m.u(t))]
                tiny = 1e-13 * cc.d
            else:
                fs = [("leave", lambda t, p=p: p.side * m.u(t) - cc.d)]
                tiny = 1e-13 * cc.d
            for name, g in fs:
                t = _first_crossing(g, p.t0, t_end, dt_scan, tiny)
                if t is not None:
                    cands.append((t, name))
            if p.mode == STATE_STICK:
                for name, sgn in (("slip+", 1), ("slip-", -1)):
                    g = lambda t, sgn=sgn, p=p: self.b * (p.side * m.u(t) - cc.d) - sgn * self._friction(p, m.u(t))
                    t = _first_crossing(g, p.t0, t_end, dt_scan, 1e-12 * scale)
                    if t is not None:
                        cands.append((t, name))
            elif p.mode == STATE_SLIP:
                cs = p.s * self.a - p.side * self.b  # slip goes on while cs u' >= 0
                if cs != 0:
                    g = lambda t, c=math.copysign(1.0, cs): c * m.du(t)
                    t = _first_crossing(g, p.t0, t_end, dt_scan, 1e-13 * abs(m.du(p.t0)) + 1e-18)
                    if t is not None:
                        cands.append((t, "stick"))
            if not cands:
                p.t1 = t_end
                out.append(p)
                return out
            te, name = min(cands, key=lambda c: c[0])  # leave is listed first: wins ties
            p.t1 = te
            out.append(p)
            E = p.E0 + (
                quad(lambda t, p=p: self._power(m, p, t), p.t0, te, epsabs=0, epsrel=1e-13, limit=200)[0]
                if p.mode == STATE_SLIP and te > p.t0
                else 0.0
            )
            ue = m.u(te)
            Ff = self._friction(p, ue)
            if name.startswith("enter"):
                side = 1 if name == "enter+" else -1
                if self.a > self.b:  # arrives sliding (model-notes s.2)
                    due = m.du(te)
                    s = 1 if due > 0 else (-1 if due < 0 else side)
                    p = _Piece(te, t_end, STATE_SLIP, side, s, 0.0, ue, E)
                else:
                    p = _Piece(te, t_end, STATE_STICK, side, side, 0.0, ue, E)
            elif name == "leave":
                p = _Piece(te, t_end, STATE_OPEN, p.side, p.s, 0.0, ue, E)
            elif name.startswith("slip"):
                p = _Piece(te, t_end, STATE_SLIP, p.side, 1 if name == "slip+" else -1, 0.0, ue, E)
            else:
                p = _Piece(te, t_end, STATE_STICK, p.side, p.s, Ff, ue, E)
        raise RuntimeError("more than 100000 contact events")

    def evaluate(self, m: Motion, t_out: np.ndarray, dt_scan: float) -> dict[str, np.ndarray]:
        """forceA, forceB, normalForce, frictionForce, contactState, dissipatedEnergy at t_out."""
        ps = self.pieces(m, float(t_out[-1]), dt_scan)
        res = {
            k: np.zeros(len(t_out))
            for k in ("forceA", "forceB", "normalForce", "frictionForce", "contactState", "dissipatedEnergy")
        }
        j = 0
        for i, t in enumerate(t_out):
            while j + 1 < len(ps) and t > ps[j].t1:
                j += 1
            p = ps[j]
            u = m.u(t)
            Fn = self.cc.kn * self.cg * (u - p.side * self.cc.d) if p.mode != STATE_OPEN else 0.0  # eq. 3
            Ff = self._friction(p, u)
            Fc = Fn * self.cg + Ff * self.sg  # eq. 14
            E = p.E0
            if p.mode == STATE_SLIP and t > p.t0:
                E += quad(lambda x: self._power(m, p, x), p.t0, t, epsabs=0, epsrel=1e-13, limit=200)[0]
            res["forceA"][i], res["forceB"][i] = -Fc, Fc
            res["normalForce"][i], res["frictionForce"][i] = Fn, Ff
            res["contactState"][i], res["dissipatedEnergy"][i] = p.mode, E
        return res


def df_pair(
    params: Mapping[str, Any],
    m: Motion,
    t_out: np.ndarray,
    omega: float,
    model: int,
    B: float,
    projection: int = 1,
    gating: bool = True,
    dt_scan: float = 1e-5,
) -> dict[str, np.ndarray]:
    """The describing-function variant at the fixed amplitude B and frequency omega [rad/s]."""
    if model == MACROSLIP_TD:
        raise ValueError("df_pair is for frictionModel 1 and 2")
    cc = contact_consts(params)
    df = describing_function(params, B, omega, model, projection)
    if not B > cc.d:
        df_zero = True
    else:
        df_zero = False
    # gate switches: |u| crosses d
    t_end = float(t_out[-1])
    g = lambda t: abs(m.u(t)) - cc.d  # noqa: E731
    ts = np.linspace(0.0, t_end, max(2, int(math.ceil(t_end / dt_scan)) + 1))
    gv = np.array([g(t) for t in ts])
    cross = [brentq(g, ts[i], ts[i + 1], xtol=1e-16) for i in range(len(ts) - 1) if (gv[i] > 0) != (gv[i + 1] > 0)]
    edges = np.array([0.0, *cross, t_end])

    def on(t: float) -> bool:
        return (not gating) or abs(m.u(t)) > cc.d

    res = {k: np.zeros(len(t_out)) for k in ("forceA", "forceB", "normalForce", "frictionForce", "dissipatedEnergy")}
    E, k = 0.0, 0  # energy up to edges[k]
    for i, t in enumerate(t_out):
        while k + 1 < len(edges) and edges[k + 1] <= t:
            mid = 0.5 * (edges[k] + edges[k + 1])
            if not df_zero and on(mid):
                E += quad(lambda x: df.Ceq * m.du(x) ** 2, edges[k], edges[k + 1], epsabs=0, epsrel=1e-13)[0]
            k += 1
        Ei = E
        if not df_zero and t > edges[k] and on(0.5 * (edges[k] + t)):
            Ei += quad(lambda x: df.Ceq * m.du(x) ** 2, edges[k], t, epsabs=0, epsrel=1e-13)[0]
        u, du = m.u(t), m.du(t)
        gate = (not df_zero) and on(t)
        Fc = (df.Keq * u + df.Ceq * du) if gate else 0.0
        res["forceA"][i], res["forceB"][i] = -Fc, Fc
        res["normalForce"][i] = df.pk * u if gate else 0.0
        res["frictionForce"][i] = (df.fk * u + df.fc * du) if gate else 0.0
        res["dissipatedEnergy"][i] = Ei
    return res
