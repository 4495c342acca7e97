"""The Fourier content of periodic orbits (harness.analysis.periodic.harmonics) against independent sources.

- Gating off, the fixed-B ODE is linear: the orbit is one harmonic (higher ones below 1e-8 of the
  amplitude) and its amplitude is the reference's harmonic balance root (1e-8).
- Gated (the paper's model), the FMU's samples of the orbit and the reference's exact piecewise-
  linear solution (harness.reference.fixedpoint.PiecewiseStepper, own event location) from the
  same state give the same first and third harmonic (1e-6 of the amplitude: RK4 at maxStep
  2.5e-6 s vs exact, through the located switchings).
"""

from __future__ import annotations

import math

import numpy as np
import pytest

from harness.analysis.periodic.branches import orbits_at
from harness.analysis.periodic.harmonics import SAMPLES, fourier_amplitudes, harmonic_row, hb_parameters
from harness.analysis.periodic.period_map import PeriodMap, omega
from harness.reference.fixedpoint import PiecewiseStepper

FINE = {"maxStep": 2.5e-6}


def test_ungated_orbits_are_one_harmonic_equal_to_harmonic_balance(fmu):
    pm = PeriodMap(fmu, dict(FINE, gating=False), "fixedPoint")
    rows = [
        harmonic_row(pm, o.x, o.speed, o.amplitude, o.stable, hb_parameters(pm))
        for o in orbits_at(pm, 6000.0)
        if o.amplitude > pm.d
    ]
    assert len(rows) >= 2
    for r in rows:
        assert r.higher <= 1e-8 * r.amplitude
        assert abs(r.hb - r.a1) <= 1e-8 * r.a1 and abs(r.amplitude - r.a1) <= 1e-8 * r.a1


@pytest.mark.parametrize("n", [6000.0, 8000.0])
def test_gated_orbit_harmonics_equal_the_exact_solution(fmu, n):
    pm = PeriodMap(fmu, FINE, "fixedPoint")
    o = max(orbits_at(pm, n), key=lambda o: o.amplitude)
    assert o.amplitude > pm.d
    r = harmonic_row(pm, o.x, n, o.amplitude, o.stable, hb_parameters(pm))
    st = PiecewiseStepper(dict(pm.p, amplitudeMode=1), n, o.B)
    T = 2 * math.pi / omega(pm.p, n)
    q, v, g, t = float(o.x[0]), float(o.x[1]), st.initial_g(float(o.x[0])), 0.0
    exact = [q]
    for k in range(1, SAMPLES):
        q, v, g, _ = st.advance(t, q, v, g, k * T / SAMPLES, track=False)
        t = k * T / SAMPLES
        exact.append(q)
    a = fourier_amplitudes(np.array(exact))
    assert r.higher > 1e-3 * r.amplitude  # the gate makes higher harmonics (else this tests nothing)
    assert abs(r.a1 - a[1]) <= 1e-6 * r.amplitude and abs(r.a3 - a[3]) <= 1e-6 * r.amplitude
