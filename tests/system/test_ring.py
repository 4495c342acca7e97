"""The ring co-simulation (harness/system/ring.py): N BladeExternalContact + N ShroudContact FMUs
(the blades' built-in load) under the fmpy Jacobi master.

- contacts open (d = 1 m): every blade equals ShroudedBlade run alone (contact open, amplitudeMode 1)
  with the same built-in load (Fw0, bladeIndex, bladeCount, engineOrder), bit for bit;
- tuned ring, travelling wave (N = 4, EO = 3: neighbours 3 pi / 2 apart, the contacts stick, slip
  and open; blade i's time shift is a whole number of steps, so the discrete solution keeps the
  cyclic symmetry): after 0.4 s (the transient decays with 2M/C0 = 0.022 s at c = 298 N s/m2) the
  first-harmonic amplitudes are equal within 1e-6 relative and the phase lags equal 2 pi EO i / N
  within 1e-6 rad (computed independently of the ring: the excitation's closed form);
- every step: forceA = -forceB exactly for every contact, and the contact forces on the blades sum
  to zero within 1e-12 of the largest;
- N = 36 (EO = 3, paper parameters, near resonance: the contacts close) runs and keeps the force
  balance;
- stability with kn = 1e7 (measured, docs/model.md s.8): held inputs diverge at h = 1e-4 s (the
  master stops with RingDiverged naming the step, before 0.1 s), linear extrapolation of the input
  derivatives is stable there;
- Ring(coupling=...) accepts "feedthrough" and "libcosim" (with order 0 only): anything else is a
  ValueError naming the value and the accepted ones.
"""

from __future__ import annotations

import math

import numpy as np
import pytest

from harness.fmu.build import FMU_PATH, build
from harness.fmu.slave import Unpacked
from harness.system.ring import Ring, RingDiverged, harmonic, run

TUNED = dict(blade={"c": 298.0}, fw0=300.0)


def lag_error(ring: Ring, res) -> tuple[float, float]:
    omega = ring.engine_order * 2 * math.pi * ring.speed / 60
    c = harmonic(res, omega)
    expect = 2 * math.pi * ring.engine_order * np.arange(ring.n) / ring.n  # the built-in load's lead
    err = np.angle(np.exp(1j * (np.angle(c / c[0]) - expect)))
    amp = np.abs(c)
    return float(np.ptp(amp) / amp.mean()), float(np.abs(err).max())


def assert_force_balance(res) -> None:
    assert np.all(res["forceA"] == -res["forceB"])
    f = res["contactForce"]
    assert np.abs(f.sum(axis=1)).max() <= 1e-12 * max(np.abs(f).max(), 1e-300)


def _stepped_alone(s, res: dict, n_steps: int, set_inputs) -> np.ndarray:
    """Blade instance `s` stepped over the ring's communication points (set_inputs(k) before step k),
    then freed: its (tipDisplacement, tipVelocity) at every point."""
    try:
        rows = [s.get(["tipDisplacement", "tipVelocity"])]
        for k in range(n_steps):
            set_inputs(k)
            s.step(float(res["time"][k]), float(res["time"][k + 1] - res["time"][k]))
            rows.append(s.get(["tipDisplacement", "tipVelocity"]))
    finally:
        s.free()
    return np.array(rows)


def test_open_contacts_equal_single_blade_with_its_load_bit_for_bit():
    ring = Ring(n=3, engine_order=3, stop_time=0.03, contact={"d": 1.0}, order=2, speed=5300.0)
    res = run(ring)
    assert np.all(res["state"] == 0) and np.all(res["contactForce"] == 0.0)
    build(("fmu",))
    with Unpacked(FMU_PATH) as sb:
        for i in range(ring.n):
            s = sb.instance(
                "alone",
                {
                    "d": 1.0,
                    "amplitudeMode": 1,
                    "Fw0": ring.fw0,
                    "bladeIndex": i,
                    "bladeCount": ring.n,
                    "engineOrder": ring.engine_order,
                },
                inputs={"rotorSpeed": ring.speed},
            )
            rows = _stepped_alone(s, res, ring.n_steps, lambda k: s.set_inputs({"rotorSpeed": ring.speed}))
            assert np.abs(rows[:, 0]).max() > 1e-5
            assert np.array_equal(rows[:, 0], res["q"][:, i]) and np.array_equal(rows[:, 1], res["v"][:, i])


@pytest.mark.parametrize("n,eo", [(4, 3), (2, 1)])
def test_travelling_wave(n, eo):
    ring = Ring(n=n, engine_order=eo, stop_time=0.4, **TUNED)
    res = run(ring)
    assert {1.0, 2.0} <= set(np.unique(res["state"]))  # the contacts stick and slip
    spread, lag = lag_error(ring, res)
    assert spread <= 1e-6 and lag <= 1e-6, (spread, lag)
    assert_force_balance(res)
    assert np.all(np.diff(res["Ec"], axis=0) >= -1e-15)  # friction energy never decreases


def test_ring_of_36():
    ring = Ring(n=36, engine_order=3, stop_time=0.03)  # paper parameters: near resonance, the contacts close
    res = run(ring)
    assert np.all(np.isfinite(res["q"]))
    assert {1.0, 2.0} <= set(np.unique(res["state"]))
    assert_force_balance(res)


def test_stability_limit_kn_1e7():
    with pytest.raises(
        RingDiverged,
        match=r"diverged at step \d+ \(t = .* s\): blade \d \|q\| = .* m > 0.01 m; "
        r"raise --order .* reduce --step \(now 0.0001 s",
    ):
        run(Ring(n=4, stop_time=0.1, order=0, step=1e-4, **TUNED))  # grows without bound (1e23 m at 0.3 s)
    linear = run(Ring(n=4, stop_time=0.1, order=1, step=1e-4, **TUNED))
    assert np.abs(linear["q"]).max() < 1e-4


@pytest.mark.parametrize(
    "kw, word", [(dict(coupling="jacobi"), "'jacobi'"), (dict(coupling="libcosim", order=1), "order must be 0")]
)
def test_bad_coupling_is_refused(kw, word):
    with pytest.raises(ValueError, match=word) as e:
        Ring(**kw)
    if "jacobi" in word:
        assert "'feedthrough'" in str(e.value) and "'libcosim'" in str(e.value)
