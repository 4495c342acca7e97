"""The counts quoted on docs/findings/ring-completeness.md against the file they come from
(results/ring_completeness.json, written by `python -m harness ring-completeness`), so the page
cannot drift from the last run."""

from __future__ import annotations

import json
from pathlib import Path

import pytest

REPO = Path(__file__).resolve().parents[2]


def test_the_page_quotes_the_results_counts():
    d = json.loads((REPO / "results" / "ring_completeness.json").read_text())
    page = (REPO / "docs" / "findings" / "ring-completeness.md").read_text()
    on = d["on_branches"] - d["on_branches_by_newton"]
    quoted = [
        f"{len(d['missed'])}\nof the {d['distinct_states']} distinct stable periodic states",
        f"| runs | {d['runs']} (",
        f"| not settled in {d['settings']['max_periods']} periods | {len(d['not_settled'])},",
        f"| settled, polished, unstable | {len(d['unstable_after_settling'])},",
        f"| settled stable orbits | {d['settled_stable_orbits']}: {d['distinct_states']} distinct states",
        f"| on the engine's branches | {on + d['on_branches_by_newton']} orbits ({d['on_branches_by_newton']} of them",
        f"**{d['settled_stable_orbits'] - d['on_branches']} orbits: {len(d['missed'])} distinct states**",
        f"on none of the engine's {d['engine']['branches']}\nbranches",
        f"{d['cost']['settle_periods'] + d['cost']['polish_periods'] + d['cost']['compare_periods']} periods",
        f"the engine {d['engine']['periods']} periods, {d['engine']['cpu_s']:.0f} CPU s",
    ]
    missing = [q for q in quoted if q not in page]
    assert not missing, missing


def test_the_page_quotes_the_pattern_rings_counts():
    """The 5 % pattern 0 ring's run (results/ring_completeness_pattern/, `--pattern 0.05 0`)."""
    d = json.loads((REPO / "results" / "ring_completeness_pattern" / "ring_completeness.json").read_text())
    page = " ".join((REPO / "docs" / "findings" / "ring-completeness.md").read_text().split())
    assert d["settings"]["pattern"] == [0.05, 0]
    quoted = [
        f"{d['settled_stable_orbits']} settled stable orbits, {d['distinct_states']} distinct states",
        f"**{len(d['missed'])} lie on none of the engine's {d['engine']['branches']} branches**",
        f"the {len(d['not_settled'])} runs that do not settle",
    ]
    missing = [q for q in quoted if q not in page]
    assert not missing, missing


def _json(name: str, file: str = "ring_completeness.json") -> dict:
    return json.loads((REPO / "results" / name / file).read_text())


def _flat(path: Path) -> str:
    return " ".join(path.read_text().split())


def _m(x: float, fmt: str) -> str:
    """x as the pages write metres: 4.18e-5, not 4.18e-05."""
    return format(x, fmt).replace("e-0", "e-")


def test_the_page_and_readme_quote_the_whole_band_run():
    """The tuned ring over the whole study band (results/ring_completeness_band/)."""
    import csv

    d = _json("ring_completeness_band")
    page = _flat(REPO / "docs" / "findings" / "ring-completeness.md")
    rows = list(csv.DictReader((REPO / "results" / "ring_completeness_band" / "ring_completeness.csv").open()))
    stable = [max(float(r[f"amplitude{i}_m"]) for i in range(6)) for r in rows if r["stable"] == "yes"]
    unsettled = max(m["largest_range_m"][1] for m in d["not_settled"])
    cost = d["cost"]
    quoted = [
        f"on {d['distinct_states']} distinct stable states, {len(d['missed'])} of them on none of the engine's"
        f" {d['engine']['branches']} branches",
        f"| settled stable orbits | {d['settled_stable_orbits']}: {d['distinct_states']} distinct states |",
        f"| not settled in 1500 periods | {len(d['not_settled'])}, at",
        f"at most {_m(unsettled, '.4g')} m)",
        f"no unsettled run {_m(unsettled, '.4g')} m.",
        f"| on none of the engine's {d['engine']['branches']} branches | {len(d['missed'])} distinct states |",
        f"| the largest settled stable orbit | {_m(max(stable), '.5g')} m",
        f"{cost['settle_periods'] + cost['polish_periods'] + cost['compare_periods']} periods and"
        f" {cost['cpu_s']:.0f} CPU s for the runs; the engine {d['engine']['periods']} periods,"
        f" {d['engine']['cpu_s']:.0f} CPU s",
    ]
    missing = [q for q in quoted if q not in page]
    assert not missing, missing
    assert f"settle on {len(d['missed'])} of {d['distinct_states']} it did not" in _flat(REPO / "README.md")


