"""The convergence study in the number of modes (harness.studies.modes_convergence) on a narrow speed
window, its root moment against the reference's modal reduction, and the claims row's verdict rule."""

from __future__ import annotations

import math

import numpy as np
import pytest

from harness.analysis.periodic.period_map import PeriodMap
from harness.analysis.periodic.curve import peak_orbit, trace_curve
from harness.reference.modes import modal_galerkin
from harness.studies.claims import _modes
from harness.studies.modes_convergence import ModesConvergence, ModesRow, modes_convergence, modes_tasks
from harness.studies.paper import base_params

WINDOW = (10300.0, 11300.0)  # around the Jenkins peak of the base case (10672 rpm at m = 1, 10826 at m = 2)


@pytest.fixture(scope="module")
def curves(fmu_path):
    tasks = [t for t in modes_tasks(base_params(), WINDOW, 1000.0, str(fmu_path), (1, 2)) if t.model == "jenkins"]
    return [trace_curve(t) for t in tasks]


def test_peaks_located_and_root_moment(fmu, curves, tmp_path):
    conv = modes_convergence(fmu, tmp_path, curves)
    assert [(r.model, r.modes) for r in conv.rows] == [("jenkins", 1), ("jenkins", 2)]
    for r, c in zip(conv.rows, curves):
        o = peak_orbit(c.branches, speed_range=WINDOW)
        assert any(e.kind == "peak" and e is o for b in c.branches for e in b.extrema), "the peak is located"
        assert WINDOW[0] < r.speed < WINDOW[1]
        # the peak is at least every stable orbit the tracing found in the window (a located maximum
        # lies above its sampled neighbours; the sampled points are the tracing's, not the row's)
        stable = [
            pt.amplitude for b in c.branches for pt in b.points if pt.stable and WINDOW[0] <= pt.speed <= WINDOW[1]
        ]
        assert stable and r.peak >= max(stable) * (1 - 1e-12), (r.peak, max(stable))
        # the root moment: the reference's EI sum psi_i''(0) q_i(t) on the FMU's modal coordinates over
        # the peak orbit's period (1024 samples, as the study): measured 1.0e-12 (m = 1) and 1.4e-12
        # (m = 2), the two reductions' psi_i''(0); tolerance 1e-11
        pm = PeriodMap(fmu, c.task.params, "jenkins")
        T = 60.0 / (int(pm.p["engineOrder"]) * o.speed)
        names = [f"modalDisplacement[{i + 1}]" for i in range(r.modes)]
        res = fmu.run(
            dict(pm.p, **pm.start_values(o.x)),
            T,
            T / 1024,
            speed_rpm=o.speed,
            outputs=names,
            input_fit="chebyshev",
            carry_values=True,
        )
        q = np.array([res[n] for n in names])
        ref = float(np.abs(modal_galerkin(c.task.params).root_moment(q)).max())
        assert r.root_moment == pytest.approx(ref, rel=1e-11)
    assert (tmp_path / "modes_convergence.csv").is_file() and (tmp_path / "modes_convergence_jenkins.png").is_file()
    d = conv.differences(conv.rows[0])
    assert d[0] == pytest.approx(conv.rows[0].peak / conv.rows[1].peak - 1.0)


def _conv(peak1: float, peak4: float = 1.0) -> ModesConvergence:
    rows = [
        ModesRow(m, k, p, 10000.0, 5.0, 1, 100) for m in ("jenkins", "fixedPoint") for k, p in ((1, peak1), (4, peak4))
    ]
    return ModesConvergence(rows, (3000.0, 12000.0))


@pytest.mark.parametrize(
    "peak1, verdict",
    [
        (1.03, "one mode suffices within 3.0 %"),
        (0.90, "one mode does not suffice: 10.0 % (peak amplitude"),
        (math.nan, "not computed"),
    ],
)
def test_claims_row_verdict(peak1, verdict):
    (row,) = _modes(_conv(peak1))
    assert row.verdict.startswith(verdict), row.verdict
    assert _modes(None) == []
    assert np.isfinite(_conv(1.0).one_mode_error()[0])


def test_second_mode_crossing_with_contact(fmu, tmp_path):
    """EO 8 crosses mode 2 (contact-free) where the reference's reduction says; with the contact the
    Jenkins element's located peak lies in contact (max|q| > d) and above that speed (stiffening)."""
    from scipy.optimize import brentq

    from harness.studies.mode2_crossing import mode2_crossing

    base = base_params()
    r = mode2_crossing(fmu, tmp_path, base)
    g = modal_galerkin(dict(base, formulation=2), 2)
    free = brentq(lambda n: g.frequencies_hz(n)[1] - 8 * n / 60.0, 8000.0, 30000.0, xtol=1e-9)
    assert r.free_crossing == pytest.approx(free, rel=1e-9)
    jen = next(b for b in r.branches if b.model == "jenkins")
    assert jen.peak > base["d"] and free < jen.speed < 1.15 * free
    assert (tmp_path / "mode2_crossing_branches.csv").is_file() and (tmp_path / "mode2_crossing.png").is_file()
