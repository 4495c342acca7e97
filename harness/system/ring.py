"""A bladed disk as a co-simulation: a ring of N BladeExternalContact FMUs coupled by N
ShroudContact FMUs, each blade loaded by its built-in aerodynamic load (travelling wave: blade i's
load leads blade 0's by 2 pi EO i / N; the FMU integrates the phase from rotorSpeed, so the load is
exact at any step), run by a fixed-step Jacobi master on the project's FMI binding (harness.fmu.slave).

Coupling (docs/model.md s.8): contact j joins blade j (side A) and blade j+1 mod N (side B),
u_j = q_j - q_{j+1}. At each communication point t_k the master
1. reads every blade's tipDisplacement q and tipVelocity v (state outputs: no feedthrough);
2. sets each contact's displacementA/velocityA, displacementB/velocityB (the velocities with the
   derivatives extrapolated from their history, so u(tau) inside the step is a polynomial of
   order `order` + 1) and rotorSpeed, and reads its forces (direct feedthrough, at the q just set);
3. sets each blade's contactForce_i = forceB_{i-1} + forceA_i (equal and opposite pairs: the sum
   over the ring is 0) and rotorSpeed, with the derivatives of order 1..`order` of contactForce
   extrapolated from the last `order` + 1 communication points (order 0: inputs held);
4. steps every FMU from t_k to t_{k+1} (Jacobi: all from the data at t_k); t_k are libcosim's
   integer-nanosecond points (harness/system/ring_libcosim.py runs the same ring in libcosim).
A blade |q| above Ring.q_limit (or not finite) stops the run with RingDiverged naming the step.
Ring.coupling "libcosim" reproduces libcosim's fixed-step data flow instead (held inputs, order 0):
at t_0 as above (libcosim's initialization sets the contacts' inputs and reads their forces, so the
blades start with the feedthrough forces); at t_k, k >= 1, the blades get the forces each contact
reported right after its previous doStep (the state at the end of its own step, u moved along the
held velocities), read before its inputs are set to the new q, v. The FMUs then do exactly
libcosim's work (tests/system/test_ring_libcosim.py: equal to libcosim and Ecos).
The command is `python -m harness ring` (harness/cli/ring.py).
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field
from math import factorial
from typing import Any, Callable, Mapping

import numpy as np

from harness.fmu.slave import Slave
from harness.system.ring_instances import open_ring


# "feedthrough": the blades get the contact forces read at the q, v just set (our Jacobi master);
# "libcosim": the forces read after the contacts' previous step (libcosim's fixed-step algorithm)
COUPLINGS = ("feedthrough", "libcosim")


class RingDiverged(RuntimeError):
    """A blade's |q| passed Ring.q_limit: the Jacobi coupling blows up at this step."""


@dataclass(frozen=True)
class Ring:
    """A ring of N blades coupled by N shroud contacts at constant speed (a frozen record).

    Parameters
    ----------
    n : int
        Number of blades N (and of contacts).
    engine_order : int
        Engine order EO of the aerodynamic load.
    speed : float
        Rotor speed n [rpm].
    fw0 : float
        Amplitude Fw0 of every blade's built-in aerodynamic load [N/m].
    blade : Mapping[str, Any]
        BladeExternalContact parameters by name, common to every blade.
    contact : Mapping[str, Any]
        ShroudContact parameters by name, common to every contact.
    blade_each : tuple of Mapping[str, Any]
        Per-blade overrides of `blade` (mistuning): empty (a tuned ring) or N of them.
    step : float
        Communication step h [s].
    stop_time : float
        Stop time of a run [s].
    order : int
        Extrapolation order of the input derivatives (0: inputs held over a step).
    coupling : str
        How the blades get the contact forces, one of COUPLINGS: "feedthrough" (read at the q, v
        just set) or "libcosim" (libcosim's fixed-step data flow; needs `order` 0).
    q_limit : float
        A blade |q| above it stops the run with RingDiverged [m] (about 1000x the forced response).

    Raises
    ------
    ValueError
        An unknown `coupling`, or "libcosim" with `order` other than 0.
    """

    n: int = 4
    engine_order: int = 3
    speed: float = 5000.0
    fw0: float = 100.0
    blade: Mapping[str, Any] = field(default_factory=dict)
    contact: Mapping[str, Any] = field(default_factory=dict)
    blade_each: tuple[Mapping[str, Any], ...] = ()
    step: float = 1e-4
    stop_time: float = 0.1
    order: int = 1
    coupling: str = "feedthrough"
    q_limit: float = 1e-2

    def __post_init__(self) -> None:
        if self.coupling not in COUPLINGS:
            raise ValueError(f"coupling {self.coupling!r}: not one of {', '.join(map(repr, COUPLINGS))}")
        if self.coupling == "libcosim" and self.order != 0:
            # libcosim sets values only: its data flow has no input derivatives
            raise ValueError(f"coupling 'libcosim' holds the inputs: order must be 0, got {self.order}")

    @property
    def n_steps(self) -> int:
        """Communication steps of a run: stop_time / step, rounded."""
        return round(self.stop_time / self.step)

    def blade_params(self, i: int) -> dict[str, Any]:
        """Parameters of one blade.

        Parameters
        ----------
        i : int
            The blade, 0..N-1.

        Returns
        -------
        dict[str, Any]
            The common parameters (`blade`) with blade i's own overrides (`blade_each[i]`) on top.
        """
        return {**dict(self.blade), **(dict(self.blade_each[i]) if self.blade_each else {})}

    def blade_instance_params(self, i: int) -> dict[str, Any]:
        """What every master sets on one blade's FMU.

        Parameters
        ----------
        i : int
            The blade, 0..N-1.

        Returns
        -------
        dict[str, Any]
            `blade_params(i)` and its built-in load's: Fw0 (always explicit), engineOrder and blade
            i's place in the travelling wave (bladeIndex, bladeCount).
        """
        return {
            **self.blade_params(i),
            "Fw0": float(self.fw0),
            "bladeIndex": i,
            "bladeCount": self.n,
            "engineOrder": int(self.engine_order),
        }

    @property
    def omega(self) -> float:
        """Excitation frequency EO 2 pi n / 60 [rad/s]."""
        return self.engine_order * 2 * math.pi * self.speed / 60


