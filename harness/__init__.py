"""ShroudedBlade harness: drive the FMU with fmpy, sweep, reproduce the paper, validate."""
