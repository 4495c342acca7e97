"""The error a bad study or run configuration raises (a ParameterError: the CLI prints it as one
line, naming the value)."""

from __future__ import annotations

from harness.model import params as _params


class ConfigError(_params.ParameterError):
    """A study/run configuration value is not acceptable; the message names it."""
