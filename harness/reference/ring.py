"""Monolithic reference of the bladed-disk ring (docs/model.md s.8): N blades and N
Jenkins contacts as ONE ODE, integrated by scipy (DOP853) with its own event location
(solve_ivp terminal events, restarted after each discrete update).

Blade i (Galerkin constants of harness.reference.galerkin, constant speed):
    M q_i'' + C0 q_i' + K0(Omega) q_i = G f_i(t) - F_c,i + F_c,i-1,
    f_i(t) = F_w0 sin(omega t + 2 pi EO i / N)   (the blades' built-in travelling wave),
contact j between blade j and blade j+1 mod N on u_j = q_j - q_{j+1}: the time-domain element of
harness.reference.shroud_contact written on the ODE state (friction force F_f as the stick state,
F_c = F_n cos g + F_f sin g, eq. 14). Extra states: the friction energy of every contact, and per
blade the viscous dissipation int C0 q'^2 and the aero work int G f q' (energy balance).
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field, replace
from typing import Any, Mapping

import numpy as np
from scipy.integrate import solve_ivp

from harness.reference.blade import galerkin
from harness.model.contact import STATE_OPEN, STATE_SLIP, STATE_STICK
from harness.reference.contact import contact_consts
from harness.model.params import validate


@dataclass
class _Contact:
    mode: int = STATE_OPEN
    side: int = 1
    s: int = 1
    F0: float = 0.0  # friction force at the stick anchor [N]
    u0: float = 0.0  # u at the stick anchor [m]


@dataclass(frozen=True)
class RingSpec:
    """The ring: as harness.system.ring.Ring (parameters by FMU variable name)."""

    n: int = 4
    engine_order: int = 3
    speed: float = 5000.0  # [rpm]
    fw0: float = 100.0  # [N/m]
    blade: Mapping[str, Any] = field(default_factory=dict)
    contact: Mapping[str, Any] = field(default_factory=dict)
    blade_each: tuple[Mapping[str, Any], ...] = ()  # per-blade overrides of `blade` (mistuning), empty or N


@dataclass
class RingState:
    """The reference's full state at time t: y (q, v and the energy integrals, as in `solve`) and
    every contact's discrete state (mode, side, slip sign, stick anchor)."""

    t: float
    y: np.ndarray
    contacts: list[_Contact]

    @classmethod
    def rest(cls, n: int) -> "RingState":
        """At rest at t = 0, every contact open."""
        return cls(0.0, np.zeros(5 * n), [_Contact() for _ in range(n)])

    def copy(self) -> "RingState":
        return RingState(self.t, self.y.copy(), [replace(c) for c in self.contacts])


