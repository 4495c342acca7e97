"""Every default a command's `--help` states is the default it uses.

The stated value is read from the help text, "(default X)", "(default: X)" or "; default X)", and
compared with the value the command takes when the option is not given: the parser's default, or,
where the parser leaves None and the command resolves it (the mistuning study's size, `ring
--order`, `campbell --speed`), the resolved value. A default given in words ("none", "all", "number
of CPUs", "the installed package's", ...) is not a value; "none" must mean no value. A help that lies,
e.g. in harness/cli/ring.py

    -    g.add_argument("--points", type=int, default=26, ...
    +    g.add_argument("--points", type=int, default=25, ...

(help still "(default: 26)") fails test_stated_defaults_are_the_parsers: "ring --points: help says
'26', the default is 25".
"""

from __future__ import annotations

import argparse
import importlib
import json
import re
from pathlib import Path
from typing import Any

import pytest

from harness.cli.main import COMMANDS, _Parser, main

# defaults stated in words: what they mean is checked by the commands' own tests
WORDS = (
    "all",
    "every",
    "number of",
    "the ",
    "each",
    "no plot",
    "warnings",
    "--speeds",
    "t/160",
    "0.8x",
    "build/shroudedblade.fmu",
    "at most",
)
STATED = re.compile(r"(?:^|[(;,] ?)default:? ([^);]+)")
RESOLVED_IN_CODE = {("ring", "--order"), ("campbell", "--speed")}  # see test_defaults_resolved_in_code


def _parser(command: str) -> argparse.ArgumentParser:
    p = _Parser(prog=command)
    importlib.import_module(COMMANDS[command]).configure_parser(p)
    return p


def _stated(action: argparse.Action) -> str | None:
    """The default the help states, or None (none stated, or one in words). `--start-values`' help
    also names Fw0's default before its own: the last statement is the option's."""
    found = STATED.findall(action.help or "")
    if not found:
        return None
    text = found[-1].strip().rstrip(".").removesuffix(" of the checkout")
    if text.lower().startswith(WORDS):
        return None
    return text


def _same(stated: str, value: Any) -> bool:
    words = stated.split(",")[0].split()
    if words and words[-1] in ("s", "rpm"):
        words = words[:-1]  # a unit after the value
    if words and words[0].lower() == "none":
        return value is None or value == []
    values = value if isinstance(value, (list, tuple)) else [value]
    if len(words) != len(values):
        return False
    for w, v in zip(words, values):
        if isinstance(v, Path) or (isinstance(v, str) and "/" in w):
            if not str(v).endswith(w.removeprefix("./")):
                return False
        elif isinstance(v, (int, float)) and not isinstance(v, bool):
            if float(w) != float(v):
                return False
        elif str(v) != w:
            return False
    return True


def _mistuning_defaults() -> dict[str, Any]:
    from harness.cli.mistuning import study_from

    s = study_from(_parser("mistuning").parse_args([]))
    return {
        "--blades": s.n,
        "--levels": list(s.levels),
        "--patterns": s.patterns,
        "--parameter": s.parameter,
        "--seed": s.seed,
        "--points": s.points,
        "--rtol": s.rtol,
        "--max-time": s.max_time,
        "--variants": list(s.variants),
        "--state-patterns": s.state_patterns,
        "--search": s.search_budget,
    }


def _cases() -> list[tuple[str, argparse.Action]]:
    return [
        (c, a)
        for c in COMMANDS
        for a in _parser(c)._actions
        if a.option_strings and not isinstance(a, argparse._HelpAction)
    ]


def test_stated_defaults_are_the_parsers() -> None:
    from harness.cli.continuation import DEFAULT_CSV

    resolved = {("mistuning", k): v for k, v in _mistuning_defaults().items()}
    resolved["continue", "--output-file"] = str(DEFAULT_CSV)  # set in the command when --json is not given
    wrong, checked = [], 0
    for command, a in _cases():
        stated = _stated(a)
        if stated is None or (command, a.option_strings[0]) in RESOLVED_IN_CODE:
            continue
        value = resolved.get((command, a.option_strings[0]), a.default)
        if a.option_strings[0] == "--size":  # the help names the default size among the others
            continue
        checked += 1
        if not _same(stated, value):
            wrong.append(f"{command} {a.option_strings[0]}: help says {stated!r}, the default is {value!r}")
    assert not wrong, "\n".join(wrong)
    assert checked >= 60  # the statements were read (63 when written)


def test_the_default_sizes_are_the_stated_ones() -> None:
    sizes = {c: a.default for c, a in _cases() if a.option_strings[0] == "--size"}
    assert sizes == {"run": "default", "reproduce": "default", "bench": "default", "mistuning": "small"}
    for command, a in _cases():
        if a.option_strings[0] == "--size":
            # "small (default; ...)", "default (make run)" or "(default: default)"
            assert re.search(rf"\b{a.default} \((default|make run)|\(default: {a.default}\)", a.help), (command, a.help)


def test_defaults_resolved_in_code(capsys: pytest.CaptureFixture) -> None:
    # ring --order: "(default: 2)", resolved in the command
    assert main(["ring", "--blades", "2", "--master", "c", "--stop-time", "5e-3", "--json"]) == 0
    assert json.loads(capsys.readouterr().out)["order"] == 2
    assert "(default: 2)" in {a.option_strings[0]: a for a in _parser("ring")._actions}["--order"].help
    # campbell --speed: "(default 5000)"
    assert main(["campbell", "--modes", "2", "--json"]) == 0
    assert json.loads(capsys.readouterr().out)["speed_rpm"] == 5000.0
    assert "(default 5000)" in {a.option_strings[0]: a for a in _parser("campbell")._actions}["--speed"].help


def test_a_long_steady_state_study_is_announced():
    """24 blades with the engine on: the cost (rings x the measured CPU-minutes of a 24-blade ring) is
    announced with the way out; the make-run size is not. Between the two measured sizes the power law
    gives the geometric mean at 12 blades (the midpoint of 6 and 24 on a log scale)."""
    from harness.cli.mistuning import ENGINE_CPU_MIN, engine_cost_notice, engine_cpu_minutes, study_from

    assert engine_cost_notice(study_from(_parser("mistuning").parse_args([]))) is None
    big = study_from(_parser("mistuning").parse_args(["--blades", "24", "--patterns", "2", "--state-patterns", "1"]))
    rings = 1 + len(big.levels)
    note = engine_cost_notice(big)
    assert note is not None and "--state-patterns 0" in note
    per_ring = dict(ENGINE_CPU_MIN)
    assert f"about {rings * per_ring[24] / 60:.1f} CPU-hours" in note, note
    assert abs(engine_cpu_minutes(12) - (per_ring[6] * per_ring[24]) ** 0.5) < 1e-9 * per_ring[24]
    assert (
        engine_cost_notice(study_from(_parser("mistuning").parse_args(["--blades", "24", "--state-patterns", "0"])))
        is None
    )
