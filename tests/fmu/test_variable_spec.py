"""The variable specs (fmu_src/models/<Name>/model.toml) and their generator (fmu_src/gen).

- the committed model descriptions and typed parameter records (harness/model/records/) are what
  the specs generate (no drift); each record holds what its model description declares;
- the patterns expand to the rows the FMU declares (names, value references by an independent loop);
- ShroudedBlade and BladeExternalContact declare the blade's variables identically (the shared block);
- the FMU packing is deterministic: the same files give the same bytes, whatever their time stamps,
  and the build's archive is that packing of its staging folder;
- adding a variable is one spec entry plus the C that computes it: a copy of the sources with one
  more Excitation output builds, and fmpy reads the new output at the value of its closed form;
- the two outputs of a spec agree: each built FMU refuses a parameter just beyond a declared bound
  and accepts the bound itself unless the description marks it open.
"""

from __future__ import annotations

import os
import shutil
import subprocess
import sys
import time
import xml.etree.ElementTree as ET
import zipfile
from pathlib import Path

import importlib
from dataclasses import fields

import pytest

REPO = Path(__file__).resolve().parents[2]
GEN = REPO / "fmu_src" / "gen"
MODELS = REPO / "fmu_src" / "models"
SPECS = sorted(MODELS.glob("*/model.toml"))


def _gen(*args: str) -> subprocess.CompletedProcess:
    return subprocess.run([sys.executable, str(GEN / "fmugen.py"), *args], capture_output=True, text=True)


def _variables(xml: Path) -> dict[str, ET.Element]:
    root = ET.parse(xml).getroot()
    return {sv.get("name"): sv for sv in root.iter("ScalarVariable")}


def test_every_model_has_a_spec():
    assert sorted(p.parent.name for p in SPECS) == [
        "BladeExternalContact",
        "Excitation",
        "ShroudContact",
        "ShroudedBlade",
    ]


def test_committed_generated_files_match_the_specs():
    proc = _gen(*map(str, SPECS), "--check")
    assert proc.returncode == 0, proc.stderr


RECORDS = REPO / "harness" / "model" / "records"


def _record_module(model: str) -> str:
    return {
        "ShroudedBlade": "shrouded_blade",
        "BladeExternalContact": "blade_external_contact",
        "Excitation": "excitation",
        "ShroudContact": "shroud_contact",
    }[model]


@pytest.mark.parametrize("spec", SPECS, ids=lambda p: p.parent.name)
def test_record_holds_what_the_model_description_declares(spec):
    # read independently from the committed modelDescription.xml: every parameter is a field of the
    # record, in order, with its start value, unit and bounds; open bounds from the vendor annotation
    root = ET.parse(spec.parent / "modelDescription.xml").getroot()
    ob = root.find("VendorAnnotations/Tool/OpenBounds")
    low_open = set(ob.get("lower", "").split()) if ob is not None else set()
    high_open = set(ob.get("upper", "").split()) if ob is not None else set()
    mod = importlib.import_module(f"harness.model.records.{_record_module(spec.parent.name)}")
    record = getattr(mod, f"{spec.parent.name}Parameters")
    got = {f.name: f for f in fields(record)}
    declared, starts = [], {}
    for sv in root.iter("ScalarVariable"):
        (typ,) = list(sv)
        conv = {"Real": float, "Integer": int, "Boolean": lambda x: x == "true"}[typ.tag]
        entry = {
            "type": typ.tag,
            "unit": typ.get("unit", ""),
            "min": None if typ.get("min") is None else float(typ.get("min")),
            "max": None if typ.get("max") is None else float(typ.get("max")),
            "min_open": sv.get("name") in low_open,
            "max_open": sv.get("name") in high_open,
            "value_reference": int(sv.get("valueReference")),
            "description": sv.get("description", ""),
        }
        if sv.get("causality") == "parameter":
            declared.append(sv.get("name"))
            f = got[sv.get("name")]
            assert f.default == conv(typ.get("start")) and type(f.default) is type(conv(typ.get("start")))
            assert dict(f.metadata) == entry, sv.get("name")
        elif sv.get("causality") == "output" and sv.get("initial") == "exact":
            starts[sv.get("name")] = dict(entry, start=conv(typ.get("start")))
    assert list(got) == declared
    assert mod.STATE_STARTS == starts
    with pytest.raises(Exception):  # frozen
        setattr(record(), declared[0], 1)


