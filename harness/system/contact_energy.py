"""The contact's stored energy in a ring of Jenkins contacts: the piece of the energy books that both
the balance (energy.py) and the energy-conserving master (ring_conserving.py) need."""

from __future__ import annotations

import math

import numpy as np

from harness.model.contact import ContactConsts
from harness.system.ring import Ring


def require_jenkins(ring: Ring) -> None:
    """The spring energy below is the Jenkins element's (frictionModel 3, the default)."""
    if int(dict(ring.contact).get("frictionModel", 3)) != 3:
        raise ValueError("the ring energy books need the time-domain Jenkins contact (frictionModel 3)")


def spring_energy(cc: ContactConsts, q: np.ndarray, force_b: np.ndarray) -> np.ndarray:
    """Contact spring energy per row of q (rows: time, columns: blades), summed over the contacts;
    cc = contact_consts(ring.contact)."""
    cg, sg = math.cos(cc.gamma), math.sin(cc.gamma)
    u = q - np.roll(q, -1, axis=1)  # contact j: u_j = q_j - q_{j+1}
    pen = np.maximum(np.abs(u) - cc.d, 0.0)
    fn = cc.kn * cg * np.sign(u) * pen  # eq. 3 (0 when open)
    ff = (force_b - fn * cg) / sg  # F_c = F_n cos g + F_f sin g (eq. 14), forceB = +F_c
    return (0.5 * cc.kn * cg * cg * pen**2 + ff**2 / (2 * cc.kd)).sum(axis=1)
