"""harness/validation/ring_refine.py's bookkeeping on hand-made rows: which orbits are sampled, which
count as followed and as changed, and the largest amplitudes the summary quotes (each counted here
from the rows, not by the module)."""

from __future__ import annotations

import math

import numpy as np

from harness.validation.branch_match import Branch
from harness.validation.ring_refine import Refined, sample, summary

STEPS = (160, 320, 640)


def _row(speed, amps, stable):
    return Refined(0, 0, speed, list(amps), [0.9 if s else 1.1 for s in stable], list(stable))


def test_summary_counts_changes_between_the_first_and_the_finest_step():
    rows = [
        _row(5390.0, (2.01e-5, 2.01e-5, 2.01e-5), (False, False, True)),  # unstable -> stable
        _row(5400.0, (2.05e-5, 2.05e-5, 2.05e-5), (False, True, False)),  # same at both ends: unchanged
        _row(6000.0, (4.9e-5, 4.9e-5, 4.9e-5), (True, True, True)),
        _row(6100.0, (4.6e-5, 4.6e-5, 4.6e-5), (True, True, False)),  # stable -> unstable
        _row(7000.0, (5.5e-5,), (True,)),  # not followed past the first step
    ]
    s = summary(rows, STEPS)
    assert (s["orbits"], s["followed"], s["not_followed"]) == (5, 4, 1)
    assert (s["changed"], s["stable_to_unstable"], s["unstable_to_stable"]) == (2, 1, 1)
    assert s["changed_largest_m"] == 4.6e-5 and s["changed_speeds_rpm"] == [5390.0, 6100.0]
    assert s["largest_stable_first_m"] == 4.9e-5  # the 5.5e-5 one was not followed
    assert s["largest_stable_finest_m"] == 4.9e-5


def test_summary_of_nothing_changed_has_no_largest():
    s = summary([_row(6000.0, (4.9e-5,) * 3, (True,) * 3)], STEPS)
    assert s["changed"] == 0 and math.isnan(s["changed_largest_m"])


def test_sample_takes_every_nth_orbit_above_the_amplitude():
    a = np.array([[1e-5, 2e-5], [3e-5, 1e-5], [5e-6, 5e-6], [4e-5, 4e-5]])
    b0 = Branch(np.array([1.0, 2.0, 3.0, 4.0]), a, np.ones(4, bool))
    b1 = Branch(np.array([5.0]), np.array([[6e-5, 0.0]]), np.ones(1, bool))
    assert sample([b0, b1], 1, 1.5e-5) == [(0, 0), (0, 1), (0, 3), (1, 0)]
    assert sample([b0, b1], 2, 1.5e-5) == [(0, 0), (0, 3)]
    assert sample([b0, b1], 1, 0.0) == [(0, 0), (0, 1), (0, 2), (0, 3), (1, 0)]


def test_the_command_writes_what_it_counts(tmp_path):
    """`ring-step-check` on a small band of the tuned study ring: the JSON's counts are the CSV's rows
    (counted here), and each followed orbit's amplitude at T/320 is within 2 % of its T/160 one."""
    import csv
    import json

    from harness.cli.main import main

    assert (
        main(["ring-step-check", "--speeds", "6400", "6500", "--every", "2", "--finer", "320", "--out", str(tmp_path)])
        == 0
    )
    d = json.loads((tmp_path / "ring_step_check.json").read_text())
    rows = list(csv.DictReader((tmp_path / "ring_step_check.csv").open()))
    followed = [r for r in rows if r["stable_320"]]
    assert d["orbits"] == len(rows) >= 2 and d["followed"] == len(followed) >= 1
    assert d["changed"] == sum(r["stable_160"] != r["stable_320"] for r in followed)
    for r in followed:
        a, b = float(r["amplitude_m_160"]), float(r["amplitude_m_320"])
        assert abs(b - a) <= 0.02 * a, r
