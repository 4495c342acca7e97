"""Status codes shared by FMI 2.0 and FMI 3.0 (fmi2Status/fmi3Status have the same values), and the
exception a checked call raises when the FMU does not return OK or Warning."""

from __future__ import annotations

OK, WARNING, DISCARD, ERROR, FATAL, PENDING = 0, 1, 2, 3, 4, 5
STATUS_NAMES = {OK: "OK", WARNING: "Warning", DISCARD: "Discard", ERROR: "Error", FATAL: "Fatal", PENDING: "Pending"}
VALID_STATUSES = frozenset(STATUS_NAMES)


def status_name(status: int) -> str:
    """'Error' for 3; the number itself for a value no FMI status has (a misbehaving FMU)."""
    return STATUS_NAMES.get(status, str(status))


class FmiError(RuntimeError):
    """An FMI call returned Discard, Error, Fatal or Pending (or instantiation returned NULL).
    `function` is the FMI function, `status` its return value, `message` the FMU's last logged
    message of this instance (None if it logged nothing)."""

    def __init__(self, function: str, status: int, message: str | None):
        self.function, self.status, self.message = function, status, message
        said = f": {message}" if message else " (the FMU logged nothing)"
        super().__init__(f"{function} returned {status_name(status)}{said}")


def failed(status: int) -> bool:
    """Statuses a checked call raises on: anything but OK and Warning."""
    return status != OK and status != WARNING
