"""Branches of the ring's periodic orbits in rotor speed, their stability and bifurcations.

The continuation is the single blade's (harness.analysis.periodic.continuation: pseudo-arclength in
(x / scale, rpm / 1000), quasi-Newton corrector, step control through folds) on the ring's period
map, with forward differences for DP (the map's `central_differences`), or the low-rank DP where
the map's settings ask for it (`RingShootingSettings.dp`, derivative.py: the continuation's Jacobian,
the extrema's, the crossings' fresh DPs and the switches' come from the map's `state_jacobian`, the
speed column a forward difference in the same batch of periods); peaks (of the largest
blade's max |q|) and folds (speed turning points) are located by the single blade's
harness.analysis.periodic.extrema where a neighbour is stable (the others stay sampled). A corrector
that cannot cross a kink of the map (ds below ds_min: a contact opening or closing exactly at the
period's start, a grazing) is retried a step of kink_steps past it before the branch ends there.
Bifurcations (crossings.py: detected beyond the multipliers' noise, located in the arc by Brent's method):
- fold: the speed turns (located by extrema);
- branch point: the number of real multipliers above +1 changes where the speed does not turn (a
  symmetry-breaking pitchfork of the tuned ring passes +1 with a double multiplier: the sign of
  det(DP - I) alone would miss it);
- period doubling: the number of real multipliers below -1 changes;
- Neimark-Sacker: the number of complex multipliers outside the unit circle changes.
"""

from __future__ import annotations

from dataclasses import dataclass, field
from typing import Callable

import numpy as np

from harness.analysis.periodic.continuation import Branch, BranchProblem, ContinuationSettings, continue_branch, correct
from harness.analysis.periodic.extrema import locate
from harness.analysis.periodic.shooting import UNIT_CIRCLE_TOL
from harness.fmu.blade import FMUError
from harness.system.ring_orbits.crossings import JUMP, KINDS, detect, segment
from harness.system.ring_orbits.crossings import locate as locate_crossing
from harness.system.ring_orbits.period_map import RingPeriodMap
from harness.system.ring_orbits.shooting import RingOrbit, jacobians, monodromy, shoot

# no fresh-Jacobian retry of a failed corrector (up to 8 x 19 periods on 6 blades; a halved step costs a
# few): on the 6-blade study ring over 5500-7200 rpm 21773 -> 15475 periods in all (continuation 15942 ->
# 10908), the same largest stable state (4.94023e-5 m at 5794.83 rpm)
RING_CONTINUATION = ContinuationSettings(
    ds=0.05,
    ds_min=1e-3,
    ds_max=0.3,
    max_points=300,
    max_corrector=8,
    ds_fold=0.02,
    fresh_fallback=False,
    kink_steps=(0.01, 0.03, 0.1),
)


EXTREMUM_TOL = 1e-5  # Brent's tolerance locating a peak or fold: 1e-5 of the scaled arc, 0.01 rpm along the speed


@dataclass
class Bifurcation:
    kind: str  # "fold", "branch point", "period doubling", "Neimark-Sacker"
    speed: float  # [rpm]
    amplitude: float  # largest blade's max |q| [m]
    amplitudes: np.ndarray  # per blade [m]
    index: int  # the first branch point after it
    x: np.ndarray | None = None  # state (interpolated for all but folds)
    vector: np.ndarray | None = None  # critical eigenvector of DP (branch points: the switching direction)
    located: bool = True  # False: linear between two points (crossings.py)
    value: float = float("nan")  # the test function at the located point (crossings.py)
    bracket: float = float("nan")  # the location's final bracket [scaled arc]
    between: tuple[int, int] = (-1, -1)  # the decided points around it (crossings.detect)

    def as_dict(self) -> dict:
        out = {
            "kind": self.kind,
            "speed_rpm": self.speed,
            "amplitude_m": self.amplitude,
            "amplitudes_m": self.amplitudes.tolist(),
        }
        if self.kind != "fold":
            out.update(
                located=self.located,
                test_function=None if self.value != self.value else self.value,
                bracket_arc=None if self.bracket != self.bracket else self.bracket,
                jump=self.located and abs(self.value) > JUMP,
            )
        return out


