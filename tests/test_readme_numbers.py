"""Numbers quoted in README.md against the files they come from, so a quoted number cannot drift
from what the code last measured: the invalid-input catalogue (docs/invalid-inputs.md, generated
from real runs), the claims table (results/claims.md, written by `make run`) and the performance
table (bench/RESULTS.json, written by `make bench`). A README number is compared as printed
(rounded to the digits it shows)."""
from __future__ import annotations

import json
import re
from pathlib import Path

import pytest

REPO = Path(__file__).resolve().parent.parent
README = (REPO / "README.md").read_text()


def _one(pattern: str) -> re.Match:
    found = list(re.finditer(pattern, README))
    assert len(found) == 1, f"README must quote this exactly once: {pattern!r} ({len(found)} found)"
    return found[0]


def test_invalid_input_catalogue_size():
    m = _one(r"lists (\d+)\s+invalid inputs in (\d+) groups")
    lines = (REPO / "docs" / "invalid-inputs.md").read_text().splitlines()
    head = next(i for i, ln in enumerate(lines) if ln.startswith("| group |"))
    rows = [ln for ln in lines[head + 2:] if ln.startswith("| ")]  # the catalogue table's rows
    groups = {ln.split("|")[1].strip() for ln in rows}
    assert (int(m.group(1)), int(m.group(2))) == (len(rows), len(groups))


def test_claims_summary_counts():
    m = _one(r"(\d+) reproduced, (\d+) trend only, (\d+) not reproduced,\s+(\d+) new checks")
    verdicts = re.findall(r"\| \*\*([a-z ,-]+)\*\* \|$", (REPO / "results" / "claims.md").read_text(), re.M)
    counts = [verdicts.count(v) for v in ("reproduced", "trend only", "not reproduced", "new check")]
    assert [int(g) for g in m.groups()] == counts


@pytest.fixture(scope="module")
def bench():
    return json.loads((REPO / "bench" / "RESULTS.json").read_text())


def test_make_run_wall_times(bench):
    m = _one(r"\| `make run` \(`reproduce`[^|]*?(\d+)k periods\) \| ([\d.]+) s wall on (\d+) workers; branches ([\d.]+) s")
    r = bench["reproduce"]
    assert int(m.group(1)) == round(r["branches_evaluations"] / 1000)
    assert m.group(2) == f"{r['wall']:.1f}" and int(m.group(3)) == r["workers"]
    assert m.group(4) == f"{r['branches_wall']:.1f}"


def test_branches_vs_transient_path(bench):
    m = _one(r"\| ([\d.]+) s vs ([\d.]+) s: \*\*([\d.]+)x\*\* less wall \(whole reproduction ([\d.]+)x; "
             r"blade time (\d+) s vs (\d+) s\)")
    r, t = bench["reproduce"], bench["transient"]
    studies = r["hb_wall"] + r["branches_wall"]
    assert m.group(1) == f"{studies:.1f}" and m.group(2) == f"{t['wall']:.1f}"
    assert m.group(3) == f"{t['wall'] / studies:.2f}"
    assert m.group(4) == f"{(t['wall'] + r['extras_wall']) / r['wall']:.2f}"
    assert (int(m.group(5)), int(m.group(6))) == (round(r["branches_simulated_s"]), round(t["sim_time"]))


def test_worker_time_over_fmi_time(bench):
    m = _one(r"worker time / time inside the FMI calls \| \*\*([\d.]+)\*\* \(wall x workers / FMI time ([\d.]+)\)")
    r = bench["reproduce"]
    assert m.group(1) == f"{r['branches_worker_s'] / r['branches_fmi_s']:.2f}"
    assert m.group(2) == f"{r['branches_wall'] * r['workers'] / r['branches_fmi_s']:.2f}"


def test_rk4_step_cost(bench):
    """The range of ns per internal step at 100 internal steps per doStep (the C benchmark's second
    table), rounded as printed, and the RHS evaluations per step."""
    m = _one(r"100 steps per doStep\) \| (\d+)-(\d+) ns \(linear ... Jenkins element\); ~([\d.]+)-([\d.]+) RHS")
    table = bench["c_step"]["text"].split("(100 internal steps each)")[1]
    rows = [ln.split() for ln in table.splitlines() if ln and ln[0].isalpha() and "ns/step" not in ln
            and not ln.startswith("communication")]
    ns = [float(r[-3]) for r in rows]
    rhs = [float(r[-2]) for r in rows]
    assert (int(m.group(1)), int(m.group(2))) == (round(min(ns)), round(max(ns)))
    assert (m.group(3), m.group(4)) == (f"{min(rhs):.1f}", f"{max(rhs):.1f}")


def test_ring_row(bench):
    """The 24-blade ring row: wall / time inside fmi2DoStep (measured in C) for libcosim (whole run
    and stepping alone), the fmpy master (feedthrough and libcosim's data flow) and the C loop, and
    the compute per doStep."""
    m = _one(r"\| a 24-blade ring[^|]*\| libcosim \*\*([\d.]+)x\*\* \(stepping alone ([\d.]+)x\), fmpy master "
             r"([\d.]+)x \(in libcosim's data flow ([\d.]+)x\), C loop \*\*([\d.]+)x\*\*; ([\d.]+) us per doStep")
    g = bench["ring"]
    lc = g["libcosim"]
    assert m.groups() == (f"{lc['ratio_wall']:.2f}", f"{lc['ratio_step_wall']:.2f}",
                          f"{g['fmpy feedthrough']['ratio_wall']:.2f}",
                          f"{g['fmpy libcosim data flow']['ratio_wall']:.2f}",
                          f"{g['C loop']['ratio_wall']:.2f}",
                          f"{lc['inside_doStep'] / lc['doSteps'] * 1e6:.2f}")
