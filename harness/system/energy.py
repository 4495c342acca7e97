"""Energy balance of the co-simulated ring over an excitation period (the acceptance test: over a
steady period the aero work equals the viscous plus friction dissipation).

Books over the window [t_a, t_b] (communication points; t_b the run's end or `shift` steps
before it, t_b - t_a = `periods` excitation periods 2 pi / omega):
- blade i (BladeExternalContact): M q'' + C0 q' + K0 q = G f_w + F gives
  W_aero,i = dS_i + dE_i - dW_i, S = M v^2 / 2 + K0 q^2 / 2 (kinetic + strain), E the output
  dissipatedEnergy (viscous), W the output contactWork (work of the contact force on the blade);
  the blade integrates E and W with its own RK4 alongside q, v, so this identity holds to RK4 accuracy;
- contact j (ShroudContact, Jenkins): the forces it reports do work -dEc_j - dU_j on the blades,
  Ec the output dissipatedEnergy (friction), U = k_n cos^2 g pen^2 / 2 + F_f^2 / (2 k_d) the normal
  and tangential spring energy (pen = max(|u| - d, 0), F_f = (F_c - F_n cos g) / sin g, F_c = forceB).
The blades receive the contact forces as polynomials extrapolated from past communication points
while each contact works along its own extrapolated u, so sum_i dW_i != -sum_j (dEc_j + dU_j):
    coupling error = sum_i dW_i + sum_j (dEc_j + dU_j)   (0 for an exact coupling),
    residual       = sum W_aero - sum dE - sum dEc = sum dS + sum dU - coupling error,
the acceptance residual; over a steady period dS, dU -> 0 and residual = -coupling error.
`python -m harness ring-energy [--conserving]` prints both, relative to the aero work, vs h and
order, for the plain master or the energy-conserving one (harness/system/ring_conserving.py).
"""

from __future__ import annotations

import math
import time
from dataclasses import dataclass, replace
from typing import Iterator, Mapping, Sequence

import numpy as np

from harness.model.galerkin import galerkin
from harness.model.contact import contact_consts
from harness.model.params import validate
from harness.system import ring_conserving
from harness.system.contact_energy import require_jenkins, spring_energy
from harness.system.ring import Ring, run

# the convergence study's ring (harness/validation/ring_convergence.py): tuned, N = 4, EO = 3, 5000 rpm
STUDY_RING = Ring(n=4, engine_order=3, fw0=300.0, blade={"c": 298.0})


@dataclass(frozen=True)
class PeriodBalance:
    """Changes over the window, summed over the ring [J]."""

    aero: float  # work of the aero loads on the blades
    viscous: float  # blade viscous dissipation
    friction: float  # contact friction dissipation
    contact_work: float  # work of the contact forces on the blades (as the blades integrated it)
    stored: float  # blade kinetic + strain energy
    springs: float  # contact normal + tangential spring energy
    amplitude_change: float  # max over blades of |A_last - A_previous| / A_last, A = max |q| per period

    @property
    def coupling_error(self) -> float:
        return self.contact_work + self.friction + self.springs

    @property
    def residual(self) -> float:
        """aero - viscous - friction: the acceptance quantity (0 over an exactly steady period)."""
        return self.aero - self.viscous - self.friction


def balance(
    ring: Ring, res: Mapping[str, np.ndarray], periods: int = 1, shift: int = 0, stride: int = 1
) -> PeriodBalance:
    """The balance terms over `periods` excitation periods of a run(ring) result, ending `shift`
    recorded points before the run's end (a steady state is periodic: any phase will do); stride:
    the result keeps every stride-th communication point (harness/system/ring_c.py record_every)."""
    if ring.blade_each:
        raise ValueError("balance() takes a tuned ring (one blade parameter set)")
    require_jenkins(ring)
    T = 2 * math.pi / ring.omega
    h = ring.step * stride  # spacing of the recorded points
    n = round(periods * T / h)  # recorded intervals in the window
    if abs(n * h - periods * T) > 1e-9 * T or 2 * n + shift > ring.n_steps // stride:
        raise ValueError(
            f"the window ({periods} periods of {T:g} s) must be a whole number of recorded"
            f" intervals {h:g} s and the run at least two windows long"
        )
    b = ring.n_steps // stride - shift
    a = b - n
    g = galerkin(validate(dict(ring.blade)))
    K0 = g.K0(2 * math.pi * ring.speed / 60)
    q, v = res["q"], res["v"]
    S = (0.5 * g.M * v**2 + 0.5 * K0 * q**2).sum(axis=1)
    U = spring_energy(contact_consts(dict(ring.contact)), q, res["forceB"])
    d = lambda x: float(np.sum(x[b]) - np.sum(x[a]))  # noqa: E731
    amp = lambda k0, k1: np.abs(q[k0 : k1 + 1]).max(axis=0)  # noqa: E731
    A1, A0 = amp(a, b), amp(a - n, a)
    dS, dE, dW = d(S), d(res["E"]), d(res["W"])
    return PeriodBalance(
        aero=dS + dE - dW,
        viscous=dE,
        friction=d(res["Ec"]),
        contact_work=dW,
        stored=dS,
        springs=d(U),
        amplitude_change=float(np.max(np.abs(A1 - A0) / A1)),
    )


def measure(ring: Ring, periods: int = 1, conserving: bool = False) -> tuple[PeriodBalance, float]:
    """Runs the ring (plain Jacobi master, or with the energy-conserving correction of
    harness/system/ring_conserving.py); (balance over its last `periods` periods, wall time [s])."""
    t0 = time.perf_counter()
    res = (ring_conserving.run if conserving else run)(ring)
    return balance(ring, res, periods), time.perf_counter() - t0


def step_study(
    stop: float, orders: Sequence[int], steps: Sequence[float], conserving: bool = False
) -> Iterator[tuple[int, float, PeriodBalance | None, float]]:
    """The study ring (STUDY_RING) run to `stop` at every extrapolation order and communication
    step: (order, step, balance over the last period or None where an FMU refused a step (the run
    diverged), wall time [s])."""
    for p in orders:
        for h in steps:
            ring = replace(STUDY_RING, step=h, stop_time=stop, order=p)
            try:
                bal, wall = measure(ring, conserving=conserving)
            except Exception:  # an FMU refused a step (state out of range): diverged
                yield p, h, None, math.nan
                continue
            yield p, h, bal, wall
