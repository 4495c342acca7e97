"""How the harness writes its files, kept outside the layers (like harness.paths and
harness.outputs) so that every layer shares it: `atomic` (a file replaced in one step), `tables`
(a simulation result as CSV with units), `figures` (matplotlib set up once, PNGs written atomically)."""