def test_params_validate_through_the_record():
    from harness.model import params

    r = params.typed({"d": 4e-5, "frictionModel": 3}, source="a test")
    assert r.d == 4e-5 and r.frictionModel == 3 and r.Fw0 == 100.0 and r.gating is True
    with pytest.raises(params.ParameterError) as e:
        params.typed({"kn": -1.0}, source="a test")
    assert all(w in str(e.value) for w in ("kn = -1.0", "(0, inf) N/m", "from a test")), str(e.value)
    with pytest.raises(params.ParameterError, match="tipDisplacement: start values of the state"):
        params.typed({"tipDisplacement": 1e-5})


def test_check_reports_a_drifted_record(tmp_path):
    # a copy of the generator, the specs and the records, one record's default changed by hand
    shutil.copytree(MODELS, tmp_path / "fmu_src" / "models")
    shutil.copytree(GEN, tmp_path / "fmu_src" / "gen")
    shutil.copy(REPO / "fmu_src" / "sources.toml", tmp_path / "fmu_src" / "sources.toml")
    shutil.copytree(RECORDS, tmp_path / "harness" / "model" / "records")
    rec = tmp_path / "harness" / "model" / "records" / "excitation.py"
    text = rec.read_text()
    assert "default=5000.0," in text
    rec.write_text(text.replace("default=5000.0,", "default=6000.0,", 1))
    spec = tmp_path / "fmu_src" / "models" / "Excitation" / "model.toml"
    proc = subprocess.run(
        [sys.executable, str(tmp_path / "fmu_src" / "gen" / "fmugen.py"), str(spec), "--check"],
        capture_output=True,
        text=True,
    )
    assert proc.returncode == 1 and "records/excitation.py" in proc.stderr, proc.stderr
    assert "modelDescription" not in proc.stderr  # only the record drifted


def test_check_reports_a_drifted_description(tmp_path):
    # a copy of a model folder whose committed description lost a variable: --check must say so
    models = tmp_path / "fmu_src" / "models"
    shutil.copytree(MODELS, models)
    shutil.copytree(GEN, tmp_path / "fmu_src" / "gen")
    shutil.copy(REPO / "fmu_src" / "sources.toml", tmp_path / "fmu_src" / "sources.toml")
    md = models / "Excitation" / "modelDescription.xml"
    md.write_text(md.read_text().replace('description="rotor speed n(t)"', 'description="rotor speed"'))
    proc = subprocess.run(
        [
            sys.executable,
            str(tmp_path / "fmu_src" / "gen" / "fmugen.py"),
            str(models / "Excitation" / "model.toml"),
            "--check",
        ],
        capture_output=True,
        text=True,
    )
    assert proc.returncode == 1 and "Excitation/modelDescription.xml" in proc.stderr


def test_sensitivity_pattern_expands_row_major():
    # independent loop: sensitivity[r,c], r = 1..15, c = 1..14, vr 1000 + 14 (r - 1) + (c - 1)
    declared = {
        n: int(sv.get("valueReference"))
        for n, sv in _variables(MODELS / "ShroudedBlade" / "modelDescription.xml").items()
        if n.startswith("sensitivity[")
    }
    expected = {f"sensitivity[{r},{c}]": 1000 + 14 * (r - 1) + (c - 1) for r in range(1, 16) for c in range(1, 15)}
    assert declared == expected


def test_shared_blade_variables_identical_in_both_blades():
    sb = _variables(MODELS / "ShroudedBlade" / "modelDescription.xml")
    bx = _variables(MODELS / "BladeExternalContact" / "modelDescription.xml")
    shared = [
        "EI",
        "rho",
        "A",
        "l",
        "c",
        "m0",
        "maxStep",
        "formulation",
        "engineOrder",
        "Fw0",
        "bladeIndex",
        "bladeCount",
        "modes",
        "aeroLoad",
        "rotorSpeed",
        "tipDisplacement",
        "tipVelocity",
        "naturalFrequency",
        "rootMoment",
    ] + [f"{a}[{i}]" for a in ("modalDisplacement", "modalVelocity", "modeFrequency") for i in range(1, 7)]
    for name in shared:
        a, b = sb[name], bx[name]
        assert a.attrib == b.attrib, name
        assert [(t.tag, t.attrib) for t in a] == [(t.tag, t.attrib) for t in b], name


def test_shared_contact_parameters_identical_in_blade_and_contact():
    # the facts of ../contact.toml (value reference, type, unit, bounds); ShroudContact keeps its own
    # descriptions and frictionModel's start value
    sb = _variables(MODELS / "ShroudedBlade" / "modelDescription.xml")
    sc = _variables(MODELS / "ShroudContact" / "modelDescription.xml")
    for name in ("kn", "kdRatio", "mu", "gamma", "d", "B", "frictionModel", "projection", "engineOrder", "gating"):
        a, b = sb[name], sc[name]
        assert {k: v for k, v in a.attrib.items() if k != "description"} == {
            k: v for k, v in b.attrib.items() if k != "description"
        }, name
        ta, tb = dict(a[0].attrib), dict(b[0].attrib)
        if name == "frictionModel":
            assert (ta.pop("start"), tb.pop("start")) == ("1", "3")
        assert (a[0].tag, ta) == (b[0].tag, tb), name


