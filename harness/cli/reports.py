"""What the study commands print, shared by the commands that run the same study (`reproduce` and
`run`: the paper's studies; `mistuning` and `run`: the mistuning study)."""

from __future__ import annotations

import argparse
import math
import time
from pathlib import Path
from typing import Any, Sequence

import numpy as np

from harness.cli.options import make_runner
from harness.outputs import check_dir
from harness.studies.claims import tally, verdict_counts, write_claims
from harness.studies.paper import STUDIES, Reproduction, validate_request
from harness.validation.reproduction import reproduce


def reproduce_and_report(
    args: argparse.Namespace, size: str, studies: Sequence[str] | None, extras: bool
) -> Reproduction:
    """The paper's studies into --out (harness.validation.reproduction: with Fig. 2), their peaks and
    the claims tally on stdout; the reproduction with its claim rows."""
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
            print(
                f"  {STUDIES[name].label(r.value):<18s} {r.fp_peak * 1e3:8.5f} mm at {r.fp_speed:6.0f} rpm"
                f" (fixed point, {jump}), {r.jenkins_peak * 1e3:8.5f} mm at"
                f" {r.jenkins_speed:6.0f} rpm (Jenkins), {r.hb_peak * 1e3:8.5f} mm at {r.hb_speed:6.0f} rpm (HB)"
            )
    print(f"claims: {tally(verdict_counts(rows))} -> {out / 'claims.md'}")
    print(f"wall time {wall:.1f} s; results in {out}/")
    rep.claims = rows
    return rep


def mistuning_report(out: dict[str, Any]) -> None:
    """The mistuning study's summary on stdout."""
    sp = out["speeds_rpm"]
    print(
        f"mistuning: N = {out['n']}, {len(sp)} speeds {sp[0]:.0f}-{sp[-1]:.0f} rpm (contact-free crossing "
        f"{out['crossing_rpm']:.0f} rpm), {out['patterns']} patterns per level, {out['computed']} sweeps computed "
        f"in {out['wall_s']:.1f} s, {out['cached']} from the cache; Whitehead {out['whitehead']:.4f}"
    )
    for v, r in out["variants"].items():
        edge = " AT THE BAND'S EDGE" if r["tuned_peak_at_edge"] else ""
        print(
            f"  {v:12s} tuned peak {r['tuned_peak_m']:.4e} m at {r['tuned_peak_rpm']:.0f} rpm{edge}; "
            f"{r['unsettled_points']} of {r['points']} points not settled"
        )
        for s, a in zip(out["levels"], np.array(r["amplification"], dtype=float)):
            ok = a[~np.isnan(a)]
            text = f"mean {ok.mean():.4f}, max {ok.max():.4f}" if len(ok) else "none settled"
            print(
                f"  {v:12s} sigma {s:6.3f}: amplification {text}"
                + (f" ({len(a) - len(ok)} patterns without a settled point)" if len(ok) < len(a) else "")
            )
    st = out.get("states")
    if st:
        print(
            f"  steady states (largest stable, {st['rings']} rings, {st['evaluations']} periods simulated, "
            f"{st['wall_s']:.1f} s): tuned {st['tuned_peak_m']:.4e} m at {st['tuned_peak_rpm']:.0f} rpm"
        )
        for s, a in zip(out["levels"], np.array(st["amplification"], dtype=float)):
            ok = a[~np.isnan(a)]
            print(
                f"  {'':12s} sigma {s:6.3f}: amplification on steady states "
                + (f"mean {ok.mean():.4f}, max {ok.max():.4f} over {len(ok)} patterns" if len(ok) else "none")
            )
    se = out.get("search")
    if se:
        print(
            f"  worst pattern found at sigma {se['sigma']:g}: amplification {se['amplification']:.4f} "
            f"({se['rings']} rings from pattern {se['start_pattern']}, the {se['start_from']}' worst: "
            f"{se['start_amplification']:.4f}); Whitehead {se['whitehead']:.4f}"
        )
    print("figures:", ", ".join(out["files"]))
