"""Input signals for the FMU: rotor-speed profiles, the aerodynamic load, and what the FMU sees.

Every signal is a callable `s(t)` with `s.derivatives(t, order)` (row j = the j-th time derivative,
exact, right-sided at breakpoints: the value that holds on [t, t + dt)) and `s.breakpoints` (the
times where it is not smooth). Speed profiles (`Constant`, `LinearRamp`, `Stepped`) are piecewise
polynomials in rpm and also give their exact integral, so the aerodynamic load
`AeroLoad`: f_w(t) = Fw0 sin(psi_e(t)), psi_e = engine_order * int_0^t 2 pi n / 60 (eq. 17,
phase-continuous under any speed profile), has exact derivatives up to order 8 by truncated
Taylor-series arithmetic (sin composed with the phase series). `fmu_view(signal, grid, order)` is
the piecewise Taylor polynomial the FMU reconstructs when the master sets value and derivatives up
to `order` at each communication point (docs/model-notes.md section 1); it feeds the reference
exactly what the FMU saw.
"""

from __future__ import annotations

import math
from typing import Protocol, Sequence, runtime_checkable

import numpy as np

MAX_ORDER = 8  # highest input derivative order the FMU accepts (docs/model-notes.md s.1)
RPM_TO_RAD_S = 2.0 * math.pi / 60.0  # Omega [rad/s] per n [rpm]


class ExcitationError(ValueError):
    """An input signal is not acceptable (NaN, inconsistent lengths, out of range)."""


@runtime_checkable
class Signal(Protocol):
    breakpoints: np.ndarray

    def __call__(self, t): ...

    def derivatives(self, t: np.ndarray, order: int) -> np.ndarray: ...


def _check_finite(name: str, *values: float) -> None:
    for v in values:
        if not math.isfinite(float(v)):
            raise ExcitationError(f"{name} = {v!r} is not a finite number")


def _check_order(order: int) -> int:
    if not 0 <= int(order) <= MAX_ORDER:
        raise ExcitationError(f"derivative order {order} outside [0, {MAX_ORDER}]")
    return int(order)


