"""Benchmark of the ring's periodic steady states (harness/system/ring_orbits), for `harness bench`:
the cost of one period of the ring's period map and of one DP (its columns' periods serial and on
the map's threads), the tuned 6-blade study ring's branches over
4000-9000 rpm from every seed (with stability), the cost per continuation point in periods of the
ring, and the 24-blade ring measured on a part of one branch and extrapolated to the study's band."""

from __future__ import annotations

import os
import re
import time
from pathlib import Path
from dataclasses import replace
from typing import Any

import numpy as np

from harness.system.ring import Ring
from harness.system.ring_orbits.branches import default_seed_points, ring_branches
from harness.system.ring_orbits.continuation import RING_CONTINUATION, trace
from harness.system.ring_orbits.period_map import RingPeriodMap, RingShootingSettings
from harness.system.ring_orbits.seeds import travelling_wave
from harness.system.ring_orbits.shooting import jacobians, monodromy, shoot

SECTION = "## The ring's periodic steady states"
STUDY_RING = dict(engine_order=3, fw0=300.0, blade={"c": 298.0}, order=2)  # harness/studies/mistuning.py
STUDY_BAND = (3973.0, 14898.0)  # the mistuning study's band [rpm]


def period_cost(n: int, rpm: float = 6000.0, repeats: int = 20) -> float:
    """Least wall time of one period-map evaluation [s] (the ring's state from a few periods from rest)."""
    with RingPeriodMap(Ring(n=n, **STUDY_RING)) as pm:
        x = np.zeros(pm.dim)
        for _ in range(5):
            x = pm(x, rpm)[0]
        best = np.inf
        for _ in range(repeats):
            pm.seen.clear()
            t0 = time.perf_counter()
            pm(x, rpm)
            best = min(best, time.perf_counter() - t0)
    return float(best)


def dp_cost(n: int = 6, rpm: float = 6000.0, repeats: int = 10) -> dict[str, Any]:
    """Least wall time of one DP (forward differences, one period per acting column) at the
    travelling wave's orbit at rpm, serial (workers 1) and on the default threads, taken in turns
    (the same load on both); `cores` the threaded run's CPU over its wall time (what the machine gave)."""
    ring = Ring(n=n, **STUDY_RING)
    threaded = RingShootingSettings()
    with RingPeriodMap(ring, replace(threaded, workers=1)) as serial, RingPeriodMap(ring, threaded) as pool:
        o = shoot(serial, travelling_wave(serial, [rpm])[0].x, rpm)
        if o is None:
            raise RuntimeError(f"dp_cost: no orbit from the travelling wave at {rpm} rpm")
        Px = serial(o.x, rpm)[0]
        best = {1: np.inf, 2: np.inf}
        cores, periods = 0.0, 0
        for _ in range(repeats):
            for k, pm in ((1, serial), (2, pool)):
                pm.seen.clear()
                jacobians(pm).items.clear()  # taken afresh, not from the memo
                e0, t0, c0 = pm.evaluations, time.perf_counter(), time.process_time()
                monodromy(pm, o.x, rpm, Px)
                wall = time.perf_counter() - t0
                if wall < best[k]:
                    best[k] = wall
                    if k == 2:
                        cores = (time.process_time() - c0) / wall
                periods = pm.evaluations - e0
    return {
        "blades": n,
        "workers": threaded.threads(),
        "periods": periods,
        "serial_s": best[1],
        "threads_s": best[2],
        "ratio": best[1] / best[2],
        "cores": cores,
        "repeats": repeats,
    }


def six_blades(
    band: tuple[float, float] = (4000.0, 9000.0), seed_points: int | None = None, dp: str = "full"
) -> dict[str, Any]:
    load = os.getloadavg()[0]
    cpu = time.process_time()
    seed_points = seed_points or default_seed_points(band)
    r = ring_branches(Ring(n=6, **STUDY_RING), band, points=seed_points, settings=RingShootingSettings(dp=dp))
    cpu = time.process_time() - cpu
    return {
        "dp": r.stats.get("dp", {"mode": dp}),
        "band_rpm": list(band),
        "seed_points": seed_points,
        "wall_s": r.wall_time,
        "cpu_s": cpu,
        "by_stage": r.stats.get("evaluations_by_stage", {}),
        "branches": len(r.branches),
        "points": r.points,
        "periods": r.evaluations,
        "seed_periods": r.stats["seed_evaluations"],
        "periods_per_point": r.evaluations / max(r.points, 1),
        "peak_stable_amplitude_m": r.peak_stable_amplitude,
        "peak_stable_speed_rpm": r.peak_stable_speed,
        "load_at_start": load,
        "workers": RingShootingSettings().threads(),
        "cores": cpu / max(r.wall_time, 1e-9),
    }


