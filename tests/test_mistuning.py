"""The mistuning study (harness/studies/mistuning.py) and `python -m harness mistuning`, each
number against an independent value with the tolerance its numerics give:

- contacts open: every blade at every speed, and the amplification, against the single blade's
  closed form |G F_w0 / (K0_i(Omega) - omega^2 M + i omega C0)| (Galerkin constants in Python,
  harness.model.galerkin; the FMU computes its own in C);
- zero mistuning on a linear ring (stuck contacts, no gap): the tuned ring and the sigma-0 pattern
  against the ring's closed form (an N x N complex solve per speed, harness/system/linear_ring.py);
- the settling rule and the run-time doubling on synthetic responses whose movement is known in
  closed form; unsettled points are flagged and left out of the peak;
- the pattern generator is seeded; the cache is read, and a killed run resumes;
- the CLI: the figures, defaults and units in --help, a bad path is one line naming it, exit 2.
Tolerances: max |q| over the 160 communication points of a period is at most 1 - cos(pi / 160) =
1.9e-4 below the peak; with stop_time 0.3 s (13.6 decay times 2 M / C0 at c = 298) the transient
from rest is below 1e-5; the quadratic extrapolation of a sine load errs by (2 pi / 160)^3 / 6 = 1e-5.
"""
from __future__ import annotations

import json
import math
import re
from dataclasses import replace

import numpy as np
import pytest

from harness.cli.main import main
from harness.analysis.executor import Runner
from harness.model.galerkin import galerkin
from harness.model.params import validate
from harness.studies import mistuning
from harness.studies.mistuning import Study, run_study
from harness.system import linear_ring as LR

SAMPLING = 1 - math.cos(math.pi / 160)  # max |q| over 160 points per period, at most this far below the peak


def study(cache, **kw) -> dict:
    with Runner(workers=1, progress=False) as r:
        return run_study(Study(**{"n": 4, "patterns": 2, "points": 3, "stop_time": 0.05, **kw}), r, cache)


def single_blade(blade: dict, speeds: np.ndarray, fw0: float = 300.0, eo: int = 3) -> np.ndarray:
    """Closed-form steady amplitude [m] of one uncoupled blade per speed [rpm]."""
    g = galerkin(validate({k: v for k, v in blade.items() if k in LR.BLADE_KEYS}))
    Om = 2 * np.pi * np.asarray(speeds) / 60
    w = eo * Om
    return np.abs(g.loadGain * fw0 / (g.K0(Om) - w * w * g.M + 1j * w * g.C0))


def test_open_ring_equals_the_single_blade_closed_form():
    n0 = mistuning.resonance_speed({"c": 298.0}, 3)
    out = study(None, levels=(0.05,), variants=("open",), points=5, band=(0.97 * n0, 1.03 * n0), stop_time=0.3)
    sp, r = np.array(out["speeds_rpm"]), out["variants"]["open"]
    tuned = single_blade({"c": 298.0}, sp)
    for k in range(2):
        f = mistuning.factors(4, 0.05, 1, k)
        cf = np.stack([single_blade({"c": 298.0, "EI": 343.0 * x}, sp) for x in f], axis=1)  # speeds x blades
        got = np.array(r["amplitudes"])[0, k]
        assert np.all(np.array(r["tuned_settled"])) and np.all(np.abs(got - cf) <= (SAMPLING + 2e-5) * cf.max())
        expected = cf.max() / tuned.max()
        assert abs(r["amplification"][0][k] - expected) <= 2 * SAMPLING * expected, (k, expected)
    assert np.abs(np.array(r["tuned"]).max(axis=1) - tuned).max() <= (SAMPLING + 2e-5) * tuned.max()


def test_zero_mistuning_equals_the_linear_ring_closed_form():
    g = galerkin(validate({"c": 298.0}))
    k0 = g.K0(2 * math.pi * 5000 / 60)
    contact = {**LR.LINEAR_CONTACT, "kn": LR.kn_for(0.3 * k0)}
    base = mistuning.tuned_ring(Study(n=4, contact=contact), "friction")
    n_pk = LR.LinearRing(base).peak((3000.0, 12000.0))[1]
    out = study(None, levels=(0.0,), patterns=1, variants=("friction",), contact=contact, points=3,
                band=(0.95 * n_pk, 1.05 * n_pk), stop_time=0.3)
    r = out["variants"]["friction"]
    cf = LR.LinearRing(base).amplitudes(out["speeds_rpm"])
    # the co-simulation's coupling error at h = T / 160, quadratic extrapolation: 1e-3 of max |q|
    # (tests/test_linear_ring.py), plus the sampling of max |q|
    for curve in (r["tuned"], r["amplitudes"][0][0]):
        assert np.abs(np.array(curve) - cf).max() <= 1e-3 * cf.max()
    assert r["amplification"][0][0] == pytest.approx(1.0, abs=1e-12)


def _fake_run(envelope):
    """A stand-in for ring_c.run: every blade q = envelope(t) sin(omega t) on the ring's grid."""
    calls = []

    def run(ring):
        calls.append(ring.stop_time)
        t = np.arange(ring.n_steps + 1) * ring.step
        q = (envelope(t) * np.sin(ring.omega * t))[:, None] * np.ones(ring.n)
        return {"time": t, "q": q}
    return run, calls


