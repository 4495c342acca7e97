"""Numbers quoted in README.md and on the documentation's findings pages against the files they
come from, so a quoted number cannot drift from what the code last measured: the invalid-input
catalogue (docs/invalid-inputs.md, generated from real runs), the claims table (results/claims.md,
written by `make run`), the mistuning table (results/mistuning/mistuning_amplification.csv,
written by `python -m harness mistuning`) and the performance table (bench/RESULTS.json, written by
`make bench`) and the mistuning study's dask measurement (bench/mistuning_dask.json, written by
`python -m harness mistuning-dask`). A quoted number is compared as printed (rounded to the digits it shows),
from any value within half the quantum of the file's text (harness/digits.py: 6 significant digits)."""

from __future__ import annotations

import csv
import json
import re
from pathlib import Path

import numpy as np
import pytest

from harness import digits

REPO = Path(__file__).resolve().parents[2]
README = "README.md"
ROBUSTNESS = "docs/findings/robustness.md"
RESULTS = "docs/findings/results.md"
PERFORMANCE = "docs/findings/performance.md"
RING = "docs/guide/ring.md"
MISTUNING = "docs/guide/mistuning.md"


def _one(page: str, pattern: str) -> re.Match:
    found = list(re.finditer(pattern, (REPO / page).read_text()))
    assert len(found) == 1, f"{page} must quote this exactly once: {pattern!r} ({len(found)} found)"
    return found[0]


@pytest.fixture(scope="module")
def bench():
    return json.loads((REPO / "bench" / "RESULTS.json").read_text())


@pytest.mark.parametrize("page", [README, ROBUSTNESS])
def test_invalid_input_catalogue_size(page):
    m = _one(page, r"lists (\d+)\s+invalid inputs in (\d+) groups")
    lines = (REPO / "docs" / "invalid-inputs.md").read_text().splitlines()
    head = next(i for i, ln in enumerate(lines) if ln.startswith("| group |"))
    rows = [ln for ln in lines[head + 2 :] if ln.startswith("| ")]  # the catalogue table's rows
    groups = {ln.split("|")[1].strip() for ln in rows}
    assert (int(m.group(1)), int(m.group(2))) == (len(rows), len(groups))


def _verdicts() -> list[str]:
    """Every verdict of results/claims.md's table (the last cell, bold stripped)."""
    return re.findall(r"\| \*\*([^*|]+)\*\* \|$", (REPO / "results" / "claims.md").read_text(), re.M)


def test_claims_summary_counts():
    m = _one(RESULTS, r"(\d+) reproduced, (\d+) trend only, (\d+) not reproduced,\s+(\d+) new checks")
    verdicts = _verdicts()
    counts = [verdicts.count(v) for v in ("reproduced", "trend only", "not reproduced", "new check")]
    assert [int(g) for g in m.groups()] == counts


def test_claims_summary_in_readme():
    """README's line names every verdict group: the paper's claims add up, the new checks apart."""
    m = _one(
        README,
        r"of the paper's (\d+) claims (\d+) reproduced, (\d+) with a qualification, (\d+) in\s+"
        r"trend only, (\d+) not, (\d+) other; (\d+) new checks",
    )
    v = _verdicts()
    paper = [x for x in v if x != "new check"]
    qualified = [x for x in paper if x.startswith("reproduced") and x != "reproduced"]
    known = ("reproduced", "trend only", "not reproduced")
    counts = [
        len(paper),
        v.count("reproduced"),
        len(qualified),
        v.count("trend only"),
        v.count("not reproduced"),
        len([x for x in paper if x not in known and x not in qualified]),
        v.count("new check"),
    ]
    assert [int(g) for g in m.groups()] == counts


