"""Fig. 2 of the paper: the FMU's friction loop against the reference's.

The loop of eq. 4 at the FMU's steady amplitude B (harness.reference.contact) against (a) the
reference Jenkins element driven by v = B cos(theta) (harness.reference.dynamics) and (b) the FMU's
time-domain element (frictionModel 3) in a steady run. harness.validation.reproduction runs it
with the paper's other studies.
"""

from __future__ import annotations

import math
from pathlib import Path
from typing import Any, Mapping

import numpy as np

from harness import reference as ref
from harness.analysis.curves import omega_of
from harness.files.tables import write_csv
from harness.model import params as _params
from harness.studies import plots
from harness.studies.paper import HysteresisLoop

PI = math.pi


def _loop_area(x: np.ndarray, F: np.ndarray) -> float:
    """|closed integral F dx| (trapezoid) of a sampled loop, closed from the last to the first point."""
    xc, Fc = np.append(x, x[0]), np.append(F, F[0])
    return float(abs(np.sum(0.5 * (Fc[1:] + Fc[:-1]) * np.diff(xc))))


def hysteresis(fmu: Any, out: Path, base: Mapping[str, Any]) -> dict[str, HysteresisLoop]:
    """Fig. 2: the loop of eq. 4 at amplitude B against (a) the reference Jenkins element driven by
    v = B cos(theta) and (b) the FMU's time-domain element (frictionModel 3) in a steady run."""
    panels, rows = [], []
    info: dict[str, HysteresisLoop] = {}
    theta = np.linspace(0, 2 * PI, 721)
    for label, kn, speed in (("kn = 1e7 N/m (paper)", 1e7, 5000.0), ("kn = 1e5 N/m (soft)", 1e5, 4950.0)):
        p = _params.validate(dict(base, kn=kn, frictionModel=3))
        om = omega_of(p, speed)
        T = 2 * PI / om
        r = fmu.run(
            p,
            T * math.ceil(0.6 / T),
            T / 256,
            speed_rpm=speed,
            outputs=["tipDisplacement", "frictionForce", "normalForce", "dissipatedEnergy", "tipVelocity"],
        )
        last = r[r["time"] >= r["time"][-1] - T * (1 + 1e-9)]
        B = float(np.max(np.abs(last["tipDisplacement"])))
        sg = math.sin(p["gamma"])
        Ff_eq4 = np.array([ref.loop_friction(p, B, th, 1) for th in theta[:-1]] + [math.nan])
        du_eq4 = B * sg * np.cos(theta)
        du_fmu = last["tipDisplacement"] * sg
        E_fmu = _loop_area(du_fmu, last["frictionForce"])
        E_eq4 = _loop_area(du_eq4[:-1], Ff_eq4[:-1])
        df = ref.describing_function(p, B, om, model=1)
        E_df = float(PI * om * B * B * float(df.fc))
        jp = ref.jenkins_prescribed(p, B, om, n_cycles=2, samples_per_cycle=720)
        du_j = B * sg * np.cos(jp["theta"])
        panels.append(
            {
                "title": f"{label}, {speed:g} rpm, B = {B * 1e3:.4f} mm (FMU steady amplitude)",
                "eq4": (du_eq4, Ff_eq4),
                "fmu": (du_fmu, last["frictionForce"]),
            }
        )
        order = np.argsort(jp["theta"])
        panels[-1]["jenkins"] = (du_j[order], jp["Ff"][order])
        panels[-1]["energy"] = {"eq4": E_eq4, "jenkins": float(jp["cycle_work"][-1]), "fmu": E_fmu}
        info[label] = HysteresisLoop(kn, speed, B, E_fmu, E_eq4, E_df, float(jp["cycle_work"][-1]))
        for th, du, F in zip(theta[:-1], du_eq4[:-1], Ff_eq4[:-1]):
            rows.append((kn, 0, th, du, F))
        for du, F in zip(du_fmu, last["frictionForce"]):
            rows.append((kn, 1, math.nan, du, F))
        for th, du, F in zip(jp["theta"], du_j, jp["Ff"]):
            rows.append((kn, 2, th, du, F))
    tab = np.array(rows, dtype=[("kn", "f8"), ("source", "i4"), ("theta", "f8"), ("du", "f8"), ("Ff", "f8")])
    write_csv(
        out / "fig2_hysteresis.csv",
        tab,
        "Fig. 2: friction loop; source 0 = eq. 4 closed form, 1 = FMU frictionModel 3 (last period of a "
        "steady run), 2 = reference Jenkins element driven by v = B cos(theta); du [m], Ff [N]",
    )
    plots.hysteresis(out / "fig2_hysteresis.png", panels)
    return info