def test_settling_rule_doubles_the_run_until_settled(monkeypatch):
    tau = 0.06  # [s]: a build-up whose movement over 5 periods is known in closed form
    run, calls = _fake_run(lambda t: 1 - np.exp(-t / tau))
    monkeypatch.setattr(mistuning.ring_c, "run", run)
    ring = mistuning.at_speed(replace(mistuning.tuned_ring(Study(n=3), "open"), stop_time=0.15), 5000.0, 160)
    T = 60 / (3 * 5000.0)

    def movement(t_end: float) -> float:  # the later peak of the last period is at t_end - T / 4
        a = lambda t: 1 - math.exp(-(t - T / 4) / tau)  # noqa: E731
        return (a(t_end) - a(t_end - 5 * T)) / a(t_end)
    expected = [0.15]
    while movement(expected[-1]) > mistuning.SETTLE_TOL:
        expected.append(2 * expected[-1])
    assert expected == [0.15, 0.3, 0.6]  # the case tests two doublings
    rec = mistuning.simulate(ring)
    assert calls == pytest.approx(expected) and rec["stop_time"] == pytest.approx(0.6)
    assert rec["settle"] == pytest.approx(movement(0.6), rel=1e-6, abs=1e-9)


def test_a_ring_that_never_settles_is_flagged_and_left_out_of_the_peak(monkeypatch):
    """A beating response (its amplitude moves by 10 % forever): three doublings, then reported
    unsettled; in a sweep that point is flagged and its larger amplitude is not the peak."""
    run, calls = _fake_run(lambda t: 2.0 + 0.2 * np.sin(9.0 * t))
    monkeypatch.setattr(mistuning.ring_c, "run", run)
    ring = replace(mistuning.tuned_ring(Study(n=3), "open"), stop_time=0.15)
    rec = mistuning.simulate(mistuning.at_speed(ring, 5000.0, 160))
    assert calls == pytest.approx([0.15, 0.3, 0.6, 1.2]) and rec["settle"] > mistuning.SETTLE_TOL
    settled, _ = _fake_run(lambda t: np.ones_like(t))
    monkeypatch.setattr(mistuning.ring_c, "run", lambda r: (run if r.speed == 6000.0 else settled)(r))
    sw = mistuning.sweep(ring, [5000.0, 6000.0, 7000.0], 160)
    assert sw["settled"] == [[True] * 3, [False] * 3, [True] * 3]
    assert sw["peak_amplitude_m"] == pytest.approx(1.0, abs=1e-12) and sw["peak_speed_rpm"] in (5000.0, 7000.0)
    assert max(map(max, sw["amplitudes_m"])) > 1.5  # the unsettled point was larger


def test_unsettled_patterns_have_no_amplification():
    st = Study(n=2, levels=(0.01,), patterns=2)
    rec = lambda peak, rpm: {"speeds_rpm": [1.0, 2.0], "amplitudes_m": [[1, 1], [1, 1]], "settled": [[1, 1], [1, 1]],  # noqa: E731
                             "movement": [[0, 0], [0, 0]], "peak_amplitude_m": peak, "peak_speed_rpm": rpm}
    v = mistuning._variant(st, [(-1, 0, rec(2.0, 1.0)), (0, 0, rec(3.0, 2.0)), (0, 1, rec(math.nan, math.nan))])
    assert v["amplification"][0][0] == pytest.approx(1.5) and np.isnan(v["amplification"][0][1])
    assert v["tuned_peak_at_edge"]


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
    assert main(["mistuning", "--blades", "3", "--levels", "0", "0.02", "--patterns", "2", "--stop-time", "0.04",
                 "--points", "2", "--variants", "open", "--workers", "1", "--quiet", "--no-cache", "--out",
                 str(tmp_path), "--json"]) == 0
    out = json.loads(capsys.readouterr().out)
    assert sorted(p.split("/")[-1] for p in out["files"]) == sorted(
        f"mistuning_{k}.{e}" for k in ("response", "blades", "amplification", "histogram") for e in ("png", "csv"))


@pytest.mark.parametrize("args, words", [
    (["--levels", "0.5"], ["--levels 0.5", "[0, 0.2]"]),
    (["--band", "9000", "4000"], ["--band 9000.0 4000.0"]),
    (["--stop-time", "0.02"], ["--stop-time 0.02", "6 excitation periods"]),
    (["--out", "/proc/sb_out"], ["--out /proc/sb_out"]),
    (["--out", "FILE/sub"], ["--out FILE/sub", "a file is in the way"]),
    (["--cache-dir", "FILE"], ["--cache-dir FILE", "a file is in the way"]),
])
def test_cli_errors_are_one_line_naming_the_value(tmp_path, monkeypatch, capsys, args, words):
    monkeypatch.chdir(tmp_path)
    (tmp_path / "FILE").write_text("x")
    assert main(["mistuning", "--workers", "1", *args]) == 2
    err = capsys.readouterr().err.strip()
    assert len(err.splitlines()) == 1 and all(w in err for w in words), err
    assert not (tmp_path / "shroudedblade-results").exists()  # nothing written before the check


def test_help_shows_defaults_and_units(capsys):
    with pytest.raises(SystemExit):
        main(["mistuning", "--help"])
    text = re.sub(r"(\w)-\n\s+", r"\1-", capsys.readouterr().out)  # argparse wraps after a hyphen
    text = " ".join(text.split())
    for opt in ("--blades N", "--levels SIGMA", "--patterns K", "--parameter", "--seed", "--points K", "--band FROM TO",
                "--stop-time S", "--variants", "--out DIR", "--cache-dir DIR"):
        part = text.split(opt, 2)[-1].split(" --")[0]
        assert "default" in part, (opt, part)
    assert "rpm" in text and "[s]" in text and "./shroudedblade-results/mistuning" in text
