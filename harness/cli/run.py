"""The whole main job (what `make run` commits): every paper study plus the bladed disk's mistuning study, into --out (default ./shroudedblade-results).

`run` and `reproduce` differ on purpose: `run` is the fixed, complete job behind the committed
results (`make run` passes --out results); `reproduce` runs a chosen part of the paper's studies
(--studies, --no-extras, any --size) for a quick look, without the mistuning study.
`python -m harness run` = `python -m harness reproduce --size default` with all studies and
extras: Fig. 2, 4/5, 6-9 (the studies as branches of periodic orbits with their stability), the
section-4 Coulomb comparison and a Campbell diagram as PNG + CSV, summary.json and the claims
table claims.md; then the bladed disk's mistuning study at size small (
harness/studies/mistuning.py: <out>/mistuning/, each sweep over speed cached under
<out>/cache/mistuning, so a second run reads it back; the study alone takes 1.5-4 min on 2 cores).
"""
from __future__ import annotations

import argparse
from pathlib import Path

from harness.analysis.executor import RESULTS_DIR
from harness.cli.options import add_execution_options, make_runner
from harness.cli.reports import mistuning_report, reproduce_and_report
from harness.studies import mistuning, mistuning_plots
from harness.studies.paper import SIZES


def configure_parser(p: argparse.ArgumentParser) -> None:
    p.add_argument("--size", default="default", choices=list(SIZES), help="work size (default: default)")
    p.add_argument("--out", "--output-dir", dest="output_dir", default=str(RESULTS_DIR), metavar="DIR",
                   help=f"where to write (default ./{RESULTS_DIR})")
    add_execution_options(p, cache=False)


def run(args: argparse.Namespace) -> int:
    rc = reproduce_and_report(args, args.size, None, True)
    out = Path(args.output_dir)
    with make_runner(args) as runner:
        study = mistuning.run_study(mistuning.SIZES["small"], runner, out / "cache" / "mistuning")
    study["files"] = [str(f) for f in mistuning_plots.write(study, out / "mistuning")]
    mistuning_report(study)
    return rc
