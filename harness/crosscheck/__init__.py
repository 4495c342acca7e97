"""The same FMU in other FMI importers (importers/), compared; the cross-check deliverables."""
