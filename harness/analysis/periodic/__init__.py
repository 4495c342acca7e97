"""Periodic steady states of the FMU: shooting, Floquet stability and continuation in speed.

period_map (the FMU over one excitation period) -> shooting (Newton, multipliers, labels) ->
continuation (branches in rotor speed through folds) -> search (every orbit at a speed: harmonic
balance seeds and the fixed-B orbits scanned in B) -> branches (a study's curve: all its branches).
"""

from harness.analysis.periodic.continuation import Branch, BranchPoint, ContinuationSettings, continue_branch
from harness.analysis.periodic.period_map import MODELS, PeriodMap, ShootingSettings
from harness.analysis.periodic.shooting import Orbit, classify, shoot

__all__ = [
    "MODELS",
    "Branch",
    "BranchPoint",
    "ContinuationSettings",
    "Orbit",
    "PeriodMap",
    "ShootingSettings",
    "classify",
    "continue_branch",
    "shoot",
]
