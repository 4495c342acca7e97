"""The model's inputs: parameter sets with validation (params) and the aerodynamic excitation (excitation)."""