class Piecewise:
    """Piecewise polynomial: on [x_i, x_{i+1}) the value is sum_j c[i, j] (t - x_i)^j.

    Piece 0 also holds for t < x_0 and the last piece for t >= x_{m-1}. `breakpoints` = x_1..x_{m-1}.
    """

    def __init__(self, knots: Sequence[float], coeffs: np.ndarray):
        self.knots = np.asarray(knots, dtype=float)
        self.coeffs = np.atleast_2d(np.asarray(coeffs, dtype=float))
        if self.knots.ndim != 1 or len(self.knots) != self.coeffs.shape[0]:
            raise ExcitationError("knots and coefficient rows differ in number")
        if np.any(np.diff(self.knots) <= 0):
            raise ExcitationError("knots must be strictly increasing")
        if not (np.all(np.isfinite(self.knots)) and np.all(np.isfinite(self.coeffs))):
            raise ExcitationError("signal knots/values must be finite (got NaN or inf)")
        self.breakpoints = self.knots[1:].copy()
        self._prim: np.ndarray | None = None  # integral from x_0 to x_i (lazily)

    def _locate(self, t: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
        idx = np.clip(np.searchsorted(self.knots, t, side="right") - 1, 0, len(self.knots) - 1)
        return idx, t - self.knots[idx]

    def __call__(self, t):
        scalar = np.ndim(t) == 0
        tt = np.atleast_1d(np.asarray(t, dtype=float))
        idx, s = self._locate(tt)
        c = self.coeffs[idx]
        out = c[:, -1].copy()
        for j in range(c.shape[1] - 2, -1, -1):
            out = out * s + c[:, j]
        return float(out[0]) if scalar else out

    def derivatives(self, t, order: int) -> np.ndarray:
        order = _check_order(order)
        tt = np.atleast_1d(np.asarray(t, dtype=float))
        idx, s = self._locate(tt)
        c = self.coeffs[idx]
        deg = c.shape[1] - 1
        out = np.zeros((order + 1, len(tt)))
        for k in range(min(order, deg) + 1):
            # d^k/dt^k sum_j c_j s^j = sum_{j>=k} c_j j!/(j-k)! s^(j-k)
            acc = np.zeros(len(tt))
            for j in range(deg, k - 1, -1):
                acc = acc * s + c[:, j] * (math.factorial(j) / math.factorial(j - k))
            out[k] = acc
        return out

    def integral(self, t):
        """int_0^t of the signal (exact)."""
        if self._prim is None:
            widths = np.diff(self.knots)
            js = np.arange(self.coeffs.shape[1])
            piece_int = np.array(
                [np.sum(self.coeffs[i] * widths[i] ** (js + 1) / (js + 1)) for i in range(len(widths))]
            )
            self._prim = np.concatenate(([0.0], np.cumsum(piece_int)))
        scalar = np.ndim(t) == 0
        tt = np.atleast_1d(np.asarray(t, dtype=float))
        idx, s = self._locate(tt)
        idx0, s0 = self._locate(np.array([0.0]))
        js = np.arange(self.coeffs.shape[1])

        def antideriv(i: np.ndarray, ss: np.ndarray) -> np.ndarray:
            return self._prim[i] + np.sum(self.coeffs[i] * ss[:, None] ** (js + 1) / (js + 1), axis=1)

        out = antideriv(idx, s) - antideriv(idx0, s0)[0]
        return float(out[0]) if scalar else out


class Constant(Piecewise):
    """A constant signal, e.g. a rotor speed n [rpm]."""

    def __init__(self, value: float):
        _check_finite("constant value", value)
        self.value = float(value)
        super().__init__([0.0], [[self.value]])

    def __repr__(self) -> str:
        return f"Constant({self.value!r})"


class LinearRamp(Piecewise):
    """v0 until t0, linear to v1 at t1, then v1 (run-up / run-down of the rotor speed)."""

    def __init__(self, v0: float, v1: float, t0: float, t1: float):
        _check_finite("ramp value/time", v0, v1, t0, t1)
        if not t1 > t0:
            raise ExcitationError(f"ramp end time t1 = {t1} must be after its start t0 = {t0}")
        self.v0, self.v1, self.t0, self.t1 = float(v0), float(v1), float(t0), float(t1)
        slope = (self.v1 - self.v0) / (self.t1 - self.t0)
        super().__init__([self.t0 - 1.0, self.t0, self.t1], [[self.v0, 0.0], [self.v0, slope], [self.v1, 0.0]])

    def __repr__(self) -> str:
        return f"LinearRamp({self.v0!r}, {self.v1!r}, {self.t0!r}, {self.t1!r})"


class Stepped(Piecewise):
    """Plateaus: levels[i] held for durations[i] from `start` on (the last level is held after).

    With `ramp` > 0 each change of level is a linear transition taking the first `ramp` seconds of
    the new plateau (no jump in speed), so every duration must exceed `ramp`.
    """

    def __init__(self, levels: Sequence[float], durations: Sequence[float], start: float = 0.0, ramp: float = 0.0):
        levels = [float(v) for v in levels]
        durations = [float(d) for d in durations]
        _check_finite("plateau level", *levels)
        _check_finite("plateau duration/start/ramp", *durations, start, ramp)
        if not levels or len(levels) != len(durations):
            raise ExcitationError("Stepped needs as many durations as levels (at least one)")
        if any(d <= ramp or d <= 0 for d in durations):
            raise ExcitationError(f"every plateau duration must be > 0 and > ramp = {ramp}")
        self.levels, self.durations, self.start, self.ramp = levels, durations, float(start), float(ramp)
        knots: list[float] = [self.start]
        coeffs: list[list[float]] = [[levels[0], 0.0]]
        t = self.start + durations[0]
        for i in range(1, len(levels)):
            if ramp > 0:
                knots.append(t)
                coeffs.append([levels[i - 1], (levels[i] - levels[i - 1]) / ramp])
                knots.append(t + ramp)
            else:
                knots.append(t)
            coeffs.append([levels[i], 0.0])
            t += durations[i]
        super().__init__(knots, coeffs)

    def __repr__(self) -> str:
        return f"Stepped({self.levels!r}, {self.durations!r}, start={self.start!r}, ramp={self.ramp!r})"


def as_speed(speed_rpm: float | Piecewise) -> Piecewise:
    """A rotor-speed signal from a number [rpm] or a speed profile (must provide `integral`)."""
    if isinstance(speed_rpm, (int, float, np.floating, np.integer)):
        return Constant(float(speed_rpm))
    if not (hasattr(speed_rpm, "derivatives") and hasattr(speed_rpm, "integral")):
        raise ExcitationError(f"speed must be a number [rpm] or a speed profile, got {speed_rpm!r}")
    return speed_rpm


def sin_series(p: np.ndarray) -> np.ndarray:
    """Taylor coefficients of sin(p(s)) given those of p (rows = orders, columns = points).

    sin' = cos p', cos' = -sin p'  =>  k S_k = sum_{j=1..k} j p_j C_{k-j}, k C_k = -sum j p_j S_{k-j}.
    """
    n = p.shape[0]
    S = np.zeros_like(p)
    C = np.zeros_like(p)
    S[0], C[0] = np.sin(p[0]), np.cos(p[0])
    for k in range(1, n):
        js = np.arange(1, k + 1)
        jp = js[:, None] * p[1 : k + 1]
        S[k] = np.sum(jp * C[k - js], axis=0) / k
        C[k] = -np.sum(jp * S[k - js], axis=0) / k
    return S


class AeroLoad:
    """f_w(t) = Fw0 sin(psi_e(t)) [N/m], psi_e = engine_order * int_0^t 2 pi n(s)/60 ds (eq. 17)."""

    def __init__(self, Fw0: float, engine_order: int, speed: float | Piecewise):
        _check_finite("Fw0", Fw0)
        self.Fw0 = float(Fw0)
        self.engine_order = int(engine_order)
        self.speed = as_speed(speed)
        self.breakpoints = np.asarray(self.speed.breakpoints, dtype=float)
        self._c = self.engine_order * RPM_TO_RAD_S  # psi_e' = _c * n [rad/s per rpm]

    def phase(self, t):
        """psi_e(t) [rad]."""
        return self._c * self.speed.integral(t)

    def __call__(self, t):
        return self.Fw0 * np.sin(self.phase(t))

    def derivatives(self, t, order: int) -> np.ndarray:
        order = _check_order(order)
        tt = np.atleast_1d(np.asarray(t, dtype=float))
        p = np.zeros((order + 1, len(tt)))
        p[0] = self.phase(tt)
        if order >= 1:
            dn = self.speed.derivatives(tt, order - 1)
            for j in range(1, order + 1):
                p[j] = self._c * dn[j - 1] / math.factorial(j)
        S = sin_series(p)
        fact = np.array([math.factorial(k) for k in range(order + 1)], dtype=float)
        return self.Fw0 * S * fact[:, None]

    def __repr__(self) -> str:
        return f"AeroLoad({self.Fw0!r}, {self.engine_order!r}, {self.speed!r})"


class Modulated:
    """envelope(t) * signal(t), e.g. a load whose amplitude is ramped up slowly; derivatives by the
    Leibniz rule (d^k (e s) = sum_j C(k, j) e^(j) s^(k-j)), breakpoints of both."""

    def __init__(self, envelope: Piecewise, signal: Signal):
        self.envelope, self.signal = envelope, signal
        self.breakpoints = np.union1d(envelope.breakpoints, signal.breakpoints)

    def __call__(self, t):
        return self.envelope(t) * self.signal(t)

    def derivatives(self, t, order: int) -> np.ndarray:
        order = _check_order(order)
        e = self.envelope.derivatives(t, order)
        s = np.asarray(self.signal.derivatives(t, order))
        out = np.zeros_like(s)
        for k in range(order + 1):
            for j in range(k + 1):
                out[k] += math.comb(k, j) * e[j] * s[k - j]
        return out


def fmu_view(signal: Signal, grid: Sequence[float], order: int) -> Piecewise:
    """The input the FMU reconstructs: at each grid point t_k the Taylor polynomial of `signal` with
    value and derivatives up to `order` (0 = held value), valid until the next grid point."""
    order = _check_order(order)
    g = np.asarray(grid, dtype=float)
    d = np.asarray(signal.derivatives(g, order), dtype=float)
    fact = np.array([math.factorial(k) for k in range(order + 1)], dtype=float)
    return Piecewise(g, (d / fact[:, None]).T)
