"""The ring's forced response over a speed band: one continuous run of the C loop (harness/system/
ring_c.py) with rotorSpeed stepped from speed to speed, the state carried (the blades' built-in load
integrates its phase from rotorSpeed, so the load stays continuous across a step of the speed).

At each speed the ring runs on the exact grid of the ring's period map (harness/system/ring_orbits/
period_map.py), h = T / K (T = 60 / (EO rpm), K = steps_per_period) aligned to the load: the
blades' load phase psi carries on across a change of speed, so one partial step of length delta
(psi + omega delta the next multiple of 2 pi / K; none if psi is one already) brings the ring to a
point where it is, and from there t = t_base + j T / K (the extrapolation history restarted at the
change and again at t_base). The discrete system at a speed is then exactly the period map's: a
settled state is its fixed point, and the sweep's points at load phase 0 are grid points. (The
earlier grid of whole nanoseconds, h = round(T / K) ns, slid by up to K / 2 ns per period against
the load, 43 ns at 6300 rpm; the co-simulation's error, about 1e-3 of max |q| at T / 160, changes
with the grid's phase where contacts open and close, and such a run started on an orbit drifted off
it by up to 2e-3..5e-3 in 300 periods.) The ring runs on in windows of m = K steps (one period). A
window's amplitude per blade is max |q| over its points, refined by the parabola through the
largest sample and its two neighbours (the sampled maximum alone is up to 1 - cos(pi h / T) = 2e-4
low at h = T / 160). With a fixed `step`, m = round(T / h). Blade i has settled when its amplitude changes by less than `rtol` x (the largest blade's
amplitude) from window to window over `periods` consecutive windows; the speed is left when every
blade has settled, or after `max_time` s at that speed (then flagged: `settled` False, and
`movement` says by how much it still moves, the largest change per period over the last `periods`
windows, relative to the largest blade's amplitude).

The peak: the largest settled blade amplitude over the band is located, not sampled. Around the
largest settled sample the sweep is re-run from the state saved (settled) at the speed before it,
on 2 refine_points - 1 speeds across its two neighbours' interval, and again around the largest of
those, until the speeds are at most `speed_tol` rpm apart; the peak is the largest settled sample
then (no parabola: the tuned ring's peak is a cusp, steeper on one side, where a parabola's vertex
overshoots). A largest sample at the band's edge is reported as it is (peak_at_band_edge).

The on_settled hook sees every settled speed, the refinement's too, with the load phase psi there
(psi = sum over the speeds on the state's own path of omega_k t_k, omega = EO 2 pi rpm / 60: CRing.phase,
which a refinement's restart from a saved state puts back with the state).
"""

from __future__ import annotations

import math
import time
from dataclasses import dataclass, field, replace
from typing import Callable, Sequence

import numpy as np
import numpy.typing as npt

from harness.system.ring import Ring
from harness.system.ring_c import CRing

DIRECTIONS = ("up", "down", "both")


@dataclass
class RingSweep:
    """The forced response of a ring over speed; arrays in ascending speed, per direction swept."""

    speeds_rpm: np.ndarray  # (K,)
    amplitudes_m: dict[str, np.ndarray]  # direction -> (K, N): the last window's amplitude per blade
    settled: dict[str, np.ndarray]  # direction -> (K, N) booleans
    movement: dict[str, np.ndarray]  # direction -> (K, N): change per period / largest blade amplitude
    peak_amplitude_m: float  # largest settled blade amplitude over the band, located (nan if none settled)
    peak_speed_rpm: float
    wall_time_s: float
    peak_direction: str = ""
    peak_blade: int = -1
    peak_at_band_edge: bool = False  # the largest settled sample is the first or last speed: maybe beyond the band
    time_at_speed_s: dict[str, np.ndarray] = field(default_factory=dict)  # direction -> (K,) simulated
    refinement: list[dict] = field(default_factory=list)  # the extra speeds: direction, speed, amplitudes
    step_s: np.ndarray = field(default_factory=lambda: np.zeros(0))  # (K,) the communication step at each speed


