"""The tuned 6-blade ring at 6400 rpm (the mistuning study's settings: c = 298 N s/m2, F_w0 = 300
N/m, EO 3, h = T / 160 with quadratic extrapolation) leaves the travelling wave in the co-simulation
and in the monolithic reference alike (docs/findings/ring-steady-states.md).

From rest, 0.3 s (96 periods, 14 decay times), both runs:
- keep q_{i+3} = -q_i (an exact symmetry of the equations at EO 3 on 6 blades: lead 3 pi) to
  rounding, but settle on blade amplitudes (1.05, 3.68, 2.04)e-5 m repeated, not the wave's equal
  ones;
- agree per blade within 5e-3 of the largest amplitude (measured 5.4e-4: the co-simulation's
  error at this step is ~1e-3 of max |q| (docs/guide/mistuning.md), and both take max |q| over the
  same 160 phases of the last period), compared with the closest of the state's copies under the
  ring's symmetries (turned by k blades, or mirrored): rounding decides which copy a run lands on
  (at 7000 rpm the two runs land on mirror images);
- break the wave's symmetry q_i = -q_{i+1} from rounding at the same rate: the mirror defect grows
  by |mu| = 3.41 (co-sim) and 3.44 (reference) per period, its largest Floquet multiplier off the
  wave; the test asks for > 2 in both and agreement within 5 %.
"""

from __future__ import annotations

import numpy as np
import pytest

from harness.validation import ring_states as R

CASE = R.SETTINGS["a6400"]
T = R.period(CASE["speed"])


@pytest.fixture(scope="module")
def runs():
    ring = R.cosim_ring(CASE["n"], CASE["speed"], CASE["c"], 0.3)
    tc, qc = R.cosim(ring)
    r = R.reference(R.spec_of(ring), 0.3, 160)
    tr, qr = r["time"], r["q"]
    return (tc, qc), (tr, qr)


def test_both_leave_the_wave_for_the_same_pattern(runs):
    ac, ar = (R.period_amplitudes(t, q, T)[-1] for t, q in runs)
    for t, q in runs:
        assert np.abs(q + np.roll(q, 3, axis=1)).max() <= 1e-9 * np.abs(q).max()
    for a in (ac, ar):
        assert (a.max() - a.min()) > 0.5 * a.max(), a  # not the wave's equal amplitudes
    # which of the state's symmetric copies (the ring turned by k blades or mirrored, i -> k - i)
    # a run lands on is decided by rounding: compare with the closest copy
    n = len(ar)
    copies = [ar[(k + s * np.arange(n)) % n] for k in range(n) for s in (1, -1)]
    assert min(np.abs(ac - c).max() for c in copies) <= 5e-3 * ar.max(), (ac, ar)


def test_the_wave_is_unstable_at_the_same_rate(runs):
    mu = [R.growth_per_period(R.mirror_defect(t, q, T))[0] for t, q in runs]
    assert min(mu) > 2.0, mu
    assert abs(mu[0] - mu[1]) <= 0.05 * mu[1], mu