def test_make_run_wall_times(bench):
    m = _one(
        PERFORMANCE,
        r"\| `make run` \(`reproduce`[^|]*?(\d+)k periods\) \| ([\d.]+) s wall on (\d+) workers; "
        r"branches ([\d.]+) s",
    )
    r = bench["reproduce"]
    assert int(m.group(1)) == round(r["branches_evaluations"] / 1000)
    assert m.group(2) == f"{r['wall']:.1f}" and int(m.group(3)) == r["workers"]
    assert m.group(4) == f"{r['branches_wall']:.1f}"
    m = _one(README, r"the paper's 50 branch curves ([\d.]+) s wall on (\d+) workers")
    assert m.group(1) == f"{r['wall']:.1f}" and int(m.group(2)) == r["workers"]


def test_worker_time_over_fmi_time(bench):
    m = _one(
        PERFORMANCE,
        r"worker time / time inside the FMI calls \| \*\*([\d.]+)\*\* \(wall x workers / FMI time "
        r"([\d.]+)\)",
    )
    r = bench["reproduce"]
    assert m.group(1) == f"{r['branches_worker_s'] / r['branches_fmi_s']:.2f}"
    assert m.group(2) == f"{r['branches_wall'] * r['workers'] / r['branches_fmi_s']:.2f}"


def test_rk4_step_cost(bench):
    """The range of ns per internal step at 100 internal steps per doStep (the C benchmark's second
    table), rounded as printed, and the RHS evaluations per step."""
    m = _one(
        PERFORMANCE,
        r"100 steps per doStep\) \| (\d+)-(\d+) ns \(linear ... Jenkins element\); "
        r"~([\d.]+)-([\d.]+) RHS",
    )
    table = bench["c_step"]["text"].split("(100 internal steps each)")[1]
    rows = [
        ln.split()
        for ln in table.splitlines()
        if ln and ln[0].isalpha() and "ns/step" not in ln and not ln.startswith("communication")
    ]
    ns = [float(r[-3]) for r in rows]
    rhs = [float(r[-2]) for r in rows]
    assert (int(m.group(1)), int(m.group(2))) == (round(min(ns)), round(max(ns)))
    assert (m.group(3), m.group(4)) == (f"{min(rhs):.1f}", f"{max(rhs):.1f}")


def test_ring_row(bench):
    """The 24-blade ring row: wall / time inside fmi2DoStep (measured in C) for libcosim (whole run
    and stepping alone), the fmpy master (feedthrough and
    libcosim's data flow) and the C loop, and the compute per doStep; the same ratios where README
    and the ring page quote them."""
    m = _one(
        PERFORMANCE,
        r"\| a 24-blade ring[^|]*\| libcosim \*\*([\d.]+)x\*\* \(stepping alone ([\d.]+)x\), fmpy master ([\d.]+)x \(in libcosim's data flow ([\d.]+)x\), "
        r"C loop \*\*([\d.]+)x\*\*; ([\d.]+) µs per doStep",
    )
    g = bench["ring"]["builtin"]
    lc = g["libcosim"]
    c_loop = f"{g['C loop']['ratio_wall']:.2f}"
    assert m.groups() == (
        f"{lc['ratio_wall']:.2f}",
        f"{lc['ratio_step_wall']:.2f}",
        f"{g['fmpy feedthrough']['ratio_wall']:.2f}",
        f"{g['fmpy libcosim data flow']['ratio_wall']:.2f}",
        c_loop,
        f"{lc['inside_doStep'] / lc['doSteps'] * 1e6:.2f}",
    )
    m = _one(README, r"costs the C loop ([\d.]+)x the FMUs' own compute,\s+libcosim ([\d.]+)x")
    assert m.groups() == (c_loop, f"{lc['ratio_wall']:.2f}")
    m = _one(RING, r"The C loop costs ([\d.]+)x the FMUs' own compute against (\d+)x for the fmpy loop")
    assert m.group(1) == c_loop and int(m.group(2)) == round(g["fmpy feedthrough"]["ratio_wall"])


