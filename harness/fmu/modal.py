"""The FMU's modal Jacobian (docs/model.md s.2a): the local variables sensitivity[r,c] of
ShroudedBlade with sensitivities = true, their value references, and the monodromy sub-matrix of
an m-mode blade.

Rows r = 1..15: modalDisplacement[1..6], modalVelocity[1..6], jenkinsForce, runningMaximum,
amplitude. Columns c = 1..14: the start values of modalDisplacement[1..6], modalVelocity[1..6],
jenkinsForce, and the parameter B. Entries of modes above m are 0."""

from __future__ import annotations

import numpy as np

from harness.model import params


def _shape() -> tuple[int, int]:
    """(rows, columns) of the sensitivity[r,c] the model description declares."""
    rc = [
        tuple(map(int, n[len("sensitivity[") : -1].split(",")))
        for n in params.value_references()
        if n.startswith("sensitivity[")
    ]
    return max(r for r, _ in rc), max(c for _, c in rc)


ROWS, COLS = _shape()  # 15, 14
MODES_MAX = int(params.specs()["modes"].high)  # the largest number of modes, 6
ROW_JENKINS_FORCE, ROW_RUNNING_MAXIMUM, ROW_AMPLITUDE = 12, 13, 14  # 0-based
COL_JENKINS_FORCE, COL_B = 12, 13


def name(r: int, c: int) -> str:
    """The variable name of entry (r, c), 1-based."""
    return f"sensitivity[{r},{c}]"


def value_references() -> list[int]:
    """The 210 value references in row-major order (reshape the values to (ROWS, COLS)), from the
    model description."""
    return [params.value_reference(name(r, c)) for r in range(1, ROWS + 1) for c in range(1, COLS + 1)]


def state_indices(m: int) -> list[int]:
    """0-based rows (= columns) of the unknowns (q_1..q_m, q_1'..q_m', F) of an m-mode blade."""
    if not (isinstance(m, int) and 1 <= m <= MODES_MAX):
        raise ValueError(f"modes = {m!r} must be an integer in [1, {MODES_MAX}]")
    return list(range(m)) + [MODES_MAX + i for i in range(m)] + [ROW_JENKINS_FORCE]


def monodromy(J: np.ndarray, m: int) -> np.ndarray:
    """The (2m+1) x (2m+1) Jacobian of the period map in (q_1..q_m, q_1'..q_m', F) from the full
    (ROWS, COLS) matrix J read after one period."""
    J = np.asarray(J, dtype=float).reshape(ROWS, COLS)
    idx = state_indices(m)
    return J[np.ix_(idx, idx)]
