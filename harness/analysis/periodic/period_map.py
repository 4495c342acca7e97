"""The period map of the FMU: start state at load phase 0 -> state one excitation period later.

One evaluation is one FMU run over exactly one period T = 2 pi / (EO Omega) at constant speed:
fmi2Reset, the parameters and the start values of the state (tipDisplacement, tipVelocity,
jenkinsForce), initialization, `steps_per_period` communication steps with the load's degree-8
Chebyshev interpolant per step (9e-10 of F_w0 at 4 steps per period, 9e-12 at 8: the orbits of the
two differ by < 1e-9 of their scale, their multipliers by < 3e-9), then the state at T. The run
uses amplitudeMode 2 (tracked), whose only effect inside [0, T) is that the FMU locates every
extremum of q: B stays at its start value until the period end at T, so the dynamics are exactly
the fixed-B dynamics, and `runningMaximum` (with `amplitude` if the period-end update already
happened at T) is max |q| over the period, located, not sampled.

Unknowns x per model (MODELS):
- fixedB: (q0, q0') with B = params["B"] (frictionModel from params, 1 or 2);
- fixedPoint / coulomb: (q0, q0', B), the paper's fixed point as the augmented problem: the image's
  third component is A = max |q| over the period, so a fixed point has B = A(B). The image map
  (q0, q0', B) -> (q(T), q'(T), A) is exactly the period map of the tracked-amplitude model, so its
  multipliers are that model's stability (frictionModel 1 resp. 2);
- jenkins: (q0, q0', phi0), the time-domain macroslip element (frictionModel 3), phi = F_f / L(q)
  the element force as a fraction of its slip limit L = mu kn cos(gamma) (|q| - d) (0 while open),
  so the cone |phi| <= 1 does not move with q0.
With m = `modes` > 1 bending modes, (q0, q0') becomes the modal start state (q_1..q_m, q_1'..q_m')
(the FMU's modalDisplacement / modalVelocity start values), so the unknowns are 2m (fixedB) or
2m + 1; q above is then the tip displacement sum_i q_i (every mode normalised to 1 at the tip, the
quantity the contact, B and max |q| refer to). For m > 1 DP comes from the FMU's full Jacobian
`sensitivity[r,c]` (docs/model.md s.2a: rows modalDisplacement[1..6], modalVelocity[1..6],
jenkinsForce, runningMaximum, amplitude; columns the start values of the modal state, of
jenkinsForce and B), the sub-matrix of the m modes; an FMU without it: finite differences.
"""

from __future__ import annotations

import ctypes
import math
import time
from dataclasses import dataclass, replace
from typing import Any, Mapping

import numpy as np

from harness.model.excitation import MAX_ORDER, AeroLoad, Constant
from harness.fmu.blade import SPEED_RANGE, VR_AERO, VR_SPEED, BladeFMU, step_inputs
from harness.fmu.stepper import Derivatives, Values
from harness.model.params import ParameterError, fmu_parameters, validate

MODELS = ("fixedB", "fixedPoint", "jenkins", "coulomb")
STATE_STARTS = ("tipDisplacement", "tipVelocity", "jenkinsForce", "runningMaximum")
_OUT = ("tipDisplacement", "tipVelocity", "jenkinsForce", "runningMaximum", "amplitude")


def modal_names(m: int) -> tuple[str, ...]:
    """The FMU's modal start values / outputs (q_1..q_m, q_1'..q_m')."""
    return tuple(f"modalDisplacement[{i}]" for i in range(1, m + 1)) + tuple(
        f"modalVelocity[{i}]" for i in range(1, m + 1)
    )


def modal_sensitivities(m: int) -> tuple[str, ...]:
    """sensitivity[r,c] of the m-mode state, row-major: rows q_1..q_m, q_1'..q_m', jenkinsForce,
    runningMaximum, amplitude; columns q_1(0)..q_m(0), q_1'(0)..q_m'(0), jenkinsForce(0), B."""
    idx = list(range(1, m + 1)) + list(range(7, 7 + m))
    return tuple(f"sensitivity[{r},{c}]" for r in idx + [13, 14, 15] for c in idx + [13, 14])


def modes_of(params: Mapping[str, Any]) -> int:
    """m = params["modes"] (1 where the parameter set has none)."""
    return int(params.get("modes", 1))


