"""System-level examples: several FMUs coupled in a co-simulation."""
