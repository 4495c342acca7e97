"""Tests of the ring of blades and its masters."""
