"""The ring's periodic steady states: its period map (period_map), Newton shooting and Floquet
multipliers (shooting), continuation in speed with bifurcations (continuation), seeds (seeds), the
ring's symmetries (symmetry) and all branches over a band (branches)."""
