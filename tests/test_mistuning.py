"""The mistuning study (harness/studies/mistuning.py) and `python -m harness mistuning`.

- zero mistuning: every pattern is the tuned ring, amplification 1 within 1e-6;
- contacts open, N = 4, sigma up to 10 %: the amplification never exceeds Whitehead's bound
  (1 + sqrt(N)) / 2 (a theorem for the linear ring);
- the pattern generator is seeded: same seed same factors, another seed other factors;
- caching: a second run computes nothing (the ring run is replaced by a function that fails) and
  returns the same numbers; a run killed after 2 rings resumes with the remaining ones only;
- the CLI writes the three figures with their CSVs.
"""
from __future__ import annotations

import json

import numpy as np
import pytest

from harness.cli.main import main
from harness.analysis.executor import Runner
from harness.studies import mistuning
from harness.studies.mistuning import Study, run_study, whitehead

SHORT = dict(n=4, stop_time=0.05, patterns=2)


def study(cache, **kw) -> dict:
    with Runner(workers=1, progress=False) as r:
        return run_study(Study(**{**SHORT, **kw}), r, cache)


def test_zero_mistuning_gives_one():
    out = study(None, levels=(0.0,), variants=("friction", "open"))
    for v in ("friction", "open"):
        assert np.allclose(out["variants"][v]["amplification"], 1.0, rtol=0, atol=1e-6)


def test_open_contacts_respect_whitehead():
    out = study(None, levels=(0.02, 0.1), patterns=4, variants=("open",))
    a = np.array(out["variants"]["open"]["amplification"])
    assert a.shape == (2, 4) and np.all(np.isfinite(a))
    assert a.max() <= whitehead(4) == 1.5


def test_patterns_are_seeded():
    assert np.array_equal(mistuning.factors(6, 0.01, 1, 3), mistuning.factors(6, 0.01, 1, 3))
    assert not np.array_equal(mistuning.factors(6, 0.01, 1, 3), mistuning.factors(6, 0.01, 2, 3))


def test_cache_is_read_and_a_killed_run_resumes(tmp_path, monkeypatch):
    kw = dict(levels=(0.05,), variants=("friction",))
    first = study(tmp_path / "a", **kw)
    assert first["computed"] == 3 and first["cached"] == 0

    def no_fmu(ring):
        raise AssertionError("FMU work on a cached pattern")
    real = mistuning.simulate
    monkeypatch.setattr(mistuning, "simulate", no_fmu)
    again = study(tmp_path / "a", **kw)
    assert again["computed"] == 0 and again["variants"] == first["variants"]

    calls = []

    def killed_after_two(ring):
        if len(calls) == 2:
            raise KeyboardInterrupt
        calls.append(ring)
        return real(ring)
    monkeypatch.setattr(mistuning, "simulate", killed_after_two)
    with pytest.raises(KeyboardInterrupt):
        study(tmp_path / "b", **kw)
    monkeypatch.setattr(mistuning, "simulate", real)
    resumed = study(tmp_path / "b", **kw)
    assert resumed["cached"] == 2 and resumed["computed"] == 1
    assert resumed["variants"] == first["variants"]


def test_cli_writes_figures(tmp_path, capsys):
    assert main(["mistuning", "--blades", "3", "--levels", "0", "0.02", "--patterns", "2", "--stop-time", "0.03",
                 "--variants", "open", "--workers", "1", "--quiet", "--no-cache", "--out", str(tmp_path),
                 "--json"]) == 0
    out = json.loads(capsys.readouterr().out)
    assert sorted(p.split("/")[-1] for p in out["files"]) == sorted(
        f"mistuning_{k}.{e}" for k in ("blades", "amplification", "histogram") for e in ("png", "csv"))
    assert main(["mistuning", "--levels", "0.5"]) == 2
    assert "--levels 0.5" in capsys.readouterr().err


def test_unsettled_rings_have_no_amplification():
    """A pattern whose ring did not settle gets NaN; a variant whose tuned ring did not settle
    gets NaN everywhere (the response is not periodic)."""
    st = Study(n=2, levels=(0.01,), patterns=2)
    rec = lambda a, s: {"amplitudes": a, "settle": s}  # noqa: E731
    v = mistuning._variant(st, [(-1, 0, rec([1.0, 1.0], 0.0)), (0, 0, rec([1.2, 0.9], 1e-4)),
                                (0, 1, rec([1.5, 0.8], 0.1))])
    assert v["amplification"][0][0] == pytest.approx(1.2) and np.isnan(v["amplification"][0][1])
    assert v["unsettled"] == 1 and v["tuned_settled"]
    v = mistuning._variant(st, [(-1, 0, rec([1.0, 0.8], 0.3)), (0, 0, rec([1.2, 0.9], 1e-4)),
                                (0, 1, rec([1.1, 0.8], 1e-4))])
    assert np.all(np.isnan(v["amplification"])) and not v["tuned_settled"]
