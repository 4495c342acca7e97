"""The ring's Jacobi master (harness/system/ring.py) with an energy-conserving coupling correction
(the idea of Sadjina et al. 2017, "Energy conservation in co-simulation", NEPCE: feed the coupling's
energy residual back into the next step's inputs).

Why: each blade gets its contact force as a polynomial extrapolated from past communication
points while each contact works along its own extrapolated u, so the work the contact forces do
on the blades differs from minus the contacts' dissipated and stored energy. Near the contacts'
stick/slip/open kinks this error is O(h^2) per event with a phase-dependent sign, so the period
sum converges slowly and erratically in h (harness/system/energy.py).

Correction: the master knows the running mismatch at t_k from the FMUs' outputs,
    D_k = sum_i W_i + sum_j (Ec_j + U_j)   (W contactWork, Ec friction dissipation, U spring energy),
0 for an exact coupling. Over the step t_k -> t_k + h it adds to every blade's contactForce the
force lambda_k v_i(tau) (v_i the same extrapolated velocity polynomial the contacts get), with
    lambda_k = -D_k / sum_i int_0^h v_i(tau)^2 dtau,
so the added work is -D_k up to the velocity's extrapolation error: the mismatch does not
accumulate, D_{k+1} is the new step's error only. |lambda_k| is capped at the blade's viscous
coefficient C0 (the correction never exceeds the blade's own damping; the cap is counted).
The corrections are not equal and opposite pairs: the blades' contact forces no longer sum to 0.
Everything else is ring.run's loop (it calls `correction` after reading the forces).
"""

from __future__ import annotations

from math import factorial

import numpy as np

from harness.model.params import validate
from harness.model.galerkin import galerkin
from harness.model.contact import contact_consts
from harness.system.contact_energy import require_jenkins, spring_energy
from harness.system.ring import Ring
from harness.system.ring import run as ring_run


def _velocity_square_integral(v: np.ndarray, dv: np.ndarray, h: float) -> float:
    """sum_i int_0^h (v_i + sum_m dv[m-1, i] tau^m / m!)^2 dtau (polynomials in tau, exact)."""
    p = dv.shape[0]
    c = np.vstack([v] + [dv[m - 1] / factorial(m) for m in range(1, p + 1)])  # c[m, i]: tau^m coefficient
    sq = np.zeros((2 * p + 1, c.shape[1]))
    for a in range(p + 1):
        for b in range(p + 1):
            sq[a + b] += c[a] * c[b]
    return float(sum(sq[m].sum() * h ** (m + 1) / (m + 1) for m in range(2 * p + 1)))


def run(ring: Ring) -> dict[str, np.ndarray]:
    """As harness.system.ring.run (tuned or mistuned ring), with the correction; adds per step
    "lambda" (the correction coefficient [N s/m]) and "mismatch" D_k [J]; "contactForce" is the
    value set (correction included), "capped" the number of steps where the cap acted."""
    require_jenkins(ring)
    cc = contact_consts(dict(ring.contact))
    cap = min(galerkin(validate(ring.blade_params(i))).C0 for i in range(ring.n))
    lam_k, mismatch, capped = np.zeros(ring.n_steps + 1), np.zeros(ring.n_steps + 1), [0]

    def correction(k: int, q: np.ndarray, v: np.ndarray, dv: np.ndarray, fB: np.ndarray, res: dict) -> float:
        D = res["W"][k].sum() + res["Ec"][k].sum() + spring_energy(cc, q[None, :], fB[None, :])[0]
        den = _velocity_square_integral(v, dv, ring.step)
        lam = -D / den if den > 0 else 0.0
        if abs(lam) > cap:
            lam = float(np.sign(lam) * cap)
            capped[0] += 1
        lam_k[k], mismatch[k] = lam, D
        return lam

    res = ring_run(ring, correction=correction)
    res["lambda"], res["mismatch"], res["capped"] = lam_k, mismatch, np.array(capped[0])
    return res
