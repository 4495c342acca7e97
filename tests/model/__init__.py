"""Tests of the model's definitions (parameters, excitation, Galerkin constants)."""
