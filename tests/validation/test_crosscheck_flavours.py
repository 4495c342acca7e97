"""The FMI 2.0 model-exchange and FMI 3.0 co-simulation flavours across importers: the cross-check
deliverables of each flavour (fmus/2.0/me, fmus/3.0/cs), which tool imports which flavour (the
README table "Which tool imports which flavour"), and FMI4j's model exchange against the
co-simulation FMU.

Tolerances: FMI4j's model exchange (RK4, substep 1e-6 s, events bisected to 1e-12 s) and the
co-simulation FMU (RK4, maxStep 1e-5 s, located events) integrate the same equations with the same
held inputs; measured 1.1e-7 (q, q'), 3.6e-8 (energy) relative to the largest value over 0.052 s,
asserted < 1e-6. The ME reference (fmpy CVode, RelTol 1e-9, inputs as steps) and the co-simulation
reference stay within fmpy's validate_result band to StopTime 0.1 s (measured 1.3e-4 in q).
"""

from __future__ import annotations

import numpy as np
import pytest
from fmpy.util import read_csv, validate_result

from harness.crosscheck import deliverables as xd
from harness.crosscheck.flavours import me_only_copy, probe
from harness.crosscheck.plan import SCENARIOS, Scenario, make_plan


@pytest.fixture(scope="module")
def flavours(fmu_path, fmu3_path, tmp_path_factory):
    root = tmp_path_factory.mktemp("xcf")
    sc = SCENARIOS["steady"]
    return root, {
        ("2.0", "cs"): xd.generate(fmu_path, sc, root),
        ("2.0", "me"): xd.generate(fmu_path, sc.shortened(xd.ME_STOP_TIME), root, "2.0", "me"),
        ("3.0", "cs"): xd.generate(fmu3_path, sc, root, "3.0", "cs"),
    }


def test_every_flavour_follows_the_rules(flavours):
    root, dl = flavours
    rc, out = xd.validate_tree(root)
    assert rc == 0 and "Validated 3 FMUs" in out, out
    for (fmi, kind), d in dl.items():
        assert d.directory == xd.model_dir(root, "0.1.0", fmi, kind)
        assert d.ref_csv.stat().st_size <= 1_000_000 and d.readme.exists()
        assert xd.check_result(read_csv(d.ref_csv), d) == 0  # every reference passes its own band


def test_model_exchange_inputs_are_the_held_steps(flavours):
    """Linear interpolation of the ME table gives the held inputs: each time twice, the value before
    and after; without the repeated rows it is the co-simulation table."""
    _, dl = flavours
    me, cs = read_csv(dl[("2.0", "me")].in_csv), read_csv(dl[("2.0", "cs")].in_csv)
    t = me["time"]
    assert np.all(t[1:-1:2] == t[2::2])  # steps at every t_k
    n = len(me[0::2])  # the rows that start an interval: the co-simulation table up to StopTime
    assert np.array_equal(me[0::2]["time"], cs["time"][:n])
    assert np.array_equal(me[0::2]["aeroLoad"], cs["aeroLoad"][:n])
    assert np.array_equal(me["aeroLoad"][1::2], me["aeroLoad"][0:-1:2])  # held over each interval


def test_model_exchange_reference_agrees_with_co_simulation(flavours):
    """Two integrations (fmpy's CVode on the ME face, the FMU's own RK4 in co-simulation) of the
    same experiment: the co-simulation reference is inside the ME reference's band to 0.1 s."""
    _, dl = flavours
    me = read_csv(dl[("2.0", "me")].ref_csv)
    cs = read_csv(dl[("2.0", "cs")].ref_csv)
    cs = cs[cs["time"] <= xd.ME_STOP_TIME + 1e-12]
    assert validate_result(cs, me) == 0
    q = np.max(np.abs(cs["tipDisplacement"] - me["tipDisplacement"])) / np.max(np.abs(me["tipDisplacement"]))
    assert 0 < q < 1e-3, q  # not the same computation, but close


def test_fmi3_reference_equals_fmi2(flavours):
    _, dl = flavours
    a, b = read_csv(dl[("2.0", "cs")].ref_csv), read_csv(dl[("3.0", "cs")].ref_csv)
    for n in a.dtype.names:
        assert np.array_equal(a[n], b[n]), n


@pytest.mark.parametrize("tool", ["libcosim", "ecos"])
def test_which_flavour_the_tool_imports(tool, fmu_path, fmu3_path, tmp_path):
    """As the README table says: both take FMI 2.0 co-simulation; neither takes model exchange (an
    FMU with only <ModelExchange> kills the process); Ecos takes FMI 3.0, libcosim does not."""
    me_only = me_only_copy(fmu_path, tmp_path / "ShroudedBlade.fmu")
    assert probe(tool, fmu_path).ok
    seen = probe(tool, me_only)
    assert not seen.ok and "SIGSEGV" in seen.text, seen
    assert probe(tool, fmu3_path).ok == (tool == "ecos")


@pytest.mark.slow
def test_fmi4j_model_exchange_equals_co_simulation(fmu_path):
    """FMI4j's ModelExchangeInstance driven by crosscheck/java Fmi4jMeDriver against fmpy's
    co-simulation run with the same held inputs; output step 1.3e-4 s, incommensurate with the
    4 ms excitation period, except the last point (0.052 s = 13 periods: a period end on a sample is
    seen before its event by one master and after it by the other)."""
    from harness.crosscheck.importers import fmi4j as xj
    from harness.crosscheck.importers import fmpy as xf

    sc = Scenario("me", "5000 rpm, incommensurate steps", 5000.0, stop_time=0.052, step=1.3e-4)
    plan = make_plan(sc, 0)
    me = xj.run(fmu_path, sc, plan, model_exchange=True).result[:-1]
    cs = xf.run_simulate_fmu(fmu_path, sc, plan).result[:-1]
    for n in ("tipDisplacement", "tipVelocity", "dissipatedEnergy", "amplitude", "runningMaximum", "normalForce"):
        d = np.max(np.abs(me[n] - cs[n])) / np.max(np.abs(cs[n]))
        assert d < 1e-6, (n, d)
    assert np.sum(me["contactState"] != cs["contactState"]) <= 1
    assert len(np.unique(cs["amplitude"])) > 5  # the tracked amplitude moved: period ends were events
