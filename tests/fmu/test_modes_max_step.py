"""The RK4 stable-step check of the m-mode blade (docs/model.md s.2a) at its boundary, on both faces.

Co-simulation (FMI 2.0 and FMI 3.0) integrates with RK4 at steps <= maxStep, stable while
maxStep w_m <= 2 sqrt(2), w_m the highest contact-free mode at the speed of initialization. The
boundary is computed here from the independent Galerkin model (tests/support/modes_galerkin.py, matrices by
quadrature, eigenvalues by scipy): a maxStep 0.1 % below it must be accepted, 0.1 % above it refused
(the FMU's frequencies agree with the independent ones to 1e-9, tests/fmu/test_modes_fmu.py, so 1e-3 is
far outside their difference). Mode 5 is 25 % lower than mode 6 here, so a check against the wrong
mode moves the boundary by 25 % and fails the "refused" case; the broken variant, e.g.

    -    w = DYN_TWO_PI * f[m->modes - 1];
    +    w = DYN_TWO_PI * f[m->modes - 2];

in fmu_src/solver/blade_modes.c, accepts modes 6 with maxStep 2.5e-5 s (the limit is 2.19e-5 s at 5000 rpm)
and fails test_cosimulation_refuses_a_max_step_just_above_the_stable_one.

Model exchange does not use maxStep (the importer's solver takes the steps): every maxStep in the
declared range [1e-8, 1e-3] is accepted there and the results do not depend on it (bit for bit).
The numbers docs/model.md quotes about the modes and the step are recomputed here too.
"""

from __future__ import annotations

import math
import re
from pathlib import Path

import numpy as np
import pytest
import scipy.linalg as sl
from fmpy import simulate_fmu

from harness.reference.blade import galerkin as reference_galerkin
from tests.support.modes_galerkin import Modes

REPO = Path(__file__).resolve().parents[2]

TWO_PI = 2.0 * np.pi
SPEED = 5000.0  # rpm, the speed of initialization
STABLE_HW = 2.0 * np.sqrt(2.0)  # RK4's stability limit on the imaginary axis
M = 6


def _speed(n: float) -> np.ndarray:
    return np.array([(0.0, 0.0, n), (1.0, 0.0, n)], dtype=[("time", float), ("aeroLoad", float), ("rotorSpeed", float)])


@pytest.fixture(scope="module")
def h_max() -> float:
    """2 sqrt(2) / w_6 at 5000 rpm from the independent matrices (K + Omega^2 K2, M)."""
    Mm, _, K, K2, _ = Modes(M).matrices()
    om = TWO_PI * SPEED / 60.0
    f = np.sqrt(sl.eigh(K + om**2 * K2, Mm, eigvals_only=True)) / TWO_PI
    assert f[-2] < 0.8 * f[-1]  # the mode below is far enough to tell the two apart
    return STABLE_HW / (TWO_PI * f[-1])


def _run(path, max_step: float, fmi_type: str = "CoSimulation", **kw):
    return simulate_fmu(
        str(path),
        fmi_type=fmi_type,
        stop_time=2e-4,
        output_interval=1e-4,
        start_values={"modes": M, "formulation": 2, "maxStep": max_step},
        input=_speed(SPEED),
        output=["tipDisplacement", "modalDisplacement[6]"],
        **kw,
    )


def test_the_stable_step_is_the_documented_one(h_max):
    assert h_max == pytest.approx(2.19e-5, abs=0.005e-5)  # docs/model.md s.2a, 3 digits quoted


@pytest.mark.parametrize("face", ["fmi2", "fmi3"])
def test_cosimulation_accepts_a_max_step_just_below_the_stable_one(face, h_max, fmu_path, fmu3_path):
    r = _run(fmu_path if face == "fmi2" else fmu3_path, h_max * (1 - 1e-3))
    assert np.all(np.isfinite(r["tipDisplacement"]))


@pytest.mark.parametrize("face", ["fmi2", "fmi3"])
@pytest.mark.parametrize("factor", [1 + 1e-3, 2.5e-5 / 2.19e-5])
def test_cosimulation_refuses_a_max_step_just_above_the_stable_one(face, factor, h_max, fmu_path, fmu3_path):
    messages = []
    with pytest.raises(Exception):
        _run(fmu_path if face == "fmi2" else fmu3_path, h_max * factor, logger=lambda *args: messages.append(args[-1]))
    text = " ".join(m.decode() if isinstance(m, bytes) else str(m) for m in messages)
    assert "maxStep" in text and "2 sqrt(2)" in text and "mode 6" in text, text


