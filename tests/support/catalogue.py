"""The invalid-input catalogue's records (tests/fmu/test_fmu_errors.py, tests/support/errors_me.py,
tests/support/errors_fmi3.py): a `Case` is one invalid situation driven on a fresh instance, its `Outcome`
the first non-OK status, the call that returned it and what the FMU logged. Cases that could hang or
corrupt the test process run in a child process (`python -m tests.fmu.test_fmu_errors --case ID` from the repository root)."""

from __future__ import annotations

import json
import os
import subprocess
import sys
from dataclasses import dataclass, field
from pathlib import Path
from typing import Callable

from tests.support import fmi2raw as F
from tests.support.fmi2raw import DISCARD, ERROR, OK, STATUS_NAMES, Fmi2Library, Instance

REPO = Path(__file__).resolve().parents[2]

REFUSED = (ERROR, DISCARD)
NULL_INSTANCE = -1  # pseudo status: fmi2Instantiate returned NULL
NOT_EXPORTED = -2  # pseudo status: the function is not exported (fine for model-exchange ones)
INT_MIN, INT_MAX = -(2**31), 2**31 - 1


@dataclass
class Outcome:
    status: int  # first non-OK status (OK if everything passed), or NULL_INSTANCE
    call: str  # the call that returned it
    log: list = field(default_factory=list)  # LogRecords logged during the case
    after: str = ""  # what happened afterwards (e.g. "a later doStep: Error")
    face: str = "fmi2"  # prefix of the status names (fmi3 for the FMI 3.0 entry points)

    @property
    def refused(self) -> bool:
        return self.status in REFUSED or self.status in (NULL_INSTANCE, NOT_EXPORTED)

    def status_text(self) -> str:
        if self.status == NULL_INSTANCE:
            return "NULL (no instance)"
        if self.status == NOT_EXPORTED:
            return "not exported"
        return self.face + STATUS_NAMES.get(self.status, str(self.status))

    def errors(self) -> list:
        return [r for r in self.log if r.status >= F.WARNING]

    def first_message(self) -> str:
        """The first Warning/Error message, else the first message that is not a call trace."""
        recs = self.errors() or [r for r in self.log if r.category != "logCalls"]
        return recs[0].message if recs and recs[0].message else ""


@dataclass
class Case:
    kind: str  # table group
    label: str  # the invalid input, as shown in the table
    run: Callable[[Fmi2Library], Outcome]
    expect: str = "refuse"  # refuse | accept | either
    name: str | None = None  # variable the message must name
    value: float | None = None  # value the message must show
    low: float | None = None  # range the message must show
    high: float | None = None
    needle: str | None = None  # a word the message must contain (instead of name/value)
    isolated: bool = False  # run in a child process (could hang or kill the process)

    @property
    def id(self) -> str:
        return f"{self.kind}: {self.label}"

    def outcome(self, lib: Fmi2Library) -> Outcome:
        if not self.isolated:
            return self.run(lib)
        if self.id not in _ISOLATED_CACHE:  # a child process each: run once per session
            _ISOLATED_CACHE[self.id] = _run_isolated(self.id)
        return _ISOLATED_CACHE[self.id]


_ISOLATED_CACHE: dict[str, Outcome] = {}


ISOLATED_TIMEOUT = 300.0  # [s] a hang guard only (a refused huge step returns at once)


def _run_isolated(case_id: str) -> Outcome:
    """Runs one case in a child process (`python -m tests.fmu.test_fmu_errors --case ID` from the repository root)."""
    proc = subprocess.run(
        [sys.executable, "-m", "tests.fmu.test_fmu_errors", "--case", case_id],
        capture_output=True,
        text=True,
        timeout=ISOLATED_TIMEOUT,
        env=os.environ.copy(),
        cwd=REPO,
    )
    if proc.returncode != 0:
        raise AssertionError(
            f"child process for {case_id!r} died with code {proc.returncode}:\n"
            f"{proc.stdout[-2000:]}\n{proc.stderr[-3000:]}"
        )
    d = json.loads(proc.stdout.strip().splitlines()[-1])
    return Outcome(d["status"], d["call"], [F.LogRecord(*r) for r in d["log"]], d["after"])


def _sequence(c: Instance, calls: list[tuple[str, Callable[[], int]]]) -> Outcome:
    """Runs the calls until one fails (a Warning is a success); the first failure or the last
    call with the worst success status."""
    worst, where = OK, calls[-1][0] if calls else ""
    for name, fn in calls:
        st = fn()
        if st not in (OK, F.WARNING):
            return Outcome(st, name, list(c.log))
        if st > worst:
            worst, where = st, name
    return Outcome(worst, where, list(c.log))
