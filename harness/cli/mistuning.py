"""Mistuning study of the ring over a speed band: amplification of the largest blade amplitude against Whitehead's bound.

`python -m harness mistuning [--size small|cluster] [--blades N] [--levels SIGMA ...] [--patterns K]
[--parameter EI|m0] [--seed S] [--points K] [--band FROM TO] [--rtol R] [--max-time S] [--variants ...]
[--workers N | --scheduler ADDRESS] [--cache-dir DIR | --no-cache] [--out DIR] [--json]`. Each
(variant, pattern) is one sweep of the ring over the band (harness/studies/mistuning.py), cached in
its own file, so an interrupted study resumes; the figures (PNG + CSV) go to --out.
"""

from __future__ import annotations

import argparse
import json
import math
import sys
from dataclasses import replace
from pathlib import Path
from typing import Any

from harness.analysis.executor import Runner
from harness.paths import RESULTS_DIR
from harness.cli.options import add_execution_options, make_runner
from harness.cli.reports import mistuning_report
from harness.model.params import ParameterError
from harness.outputs import check_dir
from harness.studies import mistuning, mistuning_plots
from harness.studies.mistuning import CROSSING_BAND, PARAMETERS, SIZES, VARIANTS

_S = SIZES["small"]


def configure_parser(p: argparse.ArgumentParser) -> None:
    c = SIZES["cluster"]
    p.add_argument(
        "--size",
        choices=SIZES,
        default="small",
        help=f"small (default; in make run): {_S.n} blades, levels {' '.join(map(str, _S.levels))}, "
        f"{_S.patterns} patterns per level, {_S.points} speeds, {' '.join(_S.variants)}; cluster: "
        f"{c.n} blades, {len(c.levels)} levels x {c.patterns} patterns, {c.points} speeds, "
        f"{' '.join(c.variants)}. The options below override it",
    )
    p.add_argument("--blades", type=int, metavar="N", help=f"blades in the ring (default {_S.n})")
    p.add_argument(
        "--levels",
        type=float,
        nargs="+",
        metavar="SIGMA",
        help=f"relative standard deviations, in [0, 0.2] (default {' '.join(map(str, _S.levels))})",
    )
    p.add_argument("--patterns", type=int, metavar="K", help=f"random patterns per level (default {_S.patterns})")
    p.add_argument("--parameter", choices=PARAMETERS, help=f"scattered blade parameter (default {_S.parameter})")
    p.add_argument("--seed", type=int, metavar="S", help=f"pattern generator seed (default {_S.seed})")
    p.add_argument("--points", type=int, metavar="K", help=f"speeds across the band (default {_S.points})")
    p.add_argument(
        "--band",
        type=float,
        nargs=2,
        metavar=("FROM", "TO"),
        help=f"speed band [rpm] (default {CROSSING_BAND[0]:g}x to {CROSSING_BAND[1]:g}x the contact-free "
        "crossing: %.0f to %.0f rpm)" % mistuning.band(_S),
    )
    p.add_argument(
        "--rtol",
        type=float,
        metavar="R",
        help="settled: every blade's per-period amplitude change / the largest amplitude below this over "
        f"5 periods (default {_S.rtol:g})",
    )
    p.add_argument(
        "--max-time",
        type=float,
        metavar="S",
        help=f"simulated time at most at one speed [s]; a speed not settled by then is flagged "
        f"(default {_S.max_time:g})",
    )
    p.add_argument(
        "--variants",
        nargs="+",
        choices=VARIANTS,
        help=f"friction (contacts as given), frictionless (mu = 0), open (d = 1 m) (default {' '.join(_S.variants)})",
    )
    p.add_argument(
        "--state-patterns",
        type=int,
        metavar="K",
        help="patterns per level also taken to the ring's periodic-orbit engine: each ring's largest "
        "stable steady state over the band and the amplification on it, beside the sweep's "
        f"(default {_S.state_patterns}; 0: the sweeps only)",
    )
    p.add_argument(
        "--search",
        type=int,
        metavar="RINGS",
        help="search the worst pattern at the largest level on stable steady states (a compass search "
        "from the worst of --state-patterns, or of the sweeps if none), with this budget of rings "
        f"(default {_S.search_budget}, no search)",
    )
    p.add_argument(
        "--out",
        default=str(RESULTS_DIR / "mistuning"),
        metavar="DIR",
        help=f"figures and CSVs (default ./{RESULTS_DIR / 'mistuning'})",
    )
    p.add_argument("--json", action="store_true", help="print the study as JSON on stdout")
    add_execution_options(p, fmu=False)  # the ring's FMUs, not a --fmu of the user's


