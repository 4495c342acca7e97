"""Which steady state a tuned ring settles on: the co-simulation (C loop, harness/system/ring_c.py)
against the monolithic reference (harness/reference/ring.py), and the travelling wave's stability
(docs/findings/ring-steady-states.md).

The travelling wave (TW) of a tuned ring under f_i = F sin(omega t + 2 pi EO i / N) is the periodic
solution with q_(i+1)(t) = q_i(t + tau), tau = EO T / N (blade i+1's load leads blade i's by tau).
Its deviation per excitation period k, from the blades' first harmonics c_i over the period (the
friction contacts keep static offsets, which the first harmonic ignores):
    wave defect D_k = max_i |c_(i+1) - c_i exp(2 pi i EO / N)| / max_i |c_i|.
Where 2 EO = N (lead pi per blade) the equations keep q_i = -q_(i-1) at every instant (the ring is
odd in q), from rest too; the mirror defect max |q_i + q_(i-1)| / max |q| per period then measures
the symmetry breaking itself, without the transient. The growth of a defect per period in its
exponential phase estimates the largest transverse Floquet multiplier |mu| of the TW; the TW
itself comes from the symmetric computation `on_wave` (the full ring, made an exact TW after
every period).

`python -m harness ring-states CASE` prints the numbers of one case of the findings page.
"""

from __future__ import annotations

import math
import time
from dataclasses import replace

import numpy as np

from harness.reference.ring import MonolithicRing, RingSpec, RingState
from harness.system.ring import Ring
from harness.system.ring_c import run

SETTINGS = {  # the mistuning study's (c = 298 N s/m2) and the default damping's ring
    "a6400": dict(n=6, speed=6400.0, c=298.0),
    "a7000": dict(n=6, speed=7000.0, c=298.0),
    "b": dict(n=8, speed=5000.0, c=29.8),
}


def period(speed: float, eo: int = 3) -> float:
    return 60 / (eo * speed)


def cosim_ring(
    n: int,
    speed: float,
    c: float,
    stop_time: float,
    steps_per_period: int = 160,
    order: int = 2,
    fw0: float = 300.0,
    eo: int = 3,
) -> Ring:
    """The ring as the mistuning study runs it: h = T / steps_per_period in whole nanoseconds."""
    step = round(period(speed, eo) / steps_per_period * 1e9) * 1e-9
    return Ring(n=n, engine_order=eo, speed=speed, fw0=fw0, blade={"c": c}, step=step, stop_time=stop_time, order=order)


def spec_of(ring: Ring) -> RingSpec:
    return RingSpec(
        n=ring.n,
        engine_order=ring.engine_order,
        speed=ring.speed,
        fw0=ring.fw0,
        blade=ring.blade,
        contact=ring.contact,
        blade_each=ring.blade_each,
    )


def cosim(ring: Ring) -> tuple[np.ndarray, np.ndarray]:
    """Time and q per blade at the communication points."""
    res = run(ring)
    return res["time"], res["q"]


def reference(
    spec: RingSpec, t_end: float, samples_per_period: int, rtol: float = 1e-9, start: RingState | None = None
) -> dict:
    """MonolithicRing.solve on a grid of T / samples_per_period from start (or rest) to t_end."""
    T = period(spec.speed, spec.engine_order)
    t0 = start.t if start is not None else 0.0
    t = t0 + np.arange(round((t_end - t0) / T * samples_per_period) + 1) * (T / samples_per_period)
    return MonolithicRing(spec, rtol=rtol).solve(t, start)


def _periods(t: np.ndarray, T: float) -> list[np.ndarray]:
    """Sample indices of each whole excitation period [t0 + k T, t0 + (k + 1) T]."""
    k = np.floor((t - t[0]) / T * (1 + 1e-12)).astype(int)
    return [
        np.nonzero((k == j) | ((k == j + 1) & np.isclose(t, t[0] + (j + 1) * T, rtol=0, atol=1e-12)))[0]
        for j in range(int(k[-1]))
    ]


