"""The counts quoted on docs/findings/ring-completeness.md against the file they come from
(results/ring_completeness.json, written by `python -m harness ring-completeness`), so the page
cannot drift from the last run."""

from __future__ import annotations

import json
from pathlib import Path

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
