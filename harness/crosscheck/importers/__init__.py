"""One module per FMI importer driven by the cross-check."""
