"""Bifurcations of the ring's branches (harness/system/ring_orbits/crossings.py): crossings
detected beyond the multipliers' noise.

- detection: hand-made multiplier sequences (a real multiplier hovering within the noise band of
  +1, then leaving it) give exactly the crossings the hysteresis rule defines;
"""
from __future__ import annotations

import numpy as np

from harness.system.ring_orbits.crossings import NOISE, detect


def _mu(*real: float) -> np.ndarray:
    return np.array([complex(r) for r in real] + [0.3 + 0.4j, 0.3 - 0.4j])


def test_a_multiplier_hovering_at_one_is_no_crossing():
    h = 0.5 * NOISE
    hover = [_mu(0.9), _mu(1 + h), _mu(1 - h), _mu(1 + h), _mu(0.95)]
    assert detect(hover, "branch point") == []
    through = [_mu(0.9), _mu(1 + h), _mu(1 - h), _mu(1 + h), _mu(1.2), _mu(1 + h), _mu(0.8)]
    assert detect(through, "branch point") == [(0, 4), (4, 6)]
    # a second multiplier far above 1 does not hide the crossing of the first
    assert detect([_mu(3.0, 0.9), _mu(3.0, 1.1)], "branch point") == [(0, 1)]
    assert detect([_mu(3.0, 0.9), _mu(3.0, 1.1)], "Neimark-Sacker") == []
