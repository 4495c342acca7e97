"""The period map's restart of the ring's instances in one C call (harness/system/ring_orbits/restart.py):
the instances end up as the binding's own call sequence leaves them, and a refused start names the
FMI call and carries the FMU's message; the state read back in one C call equals the binding's reads,
and a refused read names fmi2GetReal."""

from __future__ import annotations

import numpy as np
import pytest

from harness.fmu.binding import FmiError
from harness.system.ring import Ring
from harness.system.ring_orbits.period_map import RingPeriodMap, RingShootingSettings
from harness.system.ring_orbits.restart import Reads, Restarts

SMALL = Ring(n=4, engine_order=3, fw0=300.0, blade={"c": 298.0}, order=2)
OUTPUTS = ["forceA", "forceB", "frictionForce", "contactState"]
STARTS = ["frictionForce", "displacementA", "displacementB", "rotorSpeed"]


def _contact_params(pm: RingPeriodMap) -> dict:
    """The contacts' parameters, as the period map restarts them."""
    return {**dict(SMALL.contact), "engineOrder": SMALL.engine_order}


def test_restart_leaves_the_contacts_as_the_binding_does():
    """Contacts restarted in contact (u = 2.5 d, a friction force inside the cone) by the C call and
    by the binding's checked calls one by one: the same outputs, bit for bit."""
    with RingPeriodMap(SMALL, RingShootingSettings(workers=1)) as pm:
        contacts = pm.contacts
        r = Restarts([(c, _contact_params(pm)) for c in contacts], STARTS)
        u = 2.5 * pm.d
        F = 0.5 * pm.muKnCos * (u - pm.d)
        r.starts[:] = [F, u, 0.0, 6000.0]
        r()
        fast = [c.get(OUTPUTS) for c in contacts]
        for c in contacts:
            s = c.s
            s.reset()
            s.setup_experiment(0.0)
            c.set_params(
                {
                    **_contact_params(pm),
                    "frictionForce": F,
                    "displacementA": u,
                    "displacementB": 0.0,
                    "rotorSpeed": 6000.0,
                }
            )
            s.enter_initialization_mode()
            s.exit_initialization_mode()
        slow = [c.get(OUTPUTS) for c in contacts]
    assert np.array_equal(np.array(fast), np.array(slow))
    assert np.all(np.array(fast)[:, 3] > 0)  # in contact: the case tests something


def test_a_refused_start_names_the_call_and_the_fmu_message():
    """A friction force outside the cone at the start: the contact refuses at the end of its
    initialization; the error names that call and says why."""
    with RingPeriodMap(SMALL, RingShootingSettings(workers=1)) as pm:
        r = Restarts([(c, _contact_params(pm)) for c in pm.contacts], STARTS)
        u = 2.5 * pm.d
        r.starts[:] = [0.0, u, 0.0, 6000.0]
        r.starts[2, 0] = 10.0 * pm.muKnCos * (u - pm.d)  # the third contact's
        with pytest.raises(FmiError) as e:
            r()
    assert e.value.function == "fmi2ExitInitializationMode"
    assert "friction cone" in str(e.value)


def test_reads_are_the_bindings_and_a_refused_one_is_named():
    """Reads of the contacts after a restart in contact: row i is contact i's values as the binding
    reads them, bit for bit; with contact 2 reset (instantiated: no fmi2GetReal there) the read
    fails naming fmi2GetReal."""
    with RingPeriodMap(SMALL, RingShootingSettings(workers=1)) as pm:
        r = Restarts([(c, _contact_params(pm)) for c in pm.contacts], STARTS)
        u = 2.5 * pm.d
        r.starts[:] = [0.5 * pm.muKnCos * (u - pm.d), u, 0.0, 6000.0]
        r.starts[1, 1] = 3.0 * pm.d  # one contact unlike the others: rows cannot be swapped unseen
        r()
        names = ["forceA", "forceB", "frictionForce"]
        reads = Reads(pm.contacts, names)
        got = reads()
        assert np.array_equal(got, np.array([c.get(names) for c in pm.contacts]))
        assert not np.array_equal(got[0], got[1])
        pm.contacts[2].s.reset()
        with pytest.raises(FmiError) as e:
            reads()
    assert e.value.function == "fmi2GetReal"