def extrapolation_weights(p: int, h: float) -> np.ndarray:
    """D[m, j]: derivative m (0..p) at t_k of the polynomial through y_{k-j} at t_k - j h,
    j = 0..p (Lagrange extrapolation; D @ y gives the value and derivatives)."""
    tau = -h * np.arange(p + 1)
    V = np.vander(tau, p + 1, increasing=True)  # V[j, m] = tau_j^m
    C = np.linalg.inv(V)  # coefficients c = C y
    return np.array([factorial(m) * C[m] for m in range(p + 1)])


class _History:
    """The last p + 1 values of an array of signals, for their extrapolated derivatives."""

    def __init__(self, p: int, h: float, size: int):
        self.p, self.h = p, h
        self.buf: list[np.ndarray] = []
        self.w = {q: extrapolation_weights(q, h) for q in range(p + 1)}

    def push(self, y: np.ndarray) -> np.ndarray:
        """Adds y (at t_k); returns derivatives 1..p at t_k, shape (p, size) (lower order at the start)."""
        self.buf.insert(0, np.array(y, dtype=float))
        del self.buf[self.p + 1 :]
        q = len(self.buf) - 1
        out = np.zeros((self.p, len(y)))
        if q > 0:
            out[:q] = (self.w[q] @ np.array(self.buf))[1:]
        return out


def diverged_message(ring: Ring, k: int, t: float, blade: int, q: float, master: str) -> str:
    """One line: where the ring blew up and what to change."""
    hint = (
        "raise --order (the input derivatives' extrapolation, now 0) or "
        if ring.order == 0 and ring.coupling == "feedthrough" and master in ("fmpy", "c")
        else ""
    )  # libcosim, Ecos hold inputs
    return (
        f"ring ({master}) diverged at step {k} (t = {t:.6g} s): blade {blade} |q| = {abs(q):.3g} m > "
        f"{ring.q_limit:g} m; {hint}reduce --step (now {ring.step:g} s; the Jacobi coupling of "
        f"stiff contacts is stable only below a step that depends on kn and the extrapolation order)"
    )