def window_amplitude(q: np.ndarray) -> np.ndarray:
    """Per column: max |q| over rows 1..-2 of q, refined by the parabola through the largest
    sample and its neighbours (rows 0 and -1 are the neighbours of the window's ends)."""
    a = np.abs(q)
    j = 1 + np.argmax(a[1:-1], axis=0)
    cols = np.arange(a.shape[1])
    y0, y1, y2 = a[j - 1, cols], a[j, cols], a[j + 1, cols]
    curv = y0 - 2 * y1 + y2
    cap = curv < 0  # a vertex only under a cap (elsewhere the divisor is a stand-in: no 0 / 0)
    vertex = y1 - (y0 - y2) ** 2 / (8 * np.where(cap, curv, -1.0))
    return np.where(cap, vertex, y1)


@dataclass
class Settling:
    """Settle state at one speed: per-window amplitudes and each blade's run of small changes."""

    rtol: float
    periods: int
    last: np.ndarray | None = None
    run: np.ndarray | None = None
    changes: list = field(default_factory=list)

    def add(self, amp: np.ndarray) -> None:
        if self.last is not None:
            r = np.abs(amp - self.last) / max(float(amp.max()), 1e-300)
            self.changes = (self.changes + [r])[-self.periods :]
            self.run = np.where(r < self.rtol, self.run + 1, 0)
        else:
            self.run = np.zeros(len(amp), dtype=int)
        self.last = amp

    @property
    def settled(self) -> np.ndarray:
        return self.run >= self.periods

    @property
    def movement(self) -> np.ndarray:
        return np.max(self.changes, axis=0) if self.changes else np.full(len(self.last), np.inf)


