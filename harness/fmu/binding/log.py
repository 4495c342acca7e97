"""Log capture: what an FMU reports through its logger callback, one record per call."""

from __future__ import annotations

import collections
from dataclasses import dataclass
from typing import Callable, MutableSequence

from harness.fmu.binding.status import status_name


@dataclass(frozen=True)
class LogRecord:
    instance: str | None
    status: int
    category: str | None
    message: str | None

    def __str__(self) -> str:
        return f"[{status_name(self.status)}|{self.category}] {self.message}"


def decode(b: bytes | None) -> str | None:
    return None if b is None else b.decode("utf-8", "replace")


def new_log(limit: int | None) -> MutableSequence[LogRecord]:
    """A list (limit None: the robustness tests index and slice it) or a ring of the last `limit`
    records (long product runs)."""
    return [] if limit is None else collections.deque(maxlen=limit)


LogHook = Callable[[LogRecord], None]
