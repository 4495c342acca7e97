"""The symmetries of the forced ring, acting on blade indices, for merging branches.

Blade i is loaded by F_w0 sin(psi + 2 pi EO i / N); contact j joins blade j and blade j + 1 with an
odd law (u -> -u, F -> -F). For the tuned ring (every blade the same):
- rotation by s (blade i -> i + s) with the time shift delta_s = -2 pi EO s / (N omega) maps orbits to
  orbits (blade i + s's load, delayed by delta_s, is blade i's): always a symmetry;
- reflection (blade i -> s - i, contact j -> s - 1 - j, u -> -u) turns the load's travelling wave
  round (phase -2 pi EO i / N); no time shift undoes that (it adds the same phase to every blade), so
  it is a symmetry only where the backward wave is the forward one: 2 EO = 0 mod N (a standing wave,
  e.g. EO 3 on 6 blades);
- q -> -q with the half-period shift (the load's sign) maps orbits to orbits and leaves every
  blade's max |q| as it is.
The time shifts do not act on the period map's state at load phase 0 as a permutation, so branches are
compared by what the symmetries keep: the per-blade amplitude vectors, permuted. A mistuned ring
has no symmetry (the identity only).
"""

from __future__ import annotations

import numpy as np

from harness.system.ring import Ring


def tuned(ring: Ring) -> bool:
    """True if every blade has the same parameters."""
    return not ring.blade_each or all(dict(b) == dict(ring.blade_each[0]) for b in ring.blade_each)


def index_maps(ring: Ring) -> list[np.ndarray]:
    """The permutations g of the forced ring's symmetries: an orbit with amplitudes a has an image
    with amplitudes a[g] (identity first)."""
    N = ring.n
    i = np.arange(N)
    if not tuned(ring):
        return [i]
    maps = [np.roll(i, -s) for s in range(N)]
    if (2 * ring.engine_order) % N == 0:
        maps += [(s - i) % N for s in range(N)]
    return maps


def distance(a: np.ndarray, b: np.ndarray, maps: list[np.ndarray]) -> float:
    """min over the symmetries g of max_i |a[g_i] - b_i| / max(max a, max b)."""
    scale = max(float(np.max(a)), float(np.max(b)), 1e-300)
    return min(float(np.max(np.abs(a[g] - b))) for g in maps) / scale
