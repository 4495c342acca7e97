"""Pseudo-arclength continuation of periodic orbits in rotor speed, with step control through folds.

The branch is a curve H(x, n) = P(x; n) - x = 0 in (unknowns, speed). Coordinates are scaled,
z = (x / sc, n / SPEED_SCALE) with sc the unknowns' scales at the branch start, so one unit of arc
is about one branch amplitude or 1000 rpm. Predictor: tangent t (null vector of [H_x H_n], oriented
along the previous one). Corrector on (H(z) = 0, t . (z - z_pred) = 0), one period per iteration:
with the FMU's sensitivities H_x is exact at every iterate and the speed column is the last
point's, Broyden-updated; without them the whole Jacobian is Broyden-updated. Where that fails (a
kink of the map) Newton with a fresh speed column (or a fresh Jacobian) per iteration. At each
accepted point: DP (sensitivities, or central differences in the unknowns: max |q| has a kink at
half-wave symmetric orbits; or the map's own DP where it takes one, `state_jacobian`: the ring's
low-rank DP) and a forward difference in speed give the point's Floquet multipliers and the next
tangent. Step control: ds grows 1.4x
after an easy corrector (<= EASY_CORRECTOR iterations), halves after a failure or when a step
longer than ds_fold passes a fold (resolving its tip); the branch ends outside the speed range,
after max_points, when ds falls below ds_min, or when it closes on itself (an isola). Changes of
stability between neighbours are the branch's bifurcations: fold (det(DP - I) changes sign),
period doubling (det(DP + I) changes sign), Neimark-Sacker (the number of complex multipliers
outside the circle changes).
"""

from __future__ import annotations

import csv
from dataclasses import dataclass, field
from pathlib import Path
from typing import TYPE_CHECKING, Any, Callable

import numpy as np

from harness import digits
from harness.fmu.blade import SPEED_RANGE, FMUError
from harness.model.params import ParameterError
from harness.analysis.periodic.period_map import PeriodMap
from harness.analysis.periodic.shooting import at_bound, bounded, classify, fd_direction, images, multipliers, newton

if TYPE_CHECKING:  # extrema imports this module
    from harness.analysis.periodic.extrema import Extremum

SPEED_SCALE = 1000.0  # [rpm] per unit of arc
MAX_KINKS = 8  # kinks stepped past per direction of a branch
KINK_ALONG_SPEED = 0.2  # past a kink, Newton at a fixed speed only where the tangent runs this much along it
KINK_REACH = 0.2  # ... accepted this far (scaled) from the last point: at a kink the state may turn
# steeply (6-blade study ring at 7037 rpm: 0.10 within 3.3 rpm)
EASY_CORRECTOR = 6  # ds grows after a step whose corrector took at most this many iterations


@dataclass(frozen=True)
class ContinuationSettings:
    ds: float = 0.05  # first step (scaled arc)
    ds_min: float = 1e-4
    ds_max: float = 0.4
    max_points: int = 400
    max_corrector: int = 8
    ds_fold: float = 0.02  # a step that passes a fold is refused (and halved) while longer than this
    # a corrector that fails quasi-Newton is retried with a fresh Jacobian per iteration (one period
    # per unknown each: for a map of many unknowns a halved step is cheaper)
    fresh_fallback: bool = True
    # where ds falls below ds_min (a kink of the map: a contact opening or closing exactly at the
    # period's start, a grazing), steps of these lengths (scaled arc) are tried past it, the
    # corrector with a fresh Jacobian per iteration, accepted within half a step of the predictor;
    # then, where the branch runs along the speed, damped Newton at the predictor's speed, accepted
    # within max(3 steps, KINK_REACH) of the last point; the branch goes on from there (empty: it ends)
    kink_steps: tuple[float, ...] = ()


@dataclass
class BranchPoint:
    speed: float  # [rpm]
    x: np.ndarray
    amplitude: float  # max |q| [m]
    multipliers: np.ndarray
    iterations: int = 0  # corrector iterations

    @property
    def stable(self) -> bool:
        return bool(np.max(np.abs(self.multipliers)) < 1.0 - 1e-6)

    @property
    def label(self) -> str:
        return classify(self.multipliers)