def twenty_four_part(points: int = 6, rpm: float = 6000.0, dp: str = "full") -> dict[str, Any]:
    """The 24-blade ring: the travelling wave at rpm and `points` continuation points upwards from it."""
    ring = Ring(n=24, **STUDY_RING)
    t0 = time.perf_counter()
    with RingPeriodMap(ring, RingShootingSettings(dp=dp)) as pm:
        sd = travelling_wave(pm, [rpm])[0]
        o = shoot(pm, sd.x, rpm)
        e0, t1, c1 = pm.evaluations, time.perf_counter(), time.process_time()
        br = trace(pm, o, (rpm, STUDY_BAND[1]), replace(RING_CONTINUATION, max_points=points), directions=(1,))
        wall = time.perf_counter() - t1
        return {
            "seed_and_shoot_s": t1 - t0,
            "points": len(br.orbits) - 1,
            "wall_s": wall,
            "periods": pm.evaluations - e0,
            "per_point_s": wall / max(len(br.orbits) - 1, 1),
            "periods_per_point": (pm.evaluations - e0) / max(len(br.orbits) - 1, 1),
            "cpu_s": time.process_time() - c1,
            "largest_m": float(br.amplitudes.max()),
            "last_speed_rpm": float(br.orbits[-1].speed),
            "dp": {"mode": dp, **(pm.low_rank.summary() if pm.low_rank is not None else {})},
        }


def ring_orbits_cost(
    repeats: int = 20, band: tuple[float, float] = (4000.0, 9000.0), seed_points: int | None = None, points: int = 6
) -> dict[str, Any]:
    """The section's rows (the defaults: `make bench`; smaller ones: `bench --quick`)."""
    out: dict[str, Any] = {
        "period_6_s": period_cost(6, repeats=repeats),
        "period_24_s": period_cost(24, repeats=repeats),
        "dp_6": dp_cost(6, repeats=repeats),
    }
    # both DP modes in the same run, one after the other (the same machine and about the same load)
    out["six"] = six_blades(band, seed_points)
    out["six_low_rank"] = six_blades(band, seed_points, dp="low-rank")
    out["twenty_four"] = twenty_four_part(points)
    out["twenty_four_low_rank"] = twenty_four_part(points, dp="low-rank")
    s = out["six"]
    # extrapolation: the 6-blade run's points per rpm of band, times the study's band, at the 24-blade
    # cost per point (the number of branches of the 24-blade ring is not known: taken as the 6-blade ring's)
    pts = s["points"] / (s["band_rpm"][1] - s["band_rpm"][0]) * (STUDY_BAND[1] - STUDY_BAND[0])
    out["twenty_four"]["extrapolated_points"] = pts
    out["twenty_four"]["extrapolated_s"] = pts * out["twenty_four"]["per_point_s"]
    return out


def with_before(new: dict[str, Any], old: dict[str, Any] | None, date: str, results: Path) -> dict[str, Any]:
    """new (measured at `date`) with the 6-blade row of the first run it replaces kept as `before`
    (that run's date from its section in `results` where the row does not carry one): the section
    puts the algorithm before beside the present one."""
    new = {**new, "date": date}
    if old and "before" in old:
        new["before"] = old["before"]
    elif old and "six" in old:
        when = old.get("date")
        if when is None and results.is_file():
            text = results.read_text()
            m = re.search(re.escape(SECTION) + r"[^;]*; (\d{4}-\d\d-\d\d \d\d:\d\d)\)", text)
            when = m.group(1) if m else "?"
        new["before"] = {"date": when, "six": old["six"]}
    return new


def _per_point(s: dict[str, Any]) -> str:
    n = max(s["points"], 1)
    return ", ".join(f"{k} {v / n:.1f}" for k, v in s["by_stage"].items())


