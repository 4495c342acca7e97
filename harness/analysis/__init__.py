"""From the FMU to steady states (layer above fmu): steady-state detection, plateaus, sweeps, the
fixed point, periodic orbits (shooting, continuation, Floquet), the harmonic balance and the executor
that runs tasks locally or on dask."""
