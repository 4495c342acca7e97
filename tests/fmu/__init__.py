"""Tests of the FMUs through the FMI binding, fmpy and C importers."""