def _printed(value: float, spec: str, half: float) -> set[str]:
    """How a number written as `value` prints with `spec`: the file's text stands for every value
    within half its quantum (harness/digits.py), so a quote that rounds across that interval (e.g.
    0.054895 to 5 decimals) may be either neighbour."""
    return {format(value + k * half, spec) for k in (-1.0, 0.0, 1.0)}


def _half_quanta(rows: list[dict]) -> dict[str, float]:
    """Half the writer's quantum of every numeric column of a CSV's rows (6 digits of its largest)."""
    out = {}
    for key in rows[0]:
        try:
            top = max(abs(float(r[key])) for r in rows)
        except ValueError:
            continue
        e = digits.exponent(top)
        out[key] = 0.0 if e is None else 0.5 * 10.0**e
    return out


def _amplification(folder: str) -> dict[tuple[str, str], tuple[set[str], set[str]]]:
    """(variant, sigma in %) -> (mean, max), each as the 4-decimal texts the CSV's value stands for."""
    with open(REPO / "results" / folder / "mistuning_amplification.csv", newline="") as f:
        rows = list(csv.DictReader(f))
    h = _half_quanta(rows)
    return {
        (r["variant"], f"{100 * float(r['sigma']):g}"): (
            _printed(float(r["mean"]), ".4f", h["mean"]),
            _printed(float(r["max"]), ".4f", h["max"]),
        )
        for r in rows
    }


@pytest.mark.parametrize(
    "folder, header",
    [
        ("mistuning", "| sigma (EI) | what a sweep finds |"),
        ("mistuning_24", "| sigma (EI), N = 24 | what a sweep finds |"),
    ],
)
def test_mistuning_table(folder, header):
    """Each mean / max cell of a sweep table on the mistuning page against the study's CSV."""
    csv_rows = _amplification(folder)
    text = (REPO / MISTUNING).read_text()
    table = text[text.index(header) :].split("\n\n")[0].splitlines()[2:]
    assert len(table) == len({s for _, s in csv_rows}) >= 1
    for line in table:
        sigma, cell = [c.strip() for c in line.strip("|").split("|")]
        mean, top = csv_rows[("friction", sigma.rstrip(" %"))]
        got_mean, got_top = cell.split(" / ")
        assert got_mean in mean and got_top in top, (sigma, cell, mean, top)


def _states(folder: str) -> tuple[dict, dict[str, list[float]], dict[str, float]]:
    """The tuned ring's row, the amplifications per sigma (in %) and half the writer's quantum per
    column, from mistuning_states.csv."""
    with open(REPO / "results" / folder / "mistuning_states.csv", newline="") as f:
        rows = list(csv.DictReader(line for line in f if not line.startswith("#")))
    per: dict[str, list[float]] = {}
    for r in rows[1:]:
        per.setdefault(f"{100 * float(r['sigma']):g}", []).append(float(r["amplification"]))
    return rows[0], per, _half_quanta(rows)


@pytest.mark.parametrize(
    "folder, header",
    [
        ("mistuning", "| sigma (EI), mistuning | on stable steady states |"),
        ("mistuning_24", "| sigma (EI), N = 24, mistuning | on stable steady states |"),
    ],
)
def test_mistuning_states_table(folder, header):
    """A steady-state table on the mistuning page: the tuned ring's largest stable state and
    mean / max (patterns) per sigma, against results/<folder>/mistuning_states.csv."""
    tuned, per, h = _states(folder)
    text = (REPO / MISTUNING).read_text()
    table = text[text.index(header) :].split("\n\n")[0].splitlines()[2:]
    assert len(table) == len(per) + 1
    name, cell = [c.strip() for c in table[0].strip("|").split("|")]
    amp, rpm = cell.removesuffix(" rpm").split(" m at ")
    assert name == "tuned" and amp in _printed(float(tuned["stable_peak_m"]), ".4e", h["stable_peak_m"])
    assert rpm in _printed(float(tuned["stable_peak_rpm"]), ".1f", h["stable_peak_rpm"])
    for line in table[1:]:
        sigma, cell = [c.strip() for c in line.strip("|").split("|")]
        a = per[sigma.rstrip(" %")]
        mean, top, count = cell.replace(" / ", " ").replace("(", "").replace(")", "").split()
        assert mean in _printed(float(np.mean(a)), ".4f", h["amplification"]), sigma
        assert top in _printed(float(np.max(a)), ".4f", h["amplification"]) and int(count) == len(a), sigma


