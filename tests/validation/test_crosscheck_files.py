"""The committed cross-check files are the same on every run: `make crosscheck` twice leaves the
checkout clean. Wall times (which change with the machine's load) go to an ignored file beside the
agreement table; paths are written relative to the checkout."""

from __future__ import annotations

import re
import subprocess
from pathlib import Path

import numpy as np

from harness.crosscheck import deliverables as xd
from harness.crosscheck import run as xr
from harness.crosscheck.common import Run, result_array
from harness.crosscheck.plan import SCENARIOS

REPO = Path(__file__).resolve().parents[2]
CROSSCHECK = REPO / "crosscheck"
#: what a timing or a machine-specific path looks like in the written text
VOLATILE = re.compile(r"wall time|wall\)|start-up \d|\d+(\.\d+)? s wall|/tmp/|/home/|/work/|/root/")


def _report(wall: float, jvm: float) -> xr.ScenarioReport:
    """A report of fixed results whose runs took `wall` seconds (FMI4j: `jvm` with the JVM)."""
    t = np.linspace(0.0, 0.1, 11)
    res = result_array(t, {"tipDisplacement": np.sin(t)})
    rep = xr.ScenarioReport(SCENARIOS["steady"])
    rep.rows.append(xr.Row(Run("fmpy simulate_fmu", "0.3", "held", res, wall), 0.0, "", None, "(reference)"))
    fmi4j = Run("FMI4j (Java driver)", "0.38.0", "held", res, 2 * wall, extra={"total_time": jvm})
    rep.rows.append(xr.Row(fmi4j, 1e-13, "tipDisplacement", None, "fmpy simulate_fmu, held"))
    rep.held_vs_taylor = 0.5
    return rep


def test_agreement_table_does_not_depend_on_the_wall_time():
    fast, slow = _report(0.123, 0.9), _report(4.567, 3.2)
    assert xr.table(fast) == xr.table(slow)
    assert not VOLATILE.search(xr.table(fast)), xr.table(fast)
    # the wall times are kept, in the timings file's table
    times = xr.timings_table(xr.scenario_timings(slow))
    assert "4.567" in times and "9.134" in times and "3.20 s" in times


def test_vendor_repo_summary_names_the_tree_relatively(tmp_path):
    root = tmp_path / "crosscheck"
    out = f"0 problems found in {root}\nValidated 3 FMUs and 8 results\n"
    line = xd.vendor_repo_summary(0, out, root)
    assert str(tmp_path) not in line
    assert line.endswith("exit 0; 0 problems found in crosscheck; Validated 3 FMUs and 8 results"), line


def test_committed_crosscheck_files_hold_no_timing_or_local_path():
    """Every text file `make crosscheck` writes and git tracks: no wall time, no absolute path."""
    tracked = subprocess.run(
        ["git", "ls-files", "crosscheck"], cwd=REPO, capture_output=True, text=True, check=True
    ).stdout.split()
    texts = [REPO / f for f in tracked if f.endswith(".md") and not f.startswith("crosscheck/java/")]
    assert any(p.name == "agreement.md" for p in texts), tracked[:5]
    bad = {str(p.relative_to(REPO)): m.group(0) for p in texts if (m := VOLATILE.search(p.read_text()))}
    assert not bad, f"run-dependent text in committed files: {bad}"


def test_timings_file_is_ignored():
    timings = xr.AGREEMENT_FILE.with_name(xr.AGREEMENT_FILE.stem + xr.TIMINGS_SUFFIX)
    res = subprocess.run(["git", "check-ignore", "-q", str(timings)], cwd=REPO)
    assert res.returncode == 0, f"{timings.relative_to(REPO)} is not ignored by git"
