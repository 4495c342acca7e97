"""The ring's period map: its state at load phase 0 -> its state one excitation period later.

The state x (unknowns, `RingPeriodMap.dim` of them): per blade i its modal start state
(BladeExternalContact's modalDisplacement[1..m], modalVelocity[1..m] start values, m = `modes`), then
per contact j its Jenkins element as phi_j = F_j / L(u_j), the friction force over its slip limit
L = mu kn cos(gamma) (|u_j| - d) at u_j = q_j - q_{j+1} (tips), so the cone |phi| <= 1 does not move
when q is perturbed. While contact j is open its phi_j does not act (the start force is 0) and is set
to the value it takes on touching: closing (sigma u' > 0, sigma = sign u) the element arrives
sticking with F = kd sin(gamma) (u - sigma d), phi = sigma r, r = kd sin(gamma) / (mu kn cos(gamma)),
or sliding (r > 1) with phi = sigma; opening it slides away, phi = -sigma. So phi is continuous where
a contact opens or closes at the period's end (with phi = 0 while open the image would jump by up to
1 there and Newton and continuation stall at every speed where a gap crosses d at phase 0). Then
the master's extrapolation history before point 0 (p = the ring's order, h = T / K): every blade's
tip velocity v_i(t_{-1}), ..., v_i(t_{-p}), then every blade's contact-force sum f_i(t_{-1}), ...,
f_i(t_{-p}) (forceB of contact i - 1 plus forceA of contact i), each block (p, N) row by row
(`history`): what the C loop keeps in its History buffers and extrapolates the inputs' derivatives
from. dim = 2 m N + N + 2 p N (6 blades, 1 mode, p = 2: 42).

One evaluation is one period T = 60 / (EO rpm) of the same co-simulation the sweeps run (the C loop,
harness/system/ring_c.py): every FMU reset and initialised at t = 0 (load phase 0) with the ring's
parameters and the start state x (the contacts' frictionForce start value F_j = phi_j L(u_j)), the
master's history set to x's (CRing.set_history: p values back, so point 0 already extrapolates at
the full order p), K = steps_per_period steps on the exact grid t_k = k T / K (not the nanosecond
grid: the load's phase advances exactly 2 pi), then the state at T read back (the contacts' at the
inputs of point K, after their direct feedthrough; the history before point K, rows 1..p of the
buffers once point K has been pushed).

Why this is the continuous co-simulation's period-to-period map. What a run carries from point K
into its next step is exactly: the blades' modal states (their FMU state; the load phase psi is
integrated, and restarting it at 0 instead of 2 pi j after j periods changes sin(psi) by rounding
only), every
contact's Jenkins element after its projection to the inputs of point K (its slider w, fixed by the
friction force and u: F = kd (sin(gamma) u - w); open, sticking or on the cone), and the master's
History (the last p + 1 values of v and f; the newest, point K's own, is recomputed from the state
at point K, so p values back are the memory). The input derivatives at point K and after are then
the same numbers in a continuous run and in an evaluation from x, the FMUs' steps the same, so the
image equals the continuous run's state one period on, up to rounding in t_k = k h (k counts from
0 again) and psi, and to a contact on its cone restarting in stick with its slip direction set
(it leaves at the step's first instant). tests/system/test_ring_orbits.py runs the C loop on the
exact grid for several periods without a restart and maps each period's start: the images equal the
next period's start to 1e-12 of the scale (measured 3e-13 three periods in: the run's psi carries
the rounding of its steps; the same periods with the history dropped, the earlier restart at
phase 0, miss by 1.5e-5; 4 blades, 6000 rpm). Nothing else carries over between evaluations, so the
image is a function of x alone (the same test file: bit-identical images whatever ran before).

The amplitude of blade i is max |q_i| over the period, the largest of the K sampled points refined by
the parabola through it and its neighbours (the sweeps' measure, ring_sweep.window_amplitude, with
the period's points wrapped round).
"""

from __future__ import annotations

import math
import os
import threading
from concurrent.futures import ThreadPoolExecutor
from dataclasses import dataclass, replace
from typing import Any, Sequence

import numpy as np
from threadpoolctl import threadpool_limits

from harness.fmu.binding import FmiError
from harness.fmu.blade import FMUError
from harness.system.ring import Ring, RingDiverged
from harness.system.ring_c import CRing
from harness.system.ring_orbits.derivative import DP_MODES, LowRankDP
from harness.system.ring_orbits.restart import Reads, Restarts
from harness.system.ring_sweep import window_amplitude


