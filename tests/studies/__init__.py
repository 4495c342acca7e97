"""Tests of the paper's studies and the mistuning study."""