# the FMU's sensitivities: d(row)/d(column), rows as _OUT, columns the start values q0, q0', F0 and B
_SENS = tuple(f"d{r[0].upper()}{r[1:]}_d{c}" for r in _OUT for c in ("Q0", "V0", "F0", "B"))


@dataclass(frozen=True)
class ShootingSettings:
    """Numerical settings of the period map, Newton and the multipliers."""

    steps_per_period: int = 4  # communication steps per period (load interpolant error 9e-10 of F_w0)
    fd_rel: float = 1e-6  # finite-difference step relative to each unknown's scale
    tol: float = 1e-10  # Newton converged: max scaled residual |P(x) - x| / scale
    max_iter: int = 30  # Newton iterations
    sensitivities: bool = True  # DP from the FMU's variational equations (else finite differences)

    def check(self) -> "ShootingSettings":
        if not (isinstance(self.steps_per_period, int) and 2 <= self.steps_per_period <= 4096):
            raise ParameterError(f"steps_per_period = {self.steps_per_period!r} must be an integer in [2, 4096]")
        for name, lo, hi in (("fd_rel", 1e-12, 1e-2), ("tol", 1e-14, 1e-3)):
            v = getattr(self, name)
            if not (isinstance(v, (int, float)) and lo <= v <= hi):
                raise ParameterError(f"{name} = {v!r} must be a number in [{lo:g}, {hi:g}]")
        if not (isinstance(self.max_iter, int) and self.max_iter >= 1):
            raise ParameterError(f"max_iter = {self.max_iter!r} must be an integer >= 1")
        if not isinstance(self.sensitivities, bool):
            raise ParameterError(f"sensitivities = {self.sensitivities!r} must be true or false")
        return self


def model_params(params: Mapping[str, Any] | None, model: str) -> dict[str, Any]:
    """The validated parameter set a model runs with (frictionModel forced where the model says)."""
    if model not in MODELS:
        raise ParameterError(f"model = {model!r}: choose from {', '.join(MODELS)}")
    p = validate(params or {}, source="periodic")
    if model == "jenkins":
        p["frictionModel"] = 3
    elif model == "coulomb":
        p["frictionModel"] = 2
    elif int(p["frictionModel"]) == 3:
        raise ParameterError(
            f"model {model!r} needs a describing-function frictionModel (1 or 2), got 3;"
            " use --model jenkins for the time-domain element"
        )
    p["amplitudeMode"] = 2  # see the module doc: B fixed inside the period, extrema located
    return p


def omega(params: Mapping[str, Any], speed_rpm: float) -> float:
    """Excitation circular frequency EO 2 pi n / 60 [rad/s]."""
    return int(params["engineOrder"]) * 2.0 * math.pi * float(speed_rpm) / 60.0