DEFAULT_WORKERS = 2  # threads per DP by default (a 2-core machine: see bench/RESULTS.md)
MAX_WORKERS = 64


class RingMapFailed(FMUError):
    """An evaluation of the period map failed: an FMU refused the start state or the period
    (the Jacobi coupling diverged, a contact chattered)."""


@dataclass(frozen=True)
class RingShootingSettings:
    """Numerical settings of the ring's period map, Newton and the multipliers (the fields the
    single blade's Newton and continuation read: harness.analysis.periodic)."""

    steps_per_period: int = 160  # communication steps per period (as the sweeps)
    fd_rel: float = 1e-6  # finite-difference step relative to each unknown's scale
    tol: float = 1e-10  # Newton converged: max scaled residual |P(x) - x| / scale
    max_iter: int = 30
    sensitivities: bool = False  # DP by finite differences over the state (the FMUs' are not chained)
    # threads that run the periods of a finite-difference DP's columns (RingPeriodMap.images), each on
    # its own instances; None: min(DEFAULT_WORKERS, the machine's cores). 1 where processes already
    # share the cores (the mistuning study runs one ring per worker process)
    workers: int | None = None
    # the DP (monodromy matrix, the continuation's Jacobian): "full" forward differences over the state
    # (dim + 1 periods), or "low-rank" (about 2 m N + 8 periods, checked; derivative.py)
    dp: str = "full"

    def threads(self) -> int:
        """The number of threads `workers` asks for."""
        return self.workers if self.workers is not None else max(1, min(DEFAULT_WORKERS, os.cpu_count() or 1))

    def check(self) -> "RingShootingSettings":
        if self.dp not in DP_MODES:
            raise ValueError(f"RingShootingSettings.dp = {self.dp!r}: need one of {', '.join(map(repr, DP_MODES))}")
        w = self.workers
        if w is not None and not (isinstance(w, int) and not isinstance(w, bool) and 1 <= w <= MAX_WORKERS):
            raise ValueError(
                f"RingShootingSettings.workers = {w!r}: need None (min({DEFAULT_WORKERS}, the machine's cores)) "
                f"or a whole number in [1, {MAX_WORKERS}]"
            )
        if not (isinstance(self.steps_per_period, int) and 4 <= self.steps_per_period <= 100000):
            raise ValueError(f"steps_per_period = {self.steps_per_period!r}: need a whole number in [4, 100000]")
        for name, lo, hi in (("fd_rel", 1e-12, 1e-2), ("tol", 1e-15, 1e-3)):
            v = getattr(self, name)
            if not (isinstance(v, (int, float)) and lo <= v <= hi):
                raise ValueError(f"{name} = {v!r}: need a number in [{lo:g}, {hi:g}]")
        return self


