"""From the FMU to steady states: steady-state detection, plateaus, sweeps, the fixed point, periodic
orbits (shooting, continuation, Floquet) and the executor that runs tasks locally or on dask."""