class PeriodMap:
    """P(x) at a speed for one model and parameter set, evaluated with one BladeFMU instance."""

    def __init__(
        self,
        fmu: BladeFMU,
        params: Mapping[str, Any] | None,
        model: str,
        settings: ShootingSettings = ShootingSettings(),
    ):
        self.fmu, self.model, self.s = fmu, model, settings.check()
        self.p = model_params(params, model)
        self.m = modes_of(self.p)
        if self.m > 1 and settings.sensitivities and "sensitivity[1,1]" not in fmu.variables:
            self.s = settings = replace(settings, sensitivities=False)  # finite differences (module doc)
        self.p["sensitivities"] = settings.sensitivities
        self.DP: np.ndarray | None = None  # DP at the last evaluation (with sensitivities)
        self.dim = 2 * self.m + (0 if model == "fixedB" else 1)
        self.B = float(self.p["B"])  # the fixed amplitude of fixedB (settable: scans in B) [m]
        self.d = float(self.p["d"])
        self.muKnCos = float(self.p["mu"] * self.p["kn"] * math.cos(self.p["gamma"]))  # L = muKnCos (|q| - d) [N/m]
        self.evaluations = 0
        self.simulated = 0.0  # blade seconds simulated [s]
        self.fmi_seconds = 0.0  # wall time spent in the FMI calls of the evaluations (ctypes included) [s]
        self.account: PeriodMap = self  # whose counters the evaluations add to (see with_model)
        self._fmi = fmu.prepared()
        v = fmu.variables
        fixed = {k: x for k, x in fmu_parameters(self.p).items() if k != "B"}
        reals = [(k, x) for k, x in fixed.items() if v[k].type == "Real"]
        starts = STATE_STARTS if self.m == 1 else modal_names(self.m) + STATE_STARTS[2:]
        names = [k for k, _ in reals] + ["B", *starts]
        self._reals = Values([v[k].valueReference for k in names], [x for _, x in reals] + [0.0] * (1 + len(starts)))
        self._iB = len(reals)  # index of B, then the start values in STATE_STARTS order
        ints = [(k, x) for k, x in fixed.items() if v[k].type == "Integer"]
        bools = [(k, x) for k, x in fixed.items() if v[k].type == "Boolean"]
        self._ints = Values([v[k].valueReference for k, _ in ints], [int(x) for _, x in ints], ctypes.c_int)
        self._bools = Values([v[k].valueReference for k, _ in bools], [int(bool(x)) for _, x in bools], ctypes.c_int)
        self._isens = next((i for i, (k, _) in enumerate(bools) if k == "sensitivities"), None)
        out = (
            (_OUT + (_SENS if settings.sensitivities else ()))
            if self.m == 1
            else _OUT + modal_names(self.m) + (modal_sensitivities(self.m) if settings.sensitivities else ())
        )
        self._out = Values([v[k].valueReference for k in out])
        K = MAX_ORDER
        # per step the load's derivatives 1..K; the speed's stay 0 from the reset (constant speed)
        self._der = Derivatives([VR_AERO] * K, range(1, K + 1))
        self._speed: float | None = None
        self._unit: np.ndarray | None = None

    # ---- inputs of one period at a speed (cached for the last speed) ----
    def _unit_load(self) -> np.ndarray:
        """Value and derivatives 1..K per step of the load's Chebyshev interpolant for a period of
        T = 1 s, shape (K + 1, N). In load phase the steps are the same at every speed, so the
        derivatives at period T are these times T^-j (computed once, not per speed)."""
        if self._unit is None:
            N = self.s.steps_per_period
            speed = 60.0 / int(self.p["engineOrder"])  # T = 1 s
            grid = np.arange(N + 1) / N
            grid[-1] = 1.0
            self._unit = step_inputs(
                AeroLoad(self.p["Fw0"], self.p["engineOrder"], Constant(speed)), grid, MAX_ORDER, "chebyshev"
            )
        return self._unit

    def _prepare(self, speed: float) -> None:
        if speed == self._speed:
            return
        if not (math.isfinite(speed) and 0.0 < speed <= SPEED_RANGE[1]):
            raise ParameterError(f"speed = {speed!r} rpm outside (0, {SPEED_RANGE[1]:g}] (the FMU's rotorSpeed range)")
        N, K = self.s.steps_per_period, MAX_ORDER
        T = 2.0 * math.pi / omega(self.p, speed)
        if self._unit is None:  # per step: the load's derivatives 1..K
            ua = self._unit_load()
            self._derivs = np.zeros((N, K))
            self._inputs = Values([VR_AERO, VR_SPEED], [float(ua[0, 0]), 0.0])
            self._addr = (self._derivs.ctypes.data + 8 * K * np.arange(N)).tolist()
            self._ks = np.arange(1, K + 1, dtype=float)
        np.multiply(self._unit_load()[1:].T, (1.0 / T) ** self._ks, out=self._derivs)
        self._inputs.value[1] = float(speed)
        grid = [T * k / N for k in range(N)] + [T]
        self._steps = [(grid[k], grid[k + 1] - grid[k], self._addr[k]) for k in range(N)]
        self.T, self._speed = T, speed

    # ---- unknowns <-> FMU start values ----
    def slip_limit(self, q: float) -> float:
        """L(q) = mu kn cos(gamma) (|q| - d) [N], 0 while open."""
        return self.muKnCos * max(abs(q) - self.d, 0.0)

    def tip(self, x: np.ndarray) -> tuple[float, float]:
        """(q0, q0') at the tip: the unknowns themselves for m = 1, else the sums of the modal ones."""
        m = self.m
        return (float(x[0]), float(x[1])) if m == 1 else (float(np.sum(x[:m])), float(np.sum(x[m : 2 * m])))

    def lift(self, q0: float, v0: float, third: float | None = None) -> np.ndarray:
        """Unknowns from a one-mode guess: the tip state in the first mode, the others at rest."""
        x = np.zeros(2 * self.m)
        x[0], x[self.m] = q0, v0
        return x if third is None else np.append(x, third)

    def scales(self, x: np.ndarray, speed_rpm: float) -> np.ndarray:
        """Scale of each unknown for Newton and finite differences: S, S omega (, S or 1), S the
        tip's (every modal coordinate of a mode gets the same scale)."""
        q0, v0 = self.tip(x)
        if self.m > 1:  # a modal state may cancel at the tip: its largest coordinate counts too
            q0 = max(abs(q0), float(np.max(np.abs(x[: self.m]))))
            v0 = max(abs(v0), float(np.max(np.abs(x[self.m : 2 * self.m]))))
        S = max(abs(q0), abs(v0) / omega(self.p, speed_rpm), self.d, 1e-9)
        m = self.m
        if self.dim == 2 * m:
            return np.array([S] * m + [S * omega(self.p, speed_rpm)] * m)
        third = 1.0 if self.model == "jenkins" else max(abs(x[-1]), self.d, 1e-9)
        return np.array([S] * m + [S * omega(self.p, speed_rpm)] * m + [third])

    def __call__(self, x: np.ndarray, speed: float, jacobian: bool = True) -> tuple[np.ndarray, float]:
        """(image of x, max |q| over the period); with sensitivities (the settings) and jacobian,
        also DP at x in self.DP (else None). Raises FMUError if the FMU refuses the start (e.g.
        B <= 0) or fails in the period."""
        self._prepare(float(speed))
        want = self.s.sensitivities and jacobian
        self.DP = None
        if self._isens is not None:
            self._bools.value[self._isens] = int(want)
        m = self.m
        q0, v0 = self.tip(x)
        if self.model == "jenkins":
            B, F0 = self.B, min(max(float(x[-1]), -1.0), 1.0) * self.slip_limit(q0)
        else:
            B, F0 = (self.B if self.dim == 2 * m else float(x[-1])), 0.0
        i, val = self._iB, self._reals.value
        if m == 1:
            val[i], val[i + 1], val[i + 2], val[i + 3], val[i + 4] = B, q0, v0, F0, 0.0
        else:
            val[i] = B
            for k in range(2 * m):
                val[i + 1 + k] = float(x[k])
            val[i + 1 + 2 * m], val[i + 2 + 2 * m] = F0, 0.0
        acct = self.account
        acct.evaluations += 1
        acct.simulated += self.T
        t_in = time.perf_counter()
        fmi = self._fmi
        st, call = fmi.start(self._reals, self._ints, self._bools, self._inputs)
        if st > 1:
            raise self.fmu.failure(call, st, 0.0)
        st, k, call = fmi.derivative_steps(self._steps, self._der)
        if st > 1:
            raise self.fmu.failure(call, st, self._steps[k][0])
        o = self._out.value
        st = fmi.read(self._out, None if want or m > 1 else len(_OUT))
        acct.fmi_seconds += time.perf_counter() - t_in
        if st > 1:
            raise self.fmu.failure("fmi2GetReal", st, self.T)
        q, v, F, run_max, amp = o[0], o[1], o[2], o[3], o[4]
        # the period-end update at T may or may not have happened within the last step: if it did,
        # `amplitude` holds the new maximum and the running maximum restarted at |q(T)|
        ended = amp != B
        A = amp if ended else max(run_max, abs(q))
        arow = 4 if ended else (3 if run_max >= abs(q) else -1)
        if want and m == 1:
            self.DP = self._dp(o[len(_OUT) : len(_OUT) + len(_SENS)], q0, F0, q, F, arow)
        elif want:
            k = len(_OUT) + 2 * m
            self.DP = self._dp_modal(
                np.array(o[k : k + (2 * m + 3) * (2 * m + 2)]).reshape(2 * m + 3, 2 * m + 2), q0, F0, q, F, arow
            )
        state = [q, v] if m == 1 else list(o[len(_OUT) : len(_OUT) + 2 * m])
        if self.dim == 2 * m:
            return np.array(state), A
        if self.model == "jenkins":
            L = self.slip_limit(q)
            return np.array(state + [F / L if L > 0.0 else 0.0]), A
        return np.array(state + [A]), A

    def _dp(self, s: list[float], q0: float, F0: float, q: float, F: float, arow: int) -> np.ndarray:
        """DP in the unknowns from the FMU's sensitivities s (row-major 5 x 4: rows q, q', F,
        runningMaximum, amplitude; columns q0, q0', F0, B); arow: the row of A = max |q| (-1:
        |q(T)|)."""
        if self.dim == 2:
            return np.array([[s[0], s[1]], [s[4], s[5]]])
        if arow >= 0:
            a = s[4 * arow : 4 * arow + 4]
        else:
            a = [math.copysign(1.0, q) * g for g in s[0:4]]
        if self.model != "jenkins":
            return np.array([[s[0], s[1], s[3]], [s[4], s[5], s[7]], [a[0], a[1], a[3]]])
        # jenkins: F0 = phi0 L(q0), the image's phi = F / L(q) (L = muKnCos (|q| - d) in contact)
        L0, L = self.slip_limit(q0), self.slip_limit(q)
        dL0 = self.muKnCos * math.copysign(1.0, q0) if L0 > 0.0 else 0.0
        phi0 = F0 / L0 if L0 > 0.0 else 0.0
        rows = [[s[4 * i] + s[4 * i + 2] * phi0 * dL0, s[4 * i + 1], s[4 * i + 2] * L0] for i in range(3)]
        if L > 0.0:
            dL = F / L * self.muKnCos * math.copysign(1.0, q)
            rows[2] = [(rows[2][j] - dL * rows[0][j]) / L for j in range(3)]
        else:
            rows[2] = [0.0, 0.0, 0.0]
        return np.array(rows)

    def _dp_modal(self, S: np.ndarray, q0: float, F0: float, q: float, F: float, arow: int) -> np.ndarray:
        """DP in the unknowns for m > 1 from the modal Jacobian S (rows: 2m state, F, running max,
        amplitude; columns: 2m state, F0, B), as _dp does for one mode; the tip is the sum of the
        modal displacements, so d|q_tip| and dL/dq0 act on every modal displacement alike."""
        n = 2 * self.m
        st = S[: n + 1]  # the state rows and the jenkinsForce row
        if arow >= 0:
            a = S[n + arow - 2]  # runningMaximum (arow 3) or amplitude (arow 4)
        else:
            a = math.copysign(1.0, q) * S[: self.m].sum(axis=0)
        if self.model == "fixedB":
            return st[:n, :n].copy()
        if self.model != "jenkins":
            cols = list(range(n)) + [n + 1]  # the state and B
            return np.vstack([st[:n, cols], a[cols]])
        L0, L = self.slip_limit(q0), self.slip_limit(q)
        dL0 = self.muKnCos * math.copysign(1.0, q0) if L0 > 0.0 else 0.0
        phi0 = F0 / L0 if L0 > 0.0 else 0.0
        J = np.empty((n + 1, n + 1))
        J[:, :n] = st[:, :n]
        J[:, : self.m] += st[:, [n]] * (phi0 * dL0)  # F0 = phi0 L(sum q0_i)
        J[:, n] = st[:, n] * L0
        if L > 0.0:
            dL = F / L * self.muKnCos * math.copysign(1.0, q)
            J[n] = (J[n] - dL * J[: self.m].sum(axis=0)) / L
        else:
            J[n] = 0.0
        return J

    def with_model(self, model: str) -> "PeriodMap":
        """A period map of another model on the same FMU and parameters, whose evaluations count
        in this map's counters."""
        other = PeriodMap(self.fmu, self.p, model, self.s)
        other.account = self.account
        return other

    def start_values(self, x: np.ndarray) -> dict[str, float]:
        """The FMU start values (and B) that start a run on the state x at load phase 0."""
        q0, v0 = self.tip(x)
        if self.m == 1:
            out = {"tipDisplacement": q0, "tipVelocity": v0}
        else:
            out = {k: float(x[j]) for j, k in enumerate(modal_names(self.m))}
        if self.model == "fixedB":
            out["B"] = self.B
        elif self.model == "jenkins":
            out["jenkinsForce"] = float(np.clip(x[-1], -1.0, 1.0)) * self.slip_limit(q0)
        else:
            out["B"] = float(x[-1])
        return out
