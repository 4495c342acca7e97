"""The package's FMI binding (harness.fmu.binding) itself: its signature tables against the FMI
headers shipped with fmpy (parsed here, an independent source), the status -> FmiError mapping and
raw mode, and log capture (compared with the tests' C proxy, which formats with vsnprintf)."""

from __future__ import annotations

import ctypes
import re
from pathlib import Path

import fmpy
import pytest

from tests.support import fmi2raw as F
from tests.support import fmi3raw as F3
from harness.fmu.binding import DISCARD, ERROR, FATAL, OK, PENDING, WARNING, FmiError, fmi2, fmi3
from harness.fmu.binding import fmi2_signatures, fmi3_signatures

HEADERS = Path(fmpy.__file__).parent / "c-code"
_C_BASE = {
    "void*": ctypes.c_void_p,
    "unsigned int": ctypes.c_uint,
    "double": ctypes.c_double,
    "float": ctypes.c_float,
    "int": ctypes.c_int,
    "char": ctypes.c_char,
    "bool": ctypes.c_bool,
    "size_t": ctypes.c_size_t,
    "int8_t": ctypes.c_int8,
    "uint8_t": ctypes.c_uint8,
    "int16_t": ctypes.c_int16,
    "uint16_t": ctypes.c_uint16,
    "int32_t": ctypes.c_int32,
    "uint32_t": ctypes.c_uint32,
    "int64_t": ctypes.c_int64,
    "uint64_t": ctypes.c_uint64,
}


def _strip_comments(text: str) -> str:
    return re.sub(r"//[^\n]*", "", re.sub(r"/\*.*?\*/", "", text, flags=re.S))


def _typedefs(*files: str) -> dict[str, object]:
    """The platform types of the headers as ctypes: scalar typedefs through their C base type,
    pointers (and strings: char*) by kind, enums as int (C's enum type), callbacks as pointers."""
    out: dict[str, object] = {"size_t": ctypes.c_size_t}
    for name in files:
        text = _strip_comments((HEADERS / name).read_text())
        for base, star, new in re.findall(r"typedef\s+(?:const\s+)?([\w ]+?)\s*(\*?)\s*(fmi[23]\w+)\s*;", text):
            if star:
                out[new] = ctypes.c_char_p if base.strip() in ("fmi2Char", "fmi3Char") else ctypes.c_void_p
            else:
                out[new] = out.get(base.strip(), _C_BASE.get(base.strip()))
        for new in re.findall(r"typedef\s+enum\s*\{[^}]*\}\s*(\w+)\s*;", text):
            out[new] = ctypes.c_int
        for new in re.findall(r"typedef\s+[\w*\s]+\(\s*\*\s*(\w+)\s*\)", text):
            out[new] = ctypes.c_void_p
    return out


def _prototypes(header: str, types: dict[str, object]) -> dict[str, tuple[object, list[object]]]:
    """name -> (restype, argtypes) of every `typedef R fmiXxxTYPE(args);` of the header. A pointer
    or array argument is an address (c_void_p), a const char* result a string (c_char_p)."""
    text = _strip_comments((HEADERS / header).read_text())
    out = {}
    for ret, name, args in re.findall(r"typedef\s+([\w\s*]+?)\s*(fmi[23]\w+)TYPE\s*\(([^)]*)\)\s*;", text):
        ret = " ".join(ret.split())
        restype = {"void": None, "const char*": ctypes.c_char_p}.get(ret, types.get(ret))
        argtypes = []
        for a in [x.strip() for x in args.split(",") if x.strip() not in ("", "void")]:
            words = a.replace("*", " * ").replace("[", " [").split()
            if "*" in words or any(w.startswith("[") for w in words):
                argtypes.append(ctypes.c_void_p)
            else:
                argtypes.append(types[[w for w in words if w != "const"][0]])
        out[name] = (restype, argtypes)
    return out


FMI2_HEADER = _prototypes("fmi2FunctionTypes.h", _typedefs("fmi2TypesPlatform.h", "fmi2FunctionTypes.h"))
FMI3_HEADER = _prototypes("fmi3FunctionTypes.h", _typedefs("fmi3PlatformTypes.h", "fmi3FunctionTypes.h"))


def test_the_header_parser_reads_known_prototypes() -> None:
    # a parser that reads nothing would make the table comparison vacuous
    assert len(FMI2_HEADER) == 44 and len(FMI3_HEADER) == 75  # every fmi*TYPE typedef of the headers
    assert FMI2_HEADER["fmi2DoStep"] == (
        ctypes.c_int,
        [ctypes.c_void_p, ctypes.c_double, ctypes.c_double, ctypes.c_int],
    )
    assert FMI3_HEADER["fmi3GetNumberOfVariableDependencies"][1][1] is ctypes.c_uint32


@pytest.mark.parametrize(
    "table,header",
    [(fmi2_signatures.SIGNATURES, FMI2_HEADER), (fmi3_signatures.SIGNATURES, FMI3_HEADER)],
    ids=["fmi2", "fmi3"],
)
def test_signature_tables_match_the_fmi_headers(table, header) -> None:  # noqa: ANN001
    wrong = {name: (sig, header.get(name)) for name, sig in table.items() if header.get(name) != (sig[0], list(sig[1]))}
    assert not wrong, wrong


def test_the_fmi2_table_covers_the_whole_fmi2_api() -> None:
    assert set(fmi2_signatures.SIGNATURES) == set(FMI2_HEADER)


