"""The ring as an SSP file (harness/system/ssp.py) in libcosim and Ecos.

- the SSD has N blades and N contacts (2 N components, 6 N connections) with the built-in load's
  parameters (Fw0 explicit, blade i's bladeIndex, bladeCount N, engineOrder);
- libcosim from the SSP equals libcosim built through its API (harness/system/ring_libcosim.py)
  bit for bit (N = 4, EO = 3, contacts closing);
- Ecos from the same SSP equals it within 1e-12 of max |q| (Ecos accumulates t += h: its
  communication points differ by ulps; measured 1.8e-18 m);
- with contacts open, the SSP in libcosim equals the fmpy master with held inputs bit for bit;
- N = 36 loads and runs in both tools, which agree within 1e-12.
"""

from __future__ import annotations

import xml.etree.ElementTree as ET

import numpy as np

from harness.fmu.build import BUILD_DIR
from harness.system import ring_libcosim, ssp
from harness.system.ring import Ring, run


TUNED = dict(blade={"c": 298.0}, fw0=300.0)


def test_ssd_is_well_formed_and_complete(tmp_path):
    ring = Ring(n=5, **TUNED)
    d = ssp.write(ring, tmp_path / "ring5")
    root = ET.parse(d / "SystemStructure.ssd").getroot()
    ns = {"ssd": ssp.SSD, "ssv": ssp.SSV}
    assert len(root.findall(".//ssd:Component", ns)) == 2 * 5
    assert len(root.findall(".//ssd:Connection", ns)) == 6 * 5
    assert (d.with_suffix(".ssp")).is_file()
    blade3 = next(c for c in root.findall(".//ssd:Component", ns) if c.get("name") == "blade3")
    values = {p.get("name"): p[0].get("value") for p in blade3.findall(".//ssv:Parameter", ns)}
    # Fw0 explicit on every blade (the FMU's default is another value)
    assert values["Fw0"] == "300.0"
    assert (values["bladeIndex"], values["bladeCount"], values["engineOrder"]) == ("3", "5", "3")


def test_libcosim_ssp_equals_api_and_ecos():
    ring = Ring(n=4, engine_order=3, stop_time=0.01, step=2.5e-5, order=0, **TUNED)
    d = ssp.write(ring, BUILD_DIR / "ring4_test")
    a = ssp.run_libcosim(d, ring)
    b = ring_libcosim.run(ring)
    assert np.abs(b["q"]).max() > 1e-5
    assert np.array_equal(a["q"], b["q"])
    e = ssp.run_ecos(d, ring)
    assert np.abs(e["q"] - a["q"]).max() <= 1e-12 * np.abs(a["q"]).max()


def test_open_contacts_ssp_equals_fmpy_master():
    ring = Ring(n=3, engine_order=1, stop_time=0.01, contact={"d": 1.0}, order=0)
    d = ssp.write(ring, BUILD_DIR / "ring3_open_test")
    a = ssp.run_libcosim(d, ring)
    b = run(ring)
    assert np.array_equal(a["q"], b["q"])


def test_ring_of_36_in_both_tools():
    ring = Ring(n=36, engine_order=3, stop_time=0.005, step=2.5e-5, order=0)
    d = ssp.write(ring, BUILD_DIR / "ring36_test")
    a, e = ssp.run_libcosim(d, ring), ssp.run_ecos(d, ring)
    assert np.all(np.isfinite(a["q"])) and np.abs(a["q"]).max() > 1e-6
    assert np.abs(e["q"] - a["q"]).max() <= 1e-12 * np.abs(a["q"]).max()