def period_amplitudes(t: np.ndarray, q: np.ndarray, T: float) -> np.ndarray:
    """max |q| per period (rows) and blade (columns)."""
    return np.array([np.abs(q[i]).max(axis=0) for i in _periods(t, T)])


def wave_defect(t: np.ndarray, q: np.ndarray, T: float, eo: int) -> np.ndarray:
    """D_k per period k: max_i |c_(i+1) - c_i exp(2 pi i EO / N)| / max_i |c_i|, c_i blade i's
    first harmonic over the period (trapezoidal rule)."""
    N = q.shape[1]
    lag = np.exp(2j * math.pi * eo / N)
    out = []
    for idx in _periods(t, T):
        ts = t[idx]
        w = np.gradient(ts) if len(ts) > 2 else np.full(len(ts), ts[-1] - ts[0])
        w[0], w[-1] = 0.5 * (ts[1] - ts[0]), 0.5 * (ts[-1] - ts[-2])
        c = (w * np.exp(-2j * math.pi * ts / T)) @ q[idx]
        out.append(np.abs(np.roll(c, -1) - c * lag).max() / np.abs(c).max())
    return np.array(out)


def mirror_defect(t: np.ndarray, q: np.ndarray, T: float) -> np.ndarray:
    """max |q_i + q_(i-1)| / max |q| per period (rings with lead pi per blade, 2 EO = N)."""
    e = np.abs(q + np.roll(q, 1, axis=1)).max(axis=1)
    scale = np.abs(q).max()
    return np.array([e[i].max() / scale for i in _periods(t, T)])


def growth_per_period(d: np.ndarray, lo: float = 1e-11, hi: float = 1e-4) -> tuple[float, int, int]:
    """|mu| from a least-squares line through log D_k over the first unbroken run of periods with
    lo < D_k < hi after D first exceeds lo (the exponential phase); returns (mu, first, last)."""
    above = np.nonzero(d > lo)[0]
    if not len(above):
        raise ValueError("the defect never exceeds lo: no growth")
    k0 = int(above[0])
    k1 = k0
    while k1 + 1 < len(d) and lo < d[k1 + 1] < hi:
        k1 += 1
    if k1 - k0 < 3:
        raise ValueError(f"only {k1 - k0 + 1} periods in ({lo:g}, {hi:g})")
    k = np.arange(k0, k1 + 1)
    return float(math.exp(np.polyfit(k, np.log(d[k]), 1)[0])), k0, k1


def mirrored(state: RingState) -> RingState:
    """`state` made exactly symmetric from blade 0 and contact 0 (rings with 2 EO = N): q_i, v_i =
    (-1)^i (q_0, v_0); contact j (u_j = (-1)^j u_0) has contact 0's mode and its side, slip sign,
    stick anchor force and displacement times (-1)^j (the Jenkins element is odd)."""
    s = state.copy()
    N = len(s.contacts)
    sign = (-1.0) ** np.arange(N)
    s.y[:N], s.y[N : 2 * N] = sign * s.y[0], sign * s.y[N]
    c0 = s.contacts[0]
    s.contacts = [replace(c0, side=int(g) * c0.side, s=int(g) * c0.s, F0=g * c0.F0, u0=g * c0.u0) for g in sign]
    return s


def wave_copy(res: dict, samples_per_period: int, eo: int) -> RingState:
    """The state at the end of a one-period result `res` made an exact travelling wave from blade 0
    and contact 0 over that period (q_i(t) = q_0(t + i tau), u_j(t) = u_0(t + j tau), taken modulo
    T from the period just run; at the TW's periodic orbit this changes nothing)."""
    s = res["end"].copy()
    N = len(s.contacts)
    spp = samples_per_period
    if spp % N:
        raise ValueError(f"{spp} samples per period: must be a multiple of N = {N}")
    times, switches = res["time"], res["switches"]
    for i in range(1, N):
        k = len(times) - 1 - spp + (eo * i % N) * spp // N  # sample at t_end - T + (EO i mod N) T / N
        s.y[i], s.y[N + i] = res["q"][k, 0], res["v"][k, 0]
        c0 = next(cs for ts, cs in reversed(switches) if ts <= times[k])[0]
        s.contacts[i] = replace(c0)
    return s


