"""The mistuning study (harness/studies/mistuning.py) and `python -m harness mistuning`, each
number against an independent value with the tolerance its numerics give:

- contacts open: every blade at every speed, and the amplification, against the single blade's
  closed form |G F_w0 / (K0_i(Omega) - omega^2 M + i omega C0)| (Galerkin constants in Python,
  harness.model.galerkin; the FMU computes its own in C);
- zero mistuning on a linear ring (stuck contacts, no gap): the tuned ring and the sigma-0 pattern
  against the ring's closed form (an N x N complex solve per speed, harness/system/linear_ring.py);
- the settle rule: the open ring's error follows its tolerance (rtol 1e-4 and 1e-6); a ring cut
  off before it can settle is flagged, with no peak and no amplification;
- the pattern generator is seeded; the cache is read, and a killed run resumes;
- the CLI: the figures, defaults and units in --help, a bad path is one line naming it, exit 2.
Each sweep carries the state from speed to speed (harness/system/ring_sweep.py); a blade has
settled when its per-period amplitude changes by less than rtol of the largest over 5 periods,
which leaves a linear response within rtol mu / (1 - mu) of its limit (mu the decay per period).
"""

from __future__ import annotations

import csv
import json
import math
import re
from types import SimpleNamespace

import numpy as np
import pytest

from harness.cli.main import main
from harness.analysis.executor import Runner
from harness.model.galerkin import galerkin
from harness.model.params import validate
from harness.studies import mistuning
from harness.studies.mistuning import Study, run_study
from harness.system import linear_ring as LR


def study(cache, **kw) -> dict:
    with Runner(workers=1, progress=False) as r:
        return run_study(Study(**{"n": 4, "patterns": 2, "points": 3, "speed_tol": 1e9, **kw}), r, cache)


def single_blade(blade: dict, speeds: np.ndarray, fw0: float = 300.0, eo: int = 3) -> np.ndarray:
    """Closed-form steady amplitude [m] of one uncoupled blade per speed [rpm]."""
    g = galerkin(validate({k: v for k, v in blade.items() if k in LR.BLADE_KEYS}))
    Om = 2 * np.pi * np.asarray(speeds) / 60
    w = eo * Om
    return np.abs(g.loadGain * fw0 / (g.K0(Om) - w * w * g.M + 1j * w * g.C0))


def settle_residual(rtol: float, speed: float) -> float:
    """How far from its limit a linear response may still be when its per-period change is below
    rtol: rtol mu / (1 - mu), mu = exp(-T C0 / 2 M) the decay per period (tests/system/test_ring_sweep.py)."""
    g = galerkin(validate({"c": 298.0}))
    mu = math.exp(-60 / (3 * speed) * g.C0 / (2 * g.M))
    return rtol * mu / (1 - mu)


@pytest.mark.parametrize("rtol", [1e-4, 1e-6])  # the study's, and a tight one: the error follows it
def test_open_ring_equals_the_single_blade_closed_form(rtol):
    n0 = mistuning.resonance_speed({"c": 298.0}, 3)
    out = study(None, levels=(0.05,), variants=("open",), points=5, band=(0.97 * n0, 1.03 * n0), rtol=rtol)
    sp, r = np.array(out["speeds_rpm"]), out["variants"]["open"]
    # the settle residual plus the window amplitude's parabola (4e-8) and the FMU's integration
    tol = settle_residual(rtol, sp[0]) + 1e-6  # measured 2.5e-4 at rtol 1e-4, 3.4e-6 at 1e-6
    tuned = single_blade({"c": 298.0}, sp)
    assert np.all(np.array(r["tuned_settled"]))
    assert np.abs(np.array(r["tuned"]).max(axis=1) - tuned).max() <= tol * tuned.max()
    for k in range(2):
        f = mistuning.factors(4, 0.05, 1, k)
        cf = np.stack([single_blade({"c": 298.0, "EI": 343.0 * x}, sp) for x in f], axis=1)  # speeds x blades
        got = np.array(r["amplitudes"])[0, k]
        assert np.all(np.abs(got - cf) <= tol * cf.max()), (k, np.abs(got - cf).max() / cf.max())
        expected = cf.max() / tuned.max()
        assert abs(r["amplification"][0][k] - expected) <= 2 * tol * expected, (k, expected)