def test_the_page_quotes_the_finer_step_runs():
    """The same sub-band at h = T/160, T/320 (results/ring_completeness_k160/, _k320/) and T/640."""
    page = _flat(REPO / "docs" / "findings" / "ring-completeness.md")
    missing = []
    for K in (160, 320, 640):
        d = _json(f"ring_completeness_k{K}")
        assert d["settings"]["steps_per_period"] == K
        lo, hi = d["settings"]["speeds"]
        row = (
            f"| {lo:.0f}-{hi:.0f} rpm | T/{K} | {d['settled_stable_orbits']} | {d['distinct_states']} |"
            f" {len(d['missed'])} | {len(d['not_settled'])} | {len(d['unstable_after_settling'])} |"
        )
        if row not in page:
            missing.append(row)
    assert not missing, missing


def test_the_page_and_readme_quote_the_step_checks():
    """`ring-step-check` on the tuned ring (every 6th orbit; every orbit near the largest) and on the
    study's 5 % and 2 % pattern 0 rings near theirs."""
    page = _flat(REPO / "docs" / "findings" / "ring-completeness.md")
    missing = []
    for name in ("ring_step_check", "ring_step_check_top", "ring_step_check_pattern", "ring_step_check_pattern2"):
        d = _json(name, "ring_step_check.json")
        assert d["steps_per_period"] == [160, 320, 640]
        cells = f"| {d['followed']} of {d['orbits']} | {d['changed']}"
        values = f"{_m(d['largest_stable_first_m'], '.5e')} -> {_m(d['largest_stable_finest_m'], '.5e')} m |"
        if cells not in page or values not in page:
            missing.append((name, cells, values))
    assert not missing, missing
    d = _json("ring_step_check", "ring_step_check.json")
    readme = _flat(REPO / "README.md")
    assert f"{d['changed']} of {d['followed']} orbits change verdict at T/640" in readme
    assert f"(all below {_m(d['changed_largest_m'], '.3g')} m)" in readme


@pytest.mark.parametrize(
    "name, sigma", [("ring_completeness_pattern_band", 0.05), ("ring_completeness_pattern2_band", 0.02)]
)
def test_the_page_quotes_the_pattern_rings_whole_band(name, sigma):
    """The 5 % and 2 % pattern 0 rings over the whole band (results/<name>/)."""
    import csv

    d = _json(name)
    assert d["settings"]["pattern"] == [sigma, 0]
    page = _flat(REPO / "docs" / "findings" / "ring-completeness.md")
    csv_path = REPO / "results" / name / "ring_completeness.csv"
    rows = list(csv.DictReader(csv_path.open()))
    stable = [max(float(r[f"amplitude{i}_m"]) for i in range(6)) for r in rows if r["stable"] == "yes"]
    quoted = [
        f"{d['settled_stable_orbits']} settled stable orbits, {d['distinct_states']} distinct states,"
        f" {len(d['missed'])} on none of the engine's {d['engine']['branches']} branches",
        f"the largest {_m(max(max(m['amplitudes_m']) for m in d['missed']), '.3g')} m",
        f"The largest settled stable orbit is {_m(max(stable), '.5g')} m",
        f"the {len(d['not_settled'])} unsettled runs stay at or below"
        f" {_m(max(r['largest_range_m'][1] for r in d['not_settled']), '.4g')} m",
    ]
    missing = [q for q in quoted if q not in page]
    assert not missing, missing
