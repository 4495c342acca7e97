"""Tests of steady states, sweeps, periodic orbits and their branches."""
