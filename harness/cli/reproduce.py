"""A chosen part of the paper's studies (figures 2 and 4-9, section 4, Campbell), without the mistuning study, into --out (default ./shroudedblade-results); `run` is the whole main job.

`python -m harness reproduce [--size quick|default|full] [--studies gap mass angle kn]
[--output-dir DIR] [--workers N | --scheduler ADDRESS]`. Writes one PNG and CSV files per
figure, summary.json and claims.md (paper claim | ours | settings | verdict); files are replaced
atomically. The studies are branches of periodic orbits (harness.studies.study_branches).
Fig. 2 compares the FMU's loop with the reference's: the studies come from
harness.validation.reproduction, the validation layer below the CLI (docs/layers.md).
"""
from __future__ import annotations

import argparse
import math
import time
from pathlib import Path

from harness.analysis.executor import RESULTS_DIR
from harness.cli.sweep import add_execution_options, make_runner
from harness.outputs import check_dir
from harness.studies.claims import tally, verdict_counts, write_claims
from harness.studies.paper import SIZES, STUDIES, Reproduction, validate_request
from harness.validation.reproduction import reproduce


def configure_parser(p: argparse.ArgumentParser) -> None:
    p.add_argument("--size", default="default", choices=list(SIZES),
                   help="quick (a test run: extremes only, coarse grid), default (make run), full (fine grids)")
    p.add_argument("--studies", nargs="+", choices=list(STUDIES), metavar="STUDY",
                   help=f"parameter studies to run (default all: {' '.join(STUDIES)})")
    p.add_argument("--no-extras", action="store_true",
                   help="only the parameter studies (skip Fig. 2, 4/5, Campbell, Coulomb, paper iteration)")
    p.add_argument("--out", "--output-dir", dest="output_dir", default=str(RESULTS_DIR), metavar="DIR",
                   help=f"where to write (default ./{RESULTS_DIR})")
    add_execution_options(p, cache=False)


def reproduce_and_report(args: argparse.Namespace, size: str, studies, extras: bool) -> Reproduction:
    """Run the studies, print their summary and the claims tally; the reproduction with its claim rows."""
    validate_request(size, studies)
    runner = make_runner(args)
    check_dir(args.output_dir, "--out")  # the configuration is good: can the results be written?
    out = Path(args.output_dir)
    t0 = time.perf_counter()
    with runner:
        rep = reproduce(out, size, studies, runner=runner, fmu_path=args.fmu, extras=extras)
    wall = time.perf_counter() - t0
    rows = write_claims(out / "claims.md", rep.summary)
    for name, st in rep.summary.studies.items():
        print(f"{st.figure} ({name}): largest stable max|q| and its speed per model")
        for r in st.rows:
            jump = f"jumps down at {r.fp_jump:6.0f} rpm" if math.isfinite(r.fp_jump) else "no jump in the band"
            print(f"  {STUDIES[name].label(r.value):<18s} {r.fp_peak * 1e3:8.5f} mm at {r.fp_speed:6.0f} rpm"
                  f" (fixed point, {jump}), {r.jenkins_peak * 1e3:8.5f} mm at"
                  f" {r.jenkins_speed:6.0f} rpm (Jenkins), {r.hb_peak * 1e3:8.5f} mm at {r.hb_speed:6.0f} rpm (HB)")
    print(f"claims: {tally(verdict_counts(rows))} -> {out / 'claims.md'}")
    print(f"wall time {wall:.1f} s; results in {out}/")
    rep.claims = rows
    return rep


def run(args: argparse.Namespace) -> int:
    reproduce_and_report(args, args.size, args.studies, not args.no_extras)
    return 0
