"""The ring in libcosim (harness/system/ring_libcosim.py): the same FMUs, one-to-one connections
(the blade adds its two contact-force inputs), libcosim's fixed-step Jacobi algorithm with held
inputs.

- contacts open: libcosim equals the fmpy master with held inputs (same integer-nanosecond points)
  bit for bit;
- contacts closing (N = 4, EO = 3, k_n = 1e7): libcosim converges to the monolithic reference as h
  shrinks, first order (measured 1.13 on h = 2.5e-5 .. 6.25e-6 s; tested >= 0.9), and is unstable
  at h = 1e-4 s like the held-input fmpy master (measured: 3e9 relative error at 0.05 s);
- every step forceA = -forceB for every contact;
- contacts closing (tuned ring N = 4, EO = 3, fw0 = 300, c = 298, h = 2.5e-5 s, 0.02 s): the fmpy
  master with coupling "libcosim" equals libcosim through its API and from the SSP bit for bit
  (q and the contact forces; measured difference 0), Ecos from the SSP within 1e-8 of max |q|
  (measured 4.3e-13: Ecos's t += h points differ by ulps); the same ring fed through (the default
  coupling) differs by 1.7e-2 of max |q|;
- the built-in load at another speed than the inputs' start (6300 rpm): the C loop in libcosim's data
  flow equals libcosim (API and SSP) bit for bit and Ecos within 1e-10 of max |q| (measured 1.3e-12:
  Ecos accumulates t += h), so every blade and contact gets rotorSpeed;
- travelling wave in libcosim's data flow (same ring, 0.1 s, steady: the contacts stick, slip and
  open every period): libcosim equals the fmpy master bit for bit, the first-harmonic amplitudes of
  the four blades are equal within 1e-4 relative (measured 3.4e-5, the transient's remainder) and
  the phase lags equal 2 pi EO i / N within 1e-4 rad (measured 1.9e-6).
"""

from __future__ import annotations

import numpy as np

import math

from harness.fmu.build import BUILD_DIR
from harness.reference.ring import MonolithicRing, RingSpec
from harness.system import ring_libcosim, ssp
from harness.system.ring import Ring, harmonic, run


TUNED = dict(blade={"c": 298.0}, fw0=300.0)


def test_open_contacts_equal_fmpy_master_bit_for_bit():
    ring = Ring(n=3, engine_order=1, stop_time=0.03, contact={"d": 1.0}, order=0)
    a, b = run(ring), ring_libcosim.run(ring)
    assert np.array_equal(a["time"], b["time"])
    assert np.abs(a["q"]).max() > 1e-5
    assert np.array_equal(a["q"], b["q"]) and np.array_equal(a["v"], b["v"])


def test_libcosim_converges_to_monolithic():
    T = 0.03
    q = MonolithicRing(RingSpec(n=4, engine_order=3, **TUNED)).solve(np.arange(round(T / 1e-4) + 1) * 1e-4)["q"]
    err = {}
    for h in (2.5e-5, 1.25e-5, 6.25e-6):
        c = ring_libcosim.run(Ring(n=4, engine_order=3, step=h, stop_time=T, order=0, **TUNED))
        assert np.all(c["forceA"] == -c["forceB"])
        err[h] = np.abs(c["q"][:: round(1e-4 / h)] - q).max() / np.abs(q).max()
    hs = sorted(err)
    order = np.polyfit(np.log(hs), np.log([err[h] for h in hs]), 1)[0]
    assert order >= 0.9, err
    assert err[6.25e-6] <= 0.05, err
    unstable = ring_libcosim.run(Ring(n=4, engine_order=3, step=1e-4, stop_time=0.05, order=0, **TUNED))
    assert np.abs(unstable["q"][-1]).max() > 1e-2


def test_libcosim_coupling_equals_libcosim_and_ecos_with_contacts_closing():
    ring = Ring(n=4, engine_order=3, step=2.5e-5, stop_time=0.02, order=0, coupling="libcosim", **TUNED)
    a, b = run(ring), ring_libcosim.run(ring)
    assert set(np.unique(a["state"])) == {0, 1, 2}  # open, stick and slip all occur
    assert np.array_equal(a["time"], b["time"])
    assert np.array_equal(a["q"], b["q"]) and np.array_equal(a["v"], b["v"])
    assert np.array_equal(a["forceA"], b["forceA"]) and np.array_equal(a["forceB"], b["forceB"])
    d = ssp.write(ring, BUILD_DIR / "ring4_coupling_test")
    assert np.array_equal(ssp.run_libcosim(d, ring)["q"], a["q"])
    scale = np.abs(a["q"]).max()
    assert np.abs(ssp.run_ecos(d, ring)["q"] - a["q"]).max() <= 1e-8 * scale
    # the default coupling is a different algorithm: it must not pass for libcosim's
    fed = run(Ring(n=4, engine_order=3, step=2.5e-5, stop_time=0.02, order=0, **TUNED))
    assert np.abs(fed["q"] - a["q"]).max() > 1e-3 * scale


def test_c_loop_equals_libcosim_at_another_speed():
    from harness.system import ring_c

    ring = Ring(n=4, engine_order=3, step=2.5e-5, stop_time=0.02, order=0, coupling="libcosim", speed=6300.0, **TUNED)
    a, b = ring_c.run(ring), ring_libcosim.run(ring)
    assert np.abs(a["q"]).max() > 1e-5 and np.array_equal(a["q"], b["q"])
    d = ssp.write(ring, BUILD_DIR / "ring4_6300_test")
    assert np.array_equal(ssp.run_libcosim(d, ring)["q"], a["q"])
    assert np.abs(ssp.run_ecos(d, ring)["q"] - a["q"]).max() <= 1e-10 * np.abs(a["q"]).max()


def test_travelling_wave_in_libcosim_data_flow():
    ring = Ring(n=4, engine_order=3, step=2.5e-5, stop_time=0.1, order=0, coupling="libcosim", **TUNED)
    a, b = run(ring), ring_libcosim.run(ring)
    assert np.array_equal(a["q"], b["q"])
    assert set(np.unique(a["state"][-160:])) == {0, 1, 2}  # the last period: open, stick, slip
    c = harmonic(b, ring.omega)
    amp = np.abs(c)
    assert np.ptp(amp) <= 1e-4 * amp.mean()
    expect = 2 * math.pi * ring.engine_order * np.arange(ring.n) / ring.n  # the load's lead
    assert np.abs(np.angle(np.exp(1j * (np.angle(c / c[0]) - expect)))).max() <= 1e-4
