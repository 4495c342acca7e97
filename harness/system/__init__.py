"""The bladed disk (layer above analysis): a ring of blade and contact FMUs in a co-simulation
(fmpy master, its loop in C, libcosim, SSP), and its energy books."""