def study_from(args: argparse.Namespace) -> mistuning.Study:
    s = SIZES[args.size]
    given = {
        "n": args.blades,
        "levels": tuple(args.levels) if args.levels else None,
        "patterns": args.patterns,
        "parameter": args.parameter,
        "seed": args.seed,
        "rtol": args.rtol,
        "max_time": args.max_time,
        "points": args.points,
        "state_patterns": args.state_patterns,
        "search_budget": args.search,
        "band": tuple(args.band) if args.band else None,
        "variants": tuple(args.variants) if args.variants else None,
    }
    s = replace(s, **{k: v for k, v in given.items() if v is not None})
    if not 2 <= s.n <= 10000:
        raise ParameterError(f"--blades {s.n} outside [2, 10000]")
    if s.patterns < 1:
        raise ParameterError(f"--patterns {s.patterns} must be >= 1")
    if s.points < 2:
        raise ParameterError(f"--points {s.points} must be >= 2")
    if not 0 <= s.state_patterns <= s.patterns:
        raise ParameterError(f"--state-patterns {s.state_patterns} outside [0, --patterns = {s.patterns}]")
    if s.search_budget < 0:
        raise ParameterError(f"--search {s.search_budget}: a number of rings >= 0")
    if s.band is not None and not (all(math.isfinite(x) for x in s.band) and 0 < s.band[0] < s.band[1]):
        raise ParameterError(f"--band {s.band[0]!r} {s.band[1]!r} rpm: need 0 < FROM < TO")
    bad = [x for x in s.levels if not (math.isfinite(x) and 0 <= x <= 0.2)]
    if bad:
        raise ParameterError(f"--levels {bad[0]!r} outside [0, 0.2] (relative standard deviation)")
    if not (math.isfinite(s.rtol) and 0 < s.rtol < 1):
        raise ParameterError(f"--rtol {s.rtol!r} outside (0, 1)")
    if not (math.isfinite(s.max_time) and s.max_time > 0):
        raise ParameterError(f"--max-time {s.max_time!r} s must be > 0")
    return s


# the periodic-orbit engine over the study's band, CPU-minutes per ring (one thread): 6 blades 8.5-17.5, 14 on
# average (make run's three rings, 39-80 branches each); 24 blades 17.8-23.0, 20.5 on average (the 24-blade study's five rings,
# 3-6 branches each: fewer branches offset the dearer periods). A power law through the two for other sizes.
ENGINE_CPU_MIN = ((6, 14.0), (24, 20.5))


def engine_cpu_minutes(n: int) -> float:
    """The engine's CPU-minutes for one ring of n blades over the study's band (ENGINE_CPU_MIN)."""
    (n0, c0), (n1, c1) = ENGINE_CPU_MIN
    return float(c0 * (n / n0) ** (math.log(c1 / c0) / math.log(n1 / n0)))


def engine_cost_notice(study: mistuning.Study) -> str | None:
    """A warning when the study's rings on steady states will take more than an hour of CPU (None if not)."""
    rings = (1 + len(study.levels) * study.state_patterns) * len(study.variants) + study.search_budget
    if study.state_patterns == 0 and study.search_budget == 0:
        return None
    cpu_h = rings * engine_cpu_minutes(study.n) / 60
    if cpu_h < 1.0:
        return None
    return (
        f"note: {rings} rings of {study.n} blades on steady states (--state-patterns {study.state_patterns}, "
        f"--search {study.search_budget}): about {cpu_h:.1f} CPU-hours ({engine_cpu_minutes(study.n):.1f} CPU-minutes per "
        f"{study.n}-blade ring, from the engine's cost measured at 6 and 24 blades); --state-patterns 0 runs the sweeps only"
    )


def run(args: argparse.Namespace) -> int:
    study = study_from(args)
    notice = engine_cost_notice(study)
    if notice:
        print(notice, file=sys.stderr)
    cache = None if args.no_cache else check_dir(args.cache_dir, "--cache-dir")  # before any work
    out_dir = check_dir(args.out, "--out")
    with make_runner(args) as runner:
        out = run_and_write(study, runner, cache, out_dir)
    if args.json:
        print(json.dumps(out))
        return 0
    mistuning_report(out)
    return 0


def run_and_write(study: mistuning.Study, runner: Runner, cache: Path | None, out_dir: Path) -> dict[str, Any]:
    """The sweeps of every ring, then (study.state_patterns > 0) the steady states of the tuned ring
    and those patterns, then (study.search_budget > 0) the worst-pattern search; figures and CSVs into
    out_dir. The output of run_study with "states" and "search" added."""
    out = mistuning.run_study(study, runner, cache)
    files = mistuning_plots.write(out, out_dir)
    if study.state_patterns or study.search_budget:
        from harness.studies import mistuning_states, mistuning_states_plots  # the engine: only when asked

        settings = mistuning_states.StatesSettings()
        cdir = cache / "states" if cache else None
        variant = "friction" if "friction" in study.variants else study.variants[0]
        out["states"] = mistuning_states.run_states(study, settings, runner, cdir, variant)
        if study.search_budget:
            sweep_amp = out["variants"][variant]["amplification"][-1]
            out["search"] = mistuning_states.run_search(study, out["states"], settings, runner, cdir, sweep_amp)
        files += mistuning_states_plots.write(out["states"], out, out_dir, out.get("search"))
    out["files"] = [str(f) for f in files]
    return out
