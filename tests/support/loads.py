"""Loads written in the tests, for BladeFMU.run's aero input (the aeroLoad path, the FMU's Fw0 = 0):
independent of the FMUs' built-in load code."""

from __future__ import annotations

import math

import numpy as np


class Sine:
    """f(t) = amplitude sin(omega t + lead) [N/m] and its time derivatives."""

    breakpoints = np.zeros(0)

    def __init__(self, amplitude: float, omega: float, lead: float = 0.0):
        self.amplitude, self.omega, self.lead = amplitude, omega, lead

    def __call__(self, t):
        return self.amplitude * np.sin(self.omega * np.asarray(t, dtype=float) + self.lead)

    def derivatives(self, t, order: int) -> np.ndarray:
        x = self.omega * np.atleast_1d(np.asarray(t, dtype=float)) + self.lead
        return np.array([self.amplitude * self.omega**j * np.sin(x + j * math.pi / 2) for j in range(order + 1)])