def test_a_bad_spec_is_refused_with_its_place(tmp_path):
    spec = tmp_path / "models" / "M" / "model.toml"
    spec.parent.mkdir(parents=True)
    shutil.copy(MODELS / "common.toml", tmp_path / "models" / "common.toml")
    var = 'type = "Real"\ncausality = "parameter"\nstart = 1.0\nstore = "par"\n'
    spec.write_text(
        '[model]\nname = "M"\nguid = "{g}"\ndescription = "d"\n[model.fmi2]\nsources = []\n'
        f'[[var]]\nname = "a"\nvr = 1\n{var}[[var]]\nname = "b"\nvr = 1\n{var}'
    )
    proc = _gen(str(spec), "--out", str(tmp_path / "gen"))
    assert proc.returncode == 2 and "value reference 1 of 'b' is taken by 'a'" in proc.stderr


def _stage(root: Path) -> Path:
    stage = root / "stage"
    for rel, data in [
        ("modelDescription.xml", b"<x/>"),
        ("binaries/linux64/M.so", b"\x7fELF"),
        ("sources/fmi/a.c", b"int a;"),
        ("sources/models/M/b.h", b"#define B"),
    ]:
        (stage / rel).parent.mkdir(parents=True, exist_ok=True)
        (stage / rel).write_bytes(data)
    return stage


def test_pack_gives_the_same_bytes_for_the_same_files(tmp_path):
    stage = _stage(tmp_path)
    pack = [sys.executable, str(GEN / "pack_fmu.py"), str(stage)]
    subprocess.run(pack + [str(tmp_path / "a.fmu")], check=True)
    later = time.time() + 3600.0
    for p in stage.rglob("*"):
        os.utime(p, (later, later))
    subprocess.run(pack + [str(tmp_path / "b.fmu")], check=True)
    a, b = (tmp_path / "a.fmu").read_bytes(), (tmp_path / "b.fmu").read_bytes()
    assert a == b
    with zipfile.ZipFile(tmp_path / "a.fmu") as z:
        names = z.namelist()
        assert names == sorted(names) and len(names) == 4
        assert {i.date_time for i in z.infolist()} == {(1980, 1, 1, 0, 0, 0)}


def test_built_fmu_is_the_deterministic_packing_of_its_stage(fmu_path, tmp_path):
    # the build packs build/ShroudedBlade_fmu with pack_fmu.py: packing that folder again gives the
    # archive's bytes, so a rebuild of unchanged sources leaves a copied (committed) FMU unchanged
    stage = fmu_path.parent / "ShroudedBlade_fmu"
    subprocess.run([sys.executable, str(GEN / "pack_fmu.py"), str(stage), str(tmp_path / "again.fmu")], check=True)
    assert (tmp_path / "again.fmu").read_bytes() == fmu_path.read_bytes()


# --- adding a variable: the worked example of docs/reference/architecture.md ---------------------

NEW_VAR = """
[[var]]
name = "excitationFrequency"
vr = 12
type = "Real"
causality = "output"
unit = "Hz"
output = "OutExcitationFrequency"
description = "excitation frequency engineOrder n / 60"
"""


def _copy_sources(dst: Path) -> None:
    """What the CMake project needs, without build trees or the venv."""
    shutil.copy(REPO / "CMakeLists.txt", dst / "CMakeLists.txt")
    shutil.copytree(REPO / "fmu_src", dst / "fmu_src", ignore=shutil.ignore_patterns("__pycache__"))
    for rel in (
        "harness/native/ring_master.c",
        "harness/native/ring_restart.c",
        "tests/c/CMakeLists.txt",
        "bench/bench_step.c",
    ):
        (dst / rel).parent.mkdir(parents=True, exist_ok=True)
        shutil.copy(REPO / rel, dst / rel)


