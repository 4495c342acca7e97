"""The ring's monolithic reference (harness/reference/ring.py) and the co-simulation's convergence
to it (harness/validation/ring_convergence.py).

- the reference's energy books close: aero work = blade kinetic + strain energy + contact normal
  and tangential spring energy + viscous + friction dissipation, at every output point (1e-8 of
  the aero work; DOP853 at rtol 1e-11), and over a steady excitation period the aero work equals
  the viscous plus friction dissipation within 1e-6 relative (after 0.3 s = 14 decay times);
- a symmetric ring switches mirrored contacts at the same instant: the reference keeps the
  travelling-wave symmetry (N = 4, EO = 2: blade 1 = -blade 0, blade 2 = blade 0, so u_1 = -u_0;
  within 1e-9 of max |q|);
- the fmpy Jacobi master converges to the reference as h shrinks: measured order (slope on the
  three finest steps) >= 0.9 with held inputs, >= 1.7 with linear and >= 1.9 with quadratic
  extrapolation of the input derivatives (measured 1.11, 1.86, 2.11); at h = 1.25e-5 s with
  quadratic extrapolation within 1e-3 of max |q| (measured 4.7e-4).
"""

from __future__ import annotations

import math

import numpy as np

from harness.reference.contact import contact_consts
from harness.reference.ring import MonolithicRing, RingSpec
from harness.validation.ring_convergence import Study, errors, measured_order

SPEC = RingSpec(n=4, engine_order=3, fw0=300.0, blade={"c": 298.0})


def test_energy_books_close():
    m = MonolithicRing(SPEC)
    t = np.arange(0, 0.3 + 1e-12, 1e-4)
    r = m.solve(t)
    q, v = r["q"], r["v"]
    u = q - np.roll(q, -1, axis=1)
    cc = contact_consts({})
    cg = math.cos(cc.gamma)
    pen = np.maximum(np.abs(u) - cc.d, 0.0)
    normal = 0.5 * cc.kn * cg * cg * pen**2  # F_n cos g = kn cos^2 g (|u| - d) (eq. 3, 14)
    # the tangential spring energy F_f^2 / (2 kd) is not an output: bounded by |F_f| <= mu |F_n|
    fmax = cc.mu * cc.kn * cg * pen
    stored = (0.5 * m.M * v**2 + 0.5 * m.K0 * q**2).sum(1) + normal.sum(1)
    W, Ev, Ef = r["Waero"].sum(1), r["Evisc"].sum(1), r["Efric"].sum(1)
    gap = W - (stored + Ev + Ef)  # = tangential spring energy, in [0, sum fmax^2 / (2 kd)]
    tol = 1e-8 * np.abs(W).max()
    assert np.all(gap >= -tol)
    assert np.all(gap <= (fmax**2 / (2 * cc.kd)).sum(1) + tol)
    # a steady period: the stored energies return
    T = 2 * math.pi / m.omega
    k1 = len(t) - 1
    k0 = k1 - round(T / 1e-4)
    dW, dE = W[k1] - W[k0], (Ev[k1] - Ev[k0]) + (Ef[k1] - Ef[k0])
    assert Ef[k1] - Ef[k0] > 0.01 * dE  # friction takes part
    assert abs(dW - dE) <= 1e-6 * dW, (dW, dE)


def test_symmetric_events_keep_the_wave():
    spec = RingSpec(n=4, engine_order=2, fw0=300.0, blade={"c": 298.0})
    t = np.arange(0, 0.02 + 1e-12, 1e-4)
    r = MonolithicRing(spec).solve(t)
    q = r["q"]
    assert r["events"] > 20
    # leads 0, pi, 2 pi, 3 pi: q1 = -q0, q2 = q0, so u0 = 2 q0 = -u1 (mirrored contacts)
    assert np.abs(q[:, 1] + q[:, 0]).max() <= 1e-9 * np.abs(q).max()
    assert np.abs(q[:, 2] - q[:, 0]).max() <= 1e-9 * np.abs(q).max()


def test_cosimulation_converges_to_monolithic():
    study = Study(steps=(5e-5, 2.5e-5, 1.25e-5), stop_time=0.03)
    rows = errors(study)
    orders = {p: measured_order(rows, p) for p in study.orders}
    assert orders[0] >= 0.9 and orders[1] >= 1.7 and orders[2] >= 1.9, orders
    finest = [e for p, h, e in rows if p == 2 and h == 1.25e-5][0]
    assert finest <= 1e-3, finest