def test_the_fmi3_table_covers_co_simulation_and_model_exchange() -> None:
    # left out on purpose: clocks and scheduled execution (no FMU of the project has them)
    left_out = set(FMI3_HEADER) - set(fmi3_signatures.SIGNATURES)
    assert left_out and all(
        re.search(r"Clock|Interval|Shift|ScheduledExecution|ActivateModelPartition", n) for n in left_out
    ), sorted(left_out)


def test_the_library_exports_every_required_function() -> None:
    assert F.Fmi2Library.get().missing == [] and F3.Fmi3Library.get().missing == []


# ---------------------------------------------------------------------------------------------
# status -> exception, raw mode, log capture (FMI 2.0)


def _fmi2(name: str = "bound", **kw) -> fmi2.Fmi2Instance:
    lib = F.Fmi2Library.get()
    return fmi2.Fmi2Instance(lib, name, F.GUID, F.resource_uri(lib.path), logging_on=True, **kw)


def _initialized(inst: fmi2.Fmi2Instance) -> fmi2.Fmi2Instance:
    inst.setup_experiment(0.0)
    inst.enter_initialization_mode()
    inst.exit_initialization_mode()
    return inst


@pytest.mark.parametrize("status", [OK, WARNING])
def test_ok_and_warning_do_not_raise(status: int) -> None:
    with _fmi2() as inst:
        assert inst.check("fmi2DoStep", status) == status and inst.status == status


@pytest.mark.parametrize("status", [DISCARD, ERROR, FATAL, PENDING, 7])
def test_other_statuses_raise_naming_function_status_and_message(status: int) -> None:
    with _fmi2() as inst:
        inst.log.append(fmi2.LogRecord("bound", ERROR, "logStatusError", "the last thing said"))
        with pytest.raises(FmiError) as e:
            inst.check("fmi2DoStep", status)
        assert (e.value.function, e.value.status, e.value.message) == ("fmi2DoStep", status, "the last thing said")
        assert "fmi2DoStep" in str(e.value) and "the last thing said" in str(e.value)


def test_a_refused_call_raises_with_the_fmus_own_message() -> None:
    with _initialized(_fmi2()) as inst:
        inst.do_step(0.0, 1e-4)
        with pytest.raises(FmiError) as e:
            inst.do_step(5.0, 1e-4)  # not the FMU's time
        assert e.value.function == "fmi2DoStep" and e.value.status == ERROR
        assert e.value.message == inst.log[-1].message and "currentCommunicationPoint" in e.value.message


def test_raw_mode_returns_statuses_and_values() -> None:
    with _initialized(_fmi2(raw=True)) as inst:
        assert inst.do_step(5.0, 1e-4) == ERROR and inst.status == ERROR
        inst.get_real([999])
        assert inst.status == ERROR
        inst.get_real([F.VR["q"]] if "q" in F.VR else [F.VR[F.REAL_OUTPUTS[0]]])
        assert inst.status == OK


def test_a_failed_instantiation_raises() -> None:
    with pytest.raises(FmiError) as e:
        fmi2.Fmi2Instance(F.Fmi2Library.get(), "bad", "{not-the-guid}", None)
    assert e.value.function == "fmi2Instantiate"


def test_log_records_match_a_vsnprintf_formatting_importer() -> None:
    # the same refused calls through the binding's Python logger and through the tests' C proxy
    # (vsnprintf): instance, status, category and message agree
    calls = [
        lambda i: i.do_step(5.0, 1e-4),
        lambda i: i.set_real([F.VR["aeroLoad"]], [float("nan")]),
        lambda i: i.get_real([999]),
    ]
    with _initialized(_fmi2("same", raw=True)) as mine, F.Instance(name="same") as ref:
        assert ref.initialize() == OK
        for call in calls:
            mine.log.clear()
            ref.clear_log()
            call(mine)
            call(ref.f)
            assert mine.log and list(mine.log) == list(ref.log)


def test_log_capture_is_per_instance_with_hook_and_limit() -> None:
    seen = []
    with (
        _initialized(_fmi2("a", raw=True, log_limit=2, on_log=seen.append)) as a,
        _initialized(_fmi2("b", raw=True)) as b,
    ):
        seen.clear()
        for _ in range(3):
            a.get_real([999])
        errors = [r for r in seen if r.status == ERROR]
        assert len(a.log) == 2 and list(a.log) == seen[-2:] and all(r.instance == "a" for r in seen)
        assert len(errors) == 3 and all(r.category == "logStatusError" and "999" in r.message for r in errors)
        assert not [r for r in b.log if r.status >= ERROR]


# ---------------------------------------------------------------------------------------------
# FMI 3.0


def _fmi3(**kw) -> fmi3.Fmi3Instance:
    return fmi3.Fmi3Instance(F3.Fmi3Library.get(), "three", F3.TOKEN, logging_on=True, **kw)


def test_fmi3_refused_call_raises_and_raw_mode_returns() -> None:
    with _fmi3() as inst:
        inst.enter_initialization_mode()
        inst.exit_initialization_mode()
        with pytest.raises(FmiError) as e:
            inst.get("Float64", [999])
        assert e.value.function == "fmi3GetFloat64" and e.value.status == ERROR
        assert e.value.message == inst.log[-1].message and inst.log[-1].instance == "three"
    with _fmi3(raw=True) as inst:
        inst.get("Float64", [999])
        assert inst.status == ERROR and inst.log[-1].status == ERROR
