"""The ring in libcosim (harness/system/ring_libcosim.py): the same FMUs, one-to-one connections
(the blade adds its two contact-force inputs), libcosim's fixed-step Jacobi algorithm with held
inputs.

- contacts open: libcosim equals the fmpy master with held inputs (same integer-nanosecond points)
  bit for bit;
- contacts closing (N = 4, EO = 3, k_n = 1e7): libcosim converges to the monolithic reference as h
  shrinks, first order (measured 1.13 on h = 2.5e-5 .. 6.25e-6 s; tested >= 0.9), and is unstable
  at h = 1e-4 s like the held-input fmpy master (measured: 3e9 relative error at 0.05 s);
- every step forceA = -forceB for every contact.
"""
from __future__ import annotations

import numpy as np
import pytest

from harness.reference.ring import MonolithicRing, RingSpec
from harness.system import ring_libcosim
from harness.system.ring import Ring, run

pytestmark = pytest.mark.crosscheck

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
