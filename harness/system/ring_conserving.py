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
Everything else as ring.run (same communication points, extrapolation, order of calls).
"""
from __future__ import annotations

from math import factorial

import numpy as np

from harness.crosscheck.importers.libcosim import ns_time_grid
from harness.fmu.build import EXCITATION_FMU, build
from harness.fmu.slave import Unpacked, build_ring_fmus
from harness.model.params import validate
from harness.reference.blade import galerkin
from harness.reference.contact import contact_consts
from harness.system.energy import require_jenkins, spring_energy
from harness.system.ring import Ring, _History, _set_derivatives


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
    bx_path, sc_path = build_ring_fmus()
    build(("excitation_fmu",))
    N, h, K, p = ring.n, ring.step, ring.n_steps, ring.order
    if N < 2:
        raise ValueError(f"a ring needs n >= 2 blades, got {N}")
    if ring.blade_each and len(ring.blade_each) != N:
        raise ValueError(f"blade_each has {len(ring.blade_each)} entries for {N} blades")
    require_jenkins(ring)
    cc = contact_consts(dict(ring.contact))
    cap = min(galerkin(validate(ring.blade_params(i))).C0 for i in range(N))
    res = {k: np.zeros((K + 1, N)) for k in ("q", "v", "E", "W", "contactForce", "forceA", "forceB", "Ec", "state")}
    res["lambda"], res["mismatch"] = np.zeros(K + 1), np.zeros(K + 1)
    res["time"] = tk = ns_time_grid(0.0, h, K)
    capped = 0
    with Unpacked(bx_path) as BX, Unpacked(sc_path) as SC, Unpacked(EXCITATION_FMU) as EX:
        blades = [BX.instance(f"blade{i}", ring.blade_params(i)) for i in range(N)]
        contacts = [SC.instance(f"contact{j}", {**dict(ring.contact), "engineOrder": ring.engine_order})
                    for j in range(N)]
        excs = [EX.instance(f"exc{i}", {"Fw0": ring.fw0, "n0": ring.speed, "n1": ring.speed,
                                        "engineOrder": ring.engine_order, "bladeIndex": i, "bladeCount": N})
                for i in range(N)]
        try:
            bv = [blades[0].vr(n) for n in ("tipDisplacement", "tipVelocity", "dissipatedEnergy", "contactWork")]
            ev = [excs[0].vr("aeroLoad"), excs[0].vr("rotorSpeed")]
            c_in = [contacts[0].vr(n) for n in ("displacementA", "velocityA", "displacementB", "velocityB", "rotorSpeed")]
            c_out = [contacts[0].vr(n) for n in ("forceA", "forceB", "dissipatedEnergy")]
            c_state = contacts[0].vr("contactState")
            b_in = [blades[0].vr(n) for n in ("aeroLoad", "rotorSpeed", "contactForce")]
            hv, hf, ha = _History(p, h, N), _History(p, h, N), _History(p, h, N)
            for k in range(K + 1):
                t = float(tk[k])
                st = np.array([b.s.getReal(bv) for b in blades])  # q, v, E, W
                q, v = st[:, 0], st[:, 1]
                ex = np.array([e.s.getReal(ev) for e in excs])
                dv, da = hv.push(v), ha.push(ex[:, 0])
                res["q"][k], res["v"][k], res["E"][k], res["W"][k] = st.T
                fA, fB = np.zeros(N), np.zeros(N)
                for j, c in enumerate(contacts):
                    a, b = j, (j + 1) % N
                    c.s.setReal(c_in, [q[a], v[a], q[b], v[b], ex[a, 1]])
                    if p > 0:
                        _set_derivatives(c, [c_in[1]] * p + [c_in[3]] * p, list(range(1, p + 1)) * 2,
                                         list(dv[:, a]) + list(dv[:, b]))
                    fA[j], fB[j], res["Ec"][k, j] = c.s.getReal(c_out)
                    res["state"][k, j] = c.s.getInteger([c_state])[0]
                res["forceA"][k], res["forceB"][k] = fA, fB
                force = np.array([fB[(i - 1) % N] + fA[i] for i in range(N)])
                df = hf.push(force)  # the history holds the contacts' forces, not the corrections
                D = res["W"][k].sum() + res["Ec"][k].sum() + spring_energy(cc, q[None, :], fB[None, :])[0]
                den = _velocity_square_integral(v, dv, h)
                lam = -D / den if den > 0 else 0.0
                if abs(lam) > cap:
                    lam, capped = float(np.sign(lam) * cap), capped + 1
                res["lambda"][k], res["mismatch"][k] = lam, D
                res["contactForce"][k] = force + lam * v
                if k == K:
                    break
                for i, bl in enumerate(blades):
                    bl.s.setReal(b_in, [ex[i, 0], ex[i, 1], force[i] + lam * v[i]])
                    if p > 0:
                        _set_derivatives(bl, [b_in[0]] * p + [b_in[2]] * p, list(range(1, p + 1)) * 2,
                                         list(da[:, i]) + list(df[:, i] + lam * dv[:, i]))
                for fmu in (*blades, *contacts, *excs):
                    fmu.s.doStep(currentCommunicationPoint=t, communicationStepSize=float(tk[k + 1] - tk[k]))
        finally:
            for fmu in (*blades, *contacts, *excs):
                fmu.free()
    res["capped"] = np.array(capped)
    return res