def per_period_settling(
    time_s: np.ndarray, q: np.ndarray, omega: float, rtol: float = 1e-4, periods: int = 5
) -> Settling:
    """The settle rule on a finished run (time, q per blade): the last `periods` + 1 whole windows
    of m = round(T / h) points before the last point; fewer if the run is shorter."""
    h = float(time_s[1] - time_s[0])
    m = max(2, round(2 * math.pi / omega / h))
    st = Settling(rtol, periods)
    count = min(periods + 1, (len(q) - 2) // m)
    for w in range(count, 0, -1):
        end = len(q) - 1 - (w - 1) * m  # the window ends at row end - 1; row end is its right neighbour
        st.add(window_amplitude(q[end - m - 1 : end + 1]))
    return st


def period_step(ring: Ring, rpm: float, steps_per_period: int) -> float:
    """T / steps_per_period at rpm, in whole nanoseconds (a fixed-step run's step)."""
    return round(60e9 / (ring.engine_order * rpm) / steps_per_period) / 1e9


def exact_step(ring: Ring, rpm: float, steps_per_period: int) -> float:
    """T / steps_per_period at rpm [s] (the sweep's and the period map's grid)."""
    return 60.0 / (ring.engine_order * rpm) / steps_per_period


def align(cr: CRing, rpm: float, steps_per_period: int) -> None:
    """Puts cr's next points on the exact grid T / K at rpm aligned to the load: one partial step
    of delta (cr.phase + omega delta the next multiple of 2 pi / K; skipped within 1e-9 of a step
    of one) at rpm, then t = t_base + j T / K, the history restarted at both."""
    K = steps_per_period
    h = exact_step(cr.ring, rpm, K)
    slot = 2.0 * math.pi / K
    rest = (-cr.phase) % slot  # phase to the next multiple of 2 pi / K
    if 1e-9 * slot < rest < (1.0 - 1e-9) * slot:
        cr.exact_grid(h * rest / slot)
        cr.advance(1, rpm, records=("q",))
    cr.exact_grid(h)


class _Sweeper:
    def __init__(self, cr: CRing, rtol: float, periods: int, max_time: float, steps_per_period: int | None):
        self.cr, self.rtol, self.periods, self.max_time = cr, rtol, periods, max_time
        self.spp = steps_per_period  # None: the ring's fixed step

    @property
    def psi(self) -> float:
        """The load phase at the ring's current point [rad, mod 2 pi] (CRing.phase, saved with the state)."""
        return self.cr.phase

    def save(self) -> tuple:
        return self.cr.save()

    def restore(self, state: tuple) -> None:
        self.cr.restore(state)

    def settle(self, rpm: float) -> tuple[np.ndarray, np.ndarray, np.ndarray, float]:
        """Runs on at rpm until settled or max_time: (amplitudes, settled, movement, time spent)."""
        cr = self.cr
        t0 = cr.time(cr.k)
        if self.spp is not None:
            align(cr, rpm, self.spp)
        T = 60.0 / (cr.ring.engine_order * rpm)
        m = self.spp if self.spp is not None else max(2, round(T / cr.ring.step))
        st = Settling(self.rtol, self.periods)
        prev = None  # the last two rows of the previous chunk (neighbours for the next window)
        while True:
            q = cr.advance(m, rpm, records=("q",))["q"]
            buf = q if prev is None else np.vstack([prev, q])
            if len(buf) >= m + 2:
                st.add(window_amplitude(buf[-m - 2 :]))  # window: rows -m-1 .. -2
            prev = buf[-2:]
            spent = cr.time(cr.k) - t0
            if st.last is not None and (st.settled.all() or spent >= self.max_time):
                return st.last, st.settled.copy(), st.movement, spent


def sweep(
    ring: Ring,
    speeds_rpm: Sequence[float] | npt.NDArray[np.float64],
    direction: str = "up",
    master: str = "c",
    *,
    rtol: float = 1e-4,
    periods: int = 5,
    max_time: float = 1.0,
    steps_per_period: int = 160,
    step: float | None = None,
    refine: bool = True,
    speed_tol: float = 1.0,
    refine_points: int = 3,
    on_settled: Callable[[CRing, str, float, float], None] | None = None,
) -> RingSweep:
    """Forced response of `ring` (its blades, contacts, load, order, coupling; its speed, step and
    stop time are replaced) at speeds_rpm, swept `direction` ("up", "down" or "both": up from rest
    at the lowest speed, then down from where it ended; "down" alone starts from rest at the
    highest) with the state carried, at h = T / steps_per_period at each speed (the exact grid
    aligned to the load, see the module docstring), or at the fixed step `step` [s, whole ns] when
    given. See the module docstring for the settle rule and the
    located peak. on_settled(cr, direction, rpm, psi) is called where the sweep leaves each speed,
    the refinement's speeds too (psi: the load phase there [rad], see the module docstring), with
    the running ring; it must leave it as it was."""
    if master != "c":
        raise ValueError(f"master {master!r}: the sweep runs on the C loop ('c') only")
    if direction not in DIRECTIONS:
        raise ValueError(f"direction {direction!r}: not one of {', '.join(DIRECTIONS)}")
    speeds = np.array(sorted(float(s) for s in speeds_rpm))
    if len(speeds) < 1 or np.any(speeds <= 0) or len(np.unique(speeds)) != len(speeds):
        raise ValueError(f"speeds_rpm {list(speeds_rpm)}: need distinct positive speeds")
    t_start = time.perf_counter()
    dirs = ["up", "down"] if direction == "both" else [direction]
    K, N = len(speeds), ring.n
    amps = {d: np.zeros((K, N)) for d in dirs}
    settled = {d: np.zeros((K, N), dtype=bool) for d in dirs}
    movement = {d: np.zeros((K, N)) for d in dirs}
    spent = {d: np.zeros(K) for d in dirs}
    saved: dict[str, list] = {d: [None] * K for d in dirs}
    first = speeds[0] if dirs[0] == "up" else speeds[-1]
    h = step if step is not None else period_step(ring, first, steps_per_period)
    refinement: list[dict] = []
    best = (-math.inf, math.nan, "", -1)  # amplitude, speed, direction, blade
    edge = False
    with CRing(replace(ring, speed=first, step=h, stop_time=h)) as cr:
        sw = _Sweeper(cr, rtol, periods, max_time, None if step is not None else steps_per_period)
        for d in dirs:
            order = range(K) if d == "up" else range(K - 1, -1, -1)
            for j in order:
                amps[d][j], settled[d][j], movement[d][j], spent[d][j] = sw.settle(speeds[j])
                if on_settled is not None:
                    on_settled(cr, d, float(speeds[j]), sw.psi)
                if refine:
                    saved[d][j] = sw.save()  # the state settled at speeds[j]: a refinement starts there
        for d in dirs:
            ok = np.where(settled[d].all(axis=1), amps[d].max(axis=1), -math.inf)
            if not np.isfinite(ok.max()):
                continue
            cand = (float(ok.max()), float(speeds[int(np.argmax(ok))]), d, int(np.argmax(amps[d][int(np.argmax(ok))])))
            at_edge = int(np.argmax(ok)) in (0, K - 1)
            if refine and not at_edge:
                cand = (
                    _locate(
                        sw,
                        speeds,
                        d,
                        ok,
                        np.argmax(amps[d], axis=1),
                        saved[d],
                        speed_tol,
                        refine_points,
                        refinement,
                        on_settled,
                    )
                    or cand
                )
            if cand[0] > best[0]:
                best, edge = cand, at_edge
    return RingSweep(
        speeds_rpm=speeds,
        amplitudes_m=amps,
        settled=settled,
        movement=movement,
        peak_amplitude_m=best[0] if best[2] else math.nan,
        peak_speed_rpm=best[1],
        wall_time_s=time.perf_counter() - t_start,
        peak_direction=best[2],
        peak_blade=best[3],
        peak_at_band_edge=edge,
        time_at_speed_s=spent,
        refinement=refinement,
        step_s=np.array([h if step is not None else exact_step(ring, s, steps_per_period) for s in speeds]),
    )


def _locate(
    sw: _Sweeper,
    speeds: np.ndarray,
    d: str,
    ok: np.ndarray,
    blades: np.ndarray,
    saved: list,
    speed_tol: float,
    points: int,
    log: list,
    on_settled: Callable[[CRing, str, float, float], None] | None = None,
) -> tuple | None:
    """Refines the largest settled sample of direction d (ok: the largest blade amplitude per
    speed, -inf where not settled; blades: which blade), not at the band's edge, calling
    on_settled at every refinement speed as the sweep does; returns (amplitude, speed, d, blade)."""
    visit = list(range(len(speeds))) if d == "up" else list(range(len(speeds) - 1, -1, -1))
    pos = visit.index(int(np.argmax(ok)))
    before, after = visit[pos - 1], visit[pos + 1]
    a, b = float(speeds[before]), float(speeds[after])  # in visiting order
    states = {a: saved[before]}  # the state settled at a speed
    known = {float(speeds[i]): (float(ok[i]), int(blades[i])) for i in (before, visit[pos], after)}
    for _ in range(12):  # each pass divides the spacing by `points`
        fine = np.linspace(a, b, 2 * points + 1)[1:-1]
        if abs(fine[1] - fine[0]) < 0.5 * speed_tol:
            break
        sw.restore(states[a])
        for s in fine:
            amp, st, mv, spent = sw.settle(float(s))
            if on_settled is not None:
                on_settled(sw.cr, d, float(s), sw.psi)
            states[float(s)] = sw.save()
            known[float(s)] = (float(amp.max()) if st.all() else -math.inf, int(np.argmax(amp)))
            log.append(
                {
                    "direction": d,
                    "speed_rpm": float(s),
                    "amplitudes_m": amp.tolist(),
                    "settled": bool(st.all()),
                    "movement": float(mv.max()),
                }
            )
        seq = [a, *map(float, fine), b]  # visiting order
        i = int(np.argmax([known[s][0] for s in seq]))
        a, b = seq[max(i - 1, 0)], seq[min(i + 1, len(seq) - 1)]
    speed = max(known, key=lambda s: known[s][0])
    amp, blade = known[speed]
    return (amp, speed, d, blade) if np.isfinite(amp) else None
