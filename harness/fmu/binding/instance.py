"""What FMI 2.0 and FMI 3.0 instances share: the log, the status of the last call, the check that
turns a failed status into FmiError (checked mode) or lets it through (raw mode), and freeing."""

from __future__ import annotations

from typing import Any, Callable, MutableSequence

from harness.fmu.binding.library import Library
from harness.fmu.binding.log import LogHook, LogRecord, new_log
from harness.fmu.binding.status import FmiError


class Instance:
    """`c` is the instance pointer (None once freed), `log` its LogRecords (all, the last
    `log_limit`, or the sequence passed as `log`), `status` the status of the last call made
    through the methods; `on_log` sees each record, `on_call(function, status)` each call."""

    FREE = ""  # the free function of the FMI version (fmi2FreeInstance, fmi3FreeInstance)

    def __init__(
        self,
        lib: Library,
        raw: bool,
        log: MutableSequence[LogRecord] | None,
        log_limit: int | None,
        on_log: LogHook | None,
        on_call: Callable[[str, int], None] | None,
    ):
        self.lib, self.raw = lib, raw
        self.log = new_log(log_limit) if log is None else log
        self.on_log, self.on_call = on_log, on_call
        self.status = 0
        self.c: int | None = None

    def _append(self, rec: LogRecord) -> None:
        self.log.append(rec)
        if self.on_log is not None:
            self.on_log(rec)

    def last_message(self) -> str | None:
        return self.log[-1].message if self.log else None

    def check(self, function: str, status: int) -> int:
        """Record `status` of `function`; raise FmiError for a failure unless in raw mode."""
        self.status = status
        if self.on_call is not None:
            self.on_call(function, status)
        if (status < 0 or status > 1) and not self.raw:  # status.failed, inlined: every call passes here
            raise FmiError(function, status, self.last_message())
        return status

    @property
    def ok(self) -> bool:
        return bool(self.c)

    def free_instance(self) -> None:
        if self.c:
            getattr(self.lib, self.FREE)(self.c)
            self.c = None

    def abandon(self) -> None:
        """Forget the instance without freeing it (after Fatal no call is allowed, FMI 2.0 s.2.1.3)."""
        self.c = None

    def __enter__(self) -> "Instance":
        return self

    def __exit__(self, *exc: Any) -> None:
        self.free_instance()

    def __del__(self) -> None:
        try:
            self.free_instance()
        except Exception:
            pass