@dataclass
class RingBranch:
    """A branch of periodic orbits of the ring, points in arc order."""

    orbits: list[RingOrbit]
    end_reasons: list[str]
    bifurcations: list[Bifurcation] = field(default_factory=list)
    peaks: list[RingOrbit] = field(default_factory=list)  # located peaks of the largest blade's max |q|
    folds: list[RingOrbit] = field(default_factory=list)  # located folds (largest multiplier ~ 1)
    fold_sides: list[bool] = field(default_factory=list)  # per fold: it bounds a stable part
    closed: bool = False
    cost: dict = field(default_factory=dict)  # periods simulated per stage of its tracing
    origin: str = ""  # the seed or branch point it was entered from

    @property
    def speeds(self) -> np.ndarray:
        return np.array([o.speed for o in self.orbits])

    @property
    def amplitudes(self) -> np.ndarray:
        """(points, N) per-blade max |q| [m]."""
        return np.array([o.amplitudes for o in self.orbits])

    @property
    def stable(self) -> np.ndarray:
        return np.array([o.stable for o in self.orbits])

    def as_dict(self) -> dict:
        return {
            "speeds_rpm": self.speeds.tolist(),
            "amplitudes_m": self.amplitudes.tolist(),
            "stable": self.stable.tolist(),
            "max_multiplier": [o.max_multiplier for o in self.orbits],
            "period_residual": [o.residual for o in self.orbits],
            "bifurcations": [b.as_dict() for b in self.bifurcations],
            "peaks": [
                {
                    "speed_rpm": p.speed,
                    "amplitude_m": p.amplitude,
                    "amplitudes_m": p.amplitudes.tolist(),
                    "stable": p.stable,
                    "max_multiplier": p.max_multiplier,
                }
                for p in self.peaks
            ],
            "end_reasons": self.end_reasons,
            "closed": self.closed,
            "origin": self.origin,
        }


def _orbit(pm: RingPeriodMap, x: np.ndarray, speed: float, mu: np.ndarray, it: int = 0) -> RingOrbit:
    amp, res = pm.measures(x, speed)
    return RingOrbit(float(speed), np.array(x, dtype=float), amp.copy(), mu, res, it)


def bifurcations(
    pm: RingPeriodMap, br: Branch, folds: list, settings: ContinuationSettings = RING_CONTINUATION
) -> list[Bifurcation]:
    """The bifurcations of br (see the module docstring): folds as located by extrema, the others
    detected beyond the multipliers' noise and located by Brent's method (crossings.py)."""
    out: list[Bifurcation] = []
    pts = br.points
    n = br.speeds
    mus = [p.multipliers for p in pts]
    st = [p.stable for p in pts]
    for kind in KINDS:
        for i, j in detect(mus, kind):
            k = segment(mus, i, j, kind)
            turned = any((n[m] - n[m - 1]) * (n[m + 1] - n[m]) < 0 for m in (k, k + 1) if 0 < m < len(pts) - 1)
            if kind == "branch point" and turned:
                continue  # a fold (located by extrema)
            loc = locate_crossing(pm, pts[k], pts[k + 1], kind, settings)
            amp = (
                pm.measures(loc.x, loc.speed)[0]
                if loc.located
                else 0.5 * (pm.measures(pts[k].x, pts[k].speed)[0] + pm.measures(pts[k + 1].x, pts[k + 1].speed)[0])
            )
            vec = None
            if kind == "branch point" and any(st[i : j + 1]):  # the switching direction (branches.py)
                J = loc.DP if loc.DP is not None else monodromy(pm, pts[k + 1].x, pts[k + 1].speed)
                w, V = np.linalg.eig(J)
                real = np.abs(w.imag) <= UNIT_CIRCLE_TOL * np.maximum(np.abs(w), 1e-300)
                c = int(np.argmin(np.where(real & (w.real > 0), np.abs(w.real - 1.0), np.inf)))
                vec = np.real(V[:, c])
            out.append(
                Bifurcation(
                    kind,
                    float(loc.speed),
                    float(amp.max()),
                    amp,
                    k + 1,
                    loc.x,
                    vec,
                    loc.located,
                    loc.value,
                    loc.bracket,
                    (i, j),
                )
            )
    for e in folds:
        amp = pm.measures(e.x, e.speed)[0]
        i = int(np.argmin(np.abs(n - e.speed)))
        out.append(Bifurcation("fold", float(e.speed), float(amp.max()), amp, i, e.x))
    return sorted(out, key=lambda b: b.index)


