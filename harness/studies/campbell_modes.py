"""Campbell diagram of the m-mode blade: the FMU's contact-free mode frequencies over speed, engine-order lines, crossings.

The frequencies are the FMU's outputs modeFrequency[1..m] (the m x m generalized eigenproblem of
K0(Omega) and M at the input rotorSpeed, docs/model.md) read at the start of a run at constant
speed, one run per speed. A crossing of mode i with engine order k is a root of
g(n) = f_i(n) - k n / 60: bracketed by a sign change on the speed grid and refined by brentq on
the FMU's frequency at that speed (to 1e-6 rpm), not read off the grid. More than one mode needs
the consistent formulation (the printed eq. 26 has one mode): `campbell_params` sets formulation 2
for m > 1 unless the caller chose one.
"""

from __future__ import annotations

import math
from dataclasses import asdict, dataclass
from pathlib import Path
from typing import Any, Mapping, Sequence

import numpy as np
import numpy.typing as npt
from scipy.optimize import brentq

from harness.files.tables import write_csv
from harness.fmu.blade import SPEED_RANGE
from harness.model.params import ParameterError, validate
from harness.studies import plots

MAX_MODES = 6
ORDERS = tuple(range(1, 9))  # engine orders drawn and crossed


@dataclass(frozen=True)
class Crossing:
    mode: int  # 1..m
    engine_order: int
    speed_rpm: float
    frequency_hz: float


@dataclass
class CampbellModes:
    modes: int
    speeds: np.ndarray  # [rpm], (n,)
    frequencies: np.ndarray  # [Hz], (n, m)
    crossings: list[Crossing]

    def as_dict(self) -> dict:
        return {
            "modes": self.modes,
            "speeds_rpm": self.speeds.tolist(),
            "frequencies_hz": self.frequencies.tolist(),
            "crossings": [asdict(c) for c in self.crossings],
        }


def check_modes(m: Any) -> int:
    if isinstance(m, bool) or not isinstance(m, (int, np.integer)) or not 1 <= int(m) <= MAX_MODES:
        raise ParameterError(f"modes = {m!r} outside the range [1, {MAX_MODES}]")
    return int(m)


def check_speed(n: Any, what: str = "speed") -> float:
    lo, hi = SPEED_RANGE
    if not (isinstance(n, (int, float, np.floating)) and math.isfinite(n) and lo <= n <= hi):
        raise ParameterError(f"{what} = {n!r} rpm outside the FMU's rotorSpeed range [{lo:g}, {hi:g}]")
    return float(n)


def campbell_params(params: Mapping[str, Any] | None, modes: int) -> dict[str, Any]:
    """The validated parameter set with `modes` = m (and formulation 2 for m > 1 unless given)."""
    p = dict(params or {})
    p["modes"] = check_modes(modes)
    if p["modes"] > 1:
        p.setdefault("formulation", 2)
    return validate(p, source="campbell")


def mode_frequencies(fmu: Any, params: Mapping[str, Any], speed_rpm: float) -> np.ndarray:
    """modeFrequency[1..m] [Hz] of the FMU at constant `speed_rpm` [rpm] (params from campbell_params)."""
    m = int(params["modes"])
    names = [f"modeFrequency[{i}]" for i in range(1, m + 1)]
    r = fmu.run(params, 1e-5, 1e-5, speed_rpm=float(speed_rpm), outputs=names)
    return np.array([float(r[k][0]) for k in names])


def campbell(
    fmu: Any,
    params: Mapping[str, Any],
    speeds: Sequence[float] | npt.NDArray[np.float64],
    orders: Sequence[int] = ORDERS,
) -> CampbellModes:
    """The frequencies on the speed grid and every crossing of a mode with an engine-order line inside it."""
    speeds = np.array([check_speed(float(n)) for n in speeds])
    freqs = np.array([mode_frequencies(fmu, params, n) for n in speeds])
    m = freqs.shape[1]
    found = []
    for i in range(m):
        for k in orders:
            g = freqs[:, i] - k * speeds / 60.0
            for j in np.nonzero((g[:-1] > 0.0) != (g[1:] > 0.0))[0]:  # a root on a grid point: once

                def gap(n: float, i: int = i, k: int = k) -> float:
                    return float(mode_frequencies(fmu, params, n)[i]) - k * n / 60.0

                n = float(brentq(gap, speeds[j], speeds[j + 1], xtol=1e-6, rtol=4 * np.finfo(float).eps))
                found.append(Crossing(i + 1, int(k), n, k * n / 60.0))
    found.sort(key=lambda c: (c.mode, c.engine_order))
    return CampbellModes(m, speeds, freqs, found)


def campbell_study(
    fmu: Any,
    out: Path,
    params: Mapping[str, Any],
    modes: int = 3,
    speed_range: tuple[float, float] = (0.0, 30000.0),
    points: int = 301,
) -> CampbellModes:
    """results/campbell_modes.csv (frequencies per speed, crossings in the header) and .png:
    modes 1..m (consistent formulation for m > 1, whatever params say), engine orders 1..8, over the
    FMU's whole speed range by default."""
    p = campbell_params(dict(params, formulation=2) if modes > 1 else params, modes)
    data = campbell(fmu, p, np.linspace(speed_range[0], speed_range[1], points))
    tab = np.zeros(len(data.speeds), dtype=[("speed", "f8")] + [(f"f{i}", "f8") for i in range(1, data.modes + 1)])
    tab["speed"] = data.speeds
    for i in range(data.modes):
        tab[f"f{i + 1}"] = data.frequencies[:, i]
    lines = [
        f"Campbell diagram, {data.modes} modes: FMU modeFrequency[i] [Hz] (contact-free) per speed [rpm];",
        "crossings f_i(n) = EO n / 60 (brentq on the FMU's frequencies):",
    ]
    lines += [
        f"mode {c.mode} EO {c.engine_order}: {c.speed_rpm:.4f} rpm, {c.frequency_hz:.4f} Hz" for c in data.crossings
    ]
    write_csv(out / "campbell_modes.csv", tab, "\n".join(lines))
    plot(out / "campbell_modes.png", data, int(p["engineOrder"]))
    return data


def plot(path: Path | str, data: CampbellModes, eo: int) -> Path:
    """The diagram (harness.studies.plots.campbell with every located crossing marked)."""
    return plots.campbell(
        path,
        data.speeds,
        data.frequencies,
        ORDERS,
        eo,
        math.nan,
        crossings=[(c.speed_rpm, c.frequency_hz, f"{c.speed_rpm:.0f}") for c in data.crossings],
        title=f"Campbell diagram: bending modes 1..{data.modes} (contact-free) and engine orders "
        f"{ORDERS[0]}..{ORDERS[-1]}, crossings located",
    )
