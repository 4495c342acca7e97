"""Independent Python reference, part 3: time simulation of eq. 27 (docs/model-notes.md s.1-4).

A hybrid simulation on scipy's DOP853 stepper (harness.reference.hybrid, tight tolerances):
continuous states (q, q', psi, E, w), a discrete state (amplitude B in use, gating flag g, Jenkins
mode/side/slip direction, period counter, running max |q|), integration segment by segment with
terminal events at every switching instant (|q| = d, stick/slip, period end psi = 2 pi k) and a
restart with the updated discrete state; the extrema q' = 0 located inside every step feed the
tracked amplitude (max |q| over a period in continuous time).
Inputs may be non-smooth at caller-given `breakpoints` (e.g. the FMU's communication points when
it is fed piecewise Taylor polynomials): integration restarts there. Output: a numpy structured
array, `time` first, fields named like the FMU outputs. `jenkins_prescribed` drives the Jenkins
element alone with a prescribed harmonic motion (loop and cycle dissipation checks).
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field
from typing import Any, Callable, Mapping, Sequence

import numpy as np
from harness.reference.hybrid import run_segment

from harness.model.params import ParameterError, start_values, validate
from harness.model.galerkin import Galerkin
from harness.reference.blade import galerkin
from harness.model.contact import MACROSLIP_TD
from harness.reference.contact import (
    COULOMB_DF,
    MACROSLIP_DF,
    ContactConsts,
    contact_consts,
    describing_function,
    loop_state,
)
from harness.reference.modes import modal_galerkin, split_modes

OUTPUT_DTYPE = np.dtype(
    [
        ("time", "f8"),
        ("tipDisplacement", "f8"),
        ("tipVelocity", "f8"),
        ("normalForce", "f8"),
        ("frictionForce", "f8"),
        ("Keq", "f8"),
        ("Ceq", "f8"),
        ("amplitude", "f8"),
        ("dissipatedEnergy", "f8"),
        ("naturalFrequency", "f8"),
        ("regime", "i4"),
        ("contactState", "i4"),
    ]
)


def modal_dtype(m: int) -> np.dtype:
    """OUTPUT_DTYPE plus, for m > 1 modes, the modal coordinates, the natural frequencies of modes
    1..m at the current speed and the root bending moment (named like the FMU's outputs)."""
    if m == 1:
        return OUTPUT_DTYPE
    extra = [
        (f"{name}[{i}]", "f8")
        for name in ("modalDisplacement", "modalVelocity", "modeFrequency")
        for i in range(1, m + 1)
    ]
    return np.dtype(OUTPUT_DTYPE.descr + extra + [("rootMoment", "f8")])


OPEN, STICK, SLIP = 0, 1, 2  # Jenkins element mode = contactState
TWO_PI = 2.0 * math.pi


class SimulationError(RuntimeError):
    """The run cannot continue (omega = 0 while a describing function is needed, chattering)."""


def _event(fun: Callable, direction: float, terminal: bool = True) -> Callable:
    fun.direction = direction  # type: ignore[attr-defined]
    fun.terminal = terminal  # type: ignore[attr-defined]
    return fun


class Jenkins:
    """Spring k_d in series with a Coulomb slider limited by mu |F_n(q)| (model-notes s.2); the slider
    position w [m] lives in the Delta_u = q sin(g) coordinate. Mode OPEN / STICK / SLIP, `side` the
    sign of q while in contact, `s` the slip direction."""

    def __init__(self, cc: ContactConsts):
        self.cc = cc
        self.sg, self.cg = math.sin(cc.gamma), math.cos(cc.gamma)
        self.b = cc.mu * cc.kn * self.cg  # dL/d|q| [N/m]
        self.slips_on_contact = cc.kd * self.sg > self.b  # k_d tan g > mu k_n
        self.mode, self.side, self.s = OPEN, 0, 0

    def limit(self, q: float) -> float:
        """L = mu |F_n| [N]."""
        return self.b * max(abs(q) - self.cc.d, 0.0)

    def forces(self, q: float, v: float, w: float) -> tuple[float, float, float, float]:
        """(F_n [N], F_f [N], w' [m/s], friction power F_f w' [W])."""
        cc = self.cc
        if self.mode == OPEN:
            return 0.0, 0.0, self.sg * v, 0.0
        Fn = cc.kn * (q - self.side * cc.d) * self.cg  # eq. 3 on this side
        if self.mode == STICK:
            return Fn, cc.kd * (self.sg * q - w), 0.0, 0.0
        L = self.b * (self.side * q - cc.d)
        Ldot = self.b * self.side * v
        wdot = self.sg * v - self.s * Ldot / cc.kd
        Ff = self.s * L
        return Fn, Ff, wdot, Ff * wdot

    def events(self, qi: int, vi: int, wi: int) -> list[tuple[Callable, Callable]]:
        """Terminal events for the current mode as (function of (t, y), transition) pairs; y[qi] = q,
        y[vi] = q' (vi < 0: q' supplied by the caller through y[-1]), y[wi] = w."""
        cc, d = self.cc, self.cc.d
        out: list[tuple[Callable, Callable]] = []
        if self.mode == OPEN:
            out.append((_event(lambda t, y: y[qi] - d, 1.0), lambda y: self._enter(+1, y[vi])))
            out.append((_event(lambda t, y: y[qi] + d, -1.0), lambda y: self._enter(-1, y[vi])))
            return out
        side = self.side
        out.append((_event(lambda t, y: side * (y[qi] - side * d), -1.0), lambda y: self._set(OPEN, 0, 0)))
        if self.mode == STICK:
            sg, kd, b = self.sg, cc.kd, self.b
            out.append(
                (
                    _event(lambda t, y: kd * (sg * y[qi] - y[wi]) - b * (side * y[qi] - d), 1.0),
                    lambda y: self._set(SLIP, side, +1),
                )
            )
            out.append(
                (
                    _event(lambda t, y: -kd * (sg * y[qi] - y[wi]) - b * (side * y[qi] - d), 1.0),
                    lambda y: self._set(SLIP, side, -1),
                )
            )
        else:
            coef = self.s * cc.kd * self.sg - self.b * side  # s k_d sin g q' - L'
            out.append((_event(lambda t, y: coef * y[vi], -1.0), lambda y: self._set(STICK, side, 0)))
        return out

    def _enter(self, side: int, v: float) -> None:
        if self.slips_on_contact:
            s = int(math.copysign(1.0, v)) if v != 0.0 else side
            self._set(SLIP, side, s)
        else:
            self._set(STICK, side, 0)

    def _set(self, mode: int, side: int, s: int) -> None:
        self.mode, self.side, self.s = mode, side, s

    def consistent_w(self, q: float, w: float) -> float:
        """Slider position right after a transition: unloaded spring when open, on the cone in slip."""
        if self.mode == OPEN:
            return self.sg * q
        if self.mode == SLIP:
            return self.sg * q - self.s * self.limit(q) / self.cc.kd
        return w


@dataclass
class _Discrete:
    B: float
    g: int = 0  # gating flag of the DF models (1: K_eq, C_eq act)
    k: int = 1  # the current excitation period ends at psi = 2 pi k
    qmax: float = 0.0  # running max |q| over the current period [m]
    df: Any = None  # describing function at B (omega-free parts)
    extra: dict = field(default_factory=dict)


def simulate(
    params: Mapping[str, Any] | None,
    stop_time: float,
    aero: Callable[[float], float],
    speed_rpm: Callable[[float], float],
    t_eval: Sequence[float] | np.ndarray,
    rtol: float = 1e-11,
    atol: Sequence[float] | float | None = None,
    start_time: float = 0.0,
    breakpoints: Sequence[float] | None = None,
    max_step: float = np.inf,
    initial: tuple[Any, Any] | None = None,
    modes: int | None = None,
) -> np.ndarray:
    """Simulate the FMU's model (model-notes s.1-4) from rest at `start_time` to `stop_time`.

    aero(t) -> f_w [N/m], speed(t) -> n [rpm]; `t_eval` output times in [start_time, stop_time];
    `breakpoints` times where the inputs may be non-smooth (integration restarts there); inside a
    segment [b_k, b_{k+1}] the inputs are read at min(t, b_{k+1} - ulp), i.e. a piecewise input
    callable is used on the piece that starts at b_k up to and including the segment's end (as the
    FMU uses the Taylor polynomial of a communication step up to its end). At an event instant or a
    breakpoint that is also an output time, the post-event state and the new input piece are
    reported.
    `initial` = (q0, q'0) starts elsewhere than at rest (reference-only extension for stability
    tests; psi(start) = 0; the Jenkins element then starts unloaded).
    `modes` (or params["modes"]) m = 1..6: with m > 1 the blade is the m-mode consistent reduction
    (harness.reference.modes), the state (q_1..q_m, q_1'..q_m', psi, E, w), the contact acting on
    the tip displacement sum_i q_i (the force enters every modal equation with psi_i(l) = 1);
    `initial` then holds the m modal displacements and velocities.
    """
    p, m = split_modes(params, modes)
    moved = {k: v for k, v in start_values(p).items() if v != 0}
    if moved:  # not modelled here: refuse rather than silently start at rest
        raise ParameterError(
            f"start values {moved} are not supported by the reference, which starts at rest"
            " (use initial=(q0, q'0) for a displaced start)"
        )
    cc = contact_consts(p)
    model, proj, gating = int(p["frictionModel"]), int(p["projection"]), bool(p["gating"])
    tracked = int(p["amplitudeMode"]) == 2
    EO = int(p["engineOrder"])
    sg, d = math.sin(cc.gamma), cc.d
    if m == 1:
        gal: Galerkin = galerkin(p)
        M, C0, K0s, K0w, G = gal.M, gal.C0, gal.K0static, gal.K0omega2, gal.loadGain
    else:
        mg = modal_galerkin(p, m)
        Minv = np.linalg.inv(mg.M)
    iP, iE, iW = 2 * m, 2 * m + 1, 2 * m + 2  # psi, E, w after (q_1..q_m, q_1'..q_m')

    def tq(y: np.ndarray) -> float:  # tip displacement (m = 1: the state itself, bit for bit)
        return y[0] if m == 1 else float(np.sum(y[:m]))

    def tv(y: np.ndarray) -> float:
        return y[1] if m == 1 else float(np.sum(y[m : 2 * m]))

    jen = Jenkins(cc) if model == MACROSLIP_TD else None
    dfmodel = COULOMB_DF if model == COULOMB_DF else MACROSLIP_DF

    def describe(B: float) -> Any:
        return describing_function(cc, B, 1.0, dfmodel, proj)  # omega = 1: fc holds fc * omega

    ds = _Discrete(B=float(p["B"]))
    ds.df = describe(ds.B)
    ds.g = 1 if not gating else 0  # q = 0 at the start: |q| > d is false (d >= 0)

    def omega_of(t: float) -> float:
        return EO * TWO_PI * speed_rpm(t) / 60.0

    seg = {"end_minus": math.inf}  # inputs inside a segment [a, b] are read at min(t, b - ulp)

    def rhs(t: float, y: np.ndarray) -> Any:
        q, v = tq(y), tv(y)
        t = t if t < seg["end_minus"] else seg["end_minus"]  # the piece that ends at b, not the next one
        n = speed_rpm(t)
        Om = TWO_PI * n / 60.0
        om = EO * Om
        if jen is None:
            if ds.g:
                df = ds.df
                if om == 0.0 and ds.B > d:  # model-notes s.2: the FMU discards such a step
                    raise SimulationError(
                        f"omega = 0 at t = {t:g} s while the contact force is needed (B = {ds.B:g} m > d)"
                    )
                Ceq = df.CeqOmega / om if df.CeqOmega != 0.0 else 0.0
                Fc = df.Keq * q + Ceq * v
                P = Ceq * v * v
            else:
                Fc = P = 0.0
            wdot = 0.0
        else:
            Fn, Ff, wdot, P = jen.forces(q, v, y[iW])
            Fc = Fn * jen.cg + Ff * jen.sg  # eq. 14
        if m > 1:  # M qm'' + C0 qm' + K0 qm = G f_w - Fc psi(l), psi_i(l) = 1
            qm, vm = y[:m], y[m : 2 * m]
            Cv = mg.C0 @ vm
            acc_m = Minv @ (mg.loadGain * aero(t) - Cv - mg.K0(Om) @ qm - Fc)
            return np.concatenate([vm, acc_m, [om, float(vm @ Cv) + P, wdot]])
        K0 = K0s + K0w * Om * Om
        acc = (G * aero(t) - C0 * v - K0 * q - Fc) / M
        return [v, acc, om, C0 * v * v + P, wdot]

    if atol is None:  # absolute floors: m, m/s, rad, J, m
        atol = rtol * np.array([1e-6] * m + [1e-3] * m + [1e-6, 1e-9, 1e-6])
    t_eval = np.asarray(t_eval, dtype=float)
    if np.any(np.diff(t_eval) < 0) or (t_eval.size and (t_eval[0] < start_time or t_eval[-1] > stop_time)):
        raise ValueError("t_eval must be sorted and inside [start_time, stop_time]")
    out = np.zeros(t_eval.size, dtype=modal_dtype(m))
    out["time"] = t_eval
    bps = sorted({float(b) for b in (breakpoints if breakpoints is not None else []) if start_time < b < stop_time})
    edges = [float(start_time)] + bps + [float(stop_time)]

    def outputs(idx: np.ndarray, ts: np.ndarray, Y: np.ndarray) -> None:
        for j, t, y in zip(idx, ts, Y.T):
            q, v, E, w = tq(y), tv(y), y[iE], y[iW]
            n = speed_rpm(t)
            Om = TWO_PI * n / 60.0
            om = EO * Om
            df = ds.df
            row = out[j]
            row["tipDisplacement"], row["tipVelocity"], row["dissipatedEnergy"] = q, v, E
            row["amplitude"], row["regime"] = ds.B, df.regime
            if m == 1:
                row["naturalFrequency"] = math.sqrt((K0s + K0w * Om * Om) / M) / TWO_PI
            else:
                freqs = mg.frequencies_hz(n)
                row["naturalFrequency"] = freqs[0]
                for i in range(m):
                    row[f"modalDisplacement[{i + 1}]"], row[f"modalVelocity[{i + 1}]"] = y[i], y[m + i]
                    row[f"modeFrequency[{i + 1}]"] = freqs[i]
                row["rootMoment"] = float(mg.root_moment(y[:m]))
            Ceq_full = df.CeqOmega / om if om > 0 else (0.0 if df.CeqOmega == 0 else math.nan)
            if jen is None:
                fc = df.fcOmega / om if om > 0 else (0.0 if df.fcOmega == 0 else math.nan)
                g = ds.g
                row["normalForce"] = g * df.pk * q
                row["frictionForce"] = g * (df.fk * q + fc * v) if g else 0.0
                row["Keq"] = g * df.Keq
                row["Ceq"] = g * Ceq_full if g else 0.0
                if not g:
                    row["contactState"] = 0
                else:
                    theta = math.atan2(-v / om, q) if om > 0 else math.atan2(-v, q)
                    row["contactState"] = loop_state(cc, ds.B, theta % TWO_PI, dfmodel)
            else:
                Fn, Ff, _, _ = jen.forces(q, v, w)
                row["normalForce"], row["frictionForce"] = Fn, Ff
                row["Keq"], row["Ceq"] = df.Keq, Ceq_full
                row["contactState"] = jen.mode

    y = np.zeros(2 * m + 3)
    if initial is not None:
        y[:m], y[m : 2 * m] = np.ravel(initial[0]), np.ravel(initial[1])
        q0 = tq(y)
        y[iW] = sg * q0
        if gating and abs(q0) > d:
            ds.g = 1
        if jen is not None and abs(q0) > d:
            jen._set(STICK, 1 if q0 > 0 else -1, 0)  # w = sg q: unloaded spring, inside the cone
    ds.qmax = abs(tq(y))
    t = float(start_time)
    zero_len = 0
    if m == 1:
        qv = lambda ts, Y: (Y[0], Y[1])  # noqa: E731
        view = lambda y: y  # noqa: E731  (events and transitions read q, q', w at 0, 1, 4)
        jidx = (0, 1, 4)
    else:
        qv = lambda ts, Y: (Y[:m].sum(axis=0), Y[m : 2 * m].sum(axis=0))  # noqa: E731
        view = lambda y: np.array([tq(y), tv(y), y[iW]])  # noqa: E731
        jidx = (0, 1, 2)
    for seg_i in range(len(edges) - 1):
        t_end = edges[seg_i + 1]
        seg["end_minus"] = float(np.nextafter(t_end, -math.inf)) if seg_i < len(edges) - 2 else math.inf
        last_edge = seg_i == len(edges) - 2
        while t < t_end:
            evs: list = []
            acts: list = []
            if jen is None and gating:
                if ds.g == 0:
                    evs += [(lambda t, y: tq(y) - d, 1.0), (lambda t, y: tq(y) + d, -1.0)]
                    acts += [lambda y: setattr(ds, "g", 1)] * 2
                else:
                    side = 1.0 if tq(y) > 0 else -1.0
                    evs.append((lambda t, y, side=side: side * (tq(y) - side * d), -1.0))
                    acts.append(lambda y: setattr(ds, "g", 0))
            if jen is not None:
                for f, a in jen.events(*jidx):
                    evs.append((f if m == 1 else (lambda t, y, f=f: f(t, view(y))), f.direction))
                    acts.append(a)
            if tracked:
                evs.append((lambda t, y, k=ds.k: y[iP] - TWO_PI * k, 1.0))
                acts.append(None)  # period end, handled below
            idx = np.nonzero((t_eval >= t) & ((t_eval < t_end) | (last_edge & (t_eval <= t_end))))[0]
            res = run_segment(
                rhs,
                t,
                y,
                t_end,
                evs,
                qv,
                rtol,
                atol,
                max_step,
                t_eval[idx],
                lambda m, ts, Y, idx=idx: outputs(idx[m], ts, Y),
                track_qmax=tracked,
            )
            y = np.array(res.y, dtype=float)
            if tracked:
                ds.qmax = max(ds.qmax, res.qmax)
            if res.fired is None:
                t = t_end
                break
            zero_len = zero_len + 1 if res.t - t <= 1e-14 * max(1.0, abs(t)) else 0
            if zero_len > 1000:
                raise SimulationError(f"chattering: more than 1000 events at t = {res.t:g} s")
            t = res.t
            act = acts[res.fired]
            if act is None:  # period end: B <- max |q| over the period just ended (model-notes s.3)
                ds.B = ds.qmax
                ds.df = describe(ds.B)
                ds.k += 1
                ds.qmax = abs(tq(y))
            else:
                act(view(y))
                if jen is not None:
                    y[iW] = jen.consistent_w(tq(y), y[iW])
    # an output at stop_time reached exactly by an event (post-event state)
    rest = np.nonzero(t_eval >= t)[0]
    if rest.size and t >= stop_time:
        outputs(rest, t_eval[rest], np.repeat(y[:, None], rest.size, axis=1))
    return out


def jenkins_prescribed(
    params: Mapping[str, Any] | None,
    B: float,
    omega: float,
    n_cycles: int = 2,
    rtol: float = 1e-12,
    samples_per_cycle: int = 0,
) -> dict[str, Any]:
    """Drive the Jenkins element alone with a prescribed q(t) = B cos(omega t), t in
    [0, n_cycles 2 pi / omega]. q starts at B in contact (B > d) with an unloaded spring, so the
    element starts in stick with w = B sin g; from the second cycle on the loop is periodic.

    Returns 'cycle_work' (friction work, integral of F_f w' dt, over each cycle [J]), 'switch_theta'
    (phase in [0, 2 pi) and new mode of every transition, in order) and, with samples_per_cycle > 0,
    'theta', 'Ff', 'Fn', 'mode' sampled over the last cycle."""
    p = validate(params or {})
    cc = contact_consts(p)
    jen = Jenkins(cc)
    T = TWO_PI / omega
    if B > cc.d:
        jen._set(STICK, 1, 0)
    y = np.array([0.0, jen.sg * B])  # [friction work, w]

    def qv_t(t: Any) -> tuple[Any, Any]:
        return B * np.cos(omega * t), -B * omega * np.sin(omega * t)

    def rhs(t: float, y: np.ndarray) -> list[float]:
        q, v = qv_t(t)
        _, _, wdot, P = jen.forces(float(q), float(v), y[1])
        return [P, wdot]

    def full(t: float, y: np.ndarray) -> np.ndarray:
        q, v = qv_t(t)
        return np.array([q, v, y[1]])

    work: list[float] = []
    switches: list[tuple[float, int]] = []
    samples: list[tuple[float, float, float, int]] = []
    t = 0.0
    for c in range(n_cycles):
        c_end = (c + 1) * T
        E_start = y[0]
        ts = (
            np.linspace(c * T, c_end, samples_per_cycle, endpoint=False)
            if samples_per_cycle and c == n_cycles - 1
            else np.array([])
        )

        def record(m: np.ndarray, tt: np.ndarray, Y: np.ndarray) -> None:
            for ti, wi in zip(tt, Y[1]):
                q, v = qv_t(ti)
                Fn, Ff, _, _ = jen.forces(float(q), float(v), float(wi))
                samples.append((omega * ti % TWO_PI, Ff, Fn, jen.mode))

        while t < c_end:
            pairs = jen.events(0, 1, 2)
            evs = [(lambda tt, yy, f=f: f(tt, full(tt, yy)), f.direction) for f, _ in pairs]
            sel = ts[(ts >= t) & (ts < c_end)]
            res = run_segment(
                rhs,
                t,
                y,
                c_end,
                evs,
                lambda tt, Y: qv_t(tt),
                rtol,
                rtol * np.array([1e-6, B]),
                t_eval=sel,
                on_output=record,
            )
            y = np.array(res.y, dtype=float)
            t = res.t
            if res.fired is None:
                t = c_end
                break
            pairs[res.fired][1](full(t, y))
            y[1] = jen.consistent_w(float(qv_t(t)[0]), y[1])
            switches.append(((omega * t) % TWO_PI, jen.mode))
        work.append(float(y[0] - E_start))
    out: dict[str, Any] = {"cycle_work": work, "switch_theta": switches}
    if samples:
        arr = np.array(samples)
        out.update(theta=arr[:, 0], Ff=arr[:, 1], Fn=arr[:, 2], mode=arr[:, 3].astype(int))
    return out