def run(ring: Ring, correction: Callable[..., float] | None = None) -> dict[str, np.ndarray]:
    """Runs the ring from rest; returns time [s] and, per blade (columns), q, v, dissipatedEnergy,
    contactWork, contactForce (the input set at t_k), the contacts' forceA, forceB, dissipatedEnergy,
    contactState, all at the communication points t_0..t_K (inputs and forces: those set/read at t_k,
    the last row repeats the last set; coupling "libcosim": the forces read after the step to t_k).
    `correction(k, q, v, dv, fB, res)` (feedthrough
    only; harness/system/ring_conserving.py) returns lambda_k: the blades then get contactForce +
    lambda_k v with derivatives df + lambda_k dv, and res["contactForce"] records that.
    Raises RingDiverged when a blade's |q| passes ring.q_limit."""
    if correction is not None and ring.coupling != "feedthrough":
        raise ValueError(f"a coupling correction needs the feedthrough coupling, got {ring.coupling!r}")
    N, h, K, p = ring.n, ring.step, ring.n_steps, ring.order
    res = {k: np.zeros((K + 1, N)) for k in ("q", "v", "E", "W", "contactForce", "forceA", "forceB", "Ec", "state")}
    after_step = ring.coupling == "libcosim"  # blades get the forces read after the contacts' step
    # libcosim's communication points (integer nanoseconds), so both masters see the same times
    with open_ring(ring) as (tk, blades, contacts):
        res["time"] = tk
        bv = [blades[0].vr(n) for n in ("tipDisplacement", "tipVelocity", "dissipatedEnergy", "contactWork")]
        c_in = [contacts[0].vr(n) for n in ("displacementA", "velocityA", "displacementB", "velocityB", "rotorSpeed")]
        c_out = [contacts[0].vr(n) for n in ("forceA", "forceB", "dissipatedEnergy")]
        c_state = contacts[0].vr("contactState")
        b_in = [blades[0].vr(n) for n in ("rotorSpeed", "contactForce")]
        hv, hf = _History(p, h, N), _History(p, h, N)
        for k in range(K + 1):
            t = float(tk[k])
            st = np.array([b.s.get_real(bv) for b in blades])  # q, v, E, W
            q, v = st[:, 0], st[:, 1]
            res["q"][k], res["v"][k], res["E"][k], res["W"][k] = st.T
            bad = np.flatnonzero(~(np.abs(q) <= ring.q_limit))
            if bad.size:
                raise RingDiverged(diverged_message(ring, k, t, int(bad[0]), float(q[bad[0]]), "fmpy"))
            dv = hv.push(v)
            fA, fB = np.zeros(N), np.zeros(N)
            for j, c in enumerate(contacts):
                a, b = j, (j + 1) % N
                if after_step and k > 0:  # libcosim: the outputs of the step just done
                    fA[j], fB[j], res["Ec"][k, j] = c.s.get_real(c_out)
                    res["state"][k, j] = c.s.get_integer([c_state])[0]
                c.s.set_real(c_in, [q[a], v[a], q[b], v[b], ring.speed])
                if p > 0:
                    _set_derivatives(
                        c, [c_in[1]] * p + [c_in[3]] * p, list(range(1, p + 1)) * 2, list(dv[:, a]) + list(dv[:, b])
                    )
                if not (after_step and k > 0):  # feedthrough at the q, v just set
                    fA[j], fB[j], res["Ec"][k, j] = c.s.get_real(c_out)
                    res["state"][k, j] = c.s.get_integer([c_state])[0]
            res["forceA"][k], res["forceB"][k] = fA, fB
            force = np.array([fB[(i - 1) % N] + fA[i] for i in range(N)])
            df = hf.push(force)  # the history holds the contacts' forces, not a correction
            if correction is not None:
                lam = correction(k, q, v, dv, fB, res)
                force, df = force + lam * v, df + lam * dv
            res["contactForce"][k] = force
            if k == K:
                break
            for i, bl in enumerate(blades):
                bl.s.set_real(b_in, [ring.speed, force[i]])
                if p > 0:
                    _set_derivatives(bl, [b_in[1]] * p, list(range(1, p + 1)), list(df[:, i]))
            for fmu in (*blades, *contacts):
                fmu.s.do_step(t, float(tk[k + 1] - tk[k]))
    return res


def _set_derivatives(slave: Slave, vrs: list[int], orders: list[int], values: list[float]) -> None:
    slave.s.set_real_input_derivatives(vrs, orders, values)


def harmonic(res: Mapping[str, np.ndarray], omega: float, periods: int = 1) -> np.ndarray:
    """Complex first-harmonic coefficient of q per blade over the last `periods` excitation
    periods (trapezoidal rule on the communication points; exact to rounding for a trigonometric
    polynomial when the window holds a whole number of steps)."""
    t, q = res["time"], res["q"]
    T = 2 * math.pi / omega * periods
    sel = t >= t[-1] - T - 1e-12
    ts, qs = t[sel], q[sel]
    w = np.full(len(ts), ts[1] - ts[0])
    w[0] = w[-1] = 0.5 * (ts[1] - ts[0])
    e = np.exp(-1j * omega * ts)
    coefficients: np.ndarray = 2.0 / T * (w * e) @ qs
    return coefficients


def amplitudes(time: np.ndarray, q: np.ndarray, omega: float) -> np.ndarray:
    """Steady amplitude per blade: max |q| over the communication points of the last excitation
    period 2 pi / omega (the run must be at least one period long)."""
    T = 2 * math.pi / omega
    if time[-1] - time[0] < T * (1 - 1e-9):
        raise ValueError(f"the run ({time[-1] - time[0]:g} s) is shorter than one excitation period ({T:g} s)")
    amplitude: np.ndarray = np.abs(q[time >= time[-1] - T - 1e-12]).max(axis=0)
    return amplitude