class MonolithicRing:
    """The ring ODE; `solve(t_eval)` integrates from rest, or from a RingState."""

    def __init__(self, spec: RingSpec, rtol: float = 1e-11):
        self.spec, self.N, self.rtol = spec, spec.n, rtol
        if spec.blade_each and len(spec.blade_each) != self.N:
            raise ValueError(f"blade_each has {len(spec.blade_each)} entries for {self.N} blades")
        Omega = 2 * math.pi * spec.speed / 60
        gs = [
            galerkin(validate({**dict(spec.blade), **(dict(spec.blade_each[i]) if spec.blade_each else {})}))
            for i in range(self.N)
        ]
        # per blade (arrays of N; equal for a tuned ring)
        self.M, self.C0, self.G = (np.array([getattr(g, a) for g in gs]) for a in ("M", "C0", "loadGain"))
        self.K0 = np.array([float(g.K0(Omega)) for g in gs])
        self.omega = spec.engine_order * Omega
        self.lead = 2 * math.pi * spec.engine_order * np.arange(self.N) / self.N
        cc = contact_consts(dict(spec.contact))
        self.cc = cc
        self.sg, self.cg = math.sin(cc.gamma), math.cos(cc.gamma)
        self.a, self.b = cc.kd * self.sg, cc.mu * cc.kn * self.cg

    # state y = [q (N), v (N), Efric (N), Evisc (N), Waero (N)]
    def _u(self, y: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
        q, v = y[: self.N], y[self.N : 2 * self.N]
        return q - np.roll(q, -1), v - np.roll(v, -1)

    def _friction(self, c: _Contact, u: float) -> float:
        if c.mode == STATE_STICK:
            return c.F0 + self.a * (u - c.u0)
        if c.mode == STATE_SLIP:
            return c.s * self.b * (c.side * u - self.cc.d)
        return 0.0

    def forces(self, cs: list[_Contact], y: np.ndarray) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
        """F_c per contact, F_f per contact, slip power per contact."""
        u, du = self._u(y)
        Fc, Ff, P = np.zeros(self.N), np.zeros(self.N), np.zeros(self.N)
        for j, c in enumerate(cs):
            if c.mode == STATE_OPEN:
                continue
            Fn = self.cc.kn * self.cg * (u[j] - c.side * self.cc.d)  # eq. 3
            Ff[j] = self._friction(c, u[j])
            Fc[j] = Fn * self.cg + Ff[j] * self.sg  # eq. 14
            if c.mode == STATE_SLIP:
                P[j] = Ff[j] * (self.sg * du[j] - c.s * self.b * c.side * du[j] / self.cc.kd)
        return Fc, Ff, P

    def rhs(self, t: float, y: np.ndarray, cs: list[_Contact]) -> np.ndarray:
        N = self.N
        q, v = y[:N], y[N : 2 * N]
        Fc, _, P = self.forces(cs, y)
        f = self.spec.fw0 * np.sin(self.omega * t + self.lead)
        F = -Fc + np.roll(Fc, 1)  # side A of contact i, side B of contact i-1
        acc = (self.G * f + F - self.C0 * v - self.K0 * q) / self.M
        return np.concatenate([v, acc, P, self.C0 * v * v, self.G * f * v])

    def _events(self, cs: list[_Contact]) -> list:
        """Terminal events (direction -1) of every active switching function, tagged (j, kind)."""
        evs = []
        d = self.cc.d
        for j, c in enumerate(cs):

            def mk(fun, tag):
                fun.terminal, fun.direction, fun.tag = True, -1, tag
                evs.append(fun)

            if c.mode == STATE_OPEN:
                mk(lambda t, y, *_, j=j: d - self._u(y)[0][j], (j, "enter+"))
                mk(lambda t, y, *_, j=j: d + self._u(y)[0][j], (j, "enter-"))
            else:
                mk(lambda t, y, *_, j=j, c=c: c.side * self._u(y)[0][j] - d, (j, "leave"))
            if c.mode == STATE_STICK:
                for sgn in (1, -1):
                    mk(
                        lambda t, y, *_, j=j, c=c, sgn=sgn: (
                            self.b * (c.side * self._u(y)[0][j] - d) - sgn * self._friction(c, self._u(y)[0][j])
                        ),
                        (j, "slip+" if sgn > 0 else "slip-"),
                    )
            elif c.mode == STATE_SLIP:
                cs_ = c.s * self.a - c.side * self.b  # slip goes on while cs u' >= 0
                if cs_ != 0:
                    sg = math.copysign(1.0, cs_)
                    mk(lambda t, y, *_, j=j, sg=sg: sg * self._u(y)[1][j], (j, "stick"))
        return evs

    def _apply(self, c: _Contact, kind: str, u: float, du: float) -> None:
        if kind.startswith("enter"):
            c.side = 1 if kind == "enter+" else -1
            if self.a > self.b:  # arrives sliding (model-notes s.2)
                c.mode, c.s = STATE_SLIP, (1 if du > 0 else (-1 if du < 0 else c.side))
            else:
                c.mode, c.F0, c.u0 = STATE_STICK, 0.0, u
        elif kind == "leave":
            c.mode = STATE_OPEN
        elif kind.startswith("slip"):
            c.mode, c.s = STATE_SLIP, 1 if kind == "slip+" else -1
        else:
            c.F0, c.u0, c.mode = self._friction(c, u), u, STATE_STICK

    @staticmethod
    def _due(ev: Any, t: float, y: np.ndarray, f: np.ndarray, dt: float = 1e-10) -> bool:
        """The switching function `ev` is decreasing and reaches 0 within 1e-12 s (or is below)."""
        g0 = ev(t, y)
        slope = (ev(t + dt, y + dt * f) - g0) / dt
        return slope < 0.0 and g0 <= -slope * 1e-12

    def _leaving(self, cs: list[_Contact], j: int, t: float, y: np.ndarray) -> bool:
        """Contact j's normal load vanishes at this instant (its "leave" function is due)."""
        f = self.rhs(t, y, cs)
        return any(ev.tag == (j, "leave") and self._due(ev, t, y, f) for ev in self._events(cs))

    def _simultaneous(self, cs: list[_Contact], t: float, y: np.ndarray, switched: dict[int, str]) -> int:
        """Events at the same instant as the one located, applied here: a terminal event with
        direction -1 never sees a switching function that is already below 0. Two kinds:
        - other contacts (a symmetric ring switches mirrored contacts together): a switching function
          of a contact not switched yet that is decreasing and reaches 0 within 1e-12 s (or is already
          below) crossed with the one located;
        - the contact that just left, when the gap is zero: u passes through +d and -d at once, so it
          leaves one side and enters the other at the same instant (the located point may lie a
          rounding past u = 0, where the other side's function d + sigma u is already below 0).
        `switched` maps each contact switched at this instant to its last event. Returns the number
        applied."""
        n = 0
        while True:
            hit = None
            f = self.rhs(t, y, cs)
            for ev in self._events(cs):
                j, kind = ev.tag
                if j in switched and not (switched[j] == "leave" and kind.startswith("enter")):
                    continue
                if self._due(ev, t, y, f):
                    hit = (j, kind)
                    break
            if hit is None:
                return n
            u, du = self._u(y)
            self._apply(cs[hit[0]], hit[1], u[hit[0]], du[hit[0]])
            switched[hit[0]] = hit[1]
            n += 1

    def solve(self, t_eval: np.ndarray, start: RingState | None = None) -> dict[str, np.ndarray]:
        """q, v, friction energy per contact, viscous dissipation and aero work per blade at t_eval
        (from rest at t = 0 with the contacts open, or from `start`, which is not changed; t_eval
        within [start.t, ...]), the number of events, "end": the RingState at t_eval[-1], and "switches":
        (time, contact states) at the start and after every event."""
        N = self.N
        start = (start or RingState.rest(N)).copy()
        cs, y = start.contacts, start.y
        t0, t_end = start.t, float(t_eval[-1])
        out = np.zeros((len(t_eval), 5 * N))
        done, n_events = 0, 0
        switches = [(t0, [replace(c) for c in cs])]  # the contacts' discrete states from each event on
        while t0 < t_end:
            evs = self._events(cs)
            sol = solve_ivp(
                self.rhs,
                (t0, t_end),
                y,
                method="DOP853",
                rtol=self.rtol,
                atol=1e-15,
                events=evs,
                dense_output=True,
                args=(cs,),
            )
            if sol.status < 0:
                raise RuntimeError(sol.message)
            t1 = sol.t[-1]
            sel = (t_eval >= t0) & (t_eval <= t1)
            idx = np.nonzero(sel)[0]
            idx = idx[idx >= done]
            if len(idx):
                out[idx] = sol.sol(t_eval[idx]).T
                done = idx[-1] + 1
            if sol.status == 1:  # an event: the earliest one (ties: the first listed)
                hits = [(te[0], i) for i, te in enumerate(sol.t_events) if len(te)]
                _, i = min(hits)
                j, kind = evs[i].tag
                y = sol.y_events[i][0].copy()
                if kind.startswith("slip") and self._leaving(cs, j, t1, y):
                    # the slip limit mu |F_n| and the normal load reach 0 together: the contact
                    # separates (at d = 0 both functions vanish at u = 0 and rounding picks either)
                    kind = "leave"
                u, du = self._u(y)
                self._apply(cs[j], kind, u[j], du[j])
                n_events += 1
                n_events += self._simultaneous(cs, t1, y, {j: kind})
                switches.append((t1, [replace(c) for c in cs]))
            else:
                y = sol.y[:, -1]
            t0 = t1
        names = ("q", "v", "Efric", "Evisc", "Waero")
        res = {k: out[:, i * N : (i + 1) * N] for i, k in enumerate(names)}
        res["time"] = np.asarray(t_eval)
        res["events"] = np.array(n_events)
        res["end"] = RingState(t0, np.array(y, dtype=float), cs)
        res["switches"] = switches
        return res
