"""DP of the ring's period map (the monodromy matrix at an orbit, the continuation's Jacobian): full
forward differences, or a low-rank DP from directional differences in the row space of a DP taken
before, checked.

"full" (`RingShootingSettings.dp`, the default): one forward difference per unknown, one period
each, backward for a phi in its upper half (a forward step could leave the cone |phi| <= 1), none
for an open contact's phi (it does not act: the column is 0): up to dim + 1 periods, 43 on 6 blades.

"low-rank". Why: DP of the ring's map has a small numerical rank. Scaled (D = S^-1 DP S, S the
unknowns' scales, `RingPeriodMap.scales`), the tuned 6-blade study ring's DP (42 unknowns) at its
orbits at 5800 and 7000 rpm has 12 = 2 m N singular values between 1 and 0.024 of the largest, the
13th 7.8e-11 (5800 rpm) and 6.7e-8 (7000 rpm), the rest below 4e-10: one period later the ring has
forgotten most of its start. The columns of the history's tip velocities and of a sliding or open
contact's phi are 0 (exactly, where no contact is closed at phase 0); the blades' modal state and the
history's contact forces act, but only through 2 m N combinations (the blades' states after the
first steps). So DP = (DP V) V^T with V an orthonormal basis of D's row space: k directional
differences instead of dim columns. That row space turns with the speed (6e-5 rad per rpm on the
study ring, all 12 principal angles alike: the step T / K enters every blade's first step) and with
the state, so a DP's basis is predicted, checked, and completed where the check fails:
- the basis: of the last MEMORY DPs taken on the map (full or low-rank), the one nearest to (x, n)
  (scaled as the continuation's coordinates); its right singular vectors above RANK_RTOL of the
  largest, moved along the chord from the kept DP nearest to it (linear extrapolation of the
  subspace after a Procrustes alignment, at most EXTRAPOLATE chords: the angle left is 10 to 100
  times smaller than the stale one's), plus its next MARGIN vectors; carried as covectors S^-1 V
  to the new point's scales; restricted to the unknowns whose columns acted in that DP (the
  "acting" ones) and that the full differences perturb here (not an open contact's phi); a phi
  within a step of its slip limit, where a step must go inward, is a coordinate column of its own;
- the check: PROBES random unit directions (seeded per map) on the acting unknowns orthogonal to
  the basis, and PROBES on the unknowns that did not act, in the same batch of periods (on the
  map's threads); each scaled image |D r| must stay below CHECK_RTOL of D's largest singular value
  (a direction the basis misses shows with its singular value times the probe's share of it);
- both pass: the low-rank DP (6 blades: 14 directions and 6 probes, 20 periods); a probe of the
  basis fails (the row space turned further): the rest of the acting unknowns' space orthogonal to
  the directions taken is added, an exact DP over the acting unknowns (6 blades, no contact closed:
  24 + 6 periods); a probe of the unknowns that did not act fails (a contact began to stick or
  closed), or there is no DP kept yet: the full differences (which give the next basis).
The truncation's error is the singular values left out and the unchecked rest: below CHECK_RTOL
(times about the square root of the probed room), against the full differences' own spread of
1.9e-6 (forward against central differences, 4-blade ring); measured against the full DP at the same
orbits: 1e-6..2e-5 of the largest singular value (tests/system/test_ring_low_rank_dp.py).
The gain (bench/RESULTS.md, the 6-blade study ring over 4000-9000 rpm, both modes in one run): a DP
27 periods on average (1111 low-rank, 1681 over the acting unknowns, 96 full), 101.1 periods per
continuation point against 127.8, the same largest stable state; 133 s wall against 191 s on a
quiet machine (1.43x). The branches it finds are not the full
differences' list: where a branch meets a kink of the map the corrector crosses it with one DP and
not with the other (over 5000-7500 rpm it missed 8 of the 314 stable states on a 10 rpm grid
the full differences found, at 5520-5640 and 6170-6180 rpm): opt-in, not the study's default.
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import TYPE_CHECKING, Sequence

import numpy as np

if TYPE_CHECKING:  # the period map builds one of these
    from harness.system.ring_orbits.period_map import RingPeriodMap

DP_MODES = ("full", "low-rank")
RANK_RTOL = 1e-6  # a right singular vector joins the basis with singular value above this of the largest
MARGIN = 2  # the next right singular vectors join too (a direction just emerging from the noise)
PROBES = 3  # random directions checked per low-rank DP: on the acting unknowns off the basis, and on the others
CHECK_RTOL = 1e-5  # a probe's scaled image must stay below this of the largest singular value
EXTRAPOLATE = 3.0  # the basis is moved at most this many chords (between the two kept DPs it is moved from)
MEMORY = 8  # DPs whose row spaces are kept (the basis is the nearest one's)
SPEED_STEP = 1000.0  # [rpm] per unit of the distance to a kept DP (the continuation's SPEED_SCALE)
SEED = 20261127  # the probes' random generator (per map: the same calls draw the same probes)

Points = Sequence[tuple[np.ndarray, float]]


def forward_differences(
    pm: "RingPeriodMap", x: np.ndarray, speed: float, Px: np.ndarray, extra: Points = ()
) -> tuple[np.ndarray, list[np.ndarray]]:
    """(DP at x by forward differences over the state, in physical units; the images of `extra`,
    run in the same batch on the map's threads): one period per acting column (see the module
    docstring)."""
    sc = pm.scales(x, speed)
    J = np.zeros((pm.dim, pm.dim))
    cols: list[tuple[int, float, np.ndarray]] = []  # (column, step, x + step e_j)
    for j in range(pm.dim):
        h = pm.s.fd_rel * sc[j] * pm.fd_direction(x, j)
        xp = x.copy()
        xp[j] += h
        if pm.bounded(xp)[j] != xp[j]:
            continue  # an open contact's phi: it does not act (the column is 0, as the continuation's)
        cols.append((j, h, xp))
    P = pm.images([(xp, speed) for _, _, xp in cols] + list(extra))
    for (j, h, _), Pp in zip(cols, P):
        J[:, j] = (Pp - Px) / h
    return J, P[len(cols) :]


@dataclass
class _Basis:
    """The row space of a DP taken at (x, speed): covectors S^-1 V (dim, k), the first r significant."""

    x: np.ndarray
    speed: float
    rows: np.ndarray
    r: int
    acting: np.ndarray  # (dim,) the unknowns whose columns acted


class LowRankDP:
    """The "low-rank" DP of one period map (see the module docstring): call it at (x, speed, P(x));
    it keeps the basis of the last DP it took, its counts and the last check's result."""

    def __init__(self, pm: "RingPeriodMap"):
        self.pm = pm
        self.memory: list[_Basis] = []  # the last MEMORY DPs' row spaces
        self.rng = np.random.default_rng(SEED)
        self.counts = {
            "full": 0,
            "low-rank": 0,
            "acting": 0,
            "failed check": 0,
        }  # DPs taken (failed checks among the full)
        self.periods = 0  # periods spent on DPs (with the batch's extra points)
        self.outcome = ""  # what the last call did: "low-rank", else full ("no basis", "failed check")
        self.worst = float("nan")  # the last check's largest probe image over the largest singular value
        self.directions = 0  # the last low-rank DP's periods (basis directions and probes)

    def __call__(
        self, x: np.ndarray, speed: float, Px: np.ndarray, extra: Points = ()
    ) -> tuple[np.ndarray, list[np.ndarray]]:
        """(DP at x in physical units, the images of `extra` run in the same batch)."""
        e0 = self.pm.evaluations
        got = None
        if not self.memory:
            self.outcome = "no basis"
        else:
            got = self._low_rank(x, speed, Px, extra)
        if got is None:  # (after a failed check the extra points' images are known: no period)
            got = forward_differences(self.pm, x, speed, Px, extra)
            self.counts["full"] += 1
        else:
            self.counts[self.outcome] += 1
        self.learn(got[0], x, speed)
        self.periods += self.pm.evaluations - e0
        return got

    def summary(self) -> dict[str, int]:
        """The DPs taken by kind (full ones with the failed checks among them) and their periods."""
        return {**self.counts, "periods": self.periods}

    def forget(self) -> None:
        """Drop every basis kept (the next DP is a full one)."""
        self.memory.clear()

    def learn(self, J: np.ndarray, x: np.ndarray, speed: float) -> None:
        """Keep the row space of DP J taken at (x, speed) (its right singular vectors above RANK_RTOL
        and MARGIN more, as covectors) and the unknowns whose columns act, among the last MEMORY."""
        sc = self.pm.scales(x, speed)
        D = J * sc[None, :] / sc[:, None]
        _, s, Vt = np.linalg.svd(D)
        if not s[0] > 0.0:
            return
        r = int(np.sum(s > RANK_RTOL * s[0]))
        k = min(len(s), r + MARGIN)
        acting = np.linalg.norm(D, axis=0) > RANK_RTOL * s[0]
        self.memory = [
            *self.memory[1 - MEMORY :],
            _Basis(np.array(x, dtype=float), float(speed), Vt[:k].T / sc[:, None], r, acting),
        ]

    @property
    def acting(self) -> np.ndarray | None:
        """The unknowns whose columns acted in the last DP taken (None before the first)."""
        return self.memory[-1].acting if self.memory else None

    def nearest(self, x: np.ndarray, speed: float) -> tuple[_Basis, _Basis | None]:
        """The kept basis nearest to (x, speed) (in the continuation's scaled coordinates: x / scale,
        speed / 1000 rpm), and the one nearest to it at another speed with the same rank (None if
        there is none): the pair the basis is moved along the speed from."""
        sc = self.pm.scales(x, speed)

        def far(b: _Basis, y: np.ndarray, n: float) -> float:
            return float(np.linalg.norm((b.x - y) / sc) + abs(b.speed - n) / SPEED_STEP)

        a = min(self.memory, key=lambda b: far(b, x, speed))
        others = [b for b in self.memory if b.r == a.r and abs(b.speed - a.speed) > 1e-9 * abs(a.speed)]
        return a, min(others, key=lambda b: far(b, a.x, a.speed), default=None)

    def predicted(self, x: np.ndarray, speed: float) -> tuple[np.ndarray, np.ndarray]:
        """(the basis at (x, speed), scaled by its scales, not yet restricted; the unknowns that act):
        the nearest kept DP's row space, its significant part moved along the speed as from the
        kept DP nearest to it (the row space turns with the speed, by about 6e-5 rad per rpm on the
        study ring: the step T / K enters every blade's first step; the angle left after the move
        is about 50 times smaller), and its MARGIN vectors."""
        sc = self.pm.scales(x, speed)
        a, b = self.nearest(x, speed)
        B = sc[:, None] * a.rows
        if b is None or a.r == 0:
            return B, a.acting
        Q1, Q0 = np.linalg.qr(B[:, : a.r])[0], np.linalg.qr(sc[:, None] * b.rows[:, : b.r])[0]
        U, _, Vt = np.linalg.svd(Q0.T @ Q1)
        Q0 = Q0 @ (U @ Vt)  # the other basis of its subspace closest to the nearest one's (Procrustes)
        # how far (x, speed) lies along the chord from b to a, in units of the chord (scaled coordinates)
        ab = np.append((a.x - b.x) / sc, (a.speed - b.speed) / SPEED_STEP)
        t = float(np.append((x - a.x) / sc, (speed - a.speed) / SPEED_STEP) @ ab) / float(ab @ ab)
        t = min(max(t, -EXTRAPOLATE), EXTRAPOLATE)
        return np.hstack([Q1 + t * (Q1 - Q0), B[:, a.r :]]), a.acting

    def _low_rank(
        self, x: np.ndarray, speed: float, Px: np.ndarray, extra: Points
    ) -> tuple[np.ndarray, list[np.ndarray]] | None:
        """The checked low-rank DP (outcome "low-rank"), or the acting unknowns' DP where only the
        basis probes fail ("acting"), or None where a probe of the other unknowns fails ("failed check")."""
        pm = self.pm
        B, acting = self.predicted(x, speed)
        sc = pm.scales(x, speed)
        eps = pm.s.fd_rel
        k0 = 2 * pm.m * pm.n  # the first phi
        phis = np.arange(k0, k0 + pm.n)
        free = np.ones(pm.dim, dtype=bool)
        free[phis] = np.abs(pm.gaps(x)) > pm.d  # an open contact's phi does not act
        near = np.zeros(pm.dim, dtype=bool)  # a phi a step could push out of the cone: stepped inward
        near[phis] = free[phis] & (np.abs(x[phis]) > 1.0 - 2.0 * eps)
        acting = acting & free
        inner = acting & ~near  # the basis' unknowns
        own = np.flatnonzero(acting & near)  # an acting phi at its limit: a coordinate column of its own
        B[~inner] = 0.0
        Q = _orthonormal(B)
        E = np.zeros((pm.dim, len(own)))
        E[own, np.arange(len(own))] = 1.0
        Ra = self._probes(inner, Q)
        Ri = self._probes(free & ~acting, np.zeros((pm.dim, 0)))
        dirs = np.hstack([Q, E, Ra, Ri])
        dirs[near] = np.abs(dirs[near]) * np.where(x[near] > 0.0, -1.0, 1.0)[:, None]  # inward (as fd_direction)
        k, ka = Q.shape[1] + E.shape[1], Ra.shape[1]
        Y, P = self._images(x, speed, Px, dirs, extra)
        top = float(np.linalg.norm(Y[:, :k], 2)) if k else 0.0
        if not top > 0.0:
            self._failed(np.inf)
            return None
        outside = np.linalg.norm(Y[:, k + ka :], axis=0) / top  # the unknowns that did not act
        basis = np.linalg.norm(Y[:, k : k + ka], axis=0) / top  # the acting ones outside the basis
        self.worst = float(max(np.max(outside, initial=0.0), np.max(basis, initial=0.0)))
        if np.max(outside, initial=0.0) > CHECK_RTOL:
            self._failed(self.worst)
            return None
        D = Y[:, : k + ka] @ dirs[:, : k + ka].T  # (D V) V^T, scaled
        self.directions = dirs.shape[1]
        if np.max(basis, initial=0.0) > CHECK_RTOL:
            # the row space moved: the rest of the acting unknowns' space, orthogonal to the directions taken
            rest = _complement(np.hstack([Q, Ra]), inner)
            Yr, _ = self._images(x, speed, Px, rest, ())
            D = D + Yr @ rest.T
            self.directions += rest.shape[1]
            self.outcome = "acting"
        else:
            self.outcome = "low-rank"
        return sc[:, None] * D / sc[None, :], P

    def _probes(self, where: np.ndarray, Q: np.ndarray) -> np.ndarray:
        """PROBES random unit directions on the unknowns `where`, orthonormal and orthogonal to Q
        (fewer where the room is smaller)."""
        room = int(np.sum(where)) - Q.shape[1]
        if room <= 0:
            return np.zeros((self.pm.dim, 0))
        R = self.rng.standard_normal((self.pm.dim, min(PROBES, room)))
        R[~where] = 0.0
        R -= Q @ (Q.T @ R)
        return _orthonormal(R)

    def _images(
        self, x: np.ndarray, speed: float, Px: np.ndarray, dirs: np.ndarray, extra: Points
    ) -> tuple[np.ndarray, list[np.ndarray]]:
        """(scaled directional differences D d for every column d of dirs, the images of `extra`):
        steps of fd_rel in the scaled unknowns, one period each, on the map's threads."""
        pm = self.pm
        sc = pm.scales(x, speed)
        eps = pm.s.fd_rel
        P = pm.images([(x + eps * sc * d, speed) for d in dirs.T] + list(extra))
        n = dirs.shape[1]
        Y = (np.array(P[:n]).reshape(n, pm.dim).T - Px[:, None]) / (eps * sc[:, None])
        return Y, P[n:]

    def _failed(self, worst: float) -> None:
        self.worst = worst
        self.outcome = "failed check"
        self.counts["failed check"] += 1


def _orthonormal(B: np.ndarray) -> np.ndarray:
    """An orthonormal basis of B's columns (those of its singular values above 1e-8 of the largest)."""
    if B.shape[1] == 0:
        return B
    U, s, _ = np.linalg.svd(B, full_matrices=False)
    return U[:, s > 1e-8 * s[0]] if s[0] > 0.0 else U[:, :0]


def _complement(Q: np.ndarray, where: np.ndarray) -> np.ndarray:
    """An orthonormal basis of the unknowns `where` orthogonal to Q's columns (which lie there)."""
    I = np.eye(len(where))[:, where]
    return _orthonormal(I - Q @ (Q.T @ I))