def _search() -> tuple[float, int, float]:
    """(best amplification, rings, start amplification) of results/mistuning_search/mistuning_search.csv."""
    with open(REPO / "results" / "mistuning_search" / "mistuning_search.csv", newline="") as f:
        rows = list(csv.DictReader(line for line in f if not line.startswith("#")))
    return max(float(r["amplification"]) for r in rows), len(rows), float(rows[0]["amplification"])


def test_readme_mistuning_numbers():
    tuned, per, h = _states("mistuning")
    m = _one(README, r"largest stable response over 3973-14898 rpm is ([\d.e-]+) m")
    assert m.group(1) in _printed(float(tuned["stable_peak_m"]), ".4e", h["stable_peak_m"])
    m = _one(README, r"5 % blade stiffness scatter gives ([\d.]+)x")
    assert m.group(1) in _printed(max(per["5"]), ".4f", h["amplification"])
    best, rings, _ = _search()
    m = _one(README, r"a search of (\d+) rings\s+finds at most ([\d.]+)x")
    assert int(m.group(1)) == rings and m.group(2) in _printed(best, ".4f", 5e-7)
    mean, top = _amplification("mistuning")[("friction", "5")]
    m = _one(README, r"Sweeps alone say\s+([\d.]+)x")
    assert m.group(1) in top
    m = _one(
        README,
        r"On 24 blades all 4 patterns' stable steady states[^(]*give at most\s+([\d.]+)x\s+\(sweeps: ([\d.]+)x\)",
    )
    _, per24, h24 = _states("mistuning_24")
    assert m.group(1) in _printed(max(per24["5"]), ".4f", h24["amplification"])
    assert m.group(2) in _amplification("mistuning_24")[("friction", "5")][1]


def test_mistuning_search_line():
    """The search's result on the mistuning page against results/mistuning_search/mistuning_search.csv."""
    best, rings, start = _search()
    m = _one(MISTUNING, r"at most ([\d.]+)x after (\d+) rings, from ([\d.]+)x")
    assert m.group(1) in _printed(best, ".4f", 5e-7) and int(m.group(2)) == rings
    assert m.group(3) in _printed(start, ".4f", 5e-7)


def test_dask_measurement():
    """The dask page's speed-up and cluster-cost numbers against bench/mistuning_dask.json."""
    m = json.loads((REPO / "bench" / "mistuning_dask.json").read_text())
    text = (REPO / "docs" / "guide" / "dask.md").read_text()
    assert _one("docs/guide/dask.md", r"\*\*speed-up ([\d.]+)\*\*").group(1) == f"{m['speed_up']:.2f}"
    row = re.search(r"\| wall \[h\] \| (.*) \|", text).group(1).split(" | ")
    assert row == [f"{c['wall_h']:.2f}" for c in m["cluster_cost"]]
    assert m["killed_worker"]["completed"] and m["killed_worker"]["lost"] in m["killed_worker"]["started_twice"]


def _modes_rows() -> tuple[dict, dict[str, float]]:
    """The convergence rows by (model, modes), and half the writer's quantum per column."""
    with open(REPO / "results" / "modes_convergence.csv", newline="") as f:
        rows = list(csv.DictReader(line for line in f if not line.startswith("#")))
    return {(r["model"], int(r["modes"])): r for r in rows}, _half_quanta(rows)