def test_mistuned_linear_ring_equals_the_closed_form():
    """A linear ring (coupling 0.3 of the blade stiffness) at 5 % mistuning around its peak: the
    study's tuned and mistuned curves against the closed form of each ring (a complex solve, not
    the co-simulation), and the amplification against the closed forms' ratio."""
    g = galerkin(validate({"c": 298.0}))
    k0 = g.K0(2 * math.pi * 5000 / 60)
    contact = {**LR.LINEAR_CONTACT, "kn": LR.kn_for(0.3 * k0)}
    base = mistuning.tuned_ring(Study(n=4, contact=contact), "friction")
    n_pk = LR.LinearRing(base).peak((3000.0, 12000.0))[1]
    out = study(
        None,
        levels=(0.05,),
        patterns=1,
        variants=("friction",),
        contact=contact,
        points=3,
        band=(0.95 * n_pk, 1.05 * n_pk),
    )
    r = out["variants"]["friction"]
    sp = out["speeds_rpm"]
    cf_tuned = LR.LinearRing(base).amplitudes(sp)
    ring = mistuning.mistuned(base, "EI", mistuning.factors(4, 0.05, 1, 0))
    cf = LR.LinearRing(ring).amplitudes(sp)
    assert np.ptp(cf, axis=1).max() > 1e-2 * cf.max()  # the blades differ: a mistuned ring
    # the co-simulation's coupling error at h = T / 160, quadratic extrapolation: up to 1e-3 of
    # max |q| (tests/system/test_linear_ring.py), the settle residual within it; measured 5.2e-4 tuned,
    # 5.0e-4 mistuned
    for curve, ref in ((r["tuned"], cf_tuned), (r["amplitudes"][0][0], cf)):
        assert np.abs(np.array(curve) - ref).max() <= 1e-3 * ref.max()
    expected = cf.max() / cf_tuned.max()  # on the 3 speeds, as the study's peaks (speed_tol 1e9: no refinement)
    assert abs(r["amplification"][0][0] - expected) <= 2e-3 * expected  # measured 5.1e-4


def test_a_ring_that_has_not_settled_is_flagged_and_has_no_amplification():
    """max_time 0.01 s at a speed (2.5 periods): the settle rule (5 periods) cannot be met, every
    point is flagged, with a movement above the tolerance, and no peak or amplification exists."""
    out = study(None, levels=(0.02,), patterns=1, variants=("open",), max_time=0.01)
    r = out["variants"]["open"]
    assert r["unsettled_points"] == r["points"] == 2 * 3 and not np.any(r["tuned_settled"])
    assert np.isnan(r["tuned_peak_m"]) and np.isnan(r["amplification"][0][0]) and r["movement_max"] > 1e-4


def test_unsettled_patterns_have_no_amplification():
    st = Study(n=2, levels=(0.01,), patterns=2)
    rec = lambda peak, rpm: {
        "speeds_rpm": [1.0, 2.0],
        "amplitudes_m": [[1, 1], [1, 1]],
        "settled": [[1, 1], [1, 1]],  # noqa: E731
        "movement": [[0, 0], [0, 0]],
        "peak_amplitude_m": peak,
        "peak_speed_rpm": rpm,
        "peak_at_band_edge": rpm == 1.0,
        "peak_direction": "up",
        "peak_blades_m": None,
    }
    v = mistuning._variant(st, [(-1, 0, rec(2.0, 1.0)), (0, 0, rec(3.0, 2.0)), (0, 1, rec(math.nan, math.nan))])
    assert v["amplification"][0][0] == pytest.approx(1.5) and np.isnan(v["amplification"][0][1])
    assert v["tuned_peak_at_edge"]


def test_each_speed_keeps_the_larger_settled_state_of_both_sweeps():
    """Speed 0: down larger and settled -> down; speed 1: down larger but unsettled -> up (settled);
    speed 2: neither settled -> the larger (up)."""
    up = np.array([[1.0, 2.0], [3.0, 1.0], [5.0, 1.0]])
    down = np.array([[4.0, 1.0], [9.0, 1.0], [1.0, 2.0]])
    ok_up = np.array([[True, True], [True, True], [False, True]])
    ok_down = np.array([[True, True], [True, False], [True, False]])
    sw = SimpleNamespace(
        speeds_rpm=np.array([1.0, 2.0, 3.0]),
        amplitudes_m={"up": up, "down": down},
        settled={"up": ok_up, "down": ok_down},
        movement={"up": 0 * up, "down": 1 + 0 * down},
    )
    amps, settled, moved, dirs = mistuning.larger_state(sw)
    assert dirs == ["down", "up", "up"]
    assert np.array_equal(amps, np.stack([down[0], up[1], up[2]]))
    assert np.array_equal(settled, np.stack([ok_down[0], ok_up[1], ok_up[2]]))
    assert np.array_equal(moved[:, 0], [1.0, 0.0, 0.0])


def test_patterns_are_seeded():
    assert np.array_equal(mistuning.factors(6, 0.01, 1, 3), mistuning.factors(6, 0.01, 1, 3))
    assert not np.array_equal(mistuning.factors(6, 0.01, 1, 3), mistuning.factors(6, 0.01, 2, 3))


