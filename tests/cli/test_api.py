"""The public API at the top of `harness`: cheap to import, every name in __all__ there, the version
from pyproject.toml, bad values rejected with the value, the accepted range and the argument named,
and the functions the same as the command line they are thin over."""

from __future__ import annotations

import json
import subprocess
import sys
import tomllib
from pathlib import Path

import pytest

import harness

REPO = Path(__file__).resolve().parents[2]


def test_import_loads_nothing_heavy():
    code = (
        "import sys, harness; print(sorted(m for m in ('numpy', 'fmpy', 'harness.fmu.build', 'importlib.metadata')"
        " if m in sys.modules))"
    )
    out = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, check=True).stdout
    assert json.loads(out.replace("'", '"')) == []


def test_all_names_exist_and_version_is_pyprojects():
    for name in harness.__all__:
        assert getattr(harness, name) is not None
    with open(REPO / "pyproject.toml", "rb") as fh:
        assert harness.__version__ == tomllib.load(fh)["project"]["version"]
    with pytest.raises(AttributeError):
        harness.no_such_name  # noqa: B018


def test_fmu_path_names():
    assert harness.fmu_path("ShroudedBlade").name == "ShroudedBlade.fmu"
    assert harness.fmu_path("fmi3/ShroudedBlade").parent.name == "fmi3"
    with pytest.raises(KeyError, match="choose from ShroudedBlade"):
        harness.fmu_path("NoSuchFMU")


@pytest.mark.parametrize(
    "call, expect",
    [
        (
            lambda: harness.simulate(0.1, d=-1e-5),
            ["d = -1e-05 m", "harness.simulate(**parameters)", "accepted: [0, inf) m"],
        ),
        (
            lambda: harness.simulate(0.1, speed_rpm=40000),
            ["speed_rpm = 40000 rpm", "harness.simulate(speed_rpm=...)", "[0, 30000] rpm"],
        ),
        (
            lambda: harness.simulate(0.1, step=0.5),
            ["step = 0.5 s", "harness.simulate(step=...)", "(0, stop_time = 0.1] s"],
        ),
        (lambda: harness.simulate(0.1, nope=1), ["unknown parameter 'nope'", "harness.simulate(**parameters)"]),
        (
            lambda: harness.periodic_orbits(0),
            ["speed_rpm = 0 rpm", "harness.periodic_orbits(speed_rpm=...)", "(0, 30000] rpm"],
        ),
        (
            lambda: harness.periodic_orbits(7000, model="hb"),
            ["model = 'hb'", "harness.periodic_orbits(model=...)", "fixedPoint"],
        ),
        (lambda: harness.periodic_orbits(7000, tipDisplacement=1e-5), ["tipDisplacement", "shooting solves"]),
        (lambda: harness.branch((8000, 6000)), ["speed_range_rpm = (8000, 6000) rpm", "low must be < high"]),
        (lambda: harness.branch((6000, float("nan"))), ["high = nan", "harness.branch(speed_range_rpm=(..., high))"]),
        (lambda: harness.run_ring(harness.Ring(n=1)), ["n = 1", "harness.run_ring(ring=Ring(n=...))", "[2, "]),
        (
            lambda: harness.run_ring(harness.Ring(blade={"EI": -1.0})),
            ["EI -1.0", "Ring(blade=...)", "outside [0, inf]"],
        ),
        (lambda: harness.run_ring(harness.Ring(speed=-5.0)), ["speed = -5.0 rpm", "Ring(speed=...)"]),
        (lambda: harness.run_ring(harness.Ring(), master="x"), ["master = 'x'", "harness.run_ring(master=...)"]),
    ],
)
def test_bad_values_name_value_range_and_source(call, expect):
    with pytest.raises(harness.ParameterError) as err:
        call()
    for text in expect:
        assert text in str(err.value), str(err.value)


def test_periodic_orbits_is_the_cli_periodic(tmp_path):
    """harness.periodic_orbits = `harness periodic --json` (the same orbits, every number)."""
    got = [o.as_dict() for o in harness.periodic_orbits(7000, d=4e-5)]
    cli = subprocess.run(
        [sys.executable, "-m", "harness", "periodic", "--speed", "7000", "--start-values", "d", "4e-5", "--json"],
        cwd=tmp_path,
        capture_output=True,
        text=True,
        check=True,
    ).stdout
    assert json.loads(json.dumps(got)) == json.loads(cli)["solutions"]


def test_simulate_is_bladefmu_run():
    """harness.simulate = BladeFMU.run with the same arguments (bit for bit)."""
    from harness.fmu.blade import BladeFMU

    got = harness.simulate(0.02, speed_rpm=6000, step=2e-4, kn=2e6)
    with BladeFMU(harness.fmu_path()) as fmu:
        want = fmu.run({"kn": 2e6}, 0.02, 2e-4, speed_rpm=6000.0)
    assert got.dtype == want.dtype and all((got[n] == want[n]).all() for n in want.dtype.names)


def test_run_ring_masters_agree():
    """The C loop and the Python loop of the same ring (tests/system/test_ring_c.py holds them together in
    detail); here: run_ring passes the ring through to both."""
    import numpy as np

    ring = harness.Ring(n=3, stop_time=0.005, step=2.5e-5, order=2)
    c, py = harness.run_ring(ring, "c"), harness.run_ring(ring, "fmpy")
    assert c["q"].shape == py["q"].shape == (201, 3)
    np.testing.assert_allclose(c["q"], py["q"], rtol=0, atol=1e-15)
