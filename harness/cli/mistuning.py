"""Mistuning study of the ring: amplification of the largest blade amplitude against Whitehead's bound.

`python -m harness mistuning [--size small|cluster] [--blades N] [--levels 0.005 0.01 0.02 0.05]
[--patterns K] [--parameter EI|m0] [--seed S] [--stop-time S] [--variants friction open]
[--workers N | --scheduler ADDRESS] [--cache-dir DIR | --no-cache] [--out DIR] [--json]`. Each
pattern is one ring run at the tuned ring's resonance (harness/studies/mistuning.py), cached in its
own file, so an interrupted study resumes; the figures (PNG + CSV) go to --out.
"""
from __future__ import annotations

import argparse
import json
import math
from dataclasses import replace
from pathlib import Path

import numpy as np

from harness.analysis.executor import RESULTS_DIR
from harness.cli.sweep import add_execution_options, make_runner
from harness.model.params import ParameterError
from harness.studies import mistuning, mistuning_plots
from harness.studies.mistuning import PARAMETERS, SIZES, VARIANTS


def configure_parser(p: argparse.ArgumentParser) -> None:
    p.add_argument("--size", choices=SIZES, default="small",
                   help="small: 6 blades, 100 patterns per level (in make run); cluster: 24 blades, also the open ring")
    p.add_argument("--blades", type=int, metavar="N", help="blades in the ring (overrides --size)")
    p.add_argument("--levels", type=float, nargs="+", metavar="SIGMA", help="relative standard deviations")
    p.add_argument("--patterns", type=int, metavar="K", help="random patterns per level")
    p.add_argument("--parameter", choices=PARAMETERS, help="scattered blade parameter (default EI)")
    p.add_argument("--seed", type=int, help="pattern generator seed (default 1)")
    p.add_argument("--stop-time", type=float, metavar="S", help="simulated time per ring [s]")
    p.add_argument("--variants", nargs="+", choices=VARIANTS, help="friction (contacts as given), open (d = 1 m)")
    p.add_argument("--out", default=str(RESULTS_DIR / "mistuning"), metavar="DIR", help="figures and CSVs")
    p.add_argument("--json", action="store_true", help="print the study as JSON on stdout")
    add_execution_options(p)


def study_from(args: argparse.Namespace):
    s = SIZES[args.size]
    given = {"n": args.blades, "levels": tuple(args.levels) if args.levels else None, "patterns": args.patterns,
             "parameter": args.parameter, "seed": args.seed, "stop_time": args.stop_time,
             "variants": tuple(args.variants) if args.variants else None}
    s = replace(s, **{k: v for k, v in given.items() if v is not None})
    if not 2 <= s.n <= 10000:
        raise ParameterError(f"--blades {s.n} outside [2, 10000]")
    if s.patterns < 1:
        raise ParameterError(f"--patterns {s.patterns} must be >= 1")
    bad = [x for x in s.levels if not (math.isfinite(x) and 0 <= x <= 0.2)]
    if bad:
        raise ParameterError(f"--levels {bad[0]!r} outside [0, 0.2] (relative standard deviation)")
    if not (math.isfinite(s.stop_time) and s.stop_time > 0):
        raise ParameterError(f"--stop-time {s.stop_time!r} s must be > 0")
    return s


def run(args: argparse.Namespace) -> int:
    study = study_from(args)
    with make_runner(args) as runner:
        out = mistuning.run_study(study, runner, None if args.no_cache else Path(args.cache_dir))
    files = mistuning_plots.write(out, Path(args.out))
    out["files"] = [str(f) for f in files]
    if args.json:
        print(json.dumps(out))
        return 0
    report(out)
    return 0


def report(out: dict) -> None:
    """The study's summary on stdout (also used by `make run`)."""
    print(f"mistuning: N = {out['n']}, {out['speed_rpm']:.1f} rpm (tuned resonance), {out['patterns']} patterns per level, "
          f"{out['computed']} rings computed, {out['cached']} from the cache; Whitehead {out['whitehead']:.4f}")
    for v, r in out["variants"].items():
        if not r["tuned_settled"]:
            print(f"  {v:12s} the tuned ring does not settle (amplitudes still move by {r['settle_max']:.1e}, "
                  f"blades {r['tuned_spread']:.0e} apart): not periodic, no amplification")
            continue
        for s, a in zip(out["levels"], np.array(r["amplification"], dtype=float)):
            ok = a[~np.isnan(a)]
            print(f"  {v:12s} sigma {s:6.3f}: amplification mean {ok.mean():.4f}, max {ok.max():.4f}"
                  + (f" ({len(a) - len(ok)} patterns did not settle)" if len(ok) < len(a) else ""))
        print(f"  {v:12s} tuned amplitude {max(r['tuned']):.4e} m (blades within {r['tuned_spread']:.0e}), "
              f"settled to {r['settle_max']:.1e}, {r['unsettled']} rings not settled")
    print(f"  ShroudedBlade alone (rigid neighbour behind the gap): {out['single_blade']:.4e} m")
    print("figures:", ", ".join(out["files"]))
