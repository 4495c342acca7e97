"""`python -m harness bench --quick`: every row of `make bench` once at tiny sizes, so that no row
can break unseen (its numbers mean nothing; bench/RESULTS.md is measured by `make bench`). The
quick run writes only the file it is given and never bench/RESULTS.md."""

from __future__ import annotations

import json

from harness.cli.main import main
from harness.fmu.build import REPO_ROOT

SECTIONS = (
    "## FMU internal step cost",
    "## Cost per RK4 step vs the number of modes",
    "## Cost of one fmi2DoStep through the harness loop",
    "## The same run through the Python reference",
    "## Harmonic balance for all studies",
    "## Branches: the Jacobian from the FMU's sensitivities",
    "## The bladed-disk ring",
    "## `make run` (`reproduce`)",
    "## The ring's periodic steady states",
    "## Command line start-up",
)


def test_every_bench_row_runs_at_the_quick_size(tmp_path, capsys):
    measured = (REPO_ROOT / "bench" / "RESULTS.md").read_bytes()
    out = tmp_path / "RESULTS.md"
    assert main(["bench", "--quick", "--workers", "1", "--output-file", str(out)]) == 0
    capsys.readouterr()
    text = out.read_text()
    missing = [s for s in SECTIONS if s not in text]
    assert not missing, missing
    data = json.loads(out.with_suffix(".json").read_text())
    assert data["c_step"]["available"] and data["c_step"]["text"].count("Jenkins element, tracked B") == 2
    assert len(data["modes"]["rows"]) >= 6 and len(data["dostep"]) == 3
    assert set(data["jacobians"]) == {"sensitivities", "finite differences"}
    ring = data["ring"]["builtin"]
    assert ring["libcosim"]["equals_fmpy_libcosim_data_flow"] and ring["C loop"]["finite"]
    assert data["reproduce"]["size"] == "tiny"
    assert (REPO_ROOT / "bench" / "RESULTS.md").read_bytes() == measured
