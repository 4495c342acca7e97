"""Argument parsing, one module per `python -m harness` command (main: the dispatcher)."""