@dataclass
class Branch:
    model: str
    points: list[BranchPoint] = field(default_factory=list)
    end_reasons: list[str] = field(default_factory=list)  # why each end of the branch stopped
    closed: bool = False  # an isola that closed on itself
    extrema: list[Extremum] = field(default_factory=list)  # located peaks and folds, arc order

    def located(self, kind: str) -> list[Extremum]:
        """The located extrema of one kind ("peak" or "fold")."""
        return [e for e in self.extrema if e.kind == kind]

    @property
    def speeds(self) -> np.ndarray:
        return np.array([p.speed for p in self.points])

    @property
    def amplitudes(self) -> np.ndarray:
        return np.array([p.amplitude for p in self.points])

    @property
    def stable(self) -> np.ndarray:
        return np.array([p.stable for p in self.points])

    def bifurcations(self) -> list[tuple[int, str]]:
        """(index of the first point after the change, kind) for every stability change."""
        out = []
        for i in range(1, len(self.points)):
            a, b = self.points[i - 1].multipliers, self.points[i].multipliers
            if self.points[i - 1].stable == self.points[i].stable and classify(a) == classify(b):
                continue
            kinds = []
            if np.sign(np.prod(np.real(a - 1.0))) != np.sign(np.prod(np.real(b - 1.0))):
                kinds.append("fold")
            if np.sign(np.prod(np.real(a + 1.0))) != np.sign(np.prod(np.real(b + 1.0))):
                kinds.append("period-doubling")
            na = sum(1 for m in a if abs(m.imag) > 1e-9 and abs(m) > 1)
            nb = sum(1 for m in b if abs(m.imag) > 1e-9 and abs(m) > 1)
            if na != nb:
                kinds.append("Neimark-Sacker")
            out.append((i, "+".join(kinds) or "stability change"))
        return out

    def contains(self, speed_rpm: float, amplitude: float, rtol: float = 1e-3) -> bool:
        """True if (speed, amplitude) lies on this branch: between two neighbouring points in speed,
        within rtol of the linearly interpolated amplitude (relative to the larger amplitude)."""
        pts = self.points
        for a, b in zip(pts[:-1], pts[1:]):
            lo, hi = min(a.speed, b.speed), max(a.speed, b.speed)
            if lo - 1e-9 <= speed_rpm <= hi + 1e-9:
                f = 0.0 if hi == lo else (speed_rpm - a.speed) / (b.speed - a.speed)
                amp = a.amplitude + f * (b.amplitude - a.amplitude)
                tol = rtol * max(a.amplitude, b.amplitude) + 0.5 * abs(b.amplitude - a.amplitude) * (hi > lo)
                if abs(amplitude - amp) <= max(tol, rtol * amplitude):
                    return True
        return any(
            abs(p.speed - speed_rpm) <= 1e-6 * speed_rpm and abs(p.amplitude - amplitude) <= rtol * amplitude
            for p in pts
        )