def on_wave(
    spec: RingSpec, periods: int, rtol: float = 1e-9, samples_per_period: int = 160
) -> tuple[RingState, np.ndarray]:
    """The symmetric computation: from rest, one excitation period at a time, the state made an
    exact TW after each (`mirrored` where 2 EO = N, else `wave_copy`); returns the state after
    `periods` periods and blade 0's max |q| per period (its convergence shows the TW is a periodic
    solution)."""
    T = period(spec.speed, spec.engine_order)
    state, amp = RingState.rest(spec.n), []
    for _ in range(periods):
        r = reference(spec, state.t + T, samples_per_period, rtol, start=state)
        amp.append(np.abs(r["q"][:, 0]).max())
        state = (
            mirrored(r["end"])
            if 2 * spec.engine_order == spec.n
            else wave_copy(r, samples_per_period, spec.engine_order)
        )
    return state, np.array(amp)


def kicked(state: RingState, blade: int = 0, dq: float = 1e-9) -> RingState:
    """`state` with blade `blade` displaced by dq [m]."""
    s = state.copy()
    s.y[blade] += dq
    return s


def _show(name: str, t: np.ndarray, q: np.ndarray, T: float, eo: int, every: int) -> np.ndarray:
    a = period_amplitudes(t, q, T)
    for k in range(0, len(a), every):
        print(f"  {name} period {k:4d} (t = {t[0] + (k + 1) * T:.4f} s): " + " ".join(f"{x:.4e}" for x in a[k]))
    print(f"  {name} last period: " + " ".join(f"{x:.5e}" for x in a[-1]))
    return a


def case_a(key: str, t_end: float = 0.3, kick_at: float = 0.1, kick_periods: int = 15) -> None:
    """Co-sim and reference from rest, their mirror defects; the symmetric computation to kick_at,
    then blade 0 kicked and run for kick_periods periods."""
    st = SETTINGS[key]
    T = period(st["speed"])
    ring = cosim_ring(st["n"], st["speed"], st["c"], t_end)
    t0 = time.perf_counter()
    tc, qc = cosim(ring)
    print(f"{key}: h = {ring.step:.9g} s, co-sim {time.perf_counter() - t0:.1f} s")
    ac = _show("co-sim", tc, qc, T, 3, 10)
    t0 = time.perf_counter()
    r = reference(spec_of(ring), t_end, 160)
    tr, qr = r["time"], r["q"]
    print(f"  reference (rtol 1e-9) {time.perf_counter() - t0:.1f} s")
    ar = _show("reference", tr, qr, T, 3, 10)
    print(f"  last period |co-sim - reference| / max = {np.abs(ac[-1] - ar[-1]).max() / ar[-1].max():.2e}")
    for name, (tt, qq) in (("co-sim", (tc, qc)), ("reference", (tr, qr))):
        d = mirror_defect(tt, qq, T)
        print(f"  {name} mirror defect per 5 periods: " + " ".join(f"{x:.1e}" for x in d[::5]))
        try:
            mu, k0, k1 = growth_per_period(d)
            print(f"  {name}: |mu| = {mu:.4f} per period (periods {k0}-{k1})")
        except ValueError as e:
            print(f"  {name}: {e}")
    _kick(spec_of(ring), round(kick_at / T), kick_periods, lo=1e-5)


def spectrum_lines(a: np.ndarray, lines: int = 3) -> tuple[list[float], float]:
    """The strongest `lines` frequencies [cycles per excitation period] of a per-period amplitude
    sequence (mean removed, Hann window), and the share of its power within +-1 bin of them (near 1:
    discrete lines, quasi-periodic; spread: broadband)."""
    x = (a - a.mean()) * np.hanning(len(a))
    p = np.abs(np.fft.rfft(x)) ** 2
    f = np.fft.rfftfreq(len(a))
    top: list[int] = []
    for k in np.argsort(p)[::-1]:
        if all(abs(k - j) > 2 for j in top):
            top.append(int(k))
        if len(top) == lines:
            break
    near = np.zeros(len(p), dtype=bool)
    for k in top:
        near[max(k - 1, 0) : k + 2] = True
    return [float(f[k]) for k in top], float(p[near].sum() / p.sum())


