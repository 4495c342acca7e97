"""The claims tally `make run` prints: every row of the committed results/claims.md counted once,
the new checks apart from the paper's claims, plural where there are several (no "4 new check")."""

from __future__ import annotations

import re
from pathlib import Path

from harness.studies.claims import tally

REPO = Path(__file__).resolve().parents[2]


def _verdicts() -> list[str]:
    """The verdict column of results/claims.md's table (the last cell, bold stripped)."""
    rows = [
        ln
        for ln in (REPO / "results" / "claims.md").read_text().splitlines()
        if ln.startswith("| ") and not ln.startswith("| claim |")
    ]
    return [ln.rstrip(" |").rsplit(" | ", 1)[1].strip("*") for ln in rows]


def test_tally_counts_every_claim_once():
    verdicts = _verdicts()
    counts: dict[str, int] = {}
    for v in verdicts:
        counts[v] = counts.get(v, 0) + 1
    line = tally(counts)
    paper, _, new = line.partition("; ")
    total, groups = paper.split(" claims of the paper: ")
    numbers = [int(n) for n in re.findall(r"(?:^|, )(\d+) ", groups)]
    assert int(total) == sum(numbers) == sum(v != "new check" for v in verdicts), line
    n_new = sum(v == "new check" for v in verdicts)
    assert n_new > 1 and new == f"{n_new} new checks (not in the paper)", line
    assert f"{counts['reproduced']} reproduced," in groups


def test_one_new_check_is_singular():
    assert (
        tally({"reproduced": 2, "new check": 1})
        == "2 claims of the paper: 2 reproduced; 1 new check (not in the paper)"
    )