class RingPeriodMap:
    """P(x; rpm) of a ring (harness.system.ring.Ring with the built-in load); use as a context
    manager (it keeps the ring's FMU instances open). Duck-types the single blade's PeriodMap for
    harness.analysis.periodic's Newton and continuation: dim, model, s, scales, bounded,
    fd_direction, at_bound, __call__."""

    model = "ring"
    DP = None  # no sensitivities: Newton and continuation take finite differences
    # forward differences suffice: no B among the unknowns (the single blade's max |q| kink); DP of
    # the 6-blade study ring at 5800 rpm from forward and central differences, fd_rel 1e-8..1e-4:
    # the same multipliers to 1e-4
    central_differences = False
    CACHE = 4096  # images kept (x, rpm) -> P(x): a repeated x (a clamped phi, an open contact's
    # phi column) costs no period

    def __init__(self, ring: Ring, settings: RingShootingSettings = RingShootingSettings()):
        if ring.coupling != "feedthrough":
            raise ValueError(f"coupling {ring.coupling!r}: the period map runs the Jacobi master's 'feedthrough'")
        self.s = settings.check()
        self.ring, self.n = ring, ring.n
        modes = {int(ring.blade_params(i).get("modes", 1)) for i in range(ring.n)}
        if len(modes) != 1:
            raise ValueError(f"modes {sorted(modes)}: every blade of the ring needs the same number of modes")
        self.m = modes.pop()
        self.p = ring.order
        self.nh = self.p * self.n  # values per history block
        self.dim = 2 * self.m * self.n + self.n + 2 * self.nh
        self._next = (np.arange(self.n) + 1) % self.n  # blade j + 1 of contact j (np.roll(q, -1) as an index)
        # each unknown's scale (`scales`): 0 a displacement, 1 a rate, 2 a phi, 3 a history force
        blade = [0] * self.m + [1] * self.m
        self._kinds = np.array(blade * self.n + [2] * self.n + [1] * self.nh + [3] * self.nh)
        self.evaluations = 0
        self._cr = CRing(ring, read_state=False)  # a period's record: q only
        self.blades, self.contacts = self._cr.blades, self._cr.contacts
        c0 = self.contacts[0]
        kn, kd_ratio, mu, gamma, d = c0.get(["kn", "kdRatio", "mu", "gamma", "d"])
        if int(c0.get(["frictionModel"])[0]) != 3:
            raise ValueError("the period map's contact state is the Jenkins element's: frictionModel must be 3")
        self.d, self.muKnCos, self.kn = float(d), float(mu * kn * math.cos(gamma)), float(kn)
        # phi of a contact arriving in stick (model-notes s.2: it sticks iff kd tan(gamma) <= mu kn)
        self.arrival = min(1.0, kd_ratio * kn * math.sin(gamma) / self.muKnCos) if self.muKnCos > 0 else 1.0
        names = [f"modalDisplacement[{k}]" for k in range(1, self.m + 1)] + [
            f"modalVelocity[{k}]" for k in range(1, self.m + 1)
        ]
        self._brestart = Restarts(
            [(b, ring.blade_instance_params(i)) for i, b in enumerate(self.blades)], names + ["rotorSpeed"]
        )
        cpar = {**dict(ring.contact), "engineOrder": ring.engine_order}
        self._crestart = Restarts(
            [(c, cpar) for c in self.contacts], ["frictionForce", "displacementA", "displacementB", "rotorSpeed"]
        )
        self._modal_names = names
        self._own_reads = (Reads(self.blades, names), Reads(self.contacts, ["frictionForce"]))
        # (x bytes, rpm) -> (P(x), per-blade max |q| [m], period residual max |P(x) - x| / scales)
        self.seen: dict[tuple[bytes, float], tuple[np.ndarray, np.ndarray, float]] = {}
        self.last: dict[str, np.ndarray] | None = None  # the last evaluation's record (q per point)
        self.workers = self.s.threads()
        self._helpers: list[RingPeriodMap] = []  # maps of the same ring on their own instances (images)
        self._pool: ThreadPoolExecutor | None = None
        self.low_rank = LowRankDP(self) if self.s.dp == "low-rank" else None
        self._blas: Any = None  # the BLAS thread limit while open as a context manager

    def __enter__(self) -> "RingPeriodMap":
        # BLAS on one thread while the map is open: its DPs, tangents and multipliers are small dense
        # problems between periods, and BLAS's idle threads spin on the cores the periods run on (6-blade
        # ring over 5500-7200 rpm on 2 cores: 173 -> 126 s CPU, the same periods and orbits)
        self._blas = threadpool_limits(limits=1, user_api="blas")
        return self

    def __exit__(self, *exc: object) -> None:
        self.close()

    def close(self) -> None:
        if self._blas is not None:
            self._blas.restore_original_limits()
            self._blas = None
        if self._pool is not None:
            self._pool.shutdown(wait=True)
            self._pool = None
        for h in self._helpers:
            h.close()
        self._helpers = []
        self._cr.__exit__(None, None, None)

    # --- the unknowns -------------------------------------------------------------------------
    def modal(self, x: np.ndarray) -> np.ndarray:
        """(N, 2m): blade i's q_1..q_m, q_1'..q_m'."""
        return np.asarray(x[: 2 * self.m * self.n]).reshape(self.n, 2 * self.m)

    def phi(self, x: np.ndarray) -> np.ndarray:
        k = 2 * self.m * self.n
        return np.asarray(x[k : k + self.n])

    def history(self, x: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
        """(v, f), each (p, N): row j - 1 the blades' tip velocities [m/s] and contact-force sums [N]
        at t_{-j}, j = 1..p (the master's history before point 0)."""
        k = 2 * self.m * self.n + self.n
        h = np.asarray(x[k:])
        return h[: self.nh].reshape(self.p, self.n), h[self.nh :].reshape(self.p, self.n)

    def tips(self, x: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
        """(q, q') at every blade's tip (the modal coordinates summed: every mode is 1 at the tip)."""
        y = self.modal(x)
        return y[:, : self.m].sum(axis=1), y[:, self.m :].sum(axis=1)

    def gaps(self, x: np.ndarray) -> np.ndarray:
        """u_j = q_j - q_{j+1} at the tips."""
        q = self.tips(x)[0]
        u: np.ndarray = q - q[self._next]
        return u

    def touching(self, x: np.ndarray) -> np.ndarray:
        """phi_j of every contact as it would touch (see the module docstring): sigma r closing,
        -sigma opening (only used while the contact is open)."""
        q, v = self.tips(x)
        u, du = q - q[self._next], v - v[self._next]
        sigma = np.where(u >= 0.0, 1.0, -1.0)
        return np.where(sigma * du > 0.0, sigma * self.arrival, -sigma)

    def limits(self, u: np.ndarray) -> np.ndarray:
        """L(u_j) = mu kn cos(gamma) (|u_j| - d) [N]; <= 0 where the contact is open."""
        limit: np.ndarray = self.muKnCos * (np.abs(u) - self.d)
        return limit

    def state(
        self,
        q_modal: np.ndarray,
        v_modal: np.ndarray,
        friction: np.ndarray,
        v_past: np.ndarray | None = None,
        f_past: np.ndarray | None = None,
    ) -> np.ndarray:
        """x from the blades' modal states (N, m) each, the contacts' friction forces [N] and the
        history before point 0 (v_past, f_past: (p, N), see `history`; None: zero, a ring at rest)."""
        y = np.hstack(
            [np.asarray(q_modal, float).reshape(self.n, self.m), np.asarray(v_modal, float).reshape(self.n, self.m)]
        )
        past = [np.zeros(self.nh) if a is None else np.asarray(a, float).reshape(self.nh) for a in (v_past, f_past)]
        return self._with_phi(np.concatenate([y.ravel(), np.zeros(self.n), *past]), friction)

    def _with_phi(self, x: np.ndarray, friction: np.ndarray) -> np.ndarray:
        """x with its phi from the contacts' friction forces [N] (the touching value where open)."""
        u = self.gaps(x)
        L = self.limits(u)
        k = 2 * self.m * self.n
        x[k : k + self.n] = np.where(
            np.abs(u) > self.d, np.asarray(friction, float) / np.where(L > 0, L, 1.0), self.touching(x)
        )
        return x

    def read(self, cr: CRing, v_past: np.ndarray | None = None, f_past: np.ndarray | None = None) -> np.ndarray:
        """x of a running ring right after a point pushed into its history (a run of the C loop
        stopped with `finish`: this map's own ring or another run of the same ring): blades' modal
        states, contacts' friction forces at their inputs, and the history before that point, the
        C loop's rows 1..p (right on the exact grid h = T / K) unless given (v_past, f_past)."""
        reads = (
            self._own_reads
            if cr is self._cr
            else (Reads(cr.blades, self._modal_names), Reads(cr.contacts, ["frictionForce"]))
        )
        ym, out = (r() for r in reads)
        if v_past is None or f_past is None:
            v, f = cr.history()
            v_past, f_past = v[1:], f[1:]
        # ym's rows are the blades' modal states in x's order (`state` without its reshaping)
        past = [np.asarray(a, float).reshape(self.nh) for a in (v_past, f_past)]
        x = np.concatenate([ym.ravel(), np.zeros(self.n), *past])
        return self._with_phi(x, out[:, 0])

    def bounded(self, x: np.ndarray) -> np.ndarray:
        """x moved into the domain: |phi_j| <= 1, phi_j its touching value while contact j is open."""
        x = np.array(x, dtype=float)
        open_ = np.abs(self.gaps(x)) <= self.d
        k = 2 * self.m * self.n
        x[k : k + self.n] = np.where(open_, self.touching(x), np.clip(x[k : k + self.n], -1.0, 1.0))
        return x

    def fd_direction(self, x: np.ndarray, j: int) -> float:
        """+1, or -1 for a phi at its upper half (a forward step could leave the cone)."""
        return -1.0 if self._is_phi(j) and x[j] > 0.0 else 1.0

    def at_bound(self, x: np.ndarray, j: int) -> bool:
        return self._is_phi(j) and abs(x[j]) >= 1.0

    def _is_phi(self, j: int) -> bool:
        k = 2 * self.m * self.n
        return k <= j < k + self.n

    def omega(self, rpm: float) -> float:
        return self.ring.engine_order * 2.0 * math.pi * rpm / 60.0

    def scales(self, x: np.ndarray, speed: float) -> np.ndarray:
        """S for every displacement, S omega for every rate (the history's velocities too), 1 for
        every phi, kn S for the history's forces (the contact's normal force at a penetration S, or
        the largest force there if above); S the largest tip or modal displacement (or rate /
        omega), at least the gap d."""
        w = self.omega(speed)
        q, v = self.tips(x)
        a = np.abs(x)  # (one abs, then the maxima of its parts)
        k, m = 2 * self.m * self.n, self.m
        y = a[:k].reshape(self.n, 2 * m)
        vp, fp = a[k + self.n : k + self.n + self.nh], a[k + self.n + self.nh :]
        S = max(
            float(np.abs(q).max()),
            float(np.abs(v).max()) / w,
            float(y[:, :m].max()),
            float(y[:, m:].max()) / w,
            float(vp.max(initial=0.0)) / w,
            self.d,
            1e-9,
        )
        F = max(self.kn * S, float(fp.max(initial=0.0)))
        out: np.ndarray = np.array([S, S * w, 1.0, F])[self._kinds]
        return out

    # --- one period ---------------------------------------------------------------------------
    def _start(self, x: np.ndarray, rpm: float) -> None:
        y = self.modal(x)
        q = self.tips(x)[0]
        qn = q[self._next]
        u = q - qn
        F = np.where(np.abs(u) > self.d, np.clip(self.phi(x), -1.0, 1.0) * self.limits(u), 0.0)  # in the cone
        self._brestart.starts[:, :-1] = y
        self._brestart.starts[:, -1] = rpm
        self._brestart()
        starts = self._crestart.starts
        starts[:, 0], starts[:, 1], starts[:, 2], starts[:, 3] = F, q, qn, rpm
        self._crestart()

    def _args(self, x: np.ndarray, speed: float) -> tuple[np.ndarray, float]:
        x = np.asarray(x, dtype=float)
        rpm = float(speed)
        if not (math.isfinite(rpm) and rpm > 0.0) or not np.all(np.isfinite(x)) or len(x) != self.dim:
            raise RingMapFailed(f"period map at {rpm!r} rpm: need a positive speed and {self.dim} finite unknowns")
        return x, rpm

    def _period(self, x: np.ndarray, rpm: float) -> tuple[np.ndarray, np.ndarray, dict[str, np.ndarray]]:
        """(P(x), per-blade max |q| [m], the period's record) on this map's own instances: neither
        counted nor kept (a helper of `images` runs it on its thread)."""
        K = self.s.steps_per_period
        T = 60.0 / (self.ring.engine_order * rpm)
        try:
            self._start(x, rpm)
            self._cr.rpm = rpm
            self._cr.restart_exact(T / K)
            self._cr.set_history(*self.history(x))
            rec = self._cr.advance(K, rpm, finish=True, records=("q",))
        except (FmiError, RingDiverged, RuntimeError) as e:
            raise RingMapFailed(f"period map at {rpm:.6g} rpm: {e}") from e
        Px = self.read(self._cr)
        q = rec["q"]
        amp = window_amplitude(np.vstack([q[K - 1], q[:K], q[0]]))
        return Px, amp, rec

    def _keep(self, x: np.ndarray, rpm: float, Px: np.ndarray, amp: np.ndarray, rec: dict[str, np.ndarray]) -> None:
        if len(self.seen) >= self.CACHE:
            self.seen.pop(next(iter(self.seen)))
        self.seen[(x.tobytes(), rpm)] = (Px.copy(), amp, float(np.max(np.abs(Px - x) / self.scales(x, rpm))))
        self.last = rec

    def __call__(self, x: np.ndarray, speed: float, jacobian: bool = True) -> tuple[np.ndarray, float]:
        """(P(x), the largest blade's max |q| over the period [m]); the per-blade amplitudes and the
        scaled residual are kept in `seen` under (x bytes, speed). Raises RingMapFailed if an FMU refuses the start
        state or the period. `jacobian` is accepted for the single blade's interface (unused)."""
        x, rpm = self._args(x, speed)
        key = (x.tobytes(), rpm)
        if key in self.seen:
            Px, amp, _ = self.seen[key]
            return Px.copy(), float(amp.max())
        self.evaluations += 1
        Px, amp, rec = self._period(x, rpm)
        self._keep(x, rpm, Px, amp, rec)
        return Px, float(amp.max())

    def images(self, points: Sequence[tuple[np.ndarray, float]]) -> list[np.ndarray]:
        """[P(x) for every (x, speed)], the same numbers, count and `seen` as calling the map on each
        in turn (the columns of a finite-difference DP): the periods not known are run on `workers`
        threads, this map's instances and those of workers - 1 helper maps of the same ring (made on
        first use, closed with this map; ctypes releases the GIL in the FMUs' and the C loop's calls,
        which keep no global state). An image is a function of x alone (the module docstring), so
        whichever instances run it give it bit for bit. The first failing point, in order, raises
        RingMapFailed after the points before it are kept; every period that ran is counted."""
        args = [self._args(x, n) for x, n in points]
        keys = [(x.tobytes(), rpm) for x, rpm in args]
        todo: dict[tuple[bytes, float], int] = {}  # unknown image -> its first index
        for i, k in enumerate(keys):
            if k not in self.seen and k not in todo:
                todo[k] = i
        if self.workers <= 1 or len(todo) <= 1:
            return [self(x, rpm)[0] for x, rpm in args]
        known = {k: self.seen[k][0].copy() for k in keys if k not in todo}
        order = list(todo.values())
        done = self._run(order, args)
        out: list[np.ndarray] = []
        for i, k in enumerate(keys):
            if k in known:
                out.append(known[k].copy())
                continue
            first = todo[k]
            if first == i:
                result = done[first]
                if isinstance(result, RingMapFailed):
                    raise result
                Px, amp, rec = result
                self._keep(*args[first], Px, amp, rec)
                known[k] = Px
            out.append(known[k].copy())
        return out

    def _run(self, order: list[int], args: list[tuple[np.ndarray, float]]) -> dict[int, Any]:
        """index -> (P(x), amplitudes, record) or the RingMapFailed of every index in `order` run (on
        the threads; none after a failed one); counts the periods run."""
        if self._pool is None:
            self._helpers = [RingPeriodMap(self.ring, replace(self.s, workers=1)) for _ in range(self.workers - 1)]
            self._pool = ThreadPoolExecutor(max_workers=len(self._helpers), thread_name_prefix="ring-period")
        lock = threading.Lock()
        queue = iter(order)
        done: dict[int, Any] = {}
        failed = [len(args)]  # the first failed index so far

        def drain(pm: RingPeriodMap) -> None:
            while True:
                with lock:
                    i = next(queue, None)
                    if i is None or i > failed[0]:
                        return
                    self.evaluations += 1
                try:
                    r: Any = pm._period(*args[i])
                except RingMapFailed as e:
                    r = e
                    with lock:
                        failed[0] = min(failed[0], i)
                done[i] = r

        futures = [self._pool.submit(drain, h) for h in self._helpers]
        try:
            drain(self)
        except BaseException:
            failed[0] = -1  # (an interrupt) the helpers take no more
            raise
        finally:
            for f in futures:
                f.result()
        return done

    def state_jacobian(
        self, x: np.ndarray, speed: float, Px: np.ndarray, extra: Sequence[tuple[np.ndarray, float]] = ()
    ) -> tuple[np.ndarray, list[np.ndarray]] | None:
        """(DP at x in physical units, the images of `extra` run in the same batch) as `settings.dp`
        says, for Newton's and the continuation's DPs (harness.analysis.periodic); None for "full":
        the caller takes its own forward differences (the default path, unchanged)."""
        if self.low_rank is None:
            return None
        return self.low_rank(np.asarray(x, dtype=float), float(speed), Px, extra)

    def measures(self, x: np.ndarray, speed: float) -> tuple[np.ndarray, float]:
        """(per-blade max |q| over the period [m], scaled period residual) of x at speed (one
        evaluation unless known)."""
        key = (np.asarray(x, dtype=float).tobytes(), float(speed))
        if key not in self.seen:
            self(x, speed)
        return self.seen[key][1:]
