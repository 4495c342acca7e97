"""Independent Python reference, helper: a hybrid ODE segment runner on scipy's DOP853 stepper.

solve_ivp only compares event functions at step ends, so an excursion that starts and ends inside
one step (a grazing contact) is missed. This runner drives scipy.integrate.DOP853 step by step and,
on every accepted step, samples the step's dense interpolant at a few points, adds the extrema of
q (roots of q' located by brentq), and checks every switching function on these knots. All our
switching functions are monotone in time between consecutive extrema of q (they are affine in q at
fixed discrete state, or psi, or proportional to q'), so a crossing cannot hide between knots. The
first crossing is located by brentq on the interpolant; the segment stops there so that the caller
can update the discrete state and restart.
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import Callable, Sequence

import numpy as np
from scipy.integrate import DOP853
from scipy.optimize import brentq

Event = tuple[Callable[[float, np.ndarray], float], float]  # (g(t, y), direction: +1 up, -1 down, 0 both)


@dataclass
class SegmentResult:
    t: float  # where the segment stopped [s]
    y: np.ndarray  # state there
    fired: int | None  # index of the event that stopped it (None: reached t_end)
    qmax: float  # max |q| over the segment (if tracking was requested, else 0)


def _crossed(a: float, b: float, direction: float) -> bool:
    if direction > 0:
        return a <= 0.0 < b
    if direction < 0:
        return a >= 0.0 > b
    return (a <= 0.0 < b) or (a >= 0.0 > b)


def run_segment(
    rhs: Callable,
    t0: float,
    y0: np.ndarray,
    t_end: float,
    events: Sequence[Event],
    qv: Callable[[np.ndarray, np.ndarray], tuple[np.ndarray, np.ndarray]],
    rtol: float,
    atol,
    max_step: float = np.inf,
    t_eval: np.ndarray | None = None,
    on_output: Callable[[np.ndarray, np.ndarray, np.ndarray], None] | None = None,
    n_sub: int = 4,
    track_qmax: bool = False,
) -> SegmentResult:
    """Integrate from t0 until t_end or the first event. qv(ts, Y) -> (q, q') at times ts for states
    Y (columns). Outputs: on_output(mask, ts, Y) (mask over t_eval) for the t_eval points in
    [t0, stop) (and t_end itself if the segment runs through and t_eval contains it)."""
    y0 = np.asarray(y0, dtype=float)
    te_arr = np.asarray(t_eval if t_eval is not None else [], dtype=float)
    qmax = float(np.abs(qv(np.array([t0]), y0[:, None])[0][0])) if track_qmax else 0.0
    if t_end <= t0:
        return SegmentResult(t0, y0, None, qmax)
    solver = DOP853(rhs, t0, y0, t_end, max_step=max_step, rtol=rtol, atol=atol)
    while True:
        msg = solver.step()
        if solver.status == "failed":
            raise RuntimeError(f"DOP853 failed at t = {solver.t:g}: {msg}")
        ta, tb = solver.t_old, solver.t
        sol = solver.dense_output()
        knots = np.linspace(ta, tb, n_sub + 1)
        Y = sol(knots)
        _, v = qv(knots, Y)
        extra = []
        for j in range(n_sub):
            if v[j] != 0.0 and v[j + 1] != 0.0 and np.sign(v[j]) != np.sign(v[j + 1]):
                f = lambda t: float(qv(np.array([t]), sol(t)[:, None])[1][0])  # noqa: E731
                extra.append(brentq(f, knots[j], knots[j + 1], xtol=1e-16, rtol=4 * np.finfo(float).eps))
        if extra:
            knots = np.sort(np.concatenate([knots, extra]))
            Y = sol(knots)
        # first crossing over all events
        best_t, best_i = None, None
        for i, (g, direction) in enumerate(events):
            vals = [g(knots[j], Y[:, j]) for j in range(knots.size)]
            for j in range(knots.size - 1):
                if best_t is not None and knots[j] >= best_t + 1e-13 * max(1.0, abs(best_t)):
                    break
                if _crossed(vals[j], vals[j + 1], direction):
                    if vals[j] == 0.0:
                        tr = knots[j]
                    else:
                        tr = brentq(
                            lambda t: g(t, sol(t)), knots[j], knots[j + 1], xtol=1e-16, rtol=4 * np.finfo(float).eps
                        )
                        # the root must lie on the post-crossing side (sign of the new value)
                        if not _crossed(vals[j], g(tr, sol(tr)), direction):
                            tr = np.nextafter(tr, knots[j + 1])
                    # simultaneous roots (within roundoff): the event listed first wins
                    if best_t is None or tr < best_t - 1e-13 * max(1.0, abs(tr)):
                        best_t, best_i = tr, i
                    break
        stop = tb if best_t is None else float(best_t)
        if on_output is not None and te_arr.size:
            last = best_t is None and solver.status == "finished"
            m = (te_arr >= ta) & ((te_arr < stop) | (last & (te_arr <= stop)))
            if np.any(m):
                on_output(m, te_arr[m], sol(te_arr[m]))
        if track_qmax:
            kk = knots[knots <= stop]
            qk, _ = qv(np.append(kk, stop), sol(np.append(kk, stop)))
            qmax = max(qmax, float(np.max(np.abs(qk))))
        if best_t is not None:
            return SegmentResult(stop, sol(stop), best_i, qmax)
        if solver.status == "finished":
            return SegmentResult(tb, solver.y.copy(), None, qmax)
