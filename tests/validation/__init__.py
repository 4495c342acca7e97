"""Tests of the FMU against the reference and other importers."""