def write_branches_csv(path: Path, branches: list[Branch], columns: dict[str, list[Any]] | None = None) -> None:
    """One row per point: [extra columns,] branch, kind ("point": a continuation point; "peak",
    "fold": a located extremum, after the branch's points), model, speed [rpm], amplitude [m], B [m]
    (or empty), q0 [m], q0' [m/s], stable, label, |mu|max and the multipliers. `columns` maps a
    leading column's name to one value per branch (e.g. the study value). A fold's `stable` is 1 if
    it bounds a stable part of the branch. Numbers with harness.digits.SIGNIFICANT significant
    digits of their column's largest magnitude (the multipliers' scale: the unit circle)."""
    path = Path(path)
    path.parent.mkdir(parents=True, exist_ok=True)
    tmp = path.with_suffix(path.suffix + ".tmp")
    columns = columns or {}
    rows: list[tuple[int, str, BranchPoint | Extremum, str, list[Any]]] = []  # (branch, kind, point, label, lead)
    for i, br in enumerate(branches):
        lead = [columns[c][i] for c in columns]
        rows += [(i, "point", p, p.label, lead) for p in br.points]
        rows += [(i, e.kind, e, e.stability, lead) for e in br.extrema]
    has_B = [branches[i].model not in ("fixedB", "jenkins") for i, *_ in rows]
    tips = [tip_state(p.x) for _, _, p, _, _ in rows]
    num: dict[str, Any] = {
        "speed": digits.column(p.speed for _, _, p, _, _ in rows),
        "amplitude": digits.column(p.amplitude for _, _, p, _, _ in rows),
        "B": digits.column(p.x[-1] if b else 0.0 for (_, _, p, _, _), b in zip(rows, has_B)),
        "q0": digits.column(t[0] for t in tips),
        "v0": digits.column(t[1] for t in tips),
        "mu": digits.column(np.max(np.abs(p.multipliers)) for _, _, p, _, _ in rows),
        "lead": [
            digits.column(r[4][k] for r in rows) if rows and isinstance(rows[0][4][k], float) else None
            for k in range(len(columns))
        ],
    }
    e_mu = digits.exponent(1.0)
    with open(tmp, "w", newline="") as f:
        w = csv.writer(f)
        w.writerow(
            list(columns)
            + [
                "branch",
                "kind",
                "model",
                "speed_rpm",
                "amplitude_m",
                "B_m",
                "q0_m",
                "v0_m_s",
                "stable",
                "label",
                "mu_abs_max",
                "multipliers",
            ]
        )
        for j, (i, kind, p, label, lead) in enumerate(rows):
            lead_text = [num["lead"][k][j] if num["lead"][k] is not None else v for k, v in enumerate(lead)]
            mus = " ".join(_complex_text(m, e_mu) for m in p.multipliers)
            w.writerow(
                lead_text
                + [
                    i,
                    kind,
                    branches[i].model,
                    num["speed"][j],
                    num["amplitude"][j],
                    num["B"][j] if has_B[j] else "",
                    num["q0"][j],
                    num["v0"][j],
                    int(p.stable),
                    label,
                    num["mu"][j],
                    mus,
                ]
            )
    tmp.replace(path)


def _complex_text(z: complex, e: int | None) -> str:
    """a+bj with both parts rounded to 10^e (Python's complex() reads it back)."""
    im = digits.text(z.imag, e)
    return f"{digits.text(z.real, e)}{im if im.startswith('-') else '+' + im}j"


def tip_state(x: np.ndarray) -> tuple[float, float]:
    """(q0, q0') at the tip from a branch point's unknowns: 2m or 2m + 1 of them (period_map), the
    modal ones summed for m > 1."""
    m = len(x) // 2
    return (float(x[0]), float(x[1])) if m == 1 else (float(np.sum(x[:m])), float(np.sum(x[m : 2 * m])))


class JacobianMemo:
    """DP and dP/dn (physical units) where they were taken, found again at the same point (x and n
    equal within the rounding of a round trip through another branch problem's scaled coordinates,
    1e-12 relative): a peak's or a crossing's refinement, a branch switch and a continuation from a
    shot orbit start at a point whose DP was already taken. A period map carrying one as
    `jacobians` shares it among all its branch problems."""

    RTOL = 1e-12

    def __init__(self, size: int = 256):
        self.size = size
        self.items: list[tuple[np.ndarray, float, np.ndarray, np.ndarray | None]] = []  # (x, n, DP, dP/dn)

    def get(self, x: np.ndarray, n: float) -> tuple[np.ndarray, np.ndarray | None] | None:
        """(DP, dP/dn or None) taken at (x, n), or None."""
        for xi, ni, DP, dn in reversed(self.items):
            if abs(n - ni) <= self.RTOL * abs(ni) and np.all(np.abs(x - xi) <= self.RTOL * np.abs(xi)):
                return DP.copy(), None if dn is None else dn.copy()  # (a caller may change its copy)
        return None

    def put(self, x: np.ndarray, n: float, DP: np.ndarray, dn: np.ndarray | None = None) -> None:
        if len(self.items) >= self.size:
            self.items.pop(0)
        self.items.append((np.array(x, dtype=float), float(n), DP.copy(), None if dn is None else dn.copy()))


