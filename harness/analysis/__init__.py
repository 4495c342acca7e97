"""From the FMU to steady states (layer above fmu): steady-state detection, periodic orbits
(shooting, continuation, Floquet), the harmonic balance and its curves, the point cache and the
executor that runs tasks locally or on dask."""
