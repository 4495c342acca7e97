"""The ring (co-simulation, C loop) where a single-blade computation must give the answer
(docs/guide/ring.md, "When a ring is one blade").

- contacts open (d = 1 m), mistuned, N = 5, EO = 2: every blade equals the single blade's closed
  form from rest (forced response plus the free transient fixed by q(0) = q'(0) = 0; constants from
  the independent Galerkin model of tests/support/modes_galerkin.py), at every communication point over
  0.1 s: measured 2.3e-8 of max |q|, RK4's own error (1.4e-9 at maxStep 5e-6: the ratio 16 of a
  fourth-order method); tolerance 1e-7;
- EO a multiple of N (N = 3, EO = 3): the loads are in phase, so the tuned ring moves in phase, u = 0
  and the contacts carry nothing, even where a blade moves 34 gaps (near its resonance, light
  damping): each blade is the single blade's closed form without contact (measured 1.8e-8;
  tolerance 1e-7) and every contact stays open;
- EO = N/2 (N = 2, EO = 1): q_1 = -q_0, u_0 = 2 q_0 = -u_1, and blade 0 is ShroudedBlade alone with
  the same time-domain Jenkins element at kn' = 4 kn, d' = d / 2 (the derivation in the guide):
  measured over 0.15 s from rest (contacts stick, slip and open) 5.1e-3 / 5.1e-4 / 1.5e-4 of max |q|
  at h = T/320, T/640, T/1280 (tolerances 1e-2, 1.5e-3), the coupling error shrinking; kn' = 2 kn
  stays 0.21 off at every step, d' = d 0.84;
- EO = N/2 (N = 4, EO = 2): the same mapping while the wave keeps its symmetry: that wave is unstable
  at 5000 rpm (c = 298, F_w0 = 300): a rounding-size antisymmetric part grows from 1e-15 to order 1
  by 0.2 s, in the co-simulation and in the monolithic reference alike, and the ring settles on a
  state with blades 0, 2 at 1.64e-5 m and 1, 3 at 2.43e-5 m; over the first 0.04 s (symmetric to
  1e-12) blade 0 equals ShroudedBlade under the mapping within 2.3e-3 at h = T/320 (1.6e-4 at
  T/1280; tolerance 5e-3).
"""

from __future__ import annotations

import math

import numpy as np
import pytest

from harness.fmu.build import FMU_PATH, build
from harness.fmu.slave import Unpacked
from harness.system.ring import Ring
from harness.system.ring_c import run
from tests.support.ring_closed_form import CONSISTENT, blade

KN, D = 1e7, 3e-5  # Table 1, set explicitly


def from_rest(M: float, C: float, K: float, F: float, phi: float, w: float, t: np.ndarray) -> np.ndarray:
    """q(t) of M q'' + C q' + K q = F sin(w t + phi), q(0) = q'(0) = 0 (underdamped)."""
    Q = F * np.exp(1j * phi) / (K - w * w * M + 1j * w * C)
    a, b = -C / (2 * M), math.sqrt(K / M - (C / (2 * M)) ** 2)  # the free motion e^{a t} (cos, sin)(b t)
    A = -np.imag(Q)
    B = (-np.imag(1j * w * Q) - a * A) / b
    return np.imag(Q * np.exp(1j * w * t)) + np.exp(a * t) * (A * np.cos(b * t) + B * np.sin(b * t))


def _closed_form_error(ring: Ring, pattern: tuple[float, ...]) -> float:
    res = run(ring)
    t, w = res["time"], ring.omega
    Om = 2 * math.pi * ring.speed / 60
    worst = 0.0
    for i, f in enumerate(pattern):
        M, C, Ks, Kw, g = blade(343.0 * f, float(ring.blade.get("c", 29.8)))
        exact = from_rest(M, C, Ks + Kw * Om * Om, g * ring.fw0, 2 * math.pi * ring.engine_order * i / ring.n, w, t)
        worst = max(worst, float(np.abs(res["q"][:, i] - exact).max() / np.abs(exact).max()))
    assert np.all(res["state"] == 0) and np.all(res["contactForce"] == 0.0)
    return worst


def _step(n: int, eo: int, speed: float, per_period: int) -> float:
    return round(60 / (eo * speed) / per_period * 1e9) * 1e-9