def test_cache_is_read_and_a_killed_run_resumes(tmp_path, monkeypatch):
    kw = dict(levels=(0.05,), variants=("friction",))
    first = study(tmp_path / "a", **kw)
    assert first["computed"] == 3 and first["cached"] == 0

    def no_fmu(*a):
        raise AssertionError("FMU work on a cached sweep")

    real = mistuning.sweep
    monkeypatch.setattr(mistuning, "sweep", no_fmu)
    again = study(tmp_path / "a", **kw)
    assert again["computed"] == 0 and again["variants"] == first["variants"]

    calls = []

    def killed_after_two(*a):
        if len(calls) == 2:
            raise KeyboardInterrupt
        calls.append(a)
        return real(*a)

    monkeypatch.setattr(mistuning, "sweep", killed_after_two)
    with pytest.raises(KeyboardInterrupt):
        study(tmp_path / "b", **kw)
    monkeypatch.setattr(mistuning, "sweep", real)
    resumed = study(tmp_path / "b", **kw)
    assert resumed["cached"] == 2 and resumed["computed"] == 1
    assert resumed["variants"] == first["variants"]


def test_cli_writes_figures(tmp_path, capsys):
    assert (
        main(
            [
                "mistuning",
                "--blades",
                "3",
                "--levels",
                "0",
                "0.02",
                "--patterns",
                "2",
                "--points",
                "2",
                "--variants",
                "open",
                "--state-patterns",
                "0",
                "--workers",
                "1",
                "--quiet",
                "--no-cache",
                "--out",
                str(tmp_path),
                "--json",
            ]
        )
        == 0
    )
    out = json.loads(capsys.readouterr().out)
    assert sorted(p.split("/")[-1] for p in out["files"]) == sorted(
        f"mistuning_{k}.{e}" for k in ("response", "blades", "amplification", "histogram") for e in ("png", "csv")
    )
    for p in out["files"]:
        if p.endswith(".png"):
            data = open(p, "rb").read()
            assert data[:8] == b"\x89PNG\r\n\x1a\n" and len(data) > 10000, p  # a drawn figure, not an empty one
    # the amplification table holds the study's mean / max / min per level (6 digits, harness/digits.py)
    a = np.array(out["variants"]["open"]["amplification"], dtype=float)
    with open(tmp_path / "mistuning_amplification.csv") as f:
        rows = list(csv.DictReader(line for line in f if not line.startswith("#")))
    assert [float(r["sigma"]) for r in rows] == [0.0, 0.02]
    for r, level in zip(rows, a):
        for key, want in (("mean", np.mean(level)), ("max", level.max()), ("min", level.min())):
            assert float(r[key]) == pytest.approx(want, rel=1e-5), (key, r[key], want)


@pytest.mark.parametrize(
    "args, words",
    [
        (["--levels", "0.5"], ["--levels 0.5", "[0, 0.2]"]),
        (["--band", "9000", "4000"], ["--band 9000.0 4000.0"]),
        (["--rtol", "2"], ["--rtol 2.0", "(0, 1)"]),
        (["--max-time", "0"], ["--max-time 0.0"]),
        (["--out", "/proc/sb_out"], ["--out /proc/sb_out"]),
        (["--out", "FILE/sub"], ["--out FILE/sub", "not a directory"]),
        (["--cache-dir", "FILE"], ["--cache-dir FILE", "not a directory"]),
    ],
)
def test_cli_errors_are_one_line_naming_the_value(tmp_path, monkeypatch, capsys, args, words):
    monkeypatch.chdir(tmp_path)
    (tmp_path / "FILE").write_text("x")
    assert main(["mistuning", "--workers", "1", *args]) == 2
    err = capsys.readouterr().err.strip()
    assert len(err.splitlines()) == 1 and all(w in err for w in words), err
    assert not list(tmp_path.rglob("*.png")) and not list(tmp_path.rglob("*.json"))  # no work done


def test_help_shows_defaults_and_units(capsys):
    with pytest.raises(SystemExit):
        main(["mistuning", "--help"])
    text = re.sub(r"(\w)-\n\s+", r"\1-", capsys.readouterr().out)  # argparse wraps after a hyphen
    text = " ".join(text.split())
    for opt in (
        "--blades N",
        "--levels SIGMA",
        "--patterns K",
        "--parameter",
        "--seed",
        "--points K",
        "--band FROM TO",
        "--rtol R",
        "--max-time S",
        "--variants",
        "--out DIR",
        "--cache-dir DIR",
    ):
        part = text.split(opt, 2)[-1].split(" --")[0]
        assert "default" in part, (opt, part)
    assert "rpm" in text and "[s]" in text and "./shroudedblade-results/mistuning" in text
