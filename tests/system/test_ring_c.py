"""The ring's C communication loop (harness/system/ring_c.py, harness/native/ring_master.c) against
the fmpy master (harness/system/ring.py), which does the same calls from Python:

- contacts open, held inputs: bit for bit (no extrapolation arithmetic);
- contacts closing, linear and quadratic extrapolation, a tuned ring of 4 and a mistuned ring of 6 blades: every
  record within 1e-12 of its largest value (the derivative weights are summed in another order:
  measured <= 4e-12 N on forces of ~20 N, 4e-19 m on q);
- a diverging ring (held inputs at 1e-3 s, stable only below 5e-5 s: a blade refuses a step once
  its state overflows) stops with an error that names the FMU instance and the call, as the fmpy
  master does (the divergence check switched off); with the check (held inputs at 4e-4 s, where the
  unchecked fmpy master reached 1e139 m) both masters stop at the same step, naming it, the blade and
  what to change; a bad order or coupling is refused.
"""

from __future__ import annotations

import math
import re

import numpy as np
import pytest

from harness.fmu.binding import FmiError
from harness.system import ring_c
from harness.system.ring import Ring, RingDiverged, run

CLOSING = dict(fw0=300.0, blade={"c": 298.0})


def test_open_contacts_bit_for_bit():
    ring = Ring(n=3, stop_time=0.01, contact={"d": 1.0}, order=0)
    a, b = run(ring), ring_c.run(ring)
    for k in a:
        assert np.array_equal(a[k], b[k]), k


@pytest.mark.parametrize(
    "n, order, step, each",
    [
        (4, 1, 1e-4, ()),
        (6, 2, 2.5e-5, tuple({"EI": x} for x in (0.97, 1.02, 1.0, 1.05, 0.99, 1.01))),
    ],
)
def test_closing_contacts_equal_within_rounding(n, order, step, each):
    ring = Ring(n=n, stop_time=0.02, step=step, order=order, **CLOSING)
    if each:
        from harness.studies.mistuning import blade_value

        ring = Ring(
            n=n,
            stop_time=0.02,
            step=step,
            order=order,
            **CLOSING,
            blade_each=tuple({"EI": blade_value(ring, "EI") * e["EI"]} for e in each),
        )
    a, b = run(ring), ring_c.run(ring)
    assert np.any(a["state"] > 0)  # the contacts did close
    for k in a:
        scale = max(np.abs(a[k]).max(), 1e-300)
        assert np.abs(a[k] - b[k]).max() <= 1e-12 * scale, k


def test_a_diverging_ring_names_the_fmu():
    ring = Ring(n=4, stop_time=0.3, step=1e-3, order=0, q_limit=math.inf, **CLOSING)
    with pytest.raises(FmiError):
        run(ring)
    with pytest.raises(RuntimeError, match=r"fmi2DoStep failed for (blade|contact|exc)\d+ at t = .* s"):
        ring_c.run(ring)


def test_divergence_check_stops_both_masters_at_the_same_step():
    ring = Ring(n=4, stop_time=0.3, step=4e-4, order=0, **CLOSING)
    with pytest.raises(RingDiverged) as a:
        run(ring)
    with pytest.raises(RingDiverged) as b:
        ring_c.run(ring)
    step = [re.search(r"diverged at step (\d+) ", str(e.value)).group(1) for e in (a, b)]
    assert step[0] == step[1], (str(a.value), str(b.value))
    for e in (a, b):
        assert "\n" not in str(e.value) and "reduce --step (now 0.0004 s" in str(e.value)
    # below the limit the run is the same run: the check does not change it
    ok = Ring(n=4, stop_time=0.02, step=2.5e-5, order=2, **CLOSING)
    assert np.array_equal(ring_c.run(ok)["q"], ring_c.run(Ring(**{**ok.__dict__, "q_limit": math.inf}))["q"])


def test_bad_order_is_refused():
    with pytest.raises(ValueError, match="order 5 outside"):
        ring_c.run(Ring(n=2, stop_time=0.001, order=5))


def test_libcosim_data_flow_bit_for_bit():
    from harness.system import ring_libcosim

    ring = Ring(n=4, stop_time=0.01, step=2.5e-5, order=0, coupling="libcosim", **CLOSING)
    a, b = run(ring), ring_c.run(ring)
    assert np.any(a["state"] > 0)
    for k in a:
        assert np.array_equal(a[k], b[k]), k
    lc = ring_libcosim.run(Ring(n=4, stop_time=0.01, step=2.5e-5, order=0, **CLOSING))
    assert np.array_equal(lc["q"], b["q"])


def test_decimated_record_keeps_every_mth_point():
    ring = Ring(n=4, stop_time=0.01, step=2.5e-5, order=2, **CLOSING)
    a, b = ring_c.run(ring), ring_c.run(ring, record_every=8)
    assert all(np.array_equal(a[k][::8], b[k]) for k in a)
    with pytest.raises(ValueError, match="record_every 7"):
        ring_c.run(ring, record_every=7)


def test_timed_run_is_the_same_run():
    import time

    ring = Ring(n=4, stop_time=0.02, step=2.5e-5, order=2, **CLOSING)
    a = ring_c.run(ring)
    t0 = time.perf_counter()
    b = ring_c.run(ring, time_dosteps=True)
    wall = time.perf_counter() - t0
    assert all(np.array_equal(a[k], b[k]) for k in a)
    assert 0 < float(b["inside_doStep"]) < wall


def test_records_asked_for_are_the_full_runs():
    """advance(records=...) keeps only those (the others go to a spare buffer): the same numbers as
    the run that keeps every record; a name it does not know, or no q, is refused."""
    ring = Ring(n=4, stop_time=0.01, step=2.5e-5, order=2, **CLOSING)
    with ring_c.CRing(ring) as a, ring_c.CRing(ring) as b:
        full = a.advance(200, finish=True)
        some = b.advance(200, finish=True, records=("q", "forceA"))
        more = b.advance(50, records=("q",))  # the spare buffer grown or not: the run goes on the same
        rest = a.advance(50)
    assert set(some) == {"q", "forceA", "time"} and set(more) == {"q", "time"}
    assert all(np.array_equal(full[k], some[k]) for k in some)
    assert np.array_equal(rest["q"], more["q"])
    with ring_c.CRing(ring) as c:
        for bad in (("q", "speed"), ("v",)):
            with pytest.raises(ValueError, match="records"):
                c.advance(10, records=bad)