def test_open_contacts_give_the_single_blade_closed_form() -> None:
    pattern = (1.04, 0.97, 1.0, 0.95, 1.03)
    ring = Ring(
        n=5,
        engine_order=2,
        fw0=100.0,
        speed=7000.0,
        blade={"formulation": CONSISTENT},
        blade_each=tuple({"EI": 343.0 * f} for f in pattern),
        contact={"d": 1.0},
        order=2,
        step=_step(5, 2, 7000.0, 160),
        stop_time=0.1,
    )
    err = _closed_form_error(ring, pattern)
    assert err <= 1e-7, err


def test_in_phase_wave_leaves_the_contacts_unloaded() -> None:
    # EO = N: phases 2 pi i, the blades in phase; near resonance (4979 rpm) they reach 34 gaps
    ring = Ring(
        n=3,
        engine_order=3,
        fw0=100.0,
        speed=5000.0,
        blade={"formulation": CONSISTENT},
        contact={"kn": KN, "d": D},
        order=2,
        step=_step(3, 3, 5000.0, 160),
        stop_time=0.1,
    )
    err = _closed_form_error(ring, (1.0, 1.0, 1.0))
    assert err <= 1e-7, err


def _alone_under_the_mapping(ring: Ring, t: np.ndarray, kn_factor: float = 4.0, d_factor: float = 0.5) -> np.ndarray:
    """ShroudedBlade alone (time-domain Jenkins element, kn' = 4 kn, d' = d / 2) with blade 0's load,
    stepped over the ring's communication points: q at every point."""
    build(("fmu",))
    params = {
        **dict(ring.blade),
        "kn": kn_factor * KN,
        "d": d_factor * D,
        "frictionModel": 3,
        "amplitudeMode": 1,
        "Fw0": ring.fw0,
        "bladeIndex": 0,
        "bladeCount": ring.n,
        "engineOrder": ring.engine_order,
    }
    with Unpacked(FMU_PATH) as sb:
        s = sb.instance("alone", params, inputs={"rotorSpeed": ring.speed})
        try:
            q = [s.get(["tipDisplacement"])[0]]
            for k in range(len(t) - 1):
                s.set_inputs({"rotorSpeed": ring.speed})
                s.step(float(t[k]), float(t[k + 1] - t[k]))
                q.append(s.get(["tipDisplacement"])[0])
        finally:
            s.free()
    return np.array(q)


def _antisymmetric(n: int, eo: int, speed: float, per_period: int, stop: float) -> tuple[dict, Ring]:
    ring = Ring(
        n=n,
        engine_order=eo,
        fw0=300.0,
        speed=speed,
        blade={"c": 298.0},
        contact={"kn": KN, "d": D},
        order=2,
        step=_step(n, eo, speed, per_period),
        stop_time=stop,
    )
    return run(ring), ring


@pytest.mark.parametrize("per_period,tol", [(320, 1e-2), (1280, 1.5e-3)])
def test_half_order_wave_is_one_blade_with_four_times_the_contact(per_period: int, tol: float) -> None:
    res, ring = _antisymmetric(2, 1, 9000.0, per_period, 0.15)
    q = res["q"]
    assert {0.0, 1.0, 2.0} <= set(np.unique(res["state"]))  # open, stick and slip
    assert np.abs(q[:, 1] + q[:, 0]).max() <= 1e-12 * np.abs(q).max()
    alone = _alone_under_the_mapping(ring, res["time"])
    err = np.abs(q[:, 0] - alone).max() / np.abs(alone).max()
    assert err <= tol, err


@pytest.mark.parametrize("kn_factor,d_factor", [(2.0, 0.5), (4.0, 1.0)])
def test_a_wrong_mapping_stays_off(kn_factor: float, d_factor: float) -> None:
    res, ring = _antisymmetric(2, 1, 9000.0, 640, 0.15)
    alone = _alone_under_the_mapping(ring, res["time"], kn_factor, d_factor)
    assert np.abs(res["q"][:, 0] - alone).max() / np.abs(alone).max() >= 0.1


def test_half_order_wave_of_four_blades_while_it_keeps_its_symmetry() -> None:
    res, ring = _antisymmetric(4, 2, 5000.0, 320, 0.04)
    q = res["q"]
    assert np.abs(q[:, 1] + q[:, 0]).max() <= 1e-11 * np.abs(q).max()
    assert np.abs(q[:, 2] - q[:, 0]).max() <= 1e-11 * np.abs(q).max()
    alone = _alone_under_the_mapping(ring, res["time"])
    err = np.abs(q[:, 0] - alone).max() / np.abs(alone).max()
    assert err <= 5e-3, err
