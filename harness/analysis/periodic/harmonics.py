"""How far the one-harmonic balance is from the exact periodic orbit: the orbit's Fourier content.

An orbit (a root of the period map) is sampled by the FMU at N equidistant points of one period,
started on it (its start values; inside one period the tracked-amplitude model is the fixed-B
model, so the samples are the orbit). Its discrete Fourier series q(t) = sum_k a_k sin(k w t +
phi_k) gives the first-harmonic amplitude a1 and the higher harmonics' amplitude
h = sqrt(sum_{k>=2} a_k^2) (sqrt 2 times their RMS). The harmonic balance (harness.analysis.harmonic_balance:
one harmonic, gating off) is compared with a1 and with max |q|: ungated, the fixed-B ODE is linear,
h = 0 and HB equals the orbit (tests/analysis/test_periodic.py); gated, and for the Jenkins element, h
measures what one harmonic cannot hold.
"""

from __future__ import annotations

import math
from dataclasses import asdict, dataclass
from typing import Any, Mapping, Sequence

import numpy as np

from harness.analysis.periodic.period_map import PeriodMap, omega
from harness.analysis.periodic.continuation import Branch
from harness.analysis.harmonic_balance import harmonic_balance

SAMPLES = 128  # points per period: harmonics up to 63 resolved; the orbits' content above 20 is < 1e-6


@dataclass(frozen=True)
class HarmonicRow:
    model: str
    speed: float  # [rpm]
    stable: bool
    amplitude: float  # max |q| of the orbit (located extremum) [m]
    a1: float  # first-harmonic amplitude [m]
    higher: float  # h = sqrt(sum_{k>=2} a_k^2) [m]
    a3: float  # third harmonic, the largest of the odd-symmetric orbit's higher ones [m]
    hb: float  # one-harmonic balance contact root B nearest a1 (nan if HB has none) [m]

    @property
    def higher_rel(self) -> float:
        return self.higher / self.amplitude

    @property
    def hb_vs_a1(self) -> float:
        return (self.hb - self.a1) / self.a1

    @property
    def hb_vs_amplitude(self) -> float:
        return (self.hb - self.amplitude) / self.amplitude

    def as_dict(self) -> dict[str, Any]:
        return dict(
            asdict(self), higher_rel=self.higher_rel, hb_vs_a1=self.hb_vs_a1, hb_vs_amplitude=self.hb_vs_amplitude
        )


def fourier_amplitudes(q: np.ndarray) -> np.ndarray:
    """a_k, k = 0..N/2 - 1, of N equidistant samples of one period (a_0 the mean)."""
    c = np.fft.rfft(np.asarray(q, dtype=float)) / len(q)
    a = 2.0 * np.abs(c)
    a[0] = abs(c[0].real)
    return a[: len(q) // 2]


def orbit_samples(pm: PeriodMap, x: np.ndarray, speed_rpm: float, n: int = SAMPLES) -> np.ndarray:
    """q at t = k T / n, k = 0..n - 1, by the FMU started on the orbit through x at load phase 0."""
    T = 2.0 * math.pi / omega(pm.p, speed_rpm)
    r = pm.fmu.run(
        dict(pm.p, **pm.start_values(x)),
        T,
        T / n,
        speed_rpm=speed_rpm,
        outputs=["tipDisplacement"],
        input_fit="chebyshev",
        carry_values=True,
    )
    return np.asarray(r["tipDisplacement"][:n], dtype=float)


def harmonic_row(
    pm: PeriodMap, x: np.ndarray, speed_rpm: float, amplitude: float, stable: bool, hb_params: Mapping[str, Any]
) -> HarmonicRow:
    """The Fourier content of the orbit through x at `speed_rpm` (max |q| = amplitude) and the HB
    contact root (B > d) nearest its first harmonic (HB of hb_params; nan if HB has none there)."""
    a = fourier_amplitudes(orbit_samples(pm, x, speed_rpm))
    hb = [s.B for s in harmonic_balance(hb_params, speed_rpm) if s.B > pm.d]  # HB's contact roots
    nearest = min(hb, key=lambda B: abs(B - a[1])) if hb else math.nan
    return HarmonicRow(
        pm.model,
        float(speed_rpm),
        bool(stable),
        float(amplitude),
        float(a[1]),
        float(np.sqrt(np.sum(a[2:] ** 2))),
        float(a[3]),
        float(nearest),
    )


def hb_parameters(pm: PeriodMap) -> dict[str, Any]:
    """The HB the orbits of pm are compared with: the harmonic balance's, gating off (the paper's), with
    the macroslip describing function for the Jenkins element."""
    return dict(pm.p, frictionModel=1 if pm.model == "jenkins" else pm.p["frictionModel"])


def branch_harmonics(
    fmu: Any, params: Mapping[str, Any], model: str, branches: Sequence[Branch], spacing: float = 250.0
) -> list[HarmonicRow]:
    """Rows for the contact orbits (max |q| > d) of traced branches, at least `spacing` rpm apart
    along each branch."""
    pm = PeriodMap(fmu, params, model)
    hb_params = hb_parameters(pm)
    rows = []
    for b in branches:
        last = -math.inf
        for p in b.points:
            if p.amplitude > pm.d and abs(p.speed - last) >= spacing:
                rows.append(harmonic_row(pm, p.x, p.speed, p.amplitude, p.stable, hb_params))
                last = p.speed
    return rows


@dataclass(frozen=True)
class HarmonicRange:
    """One model's orbits against the harmonic balance: how many, and the range of each ratio."""

    orbits: int  # contact orbits with an HB root to compare with
    higher_rel: tuple[float, float]  # (min, max) of h / max|q|
    hb_vs_a1: tuple[float, float]  # (min, max) of (HB - a1) / a1
    hb_vs_amplitude: tuple[float, float]  # (min, max) of (HB - max|q|) / max|q|


def summarize(rows: Sequence[HarmonicRow]) -> dict[str, HarmonicRange]:
    """Per model: the range of h / max|q| and of (HB - a1) / a1 and (HB - max|q|) / max|q|."""
    out: dict[str, HarmonicRange] = {}
    for model in sorted({r.model for r in rows}):
        rs = [r for r in rows if r.model == model and math.isfinite(r.hb)]
        if not rs:
            continue
        out[model] = HarmonicRange(
            len(rs),
            (min(r.higher_rel for r in rs), max(r.higher_rel for r in rs)),
            (min(r.hb_vs_a1 for r in rs), max(r.hb_vs_a1 for r in rs)),
            (min(r.hb_vs_amplitude for r in rs), max(r.hb_vs_amplitude for r in rs)),
        )
    return out
