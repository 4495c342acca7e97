"""The whole main job (what `make run` commits): every paper study plus the bladed disk's mistuning study, into --out (default ./shroudedblade-results).

`run` and `reproduce` differ on purpose: `run` is the fixed, complete job behind the committed
results (`make run` passes --out results); `reproduce` runs a chosen part of the paper's studies
(--studies, --no-extras, any --size) for a quick look, without the mistuning study.
`python -m harness run` = `python -m harness reproduce --size default` with all studies and
extras: Fig. 2, 4/5, 6-9 (the studies as branches of periodic orbits with their stability), the
section-4 Coulomb comparison and a Campbell diagram as PNG + CSV, summary.json and the claims
table claims.md; then the bladed disk's mistuning study at size small (
harness/studies/mistuning.py: <out>/mistuning/, each sweep over speed cached under
<out>/cache/mistuning, so a second run reads it back; the sweeps take 1.5-4 min on 2 cores, the three
rings on stable steady states about 5 min more).
"""

from __future__ import annotations

import argparse
from typing import Any
from pathlib import Path

import numpy as np

from harness.paths import RESULTS_DIR
from harness.cli.mistuning import run_and_write
from harness.cli.options import add_execution_options, make_runner
from harness.cli.reports import mistuning_report, reproduce_and_report
from harness.studies import mistuning
from harness.studies.claims import grouped, verdict_counts
from harness.studies.paper import SIZES, STUDIES, Reproduction


def configure_parser(p: argparse.ArgumentParser) -> None:
    p.add_argument("--size", default="default", choices=list(SIZES), help="work size (default: default)")
    p.add_argument(
        "--out",
        "--output-dir",
        dest="output_dir",
        default=str(RESULTS_DIR),
        metavar="DIR",
        help=f"where to write (default ./{RESULTS_DIR})",
    )
    add_execution_options(p, cache=False)


def run(args: argparse.Namespace) -> int:
    rep = reproduce_and_report(args, args.size, None, True)
    out = Path(args.output_dir)
    with make_runner(args) as runner:
        study = run_and_write(mistuning.SIZES["small"], runner, out / "cache" / "mistuning", out / "mistuning")
    mistuning_report(study)
    print(f"\nresults in {out.resolve()}/ (claims.md: the paper's claims against ours; the figures *.png; mistuning/)")
    print("what it found:")
    for line in findings(rep, study):
        print(f"  {line}")
    return 0


def findings(rep: Reproduction, study: dict[str, Any]) -> list[str]:
    """Three lines: the paper's claims, the base case's resonance, the mistuned ring."""
    groups = grouped(verdict_counts(rep.claims))
    total = sum(groups.values())
    rest = ", ".join(f"{n} {k}" for k, n in groups.items() if k != "reproduced")
    lines = [f"the paper's claims: {groups.get('reproduced', 0)} of {total} reproduced ({rest})"]
    s = rep.summary
    base = next(
        ((name, r) for name, st in s.studies.items() for r in st.rows if r.value == s.base.get(STUDIES[name].param)),
        None,
    )
    crossing = (
        f"contact-free EO {s.base['engineOrder']} crossing at {s.campbell.eo_crossing_rpm:.0f} rpm"
        " (one mode, printed formulation)"
        if s.campbell
        else ""
    )
    if base is not None:
        r = base[1]
        lines.append(
            f"base case (paper Table 1): resonance peak max|q| = {r.fp_peak * 1e3:.4f} mm at"
            f" {r.fp_speed:.0f} rpm (fixed point B = A(B)), the shroud contact stiffening it above the "
            + (crossing or "contact-free crossing")
        )
    elif crossing:
        lines.append(f"base case (paper Table 1): {crossing}")
    variant = "friction" if "friction" in study["variants"] else next(iter(study["variants"]))
    states = study.get("states")
    amp = np.array((states or study["variants"][variant])["amplification"], dtype=float)
    what = "on stable steady states" if states else "from the sweeps"
    if np.isfinite(amp).any():
        level, _ = np.unravel_index(np.nanargmax(amp), amp.shape)
        lines.append(
            f"mistuned ring ({study['n']} blades, {variant}): amplification {what} up to {np.nanmax(amp):.3f}"
            f" (sigma = {study['levels'][level]:g}), Whitehead's bound {study['whitehead']:.3f}"
        )
    else:
        lines.append(f"mistuned ring ({study['n']} blades, {variant}): no settled response, no amplification")
    return lines
