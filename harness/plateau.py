"""One constant-speed plateau of the FMU, run until its periodic steady state (or a time cap).

Shared by the time-domain sweeps and the fixed-point procedure: one FMU instance per worker
(`worker_fmu`, reset per run), the FMU file's hash for cache keys (`fmu_identity`), the aero load
of a plateau continuing the phase of the previous one (`PhasedSine`), where a plateau starts
(`Start`: at rest or from a saved FMU state) and `settle`: chunks of FMU steps until
`harness.steady_state.analyze` finds the steady state, with a cheap necessary check first.
"""
from __future__ import annotations

import atexit
import hashlib
import math
import threading
from dataclasses import dataclass
from pathlib import Path
from typing import Any, Mapping

import numpy as np

from harness.sweep_config import SweepSettings

_LOCAL = threading.local()


def worker_fmu(path: str) -> Any:
    """One BladeFMU per worker (process or thread), created on first use, reset per run."""
    fmus = getattr(_LOCAL, "fmus", None)
    if fmus is None:
        fmus = _LOCAL.fmus = {}
    if path not in fmus:
        from harness.fmu import BladeFMU

        fmu = BladeFMU(path)
        fmu.__enter__()
        atexit.register(fmu.__exit__, None, None, None)
        fmus[path] = fmu
    return fmus[path]


_HASHES: dict[str, str] = {}


def fmu_identity(path: str | Path | None = None) -> tuple[str, str]:
    """(path, sha256 of the FMU file): the hash enters every cache key (a rebuilt FMU is new)."""
    if path is None:
        from harness.fmu import fmu_path

        path = fmu_path(build=True)
    path = str(Path(path).resolve())
    st = Path(path).stat()
    tag = f"{path}:{st.st_mtime_ns}:{st.st_size}"
    if tag not in _HASHES:
        _HASHES[tag] = hashlib.sha256(Path(path).read_bytes()).hexdigest()
    return path, _HASHES[tag]


# ---------------------------------------------------------------------------------------------
# Signals
# ---------------------------------------------------------------------------------------------
class PhasedSine:
    """f(t) = amplitude sin(phase + omega (t - t0)): the aero load on one constant-speed plateau,
    continuing the phase of the previous plateau (MODEL.md eq. 17 with a piecewise-constant n)."""

    breakpoints = np.zeros(0)

    def __init__(self, amplitude: float, omega: float, phase: float, t0: float):
        self.amplitude, self.omega, self.phase, self.t0 = float(amplitude), float(omega), float(phase), float(t0)

    def __call__(self, t):
        return self.amplitude * np.sin(self.phase + self.omega * (np.asarray(t, dtype=float) - self.t0))

    def derivatives(self, t, order: int) -> np.ndarray:
        x = self.phase + self.omega * (np.atleast_1d(np.asarray(t, dtype=float)) - self.t0)
        return np.array([self.amplitude * self.omega ** j * np.sin(x + j * math.pi / 2) for j in range(order + 1)])


def omega_of(params: Mapping[str, Any], speed: float) -> float:
    """Excitation circular frequency omega = engineOrder * 2 pi n / 60 [rad/s]."""
    return params["engineOrder"] * 2.0 * math.pi * speed / 60.0


# ---------------------------------------------------------------------------------------------
# One plateau of a time-domain sweep (tracked amplitude)
# ---------------------------------------------------------------------------------------------
@dataclass(frozen=True)
class Start:
    """Where a plateau starts: fresh (state None, at rest at t = 0) or a saved FMU state."""

    state: bytes | None = None
    time: float = 0.0  # [s]
    phase: float = 0.0  # aero load phase at `time` [rad], in [0, 2 pi)

    def key(self) -> Any:
        if self.state is None:
            return "rest"
        return [hashlib.sha256(self.state).hexdigest(), self.time, self.phase]


def settle(fmu: Any, params: dict, speed: float, start: Start, s: SweepSettings, cap: float,
            outputs: list[str]) -> tuple[np.ndarray, Any, float, float]:
    """Run chunks at constant `speed` from `start` until analyze() finds the steady state or
    `cap` seconds are simulated. Returns (samples of the plateau, SteadyState, t_end, phase_end)."""
    from harness.steady_state import analyze

    omega = omega_of(params, speed)
    period = 2.0 * math.pi / omega
    h = period / s.steps_per_period
    aero = PhasedSine(params["Fw0"], omega, start.phase, start.time)
    if start.state is not None:
        from harness.fmu import FMUState

        st = FMUState(start.state)
        st.time, st.params = start.time, dict(params)
        fmu.set_state(st)
    t = start.time
    chunks: list[np.ndarray] = []
    spp = s.steps_per_period
    n_chunk = s.chunk_periods * spp
    n_cap = max(int(math.ceil(cap / period - 1e-9)), s.min_periods + 2) * spp  # whole periods
    n_done = 0
    window = (3 * s.min_periods + 4) * spp
    ss = None
    first = True
    while n_done < n_cap:
        n = min(n_chunk, n_cap - n_done)
        t_stop = start.time + (n_done + n) * h
        fresh = first and start.state is None
        # reset=False continues with the parameters already in the FMU (None: no re-validation)
        res = fmu.run(params if fresh else None, t_stop, h, aero=aero, speed=float(speed), outputs=outputs,
                      derivative_order=s.derivative_order, start_time=t, reset=fresh)
        if not first and len(res) and abs(res["time"][0] - t) <= 1e-12 * max(1.0, abs(t)):
            res = res[1:]  # the chunk's first row repeats the previous chunk's last one
        chunks.append(res)
        first = False
        n_done += n
        t = float(res["time"][-1])
        if n_done < (s.min_periods + 1) * spp:
            continue
        data = np.concatenate(chunks)
        # Cheap necessary condition first: analyze() needs the period maximum to change by less
        # than rtol over the last min_periods periods (with 2x slack for its spline refinement).
        last = np.abs(data["tipDisplacement"][-(s.min_periods + 1) * spp:]).reshape(s.min_periods + 1, spp)
        pm = last.max(axis=1)
        if np.max(np.abs(np.diff(pm))) > 2 * s.rtol * max(float(pm.max()), 1e-300):
            continue
        w = data[-(window + 1):]  # decide on the last periods only; the full record is analysed once
        ss = analyze(w["time"], w["tipDisplacement"], period, rtol=s.rtol, min_periods=s.min_periods)
        if ss.reached:
            break
    data = np.concatenate(chunks)
    if ss is not None and ss.reached:
        ss_full = analyze(data["time"], data["tipDisplacement"], period, rtol=s.rtol, min_periods=s.min_periods)
        if ss_full.reached:
            ss = ss_full  # same verdict, t_steady from the whole plateau
    else:
        w = data[-(window + 1):]
        ss = analyze(w["time"], w["tipDisplacement"], period, rtol=s.rtol, min_periods=s.min_periods)
    phase = (start.phase + omega * (t - start.time)) % (2.0 * math.pi)
    return data, ss, t, phase

