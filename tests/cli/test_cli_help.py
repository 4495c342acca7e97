"""Every option of every command that takes a value says its default (or that it is required) in
`--help`, and no help shows a raw metavar (an option name in capitals, argparse's fallback). The
top-level `--help` and `--version` import no command module and none of numpy, scipy, fmpy or
matplotlib (what made them take a second); every way to run the harness from the shell is a command
of `python -m harness` (no module of the package runs as a script of its own)."""

from __future__ import annotations

import argparse
import importlib
import json
import re
import subprocess
import sys
from importlib import metadata
from pathlib import Path

import pytest

from harness.cli.main import COMMANDS, _Parser
from harness.paths import IN_CHECKOUT

OWN = list(COMMANDS)
PACKAGE = Path(__file__).resolve().parents[2] / "harness"
HEAVY = ("numpy", "scipy", "fmpy", "matplotlib")


def _options(command: str) -> list[argparse.Action]:
    p = _Parser(prog=command)
    importlib.import_module(COMMANDS[command]).configure_parser(p)
    return [a for a in p._actions if a.option_strings and a.nargs != 0 and not isinstance(a, argparse._HelpAction)]


@pytest.mark.parametrize("command", OWN)
def test_every_value_option_states_its_default(command):
    if command in ("crosscheck", "bench"):
        assert IN_CHECKOUT  # these run in a checkout only; the tests always do
    for a in _options(command):
        text = (a.help or "").lower()
        assert a.required or "default" in text or "required" in text, f"{command} {a.option_strings[0]}: {a.help!r}"
        raw = a.dest.upper()
        assert a.metavar is not None or a.choices is not None, f"{command} {a.option_strings[0]} shows {raw}"


@pytest.mark.parametrize("flag", ["--help", "--version"])
def test_top_level_loads_no_numerics(flag):
    """The modules loaded by `python -m harness FLAG`, listed by the child process itself."""
    code = (
        "import sys\nfrom harness.cli.main import main\ntry:\n    main([sys.argv[1]])\nexcept SystemExit:\n    pass\n"
        "print('MODULES=' + __import__('json').dumps(sorted(sys.modules)))"
    )
    proc = subprocess.run([sys.executable, "-c", code, flag], capture_output=True, text=True, timeout=120)
    loaded = json.loads(proc.stdout.rsplit("MODULES=", 1)[1])
    heavy = [m for m in loaded if m.split(".")[0] in HEAVY]
    assert not heavy, f"{flag} imports {heavy[:5]}"
    commands = [m for m in loaded if m in COMMANDS.values()]
    assert not commands, f"{flag} imports the command modules {commands}"
    if flag == "--version":
        assert proc.stdout.split("MODULES=")[0].split()[-1] == metadata.version("shroudedblade-harness"), proc.stdout


def test_every_command_is_listed_and_no_module_runs_as_a_script():
    proc = subprocess.run([sys.executable, "-m", "harness", "--help"], capture_output=True, text=True, timeout=120)
    for name in COMMANDS:
        assert re.search(rf"^\s+{re.escape(name)}\s", proc.stdout, re.M), f"{name} not in --help:\n{proc.stdout}"
    scripts = [
        str(f.relative_to(PACKAGE))
        for f in PACKAGE.rglob("*.py")
        if re.search(r"__name__\s*==\s*[\"']__main__[\"']", f.read_text())
    ]
    assert not scripts, f"modules with their own entry point: {scripts} (make them a command of harness/cli)"
