"""One constant-speed plateau of the FMU, run until its periodic steady state (or a time cap).

Shared by the time-domain sweeps and the fixed-point procedure (one FMU instance per worker:
harness.fmu.pool.worker_fmu, reset per run): the FMU file's hash for cache keys (`fmu_identity`), the aero load
of a plateau continuing the phase of the previous one (`PhasedSine`), where a plateau starts
(`Start`: at rest or from a saved FMU state), `settle`: chunks of FMU steps until
`harness.analysis.steady_state.analyze` finds the steady state (chunk lengths from the fitted decay of the
transient), and `period_peak`: the max |q| of one more period, finely sampled.
"""

from __future__ import annotations

import hashlib
import math
from dataclasses import dataclass
from pathlib import Path
from typing import Any, Mapping

import numpy as np

from harness.analysis.config import SweepSettings
from harness.analysis.steady_state import WINDOW, analyze, decide, hermite_peak
from harness.fmu.blade import FMUState, fmu_path

_HASHES: dict[str, str] = {}


def fmu_identity(path: str | Path | None = None) -> tuple[str, str]:
    """(path, sha256 of the FMU file): the hash enters every cache key (a rebuilt FMU is new)."""
    if path is None:
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
    continuing the phase of the previous plateau (paper eq. 17 with a piecewise-constant n)."""

    breakpoints = np.zeros(0)

    def __init__(self, amplitude: float, omega: float, phase: float, t0: float):
        self.amplitude, self.omega, self.phase, self.t0 = float(amplitude), float(omega), float(phase), float(t0)

    def __call__(self, t):
        return self.amplitude * np.sin(self.phase + self.omega * (np.asarray(t, dtype=float) - self.t0))

    def derivatives(self, t, order: int) -> np.ndarray:
        x = self.phase + self.omega * (np.atleast_1d(np.asarray(t, dtype=float)) - self.t0)
        return np.array([self.amplitude * self.omega**j * np.sin(x + j * math.pi / 2) for j in range(order + 1)])


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


SETTLE_OUTPUTS = ("tipDisplacement", "tipVelocity")  # the state the steady-state test compares
PLATEAU_OUTPUTS = SETTLE_OUTPUTS + ("amplitude",)  # what sweep plateaus and fixed-point runs record
PEAK_STEPS = 64  # samples of the extra period of `period_peak` (Hermite error <~1e-5 with contact)


def settle(
    fmu: Any, params: dict, speed: float, start: Start, s: SweepSettings, cap: float, outputs: list[str]
) -> tuple[np.ndarray, Any, float, float]:
    """Run chunks at constant `speed` from `start` until analyze() finds the steady state or
    `cap` seconds are simulated; a response that converges with a fitted decay fast enough to
    reach rtol within `s.extend` x cap may go on to that (an irregular one stops at the cap).
    Returns (samples of the plateau, SteadyState, t_end, phase_end).

    The FMU is sampled once per period, at the period starts (q and q' always: the decision
    compares the state (q, q') one period apart, the Poincare section of the period map); the
    load values are carried over by the FMU between steps (`BladeFMU.run(carry_values=True)`).
    The returned samples are these (one row per period, `time` first).
    The first chunk holds enough periods for one decision; after that each chunk is as long as the
    fitted decay of the transient says is still needed to reach rtol (+ min_periods, + 10 %), at
    most `chunk_periods`, so a plateau stops within a few periods of its steady state; without a
    fitted decay (a strongly nonlinear start, an irregular response) the chunk triples. Decisions
    use `steady_state.decide`; the final record is analysed once by `steady_state.analyze`. Each decision
    analyses only the periods since the previous one plus the fit window: the converged run that
    ends the record started after the previous (negative) decision, so t_steady is exact."""
    outputs = list(outputs) + [o for o in SETTLE_OUTPUTS if o not in outputs]
    omega = omega_of(params, speed)
    period = 2.0 * math.pi / omega
    spp = s.steps_per_period
    h = period / spp
    aero = PhasedSine(params["Fw0"], omega, start.phase, start.time)
    if start.state is not None and not fmu.holds(start.state):  # (a chain's next plateau: held)
        st = FMUState(start.state)
        st.time, st.params = start.time, dict(params)
        fmu.set_state(st)
    t = start.time
    chunks: list[np.ndarray] = []
    lookback = WINDOW + s.min_periods + 2  # periods before a decision's new ones that it needs
    p_soft = max(int(math.ceil(cap / period - 1e-9)), lookback + s.min_periods)  # whole periods
    p_hard = max(int(math.ceil(s.extend * cap / period - 1e-9)), p_soft)
    limit = p_soft  # the periods the current plan allows
    p_done = 0
    n_next = min(lookback + s.min_periods, p_soft)
    last_decision = 0  # period count at the previous decision
    first = True
    while True:
        n = min(n_next, limit - p_done)
        t_stop = start.time + (p_done + n) * period
        fresh = first and start.state is None
        # reset=False continues with the parameters already in the FMU (None: no re-validation)
        res = fmu.run(
            params if fresh else None,
            t_stop,
            h,
            aero=aero,
            speed=float(speed),
            outputs=outputs,
            derivative_order=s.derivative_order,
            start_time=t,
            reset=fresh,
            input_fit=s.input_fit,
            carry_values=True,
            sample_every=spp,
        )
        if not first and len(res) and abs(res["time"][0] - t) <= 1e-12 * max(1.0, abs(t)):
            res = res[1:]  # the chunk's first row repeats the previous chunk's last one
        chunks.append(res)
        first = False
        p_done += n
        t = float(res["time"][-1])
        # the periods since the previous decision plus the lookback: row i at start + i T
        k0 = max(0, last_decision - lookback)
        w = _tail(chunks, p_done - k0 + 1)
        last_decision = p_done
        if p_done >= p_hard:
            break
        reached, rel, decay = decide(
            w["tipDisplacement"][:-1, None], w["tipVelocity"][:-1, None], omega, rtol=s.rtol, min_periods=s.min_periods
        )
        if reached:
            break
        converging = math.isfinite(rel) and 0.0 < decay < 1.0
        if converging:
            need = math.log(s.rtol / rel) / math.log(decay) + s.min_periods  # periods to reach rtol
            n_next = int(min(max(math.ceil(1.1 * need), s.min_periods + 1), s.chunk_periods))
        else:  # no decay fitted yet (strongly nonlinear start, irregular response): triple the chunk
            n_next = min(3 * n, s.chunk_periods)
        # a response converging with a fitted decay that reaches rtol before extend x cap may run
        # to that; anything else (irregular, too slow) stops at the cap
        limit = p_hard if converging and p_done + need <= p_hard else p_soft
        if p_done >= limit:
            break
    ss = analyze(
        w["time"], w["tipDisplacement"], period, rtol=s.rtol, min_periods=s.min_periods, velocity=w["tipVelocity"]
    )
    data = np.concatenate(chunks)
    phase = (start.phase + omega * (t - start.time)) % (2.0 * math.pi)
    return data, ss, t, phase


def _tail(chunks: list[np.ndarray], n: int) -> np.ndarray:
    """The last n rows of the concatenated chunks (concatenating only what is needed)."""
    got, parts = 0, []
    for c in reversed(chunks):
        parts.append(c)
        got += len(c)
        if got >= n:
            break
    return np.concatenate(parts[::-1])[-n:]


def period_peak(
    fmu: Any, params: dict, speed: float, t: float, phase: float, s: SweepSettings, steps: int = PEAK_STEPS
) -> float:
    """max |q| over one more excitation period from the FMU's current state at time t (load phase
    `phase`), on `steps` samples with the cubic Hermite interpolant through (q, q'): relative error
    ~ (2 pi f_max / (f steps))^4 / 384 for the fastest local frequency f_max (2.5e-7 at 64 steps for
    a sine at the excitation frequency; measured against 1024 steps: <= 1.5e-6 in the base case's
    impacts). Advances the FMU by one period."""
    omega = omega_of(params, speed)
    period = 2.0 * math.pi / omega
    aero = PhasedSine(params["Fw0"], omega, phase, t)
    r = fmu.run(
        None,
        t + period,
        period / steps,
        aero=aero,
        speed=float(speed),
        outputs=list(SETTLE_OUTPUTS),
        derivative_order=s.derivative_order,
        start_time=t,
        reset=False,
        input_fit=s.input_fit,
        carry_values=True,
    )
    return hermite_peak(r["time"], r["tipDisplacement"], r["tipVelocity"])