@pytest.mark.parametrize("max_step", [1e-3, 2.5e-5, 1e-8])
def test_model_exchange_accepts_every_max_step_and_does_not_use_it(max_step, fmu_path):
    kw = dict(fmi_type="ModelExchange", solver="Euler", step_size=1e-7)
    ref = _run(fmu_path, 1e-5, **kw)
    got = _run(fmu_path, max_step, **kw)
    assert np.all(np.isfinite(got["tipDisplacement"]))
    for name in ("tipDisplacement", "modalDisplacement[6]"):
        assert np.array_equal(got[name], ref[name])


def _quoted(pattern: str) -> re.Match:
    text = " ".join((REPO / "docs" / "model.md").read_text().split())  # the page's line breaks as spaces
    found = list(re.finditer(pattern, text))
    assert len(found) == 1, (pattern, len(found))
    return found[0]


def _same(quote: str, value: float) -> bool:
    """The quote is the value rounded to the digits the quote shows."""
    if "e" in quote.lower():
        mant, exp = quote.lower().split("e")
        decimals = len(mant.split(".")[1]) if "." in mant else 0
        return f"{value / 10.0 ** int(exp):.{decimals}f}" == mant
    decimals = len(quote.split(".")[1]) if "." in quote else 0
    if decimals == 0 and len(quote) > 3 and quote.endswith("0"):  # 2830: three significant digits
        return f"{value:.3g}" == f"{float(quote):.3g}"
    return f"{value:.{decimals}f}" == quote


def test_model_page_numbers(h_max):
    """The numbers docs/model.md s.2a quotes, recomputed here (independent Galerkin model, reference
    one-mode reduction, RK4's amplification factor)."""
    g6 = Modes(M)
    Mm, _, K, K2, _ = g6.matrices()
    om = TWO_PI * SPEED / 60.0
    f = np.sqrt(sl.eigh(K + om**2 * K2, Mm, eigvals_only=True)) / TWO_PI
    m = _quoted(r"lambda_i l = ([\d., ]+?);")
    assert all(_same(q.strip(), v) for q, v in zip(m.group(1).split(","), g6.aL))
    m = _quoted(r"contact-free frequencies at rest ([\d., ]+?) Hz")
    rest = np.sqrt(g6.EI / g6.rhoA) * (g6.aL / g6.l) ** 2 / TWO_PI
    assert all(_same(q.strip(), v) for q, v in zip(m.group(1).split(","), rest))
    m = _quoted(r"m = 6 at 5000 rpm: ([\d.]+) kHz, maxStep <= ([\d.e-]+) s")
    assert _same(m.group(1), f[-1] / 1e3) and _same(m.group(2), h_max)
    m = _quoted(r"up to w_1 = (\d+) rad/s, (\d+) Hz")
    assert _same(m.group(1), STABLE_HW / 1e-3) and _same(m.group(2), STABLE_HW / 1e-3 / TWO_PI)
    g1 = reference_galerkin({})  # the FMU's defaults: one mode, printed formulation
    m = _quoted(r"the defaults give (\d+) Hz at 5000 rpm")
    assert _same(m.group(1), math.sqrt(g1.K0(om) / g1.M) / TWO_PI)
    hw = 1e-5 * TWO_PI * f[-1]
    R = sum((1j * hw) ** k / math.factorial(k) for k in range(5))
    m = _quoted(
        r"h w_6 = ([\d.]+) \(m = 6 at the default maxStep\) mode 6 loses ([\d.]+) % of its amplitude and "
        r"([\d.]+) rad of phase per step"
    )
    assert _same(m.group(1), hw) and _same(m.group(2), 100 * (1 - abs(R))) and _same(m.group(3), hw - np.angle(R))
    m = _quoted(r"0.3 / w_m \(m = 6 at 5000 rpm: ([\d.e-]+) s\)")
    assert _same(m.group(1), 0.3 / (TWO_PI * f[-1]))