def test_adding_a_variable_is_one_spec_entry_plus_its_c(tmp_path):
    fmpy = pytest.importorskip("fmpy")
    from fmpy import read_model_description, simulate_fmu

    src = tmp_path / "src"
    src.mkdir()
    _copy_sources(src)
    model = src / "fmu_src" / "models" / "Excitation"
    (model / "model.toml").write_text((model / "model.toml").read_text() + NEW_VAR)
    c = (model / "model.c").read_text()
    c = c.replace(
        "enum { OutAeroLoad = 0, OutRotorSpeed };", "enum { OutAeroLoad = 0, OutRotorSpeed, OutExcitationFrequency };"
    )
    c = c.replace(
        "    return id == OutAeroLoad ? o->aeroLoad : o->rotorSpeed;",
        "    if (id == OutExcitationFrequency)\n"
        "        return ((const ExcitationData *)inst->data)->ipar[IparEngineOrder] * o->rotorSpeed / 60.0;\n"
        "    return id == OutAeroLoad ? o->aeroLoad : o->rotorSpeed;",
    )
    assert "OutExcitationFrequency)" in c, "the C edit did not apply: model.c changed, update this test"
    (model / "model.c").write_text(c)
    headers = Path(fmpy.__file__).parent / "c-code"
    build = tmp_path / "build"
    for cmd in (
        [
            "cmake",
            "-S",
            str(src),
            "-B",
            str(build),
            "-DCMAKE_BUILD_TYPE=Release",
            f"-DPython3_EXECUTABLE={sys.executable}",
            f"-DFMI_HEADERS_DIR={headers}",
        ],
        ["cmake", "--build", str(build), "-j", "2", "--target", "excitation_fmu"],
    ):
        proc = subprocess.run(cmd, capture_output=True, text=True)
        assert proc.returncode == 0, proc.stdout[-3000:] + proc.stderr[-3000:]
    fmu = build / "Excitation.fmu"
    md = read_model_description(str(fmu))
    (var,) = [v for v in md.modelVariables if v.name == "excitationFrequency"]
    assert (var.valueReference, var.causality, var.unit) == (12, "output", "Hz")
    n0, eo = 4800.0, 5
    res = simulate_fmu(
        str(fmu),
        stop_time=0.01,
        output_interval=0.005,
        start_values={"n0": n0, "n1": n0, "engineOrder": eo},
        output=["excitationFrequency"],
    )
    # closed form eo n / 60 = 400 Hz; one rounding of the product and the division
    assert res["excitationFrequency"] == pytest.approx(eo * n0 / 60.0, rel=1e-15)


# --- the two outputs of a spec agree: the C table's range checks are the description's bounds ------


@pytest.mark.parametrize("name", ["ShroudedBlade", "BladeExternalContact", "ShroudContact", "Excitation"])
def test_the_fmu_accepts_exactly_the_declared_ranges(name, tmp_path):
    """Every bounded parameter through the built binary: a value just outside a bound is refused, the
    bound itself is accepted unless the description's OpenBounds annotation excludes it."""
    from fmpy import extract, read_model_description
    from fmpy.fmi1 import FMICallException
    from fmpy.fmi2 import FMU2Slave

    from harness.fmu.build import fmu_file

    fmu = fmu_file(name)
    md = read_model_description(str(fmu))
    root = ET.fromstring(zipfile.ZipFile(fmu).read("modelDescription.xml"))
    ob = root.find("VendorAnnotations/Tool/OpenBounds")
    open_low = set(ob.get("lower", "").split()) if ob is not None else set()
    open_high = set(ob.get("upper", "").split()) if ob is not None else set()
    slave = FMU2Slave(
        guid=md.guid,
        unzipDirectory=extract(str(fmu), str(tmp_path / "x")),
        modelIdentifier=md.coSimulation.modelIdentifier,
        instanceName="bounds",
    )
    slave.instantiate()

    def accepted(v, x) -> bool:
        try:
            (slave.setReal if v.type == "Real" else slave.setInteger)([v.valueReference], [x])
            return True
        except FMICallException:
            return False

    checked = 0
    try:
        for v in md.modelVariables:
            if v.causality != "parameter" or v.type not in ("Real", "Integer"):
                continue
            for bound, outward, is_open in ((v.min, -1, v.name in open_low), (v.max, 1, v.name in open_high)):
                if bound is None:
                    continue
                b = float(bound) if v.type == "Real" else int(bound)
                beyond = b + outward * max(abs(b), 1.0) * 1e-9 if v.type == "Real" else b + outward
                assert not accepted(v, beyond), f"{name}: {v.name} = {beyond!r} accepted beyond {b!r}"
                assert accepted(v, b) != is_open, f"{name}: {v.name} = {b!r} (open: {is_open})"
                accepted(v, float(v.start) if v.type == "Real" else int(v.start))  # back to the default
                checked += 1
    finally:
        slave.freeInstance()
    assert checked >= 4


# ShroudedBlade's two FMUs: tests/fmu/test_fmu_basics.py and tests/fmu/test_fmi3.py
@pytest.mark.parametrize("name", ["BladeExternalContact", "ShroudContact", "Excitation"])
def test_generated_descriptions_pass_fmpy_validation(name):
    from fmpy.validation import validate_fmu

    from harness.fmu.build import fmu_file

    assert validate_fmu(str(fmu_file(name))) == []
