"""Validation: the same FMU in other FMI importers (importers/), compared; the cross-check
deliverables; the two-blade system example in fmpy and libcosim."""