def test_modes_convergence_table():
    """Every row of the convergence table on docs/modes.md against results/modes_convergence.csv."""
    rows, h = _modes_rows()
    text = (REPO / "docs" / "modes.md").read_text()
    model, seen = None, 0
    for m in re.finditer(r"^\|\s*([a-zA-Z =().]*?)\s*\| (\d) \| ([\d.]+) \| (\d+) \| ([\d.]+) \|$", text, re.M):
        name = {"Jenkins element": "jenkins", "fixed point B = A(B)": "fixedPoint"}.get(m.group(1).strip(), model)
        model = name
        r = rows[(name, int(m.group(2)))]
        assert m.group(3) in _printed(float(r["peak_m"]) * 1e3, ".5f", h["peak_m"] * 1e3)
        assert m.group(4) in _printed(float(r["speed_rpm"]), ".0f", h["speed_rpm"])
        assert m.group(5) in _printed(float(r["root_moment_Nm"]), ".2f", h["root_moment_Nm"])
        seen += 1
    assert seen == len(rows), f"docs/modes.md quotes {seen} of the {len(rows)} convergence rows"


def test_readme_modes():
    rows, h = _modes_rows()
    m = _one(
        README,
        r"one mode is ([\d.]+) % low in the base case's\s+peak amplitude \(two modes are within "
        r"([\d.]+) % of four\) but gives (\d+) % of the root bending moment\s+\(([\d.]+) N m against "
        r"([\d.]+) N m at m = 4\)",
    )
    j1, j2, j4 = rows[("jenkins", 1)], rows[("jenkins", 2)], rows[("jenkins", 4)]
    assert m.group(1) in _printed(-100 * float(j1["d_peak"]), ".1f", 100 * h["d_peak"])
    assert m.group(2) in _printed(-100 * float(j2["d_peak"]), ".2f", 100 * h["d_peak"])
    ratio = 100 * float(j1["root_moment_Nm"]) / float(j4["root_moment_Nm"])
    assert m.group(3) in _printed(ratio, ".0f", ratio * 2 * h["root_moment_Nm"] / float(j1["root_moment_Nm"]))
    assert m.group(4) in _printed(float(j1["root_moment_Nm"]), ".2f", h["root_moment_Nm"])
    assert m.group(5) in _printed(float(j4["root_moment_Nm"]), ".2f", h["root_moment_Nm"])


@pytest.mark.parametrize("page", [RESULTS, "docs/guide/install.md"])
def test_base_case_peak_and_crossing(page):
    """The base case's peak (fixed point) and the contact-free EO 3 crossing where the results page
    and the install guide's `make run` output quote them, against results/summary.json."""
    s = json.loads((REPO / "results" / "summary.json").read_text())
    row = next(r for r in s["studies"]["gap"]["rows"] if abs(r["value"] - s["base"]["d"]) < 1e-15)
    text = (REPO / page).read_text()
    peak_mm, speed, crossing = row["fp_peak"] * 1e3, row["fp_speed"], s["campbell"]["eo_crossing_rpm"]
    if page == RESULTS:
        m = _one(page, r"\*\*(\d+) rpm\*\* \(fixed point, ([\d.]+) mm\)")
        assert (int(m.group(1)), m.group(2)) == (round(speed), f"{peak_mm:.4f}")
    else:
        m = _one(page, r"max\|q\| = ([\d.]+) mm at (\d+) rpm")
        assert (m.group(1), int(m.group(2))) == (f"{peak_mm:.4f}", round(speed))
    assert f"{crossing:.0f} rpm (one mode, printed formulation)" in text


def test_whitehead_bound():
    """Whitehead's bound (1 + sqrt N) / 2 where README and the mistuning page quote it."""
    m = _one(README, r"Whitehead's bound ([\d.]+)x")
    assert m.group(1) == f"{(1 + 6**0.5) / 2:.2f}"
    m = _one(MISTUNING, r"for\s+linear rings: ([\d.]+) \(N = 6\), ([\d.]+) \(N = 24\)")
    assert m.groups() == (f"{(1 + 6**0.5) / 2:.3f}", f"{(1 + 24**0.5) / 2:.2f}")