def case_b(
    t_end: float = 2.0, rtols: tuple[float, ...] = (1e-9,), wave_periods: int = 150, kick_periods: int = 60
) -> None:
    """The 8-blade ring at the default damping: co-sim at h = T/160, T/320, T/640 and the reference
    at each rtol, from rest to t_end; amplitudes, wave defect, spectra, how far runs drift apart; then
    the symmetric computation and the kick."""
    st = SETTINGS["b"]
    T = period(st["speed"])
    runs: dict[str, tuple[np.ndarray, np.ndarray]] = {}
    for spp in (160, 320, 640):
        ring = cosim_ring(st["n"], st["speed"], st["c"], t_end, steps_per_period=spp)
        runs[f"co-sim T/{spp}"] = cosim(ring)
    for rtol in rtols:
        t0 = time.perf_counter()
        r = reference(spec_of(ring), t_end, 160, rtol=rtol)
        t, q = r["time"], r["q"]
        print(f"reference rtol {rtol:g}: {time.perf_counter() - t0:.0f} s")
        runs[f"reference rtol {rtol:g}"] = (t, q)
    amps = {}
    half = round(t_end / T / 2)
    for name, (t, q) in runs.items():
        a = amps[name] = period_amplitudes(t, q, T)
        d = wave_defect(t, q, T, 3)
        late = a[-half:]
        lines, share = spectrum_lines(late[:, 0])
        print(f"{name}: last period " + " ".join(f"{x:.3e}" for x in a[-1]))
        print(
            f"  last {half} periods: blade max |q| from {late.min():.3e} to {late.max():.3e}; "
            f"wave defect from {d[-half:].min():.2f} to {d[-half:].max():.2f}; "
            f"|q_(i+4) + q_i| / max |q| = {np.abs(q + np.roll(q, 4, axis=1)).max() / np.abs(q).max():.1e}"
        )
        print(
            "  blade 0 amplitude spectrum: lines at "
            + ", ".join(f"{x:.4f}" for x in lines)
            + f" per period, {share:.2f} of the power within +-1 bin"
        )
    names = list(amps)
    y = names[3]  # the reference at the first rtol
    for x in (n for n in names if n != y):
        diff = np.abs(amps[x] - amps[y]).max(axis=1) / amps[y].max()
        print(
            f"{x} vs {y}: per-period max |diff| / max every 50 periods "
            + " ".join(f"{v:.0e}" for v in diff[::50])
            + f" (max {diff.max():.1e})"
        )
    _kick(spec_of(ring), wave_periods, kick_periods)


def _kick(spec: RingSpec, wave_periods: int, kick_periods: int, lo: float = 1e-7, hi: float = 1e-2) -> None:
    """The symmetric computation for wave_periods periods, then blade 0 kicked by 1e-9 m (and not
    kicked) for kick_periods periods: wave defect per period and its growth (< 1: decay)."""
    T = period(spec.speed, spec.engine_order)
    mirror = 2 * spec.engine_order == spec.n
    state, amp = on_wave(spec, wave_periods)
    print(
        f"on the wave at t = {state.t:.4f} s: blade max |q| {amp[-1]:.6e}, change over the last period "
        f"{abs(amp[-1] - amp[-2]) / amp[-1]:.1e}"
    )
    for name, s in (("kicked", kicked(state)), ("not kicked", state)):
        r = reference(spec, state.t + kick_periods * T, 160, start=s)
        d = mirror_defect(r["time"], r["q"], T) if mirror else wave_defect(r["time"], r["q"], T, spec.engine_order)
        print(f"  {name}: {'mirror' if mirror else 'wave'} defect per period " + " ".join(f"{x:.1e}" for x in d))
        if name == "kicked":
            mu, k0, k1 = growth_per_period(d, lo, hi)
            print(f"  kicked: |mu| = {mu:.4f} per period (periods {k0}-{k1} after the kick)")
