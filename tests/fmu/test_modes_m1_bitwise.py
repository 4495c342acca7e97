"""modes = 1 is the one-mode model bit for bit: every scenario of tests/support/modes_reference.py (FMI 2.0
co-simulation with each friction model, a run-up, start values and the sensitivities; model
exchange with fmpy's Euler; FMI 3.0; BladeExternalContact with its force inputs) gives, on the
current build, the same bytes in every output the FMUs had before the modes existed (recorded
from them in tests/data/modes_m1_reference.json), with `modes` left at its default and set to 1.
The modal outputs of mode 1 equal the tip ones bit for bit."""

from __future__ import annotations

import json
from pathlib import Path

import numpy as np
import pytest
from fmpy import simulate_fmu

from harness.fmu import build as _build
from tests.support.modes_reference import SCENARIOS, run

REFERENCE = json.loads((Path(__file__).resolve().parents[1] / "data" / "modes_m1_reference.json").read_text())


@pytest.fixture(scope="module")
def build_dir(fmu_path, fmu3_path) -> Path:
    _build.build(("blade_external_fmu",))
    return fmu_path.parent


def _differences(got: dict, ref: dict) -> list[str]:
    bad = []
    for name, r in ref.items():
        g = got[name]
        if g["sha256"] != r["sha256"]:
            bad.append(f"{name}: last {float.fromhex(g['last'])!r} vs {float.fromhex(r['last'])!r}")
    return bad


@pytest.mark.parametrize("scenario", sorted(SCENARIOS))
def test_default_modes_bit_identical(build_dir, scenario):
    got = run(build_dir, scenario, list(REFERENCE[scenario]))
    assert not _differences(got, REFERENCE[scenario])


@pytest.mark.parametrize(
    "scenario",
    [
        "cs_jenkins_consistent_runup",
        "cs_sensitivities_jenkins",
        "me_euler_jenkins",
        "fmi3_macroslip",
        "external_contact",
    ],
)
def test_modes_one_set_explicitly_bit_identical(build_dir, scenario, monkeypatch):
    rel, kw, extra = SCENARIOS[scenario]
    kw = dict(kw, start_values=dict(kw["start_values"], modes=1))
    monkeypatch.setitem(SCENARIOS, scenario, (rel, kw, extra))
    got = run(build_dir, scenario, list(REFERENCE[scenario]))
    assert not _differences(got, REFERENCE[scenario])


def test_comparison_can_fail(build_dir, monkeypatch):
    """A change far below any tolerance (c by one ulp) is seen."""
    rel, kw, extra = SCENARIOS["cs_macroslip_tracked"]
    kw = dict(kw, start_values=dict(kw["start_values"], c=np.nextafter(29.8, 30.0)))
    monkeypatch.setitem(SCENARIOS, "cs_macroslip_tracked", (rel, kw, extra))
    got = run(build_dir, "cs_macroslip_tracked", list(REFERENCE["cs_macroslip_tracked"]))
    assert _differences(got, REFERENCE["cs_macroslip_tracked"])


@pytest.mark.parametrize("rel", ["ShroudedBlade.fmu", "fmi3/ShroudedBlade.fmu"])
def test_mode_one_outputs_are_the_tip(build_dir, rel):
    res = simulate_fmu(
        str(build_dir / rel),
        stop_time=0.02,
        output_interval=1e-4,
        start_values={"Fw0": 100.0, "frictionModel": 3},
        output=[
            "tipDisplacement",
            "tipVelocity",
            "modalDisplacement[1]",
            "modalVelocity[1]",
            "modalDisplacement[2]",
            "modeFrequency[1]",
            "modeFrequency[2]",
            "naturalFrequency",
        ],
    )
    assert np.abs(res["tipDisplacement"]).max() > 1e-5
    for a, b in (
        ("tipDisplacement", "modalDisplacement[1]"),
        ("tipVelocity", "modalVelocity[1]"),
        ("naturalFrequency", "modeFrequency[1]"),
    ):
        assert np.array_equal(res[a].view(np.int64), res[b].view(np.int64)), (a, b)
    assert not res["modalDisplacement[2]"].any() and not res["modeFrequency[2]"].any()