def section(d: dict[str, Any], machine_text: str, date: str) -> list[str]:
    s, t = d["six"], d["twenty_four"]
    b = d.get("before", {}).get("six")
    before = (
        [
            f"- the same row before ({d['before'].get('label', 'run')} of {d['before']['date']}, load average "
            f"{b['load_at_start']:.1f} at its start): "
            f"{b['wall_s']:.1f} s wall, {b['cpu_s']:.1f} s CPU, {b['branches']} branches, {b['points']} points, "
            f"{b['periods']} periods: **{b['periods_per_point']:.1f} periods per point**; per point by stage: "
            + _per_point(b)
            + f"; now per point by stage: {_per_point(s)}"
        ]
        if b
        else []
    )
    dp = d.get("dp_6")
    dp_row = (
        [
            f"- one DP of the {dp['blades']}-blade ring at the travelling wave's orbit at 6000 rpm ({dp['periods']} "
            f"periods, forward differences): serial {dp['serial_s'] * 1e3:.1f} ms, on {dp['workers']} threads "
            f"{dp['threads_s'] * 1e3:.1f} ms (least of {dp['repeats']}, taken in turns): **{dp['ratio']:.2f}x**; the "
            f"threaded run used {dp['cores']:.2f} cores (CPU over wall)"
        ]
        if dp
        else []
    )
    low = d.get("six_low_rank")
    low_rows = [_low_rank_row(s, low)] if low else []
    t_low = d.get("twenty_four_low_rank")
    t_low_rows = (
        [
            f"- 24 blades, the same part with the low-rank DP: {t_low['points']} points in {t_low['wall_s']:.1f} s wall, "
            f"{t_low['cpu_s']:.1f} s CPU ({t_low['per_point_s']:.2f} s and **{t_low['periods_per_point']:.1f} periods "
            f"per point**; full DP: {t['wall_s']:.1f} s wall, {t.get('cpu_s', float('nan')):.1f} s CPU, "
            f"{t['periods_per_point']:.1f} periods per point); largest blade amplitude "
            f"{t_low['largest_m']:.6g} m (full: {t.get('largest_m', float('nan')):.6g} m), last point "
            f"{t_low['last_speed_rpm']:.1f} rpm (full: {t.get('last_speed_rpm', float('nan')):.1f} rpm); DPs: "
            + _dp_counts(t_low["dp"])
        ]
        if t_low
        else []
    )
    threads = f" on {s['workers']} threads ({s['cores']:.2f} cores used: CPU over wall)" if "workers" in s else ""
    return [
        SECTION,
        "",
        f"`python -m harness bench --only ring-orbits` ({machine_text}; {date}). The mistuning study's tuned "
        "ring (EO 3, c = 298 N s/m2, Fw0 = 300 N/m, extrapolation order 2, 160 steps per period).",
        "",
        f"- one period of the period map (every FMU reset and initialised, 160 steps of the C loop): "
        f"6 blades {d['period_6_s'] * 1e3:.2f} ms, 24 blades {d['period_24_s'] * 1e3:.2f} ms (least of 20)",
        *dp_row,
        f"- 6 blades, {s['band_rpm'][0]:.0f}-{s['band_rpm'][1]:.0f} rpm, every seed ({s['seed_points']} seed "
        f"speeds){threads}: **{s['wall_s']:.1f} s wall**, {s['cpu_s']:.1f} s CPU (target 60 s wall; the machine is shared: "
        f"at the least period cost the same periods take {s['periods'] * d['period_6_s']:.0f} s), "
        f"{s['branches']} branches, {s['points']} points "
        f"with stability, {s['periods']} periods of the ring ({s['seed_periods']} of them for the seeds): "
        f"**{s['periods_per_point']:.1f} periods per continuation point**; largest stable steady state "
        f"{s['peak_stable_amplitude_m']:.5g} m at {s['peak_stable_speed_rpm']:.1f} rpm; load average "
        f"{s['load_at_start']:.1f} at its start; periods by stage: "
        + ", ".join(f"{k} {v}" for k, v in s["by_stage"].items()),
        *low_rows,
        *before,
        f"- 24 blades: measured on a part, extrapolated (not run over the band): {t['points']} continuation "
        f"points from the travelling wave at 6000 rpm in {t['wall_s']:.1f} s ({t['per_point_s']:.2f} s and "
        f"{t['periods_per_point']:.1f} periods per point); the study's band "
        f"{STUDY_BAND[0]:.0f}-{STUDY_BAND[1]:.0f} rpm at the 6-blade ring's density of points "
        f"({t['extrapolated_points']:.0f} points) would take about {t['extrapolated_s'] / 60:.1f} min "
        "(target 15 min), if the 24-blade ring had as many branches as the 6-blade one",
        *t_low_rows,
        "",
    ]


def _dp_counts(dp: dict[str, Any]) -> str:
    return (
        f"{dp['low-rank']} low-rank, {dp['acting']} over the acting unknowns, {dp['full']} full "
        f"({dp['failed check']} after a failed check), {dp['periods']} periods in DPs"
    )


def _low_rank_row(full: dict[str, Any], low: dict[str, Any]) -> str:
    """The 6-blade row with the low-rank DP beside the full one's (the same run)."""
    return (
        f'- the same band with the low-rank DP (`RingShootingSettings(dp="low-rank")`, run right after the '
        f"full one; load average {low['load_at_start']:.1f} at its start): **{low['wall_s']:.1f} s wall** (full "
        f"{full['wall_s']:.1f} s), {low['cpu_s']:.1f} s CPU (full {full['cpu_s']:.1f} s; per period "
        f"{low['cpu_s'] / low['periods'] * 1e3:.2f} ms, full {full['cpu_s'] / full['periods'] * 1e3:.2f} ms), "
        f"{low['branches']} branches "
        f"({full['branches']}), {low['points']} points ({full['points']}), {low['periods']} periods: "
        f"**{low['periods_per_point']:.1f} periods per point** ({full['periods_per_point']:.1f}); largest stable "
        f"steady state {low['peak_stable_amplitude_m']:.6g} m at {low['peak_stable_speed_rpm']:.2f} rpm (full "
        f"{full['peak_stable_amplitude_m']:.6g} m at {full['peak_stable_speed_rpm']:.2f} rpm); DPs: "
        + _dp_counts(low["dp"])
        + "; per point by stage: "
        + _per_point(low)
    )
