"""Every option of every command that takes a value says its default (or that it is required) in
`--help`, and no help shows a raw metavar (an option name in capitals, argparse's fallback)."""
from __future__ import annotations

import argparse
import importlib

import pytest

from harness.cli.main import COMMANDS, _Parser
from harness.paths import IN_CHECKOUT

OWN = ["simulate", "periodic", "continue", "sweep", "run", "reproduce", "validate", "crosscheck", "bench", "ring"]


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
