"""Independent numpy/scipy reference implementation of docs/model.md and docs/model-notes.md.

Written without reading the C sources and by other means than the product (root finding and
quadrature instead of closed forms where possible, an adaptive DOP853 hybrid simulation instead of
fixed-step RK4). It imports only the model's definitions (parameter validation, the contact's
constants, the Galerkin record), never the product's version of what it checks; what drives the
FMU against it is harness.validation (docs/layers.md). This
module only re-exports the public API of the parts: `blade` (Galerkin reduction), `contact` (normal
force, friction loop, describing functions by quadrature), `dynamics` (time simulation with located
events), `fixedpoint` (the paper's fixed point A(B) = B and the naive iteration's 2-cycle) and
`tracked` (the tracked-amplitude map at a harmonic-balance root).
"""

from __future__ import annotations

from harness.reference.blade import galerkin
from harness.reference.contact import (
    DF,
    ContactConsts,
    contact_consts,
    describing_function,
    jenkins_cycle_dissipation,
    loop_angles,
    loop_friction,
    loop_state,
    normal_force,
    regime,
)
from harness.reference.dynamics import OUTPUT_DTYPE, SimulationError, jenkins_prescribed, simulate
from harness.reference.fixedpoint import (
    FixedPointResult,
    FixedPointRoot,
    PiecewiseStepper,
    SteadyState,
    finite_horizon_amplitude,
    fixed_point,
    naive_iteration,
    steady_amplitude,
)
from harness.reference.tracked import tracked_map_radius, tracked_radii

__all__ = [
    "galerkin",
    "DF",
    "ContactConsts",
    "contact_consts",
    "describing_function",
    "jenkins_cycle_dissipation",
    "loop_angles",
    "loop_friction",
    "loop_state",
    "normal_force",
    "regime",
    "OUTPUT_DTYPE",
    "SimulationError",
    "jenkins_prescribed",
    "simulate",
    "FixedPointResult",
    "FixedPointRoot",
    "SteadyState",
    "finite_horizon_amplitude",
    "fixed_point",
    "naive_iteration",
    "steady_amplitude",
    "PiecewiseStepper",
    "tracked_map_radius",
    "tracked_radii",
]
