"""Tests of the repository as a whole: docs, layers, lint, types, packaging, quoted numbers."""