def trace(
    pm: RingPeriodMap,
    orbit: RingOrbit,
    band: tuple[float, float],
    settings: ContinuationSettings = RING_CONTINUATION,
    directions: tuple[int, ...] = (-1, 1),
    joined: Callable[[float, np.ndarray], bool] | None = None,
) -> RingBranch:
    """The branch through `orbit` across `band` [rpm] (both directions; an end that left the band
    replaced by the orbit at the band's edge), with its located peaks, folds and bifurcations; a
    direction ends where joined(speed, per-blade amplitudes) says the branch ran onto one traced
    before."""
    jacobians(pm)  # the map's memo of DPs: the extrema, crossings and switches start from the points' DPs
    stop = None
    if joined is not None:

        def stop(p) -> str | None:
            return (
                f"joined a branch traced before at {p.speed:.1f} rpm"
                if joined(p.speed, pm.measures(p.x, p.speed)[0])
                else None
            )

    e0 = pm.evaluations
    br = continue_branch(pm, orbit.x, orbit.speed, band, settings, directions, stop)
    e1 = pm.evaluations
    st = [p.stable for p in br.points]  # (the last point of a direction may lie just outside the band)
    try:  # only the peaks and folds next to a stable point: those bound the stable steady states
        br.extrema = locate(pm, br, settings, keep=lambda i, kind: st[i - 1] or st[i] or st[i + 1], xatol=EXTREMUM_TOL)
    except FMUError:
        br.extrema = []
    e2 = pm.evaluations
    orbits = [_orbit(pm, p.x, p.speed, p.multipliers, p.iterations) for p in br.points]
    for end, nxt in ((0, 1), (-1, -2)):  # a direction that left the band: its last point at the band's edge
        if len(orbits) > 1 and not band[0] <= orbits[end].speed <= band[1] and band[0] <= orbits[nxt].speed <= band[1]:
            edge = band[0] if orbits[end].speed < band[0] else band[1]
            a, b = orbits[nxt], orbits[end]
            f = (edge - a.speed) / (b.speed - a.speed)
            o = shoot(pm, a.x + f * (b.x - a.x), edge)
            if o is not None:
                orbits[end] = o
    folds = [e for e in br.extrema if e.kind == "fold"]
    peaks = [_orbit(pm, e.x, e.speed, e.multipliers) for e in br.extrema if e.kind == "peak"]
    e3 = pm.evaluations
    out = RingBranch(
        orbits,
        br.end_reasons,
        bifurcations(pm, br, folds),
        peaks,
        [_orbit(pm, e.x, e.speed, e.multipliers) for e in folds],
        [e.stable for e in folds],
        br.closed,
    )
    out.cost = {"continuation": e1 - e0, "extrema": e2 - e1, "band_edges": e3 - e2, "bifurcations": pm.evaluations - e3}
    return out


def switch(
    pm: RingPeriodMap,
    br: RingBranch,
    bif: Bifurcation,
    eps: float = 0.05,
    settings: ContinuationSettings = RING_CONTINUATION,
) -> list[RingOrbit]:
    """Orbits of the other branch through a branch point: from the point moved by +-eps (scaled
    arc) along the critical eigenvector, the corrector on the plane normal to it (so it cannot fall
    back onto this branch). Multipliers are filled in by the caller's continuation."""
    if bif.vector is None or bif.x is None:
        return []
    jacobians(pm)
    sc = pm.scales(bif.x, bif.speed)
    prob = BranchProblem(pm, sc)
    z0 = prob.to_z(bif.x, bif.speed)
    v = np.append(bif.vector / sc, 0.0)
    v /= np.linalg.norm(v)
    found = []
    try:
        Hz, Px, _ = prob.H(z0)
        Jz = prob.jac(z0, Hz, Px)[0]
    except FMUError:
        return []
    for sgn in (1.0, -1.0):
        zp = z0 + sgn * eps * v
        done = None
        for quasi in (True, False):  # Broyden from the point's Jacobian first (one period per iteration)
            try:
                done = correct(prob, zp, v, Jz, settings, quasi=quasi)
            except FMUError:
                done = None
            if done is not None:
                break
        if done is None:
            continue
        x, n = prob.from_z(done[0])
        found.append(_orbit(pm, x, n, np.array([np.nan + 0j])))
    return found
