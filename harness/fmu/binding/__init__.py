"""The project's one FMI binding (ctypes): signature tables for FMI 2.0 (co-simulation and model
exchange) and FMI 3.0 (co-simulation), a loaded binary (`Library`), instances with their callbacks
and log capture (`Fmi2Instance`, `Fmi3Instance`), and statuses turned into `FmiError` (or returned
as they are in raw mode). fmpy stays the tool for model descriptions, extraction and simulate_fmu."""

from harness.fmu.binding.log import LogRecord
from harness.fmu.binding.status import (
    DISCARD,
    ERROR,
    FATAL,
    OK,
    PENDING,
    STATUS_NAMES,
    VALID_STATUSES,
    WARNING,
    FmiError,
    status_name,
)

__all__ = [
    "DISCARD",
    "ERROR",
    "FATAL",
    "OK",
    "PENDING",
    "STATUS_NAMES",
    "VALID_STATUSES",
    "WARNING",
    "FmiError",
    "LogRecord",
    "status_name",
]
