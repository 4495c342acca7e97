"""Where a stable steady state the engine missed lives: its orbit made again from the same start
(harness/validation/ring_completeness.py: the starts are a function of speed and seed), then
continued both ways across the band by the engine's own continuation (ring_orbits.continuation.trace),
stopping where it runs onto a branch of the engine's set. The branch it traces says why it was
missed: it joins an engine branch (the engine's corrector stopped short of this part, e.g. at a kink
of the period map), or it is an isola or a branch no seed of the engine reached (its speed range
against the engine's seed speeds)."""

from __future__ import annotations

from typing import Any

import numpy as np

from harness.system.ring import Ring
from harness.system.ring_orbits.branches import default_seed_points
from harness.system.ring_orbits.continuation import trace
from harness.system.ring_orbits.period_map import RingPeriodMap
from harness.system.ring_orbits.shooting import shoot
from harness.system.ring_orbits.symmetry import index_maps
from harness.validation.branch_match import RTOL, Branch, match
from harness.validation.ring_completeness import SETTLE, STEPS, map_settings, run_to_steady, starts


def follow(
    ring: Ring,
    band: tuple[float, float],
    speed: float,
    start: str,
    seed: int,
    branches: list[Branch],
    settle: float = SETTLE,
    max_periods: int = 1500,
    steps: int = STEPS,
) -> dict[str, Any]:
    """The missed state's branch (module docstring): its speed range, stable points, how each end
    ended, its bifurcations, the engine's seed speeds inside it, and the periods it cost."""
    maps = index_maps(ring)
    with RingPeriodMap(ring, map_settings(steps)) as pm:
        x0 = dict(starts(pm, speed, int(start.split()[-1]) + 1 if start != "rest" else 0, seed))[start]
        x, res, _, _ = run_to_steady(pm, x0, speed, settle, max_periods)
        orb = shoot(pm, x, speed)
        if orb is None:
            return {"speed_rpm": speed, "start": start, "error": "Newton did not converge this time"}
        br = trace(pm, orb, band, joined=lambda n, a: match(branches, n, a, maps).distance_any <= RTOL)
        S = br.speeds
        st = br.stable
        seeds = np.linspace(*band, default_seed_points(band))
        return {
            "speed_rpm": speed,
            "start": start,
            "amplitudes_m": orb.amplitudes.tolist(),
            "max_multiplier": orb.max_multiplier,
            "branch_rpm": [float(S.min()), float(S.max())],
            "points": len(S),
            "stable_rpm": [float(S[st].min()), float(S[st].max())] if st.any() else None,
            "largest_stable_m": float(br.amplitudes[st].max()) if st.any() else None,
            "end_reasons": br.end_reasons,
            "bifurcations": [(b.kind, round(b.speed, 1)) for b in br.bifurcations],
            "engine_seed_speeds_inside": [float(s) for s in seeds if S.min() <= s <= S.max()],
            "periods": pm.evaluations,
        }