class BranchProblem:
    """H(z) in scaled coordinates for one branch."""

    def __init__(self, pm: PeriodMap, sc: np.ndarray):
        self.pm, self.sc = pm, sc
        self.m = pm.dim
        self.sens = pm.s.sensitivities
        # a period map without B in its unknowns may take forward differences (`central_differences`
        # False: the ring's, whose DP from forward and central differences agree to 1e-4)
        self.central = getattr(pm, "central_differences", True)
        self._last: tuple[np.ndarray, np.ndarray] | None = None  # (z, DP) of the last evaluation
        self.memo: JacobianMemo | None = getattr(pm, "jacobians", None)

    def to_z(self, x: np.ndarray, n: float) -> np.ndarray:
        return np.append(x / self.sc, n / SPEED_SCALE)

    def from_z(self, z: np.ndarray) -> tuple[np.ndarray, float]:
        return bounded(self.pm, z[:-1] * self.sc), float(z[-1] * SPEED_SCALE)

    def H(self, z: np.ndarray) -> tuple[np.ndarray, np.ndarray, float]:
        """(H(z) scaled, P(x), amplitude). P is evaluated at z moved into the unknowns' domain and
        compared with z itself, so a z outside (phi beyond the slip limit, phi != 0 while open) is
        pulled back by the residual."""
        x, n = self.from_z(z)
        Px, A = self.pm(x, n)
        if self.sens:
            DP = self.pm.DP
            assert DP is not None  # with sensitivities every evaluation sets DP
            self._last = (z.copy(), DP)
        return (Px - z[:-1] * self.sc) / self.sc, Px, A

    def Hs(self, zs: list[np.ndarray]) -> list[np.ndarray]:
        """H(z) scaled at every z (as `H` without sensitivities): the period map's images at once."""
        Ps = images(self.pm, [self.from_z(z) for z in zs])
        return [(Px - z[:-1] * self.sc) / self.sc for z, Px in zip(zs, Ps)]

    def state_columns(self, z: np.ndarray) -> np.ndarray | None:
        """dH/dz in the unknowns from the FMU's sensitivities of the last evaluation, if it was
        at z (else None): DP_ij sc_j / sc_i - delta_ij."""
        if self._last is None or not np.array_equal(self._last[0], z):
            return None
        cols: np.ndarray = self._last[1] * self.sc[None, :] / self.sc[:, None] - np.eye(self.m)
        return cols

    def speed_column(self, z: np.ndarray, Hz: np.ndarray) -> np.ndarray:
        """dH/dn (scaled) by a forward difference (backward at the top of the rotorSpeed range)."""
        eps = self.pm.s.fd_rel
        n = z[-1] * SPEED_SCALE
        h = eps * (1.0 if n * (1 + 2 * eps) <= SPEED_RANGE[1] else -1.0) * max(abs(z[-1]), 1e-3)
        zp = z.copy()
        zp[-1] += h
        x, n = self.from_z(zp)
        col: np.ndarray = ((self.pm(x, n, jacobian=False)[0] - zp[:-1] * self.sc) / self.sc - Hz) / h
        return col

    def jac(self, z: np.ndarray, Hz: np.ndarray, Px: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
        """(dH/dz (m x m+1), DP in physical units (m x m)): central differences in the unknowns
        (one-sided where an unknown sits on its bound, as in shooting.jacobian), forward in speed.
        Central, because max |q| is a kink at every half-wave symmetric orbit (the positive and the
        negative peak are equal): a one-sided DP picks one peak and misplaces the multipliers."""
        x, n = self.from_z(z)
        if self.sens:
            cols = self.state_columns(z)
            if cols is None:
                Hz, Px, _ = self.H(z)
                cols = self.state_columns(z)
            assert cols is not None and self._last is not None  # H(z) just evaluated at z
            DP = self._last[1]
            return np.column_stack([cols, self.speed_column(z, Hz)]), DP
        memo = self.memo
        known = memo.get(x, n) if memo is not None else None
        # dH/dz from the DP taken there: DP_ij sc_j / sc_i - delta_ij, dP/dn scaled
        if memo is not None and known is not None:
            DP, dn = known
            speed = self.speed_column(z, Hz) if dn is None else dn * SPEED_SCALE / self.sc
            if dn is None:
                memo.put(x, n, DP, speed * self.sc / SPEED_SCALE)
            return np.column_stack([DP * self.sc[None, :] / self.sc[:, None] - np.eye(self.m), speed]), DP
        eps = self.pm.s.fd_rel
        own = self._own_dp(z, x, n, Hz, Px)
        if own is not None:
            return own
        Jz = np.empty((self.m, self.m + 1))
        steps: list[tuple[float, bool]] = []  # per column: (h, central)
        zs: list[np.ndarray] = []  # the points, in order (a map with `images` runs them at once)
        for j in range(self.m + 1):
            # forward in speed, backward at the top of the FMU's rotorSpeed range
            sgn = fd_direction(self.pm, x, j) if j < self.m else (1.0 if n * (1 + 2 * eps) <= SPEED_RANGE[1] else -1.0)
            h = eps * sgn * (self.pm.scales(x, n)[j] / self.sc[j] if j < self.m else max(abs(z[-1]), 1e-3))
            zp = z.copy()
            zp[j] += h
            zs.append(zp)
            both = j < self.m and self.central and not at_bound(self.pm, x, j)
            if both:
                zm = z.copy()
                zm[j] -= h
                zs.append(zm)
            steps.append((h, both))
        Hs = iter(self.Hs(zs))
        for j, (h, both) in enumerate(steps):
            Hp = next(Hs)
            Jz[:, j] = (Hp - next(Hs)) / (2.0 * h) if both else (Hp - Hz) / h
        DP = (Jz[:, :-1] + np.eye(self.m)) * self.sc[:, None] / self.sc[None, :]
        if self.memo is not None:
            self.memo.put(x, n, DP, Jz[:, -1] * self.sc / SPEED_SCALE)
        return Jz, DP

    def _own_dp(
        self, z: np.ndarray, x: np.ndarray, n: float, Hz: np.ndarray, Px: np.ndarray
    ) -> tuple[np.ndarray, np.ndarray] | None:
        """(dH/dz, DP) from the map's own DP where it takes one (a method `state_jacobian` returning
        DP at (x, n, P(x)) and the images of extra points in the same batch: the ring's "low-rank"
        DP), the speed column a forward difference as `jac`'s; None where it has none."""
        own = getattr(self.pm, "state_jacobian", None)
        if own is None:
            return None
        eps = self.pm.s.fd_rel
        h = eps * (1.0 if n * (1 + 2 * eps) <= SPEED_RANGE[1] else -1.0) * max(abs(z[-1]), 1e-3)
        zp = z.copy()
        zp[-1] += h
        got = own(x, n, Px, [self.from_z(zp)])
        if got is None:
            return None
        DP, (Pn,) = got
        speed = ((Pn - zp[:-1] * self.sc) / self.sc - Hz) / h
        Jz = np.column_stack([DP * self.sc[None, :] / self.sc[:, None] - np.eye(self.m), speed])
        if self.memo is not None:
            self.memo.put(x, n, DP, speed * self.sc / SPEED_SCALE)
        return Jz, DP


def _tangent(Jz: np.ndarray, prev: np.ndarray | None) -> np.ndarray:
    _, _, Vt = np.linalg.svd(Jz)
    t = Vt[-1]
    if prev is not None and float(t @ prev) < 0:
        t = -t
    unit: np.ndarray = t / np.linalg.norm(t)
    return unit


def continue_branch(
    pm: PeriodMap,
    x: np.ndarray,
    speed_rpm: float,
    speed_range: tuple[float, float],
    settings: ContinuationSettings = ContinuationSettings(),
    directions: tuple[int, ...] = (-1, 1),
    stop: Callable[[BranchPoint], str | None] | None = None,
) -> Branch:
    """Trace the branch through the periodic orbit x at `speed_rpm` (a converged root of the period
    map) in both speed directions (or those in `directions`: -1 down, +1 up at the start) until it
    leaves speed_range (or stop(point) gives a reason to end there, e.g. it joined a branch traced
    before); returns the points ordered along the arc."""
    lo, hi = speed_range
    prob = BranchProblem(pm, pm.scales(x, speed_rpm))
    z0 = prob.to_z(x, speed_rpm)
    H0, P0, A0 = prob.H(z0)
    Jz0, DP0 = prob.jac(z0, H0, P0)
    t0 = _tangent(Jz0, None)
    if t0[-1] < 0:
        t0 = -t0  # +1: the direction of increasing speed at the start
    first = BranchPoint(float(speed_rpm), np.array(x, dtype=float), A0, multipliers(DP0), 0)
    down: list[BranchPoint] = []
    up: list[BranchPoint] = []
    reasons: list[str] = []
    closed = False
    for sgn in directions:
        pts, reason, closed = _march(prob, z0, sgn * t0, Jz0, (lo, hi), settings, z_first=z0, stop=stop)
        if sgn < 0:
            down = pts[::-1]
        else:
            up = pts
        reasons.append(f"{'down' if sgn < 0 else 'up'}: {reason}")
        if closed:
            break  # an isola: one direction went all the way round
    return Branch(pm.model, down + [first] + up, reasons, closed)


def _march(
    prob: BranchProblem,
    z: np.ndarray,
    t: np.ndarray,
    Jz: np.ndarray,
    rng: tuple[float, float],
    s: ContinuationSettings,
    z_first: np.ndarray,
    stop: Callable[[BranchPoint], str | None] | None = None,
) -> tuple[list[BranchPoint], str, bool]:
    pts: list[BranchPoint] = []
    kinks: list[str] = []  # kinks stepped past
    ds = s.ds
    lo, hi = rng
    while len(pts) < s.max_points:
        ok, z_new, t_new, Jz_new, point = _step(prob, z, t, Jz, ds, s)
        if ok and ds > s.ds_fold and t_new[-1] * t[-1] < 0.0:
            ok = False  # a fold passed (the speed turned back) with a long step: resolve its tip
        if not ok:
            ds *= 0.5
            if ds >= s.ds_min:
                continue
            jumped = _past_kink(prob, z, t, Jz, s) if len(kinks) < MAX_KINKS else None
            if jumped is None:
                return pts, _with(f"step size below {s.ds_min:g} at {z[-1] * SPEED_SCALE:.1f} rpm", kinks), False
            kinks.append(f"stepped past a kink at {z[-1] * SPEED_SCALE:.1f} rpm to {jumped[3].speed:.1f} rpm")
            z_new, t_new, Jz_new, point = jumped
            ds = s.ds
        assert point is not None  # a step that is ok has its point
        pts.append(point)
        if not lo <= point.speed <= hi:
            return pts, _with(f"left the speed range at {point.speed:.1f} rpm", kinks), False
        if len(pts) > 5 and np.linalg.norm(z_new - z_first) < 0.75 * ds:
            if kinks:  # past a kink it may have turned back along itself: trace the other way too
                return pts, _with("came back to its start", kinks), False
            return pts, "closed on itself (isola)", True
        why = stop(point) if stop is not None else None
        if why:
            return pts, _with(why, kinks), False
        z, t, Jz = z_new, t_new, Jz_new
        if point.iterations <= EASY_CORRECTOR:
            ds = min(ds * 1.4, s.ds_max)
    return pts, _with(f"{s.max_points} points", kinks), False


def _with(reason: str, kinks: list[str]) -> str:
    return "; ".join([*kinks, reason])


def _past_kink(
    prob: BranchProblem, z: np.ndarray, t: np.ndarray, Jz: np.ndarray, s: ContinuationSettings
) -> tuple[np.ndarray, np.ndarray, np.ndarray, BranchPoint] | None:
    """(z, tangent, dH/dz, point) a step of s.kink_steps past a kink the corrector could not
    cross, or None: the corrector from z + ds t with a fresh Jacobian per iteration, accepted if it
    ends within ds / 2 of its predictor (the branch through z, not another one)."""
    for ds in s.kink_steps:
        zp = z + ds * t
        try:
            done = correct(prob, zp, t, Jz, s, quasi=False)
        except (FMUError, ParameterError):
            continue
        if done is None or np.linalg.norm(done[0] - zp) > 0.5 * ds:
            continue
        zk, Hz, Px, A, it = done
        try:
            Jz_new, DP = prob.jac(zk, Hz, Px)
        except (FMUError, ParameterError):
            continue
        x, n = prob.from_z(zk)
        return zk, _tangent(Jz_new, t), Jz_new, BranchPoint(n, x, A, multipliers(DP), it)
    if abs(t[-1]) < KINK_ALONG_SPEED:
        return None
    for ds in s.kink_steps:  # Newton at the predictor's speed (damped, from the predictor's state)
        x0, n1 = prob.from_z(z + ds * t)
        try:
            sol = newton(prob.pm, x0, n1)
            if sol is None:
                continue
            zk = prob.to_z(sol.x, n1)
            if np.linalg.norm(zk - z) > max(3.0 * ds, KINK_REACH):
                continue  # another branch (or this one's image under a symmetry: 2 sqrt 2 away)
            Hz, Px, A = prob.H(zk)
            Jz_new, DP = prob.jac(zk, Hz, Px)
        except (FMUError, ParameterError):
            continue
        return zk, _tangent(Jz_new, t), Jz_new, BranchPoint(n1, sol.x, A, multipliers(DP), sol.iterations)
    return None


def _step(
    prob: BranchProblem, z: np.ndarray, t: np.ndarray, Jz: np.ndarray, ds: float, s: ContinuationSettings
) -> tuple[bool, np.ndarray, np.ndarray, np.ndarray, BranchPoint | None]:
    """One predictor-corrector step from the branch point z (tangent t, dH/dz Jz there). The
    corrector is first quasi-Newton: Jz updated by Broyden after every iteration (one period per
    iteration); where that fails (a kink of the map: an event appears or vanishes) Newton with a
    fresh finite-difference Jacobian per iteration. The Jacobian at the new point gives its
    multipliers and the next tangent."""
    fail = (False, z, t, Jz, None)
    zp = z + ds * t
    for quasi in (True, False) if s.fresh_fallback else (True,):
        try:
            done = correct(prob, zp, t, Jz, s, quasi)
        except (FMUError, ParameterError):  # the FMU refused the start, or the speed left its range
            done = None
        # a corrector that jumped to another branch or fell back onto the last point: the new
        # point must be about ds away
        if done is not None and 0.2 * ds <= np.linalg.norm(done[0] - z) <= 3.0 * ds:
            break
    else:
        return fail
    zk, Hz, Px, A, it = done
    try:
        Jz_new, DP = prob.jac(zk, Hz, Px)
    except (FMUError, ParameterError):
        return fail
    x, n = prob.from_z(zk)
    return True, zk, _tangent(Jz_new, t), Jz_new, BranchPoint(n, x, A, multipliers(DP), it)


def correct(
    prob: BranchProblem,
    zp: np.ndarray,
    t: np.ndarray,
    Jz: np.ndarray,
    s: ContinuationSettings,
    quasi: bool,
    fresh_start: bool = False,
) -> tuple[np.ndarray, np.ndarray, np.ndarray, float, int] | None:
    """Newton on (H(z) = 0, t . (z - zp) = 0) from the predictor zp: (z, H, P, amplitude,
    iterations) or None. quasi: Jz (with fresh_start a fresh Jacobian at zp instead), Broyden-updated;
    else a fresh Jacobian every iteration."""
    zk = zp.copy()
    Hz, Px, A = prob.H(zk)
    J = prob.jac(zk, Hz, Px)[0] if fresh_start and quasi else Jz.copy()
    for it in range(1, s.max_corrector + 1):
        if prob.sens:  # exact in the unknowns; the speed column from the last point, or fresh
            J[:, :-1] = prob.state_columns(zk)
            if not quasi:
                J[:, -1] = prob.speed_column(zk, Hz)
        elif not quasi:
            J = prob.jac(zk, Hz, Px)[0]
        G = np.append(Hz, t @ (zk - zp))
        try:
            dz = np.linalg.solve(np.vstack([J, t]), -G)
        except np.linalg.LinAlgError:
            return None
        zn = zk + dz
        if not np.all(np.isfinite(zn)):
            return None
        Hn, Px, A = prob.H(zn)
        if quasi:  # Broyden, in scaled coordinates (with sensitivities: its speed column counts)
            J = J + np.outer(Hn - Hz - J @ dz, dz) / float(dz @ dz)
        zk, Hz = zn, Hn
        if np.max(np.abs(Hz)) <= prob.pm.s.tol * 10:
            return zk, Hz, Px, A, it
    return None
