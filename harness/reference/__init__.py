"""Independent numpy/scipy reference implementation of docs/model.md and docs/model-notes.md.

Written without reading the C sources and by other means (root finding and quadrature instead of
closed forms where possible, an adaptive DOP853 hybrid simulation instead of fixed-step RK4). This
module only re-exports the public API of the parts: `reference_blade` (Galerkin reduction),
`reference_contact` (normal force, friction loop, describing functions), `reference_dynamics`
(time simulation with located events), `reference_hb` (harmonic balance) and
`reference_fixedpoint` (the paper's fixed point A(B) = B and the naive iteration's 2-cycle).
"""
from __future__ import annotations

from harness.reference.blade import Galerkin, galerkin
from harness.reference.contact import (DF, ContactConsts, contact_consts, describing_function,
                                       jenkins_cycle_dissipation, loop_angles, loop_friction, loop_state, normal_force,
                                       regime)
from harness.reference.dynamics import OUTPUT_DTYPE, SimulationError, jenkins_prescribed, simulate
from harness.reference.fixedpoint import (FixedPointResult, FixedPointRoot, PiecewiseStepper, SteadyState,
                                          finite_horizon_amplitude, fixed_point, naive_iteration, steady_amplitude)
from harness.reference.hb import HBSolution, harmonic_balance, stability, tracked_map_radius

__all__ = [
    "Galerkin", "galerkin", "DF", "ContactConsts", "contact_consts", "describing_function", "jenkins_cycle_dissipation", "loop_angles",
    "loop_friction", "loop_state", "normal_force", "regime", "OUTPUT_DTYPE", "SimulationError",
    "jenkins_prescribed", "simulate", "HBSolution", "harmonic_balance", "FixedPointResult", "FixedPointRoot",
    "SteadyState", "finite_horizon_amplitude", "fixed_point", "naive_iteration", "steady_amplitude",
    "PiecewiseStepper", "stability", "tracked_map_radius",
]
