"""The FMI 3.0 co-simulation FMU (build/fmi3/ShroudedBlade.fmu, fmu_src/fmi/fmi3_cs.c) against the
FMI 2.0 one built from the same sources.

- fmpy.validate_fmu finds no problem; the capabilities declared are the real ones; the variables
  equal modelDescription.xml's (names, value references, types, causality, variability, initial,
  units, ranges, start values, descriptions) plus the independent variable time.
- Bit for bit: driven through fmpy (FMU2Slave / FMU3Slave) with the same communication points
  and the same inputs, every output of the FMI 3.0 FMU equals the FMI 2.0 one's at every point
  (compared as IEEE bit patterns), over all friction models, gating on and off, both amplitude
  modes, a run-up and a variable step; fmpy.simulate_fmu gives identical result tables, and so does
  Ecos (ecospy). Inputs are held over each step in both (FMI 3.0 co-simulation has no function to
  set input derivatives).
- FMU state: get/set and serialize/deserialize (also into a fresh instance, and a state serialized
  by the FMI 2.0 FMU) continue bit-identically.
- Invalid calls (out-of-range parameter, wrong call order, bad value reference or type, mismatched
  communication point, NULL/size arguments, unsupported functions and instantiation options) give
  fmi3Error with a logged message, and the instance stays usable (or is recovered by fmi3Reset).
"""

from __future__ import annotations

import ctypes
import shutil
from pathlib import Path

import fmpy
import numpy as np
import pytest
from fmpy import read_model_description, simulate_fmu
from fmpy.fmi1 import FMICallException
from fmpy.fmi2 import FMU2Slave
from fmpy.fmi3 import FMU3Slave, fmi3LogMessageCallback
from fmpy.validation import validate_fmu

from harness.model.excitation import AeroLoad, Constant, LinearRamp

FW0 = 100.0  # aerodynamic load amplitude [N/m]
STOP = 0.02  # run length [s] (contact starts after ~7 ms at 5000-6000 rpm)
H = 1e-4  # communication step [s]
VR_ROTOR, VR_AERO, VR_TIME = 41, 40, 0


@pytest.fixture(scope="module")
def fmus(fmu_path: Path, fmu3_path: Path, tmp_path_factory: pytest.TempPathFactory):
    """Both FMUs extracted once: (md2, dir2, md3, dir3)."""
    root = tmp_path_factory.mktemp("fmi3")
    d2, d3 = fmpy.extract(str(fmu_path), str(root / "fmi2")), fmpy.extract(str(fmu3_path), str(root / "fmi3"))
    yield read_model_description(d2), d2, read_model_description(d3), d3
    shutil.rmtree(root, ignore_errors=True)


# ------------------------------------------------------------------------------------------------
# model description


def test_validate_fmu(fmu3_path: Path) -> None:
    assert validate_fmu(str(fmu3_path)) == []


def test_capabilities(fmus) -> None:
    _, _, md3, d3 = fmus
    cs = md3.coSimulation
    assert md3.fmiVersion == "3.0" and md3.modelExchange is None and cs.modelIdentifier == "ShroudedBlade"
    assert (Path(d3) / "binaries" / "x86_64-linux" / "ShroudedBlade.so").is_file()
    assert (Path(d3) / "sources" / "buildDescription.xml").is_file()
    assert cs.canGetAndSetFMUstate and cs.canSerializeFMUstate and cs.canHandleVariableCommunicationStepSize
    # not real here, so not declared
    assert not cs.providesIntermediateUpdate and not cs.hasEventMode
    assert not cs.providesDirectionalDerivative and cs.maxOutputDerivativeOrder in (0, None)


def _attrs(v) -> tuple:
    types = {"Real": "Float64", "Integer": "Int32"}
    return (
        v.valueReference,
        types.get(v.type, v.type),
        v.causality,
        v.variability,
        v.initial,
        v.description,
        v.unit,
        v.min,
        v.max,
        v.start,
    )


def test_same_variables_as_fmi2(fmus) -> None:
    md2, _, md3, _ = fmus
    # the FMI 2.0 FMU also carries <ModelExchange>: its states without a variable so far and the
    # derivatives (the locals other than the sensitivities) are not in the FMI 3.0 co-simulation FMU,
    # nor are the states among the outputs' dependencies
    me_only = {
        v.name
        for v in md2.modelVariables
        if v.causality == "local" and v.name in ("excitationPhase", "sliderPosition") or v.name.startswith("der(")
    }
    assert len(me_only) == 7 + 10 and md2.modelExchange is not None
    v2 = {v.name: _attrs(v) for v in md2.modelVariables if v.name not in me_only}
    v3 = {v.name: _attrs(v) for v in md3.modelVariables}
    assert v3.pop("time") == (
        VR_TIME,
        "Float64",
        "independent",
        "continuous",
        None,
        "simulation time",
        "s",
        None,
        None,
        None,
    )
    assert v3 == v2
    assert md3.guid == md2.guid  # instantiationToken = guid: one model, one state format
    deps = lambda md: {
        u.variable.name: sorted(d.name for d in (u.dependencies or []) if d.causality == "input") for u in md.outputs
    }
    assert deps(md3) == deps(md2)
    assert sorted(u.variable.name for u in md3.initialUnknowns) == sorted(
        u.variable.name for u in md2.initialUnknowns if u.variable.name not in me_only
    )


# ------------------------------------------------------------------------------------------------
# bit-for-bit against the FMI 2.0 FMU


class _Pair:
    """The FMI 2.0 and 3.0 FMUs instantiated side by side, driven identically."""

    def __init__(self, fmus, params: dict, name: str = "pair") -> None:
        md2, d2, md3, d3 = fmus
        self.vars = {v.name: v for v in md2.modelVariables}
        self.f2 = FMU2Slave(guid=md2.guid, unzipDirectory=d2, modelIdentifier="ShroudedBlade", instanceName=name)
        self.f3 = FMU3Slave(guid=md3.guid, unzipDirectory=d3, modelIdentifier="ShroudedBlade", instanceName=name)
        self.f2.instantiate()
        self.f3.instantiate()
        for k, x in params.items():
            v = self.vars[k]
            {
                "Real": lambda: (self.f2.setReal([v.valueReference], [x]), self.f3.setFloat64([v.valueReference], [x])),
                "Integer": lambda: (
                    self.f2.setInteger([v.valueReference], [x]),
                    self.f3.setInt32([v.valueReference], [x]),
                ),
                "Boolean": lambda: (
                    self.f2.setBoolean([v.valueReference], [x]),
                    self.f3.setBoolean([v.valueReference], [x]),
                ),
            }[v.type]()
        self.f2.setupExperiment(startTime=0.0)
        self.f2.enterInitializationMode()
        self.f3.enterInitializationMode(startTime=0.0)
        self.f2.exitInitializationMode()
        self.f3.exitInitializationMode()
        outs = [v for v in md2.modelVariables if v.causality == "output"]
        self.real = [v.valueReference for v in outs if v.type == "Real"]
        self.int = [v.valueReference for v in outs if v.type == "Integer"]

    def outputs(self) -> tuple[np.ndarray, np.ndarray]:
        o2 = np.array(self.f2.getReal(self.real) + [float(i) for i in self.f2.getInteger(self.int)])
        o3 = np.array(self.f3.getFloat64(self.real) + [float(i) for i in self.f3.getInt32(self.int)])
        return o2, o3

    def step(self, t: float, h: float, aero: float, speed: float) -> None:
        self.f2.setReal([VR_AERO, VR_ROTOR], [aero, speed])
        self.f3.setFloat64([VR_AERO, VR_ROTOR], [aero, speed])
        self.f2.doStep(t, h)
        event, terminate, early, last = self.f3.doStep(t, h)
        assert (event, terminate, early, last) == (False, False, False, t + h)

    def free(self) -> None:
        for f in (self.f2, self.f3):
            f.terminate()
            f.freeInstance()


def _bits(a: np.ndarray) -> np.ndarray:
    return np.ascontiguousarray(a, dtype=np.float64).view(np.uint64)


SCENARIOS = {
    # frictionModel, gating, amplitudeMode, speed [rpm] (constant or run-up over the run), steps
    "macroslip DF, gated, tracked B, 6000 rpm": (dict(frictionModel=1, gating=True, amplitudeMode=2), 6000.0),
    "macroslip DF, ungated, fixed B, run-up 4000-6000 rpm": (
        dict(frictionModel=1, gating=False, amplitudeMode=1),
        (4000.0, 6000.0),
    ),
    "Coulomb DF, gated, fixed B, 5000 rpm": (dict(frictionModel=2, gating=True, amplitudeMode=1), 5000.0),
    "Coulomb DF, ungated, tracked B, run-up 4500-5500 rpm": (
        dict(frictionModel=2, gating=False, amplitudeMode=2),
        (4500.0, 5500.0),
    ),
    "Jenkins element, tracked B, run-up 4000-6000 rpm": (dict(frictionModel=3, amplitudeMode=2), (4000.0, 6000.0)),
    "Jenkins element, fixed B, 6000 rpm": (dict(frictionModel=3, gating=False, amplitudeMode=1), 6000.0),
}


def _signals(speed):
    n = Constant(speed) if isinstance(speed, float) else LinearRamp(speed[0], speed[1], 0.0, STOP)
    return AeroLoad(FW0, 3, n), n


@pytest.mark.parametrize("name", list(SCENARIOS))
def test_bit_identical_to_fmi2(fmus, name: str) -> None:
    params, speed = SCENARIOS[name]
    aero, n = _signals(speed)
    pair = _Pair(fmus, params)
    steps = int(round(STOP / H))
    rows2, rows3 = [], []
    try:
        o2, o3 = pair.outputs()
        rows2.append(o2), rows3.append(o3)
        for k in range(steps):
            t = k * H
            pair.step(t, H, float(aero(t)), float(n(t)))
            o2, o3 = pair.outputs()
            rows2.append(o2), rows3.append(o3)
    finally:
        pair.free()
    r2, r3 = np.array(rows2), np.array(rows3)
    assert np.array_equal(_bits(r2), _bits(r3)), (
        f"{name}: first differing row {np.argmax((_bits(r2) != _bits(r3)).any(axis=1))}"
    )
    # not vacuous: the blade moves and the contact acts
    q, contact, keq = r2[:, pair.real.index(50)], r2[:, len(pair.real) + pair.int.index(61)], r2[:, pair.real.index(54)]
    assert np.max(np.abs(q)) > 1e-6 and (np.any(contact > 0) or np.any(keq != 0.0)), name


def test_variable_step_bit_identical(fmus) -> None:
    """canHandleVariableCommunicationStepSize: steps of 1e-4, 2.5e-5 and 3.7e-4 s in turn."""
    aero, n = _signals((4000.0, 6000.0))
    pair = _Pair(fmus, dict(frictionModel=3))
    t, k, pattern = 0.0, 0, (1e-4, 2.5e-5, 3.7e-4)
    try:
        while t < STOP:
            h = pattern[k % 3]
            pair.step(t, h, float(aero(t)), float(n(t)))
            t, k = t + h, k + 1
            o2, o3 = pair.outputs()
            assert np.array_equal(_bits(o2), _bits(o3)), f"step {k} at t = {t}"
    finally:
        pair.free()


def test_simulate_fmu_bit_identical(fmus) -> None:
    """fmpy.simulate_fmu as the master of both FMUs (its FMI 3.0 co-simulation path), with an input
    table (run-up, held inputs): identical result tables."""
    _, d2, _, d3 = fmus
    aero, n = _signals((4000.0, 6000.0))
    t = np.linspace(0.0, STOP, 2001)
    table = np.zeros(t.size, dtype=[("time", float), ("aeroLoad", float), ("rotorSpeed", float)])
    table["time"], table["aeroLoad"], table["rotorSpeed"] = t, aero(t), n(t)
    kw = dict(stop_time=STOP, output_interval=H, input=table, start_values={"frictionModel": 3})
    r2 = simulate_fmu(d2, fmi_type="CoSimulation", **kw)
    r3 = simulate_fmu(d3, fmi_type="CoSimulation", **kw)
    assert r2.dtype.names == r3.dtype.names and len(r2) == len(r3) == 201
    for f in r2.dtype.names:
        assert np.array_equal(_bits(r2[f].astype(float)), _bits(r3[f].astype(float))), f
    assert np.max(np.abs(r3["tipDisplacement"])) > 3e-5


# ------------------------------------------------------------------------------------------------
# FMU state


def _run(f, t0: float, steps: int, aero, n, get, real) -> np.ndarray:
    rows = []
    for k in range(steps):
        t = t0 + k * H
        (f.setReal if isinstance(f, FMU2Slave) else f.setFloat64)([VR_AERO, VR_ROTOR], [float(aero(t)), float(n(t))])
        f.doStep(t, H)
        rows.append(get(real))
    return np.array(rows)


def test_state_round_trip(fmus) -> None:
    """fmi3GetFMUState/SetFMUState, Serialize/Deserialize (same instance and a fresh one), and a
    state serialized by the FMI 2.0 FMU: the continuation is bit-identical each time."""
    aero, n = _signals((4000.0, 6000.0))
    pair = _Pair(fmus, dict(frictionModel=3), name="a")
    md2, d2, md3, d3 = fmus
    f2, f3, real = pair.f2, pair.f3, pair.real
    k0, k1 = 100, 60
    try:
        for k in range(k0):
            pair.step(k * H, H, float(aero(k * H)), float(n(k * H)))
        t0 = k0 * H
        s3 = f3.getFMUState()
        blob3 = f3.serializeFMUState(s3)
        blob2 = f2.serializeFMUState(f2.getFMUState())
        assert blob2 == blob3  # one state format: the same bytes from both faces
        ref = _run(f3, t0, k1, aero, n, f3.getFloat64, real)
        assert np.array_equal(_bits(ref), _bits(_run(f2, t0, k1, aero, n, f2.getReal, real)))

        f3.setFMUState(s3)  # in-memory copy
        assert np.array_equal(_bits(ref), _bits(_run(f3, t0, k1, aero, n, f3.getFloat64, real)))

        s3b = f3.deserializeFMUState(blob3)  # deserialized copy, same instance
        f3.setFMUState(s3b)
        assert f3.getFloat64([VR_TIME]) == [t0]
        assert np.array_equal(_bits(ref), _bits(_run(f3, t0, k1, aero, n, f3.getFloat64, real)))
        f3.freeFMUState(s3)
        f3.freeFMUState(s3b)

        fresh = FMU3Slave(guid=md3.guid, unzipDirectory=d3, modelIdentifier="ShroudedBlade", instanceName="b")
        fresh.instantiate()
        try:
            for blob in (blob3, blob2):  # the FMI 2.0 FMU's state continues in the FMI 3.0 one
                s = fresh.deserializeFMUState(blob)
                fresh.setFMUState(s)
                assert np.array_equal(_bits(ref), _bits(_run(fresh, t0, k1, aero, n, fresh.getFloat64, real)))
                fresh.freeFMUState(s)
        finally:
            fresh.terminate()
            fresh.freeInstance()
    finally:
        pair.free()


# ------------------------------------------------------------------------------------------------
# invalid calls: fmi3Error with a message, no crash


class _Log:
    def __init__(self) -> None:
        self.records: list[tuple[int, str, str]] = []
        self.callback = fmi3LogMessageCallback(self)

    def __call__(self, env, status, category, message) -> None:  # noqa: ANN001
        self.records.append((status, category.decode(), message.decode()))

    def take(self) -> list[tuple[int, str, str]]:
        r, self.records = self.records, []
        return r


def _slave(fmus, log: _Log, **kw) -> FMU3Slave:
    _, _, md3, d3 = fmus
    f = FMU3Slave(guid=kw.pop("guid", md3.guid), unzipDirectory=d3, modelIdentifier="ShroudedBlade", instanceName="err")
    f.instantiate(loggingOn=True, logMessage=log, **kw)
    return f


def _bytes(buf) -> ctypes._Pointer:  # noqa: ANN001
    return ctypes.cast(buf, ctypes.POINTER(ctypes.c_uint8))


def _errors(log: _Log) -> list[str]:
    return [m for s, c, m in log.take() if s == 3 and c == "logStatusError"]


def _expect_error(log: _Log, call, *fragments: str) -> None:
    log.take()
    with pytest.raises(FMICallException) as e:
        call()
    assert e.value.status == 3  # fmi3Error
    errors = _errors(log)
    assert errors, "no error message logged"
    assert all(f in errors[-1] for f in fragments), errors[-1]


def test_invalid_calls(fmus) -> None:
    log = _Log()
    f = _slave(fmus, log)
    lib = f.dll
    try:
        # call order before initialization
        _expect_error(log, lambda: f.doStep(0.0, H), "fmi3DoStep: Illegal call sequence (state: Instantiated)")
        _expect_error(log, lambda: f.getFloat64([50]), "fmi3GetFloat64: Illegal call sequence")
        _expect_error(log, f.exitInitializationMode, "fmi3ExitInitializationMode: Illegal call sequence")
        # out-of-range parameters, unknown references, wrong types, the independent variable
        _expect_error(log, lambda: f.setFloat64([13], [1.0]), "fmi3SetFloat64", "maxStep = 1 s is out of range")
        _expect_error(log, lambda: f.setInt32([20], [4]), "fmi3SetInt32", "frictionModel = 4 is out of range [1, 3]")
        _expect_error(log, lambda: f.setFloat64([41], [-1.0]), "rotorSpeed = -1 rpm is out of range")
        _expect_error(log, lambda: f.setFloat64([999], [1.0]), "fmi3SetFloat64: unknown value reference 999")
        _expect_error(log, lambda: f.setInt32([1], [1]), "EI (vr 1) is of type Float64, not Int32")
        _expect_error(log, lambda: f.setFloat64([VR_TIME], [1.0]), "time (vr 0) is the independent variable")
        _expect_error(
            log, lambda: f.setInt64([20], [1]), "fmi3SetInt64: frictionModel (vr 20) is of type Int32, not Int64"
        )
        f.enterInitializationMode(startTime=0.0, stopTime=STOP)
        f.exitInitializationMode()
        assert _errors(log) == []
        # after initialization
        _expect_error(
            log,
            lambda: f.setFloat64([1], [300.0]),
            "parameter EI (vr 1) has variability fixed",
            "only before fmi3ExitInitializationMode (state: Step Mode)",
        )
        _expect_error(log, lambda: f.getFloat64([50, 999]), "fmi3GetFloat64: unknown value reference 999")
        _expect_error(log, lambda: f.getBoolean([50]), "tipDisplacement (vr 50) is of type Float64, not Boolean")
        _expect_error(log, lambda: f.getInt32([VR_TIME]), "time (vr 0) is of type Float64, not Int32")
        _expect_error(log, lambda: f.getString([50]), "fmi3GetString: tipDisplacement (vr 50) is of type Float64")
        n = (ctypes.c_uint32 * 1)(50)
        x = (ctypes.c_double * 2)()
        log.take()
        assert lib.fmi3GetFloat64(f.component, n, ctypes.c_size_t(1), x, ctypes.c_size_t(2)) == 3
        assert "nValues = 2 must equal nValueReferences = 1" in log.take()[-1][2]
        _expect_error(log, f.enterEventMode, "fmi3EnterEventMode: not supported: hasEventMode = false")
        _expect_error(log, f.enterStepMode, "fmi3EnterStepMode: not supported")
        _expect_error(log, lambda: f.getOutputDerivatives([50], [1]), "maxOutputDerivativeOrder = 0")
        _expect_error(log, lambda: f.setClock([1], [True]), "fmi3SetClock: not supported: this FMU has no clocks")
        _expect_error(log, lambda: f.fmi3SetTime(f.component, 0.0), "fmi3SetTime: not supported")
        # the state functions' arguments
        s = f.getFMUState()
        size = ctypes.c_size_t()
        f.fmi3SerializedFMUStateSize(f.component, s, ctypes.byref(size))
        buf = ctypes.create_string_buffer(size.value)
        log.take()
        assert lib.fmi3SerializeFMUState(f.component, s, _bytes(buf), ctypes.c_size_t(size.value - 1)) == 3
        assert "is too small: " in log.take()[-1][2]
        blob = f.serializeFMUState(s)
        bad = bytearray(blob)
        bad[40] ^= 1
        _expect_error(log, lambda: f.deserializeFMUState(bytes(bad)), "fmi3DeserializeFMUState: checksum mismatch")
        log.take()
        assert lib.fmi3GetFMUState(f.component, None) == 3 and "FMUState is NULL" in log.take()[-1][2]
        # the instance still works: a step from the right point
        assert f.doStep(0.0, H)[3] == H
        # a mismatched communication point: fmi3Error, terminal until fmi3Reset (or fmi3SetFMUState)
        _expect_error(log, lambda: f.doStep(0.5, H), "currentCommunicationPoint = 0.5", "does not match the FMU time")
        _expect_error(log, lambda: f.doStep(H, H), "Illegal call sequence (state: error")
        f.setFMUState(s)  # back to the state at t = 0 in Step Mode
        assert f.doStep(0.0, H)[3] == H
        f.freeFMUState(s)
        _expect_error(log, lambda: f.doStep(H, STOP), "goes past the stop time")
        f.reset()
        assert _errors(log) == []
        f.enterInitializationMode(startTime=0.0)
        f.exitInitializationMode()
        assert f.doStep(0.0, H)[3] == H and f.getFloat64([VR_TIME]) == [H]
        f.terminate()
        _expect_error(log, lambda: f.doStep(H, H), "Illegal call sequence (state: Terminated)")
        assert len(f.getFloat64([50, 51])) == 2  # outputs stay readable after fmi3Terminate
    finally:
        f.freeInstance()


def test_discarded_step_stays_in_step_mode(fmus) -> None:
    """fmi3Discard (rotorSpeed 0 under an ungated describing-function contact): logged, the state at
    the communication point kept (lastSuccessfulTime = it), Step Mode continues: a retry works."""
    log = _Log()
    f = _slave(fmus, log)
    try:
        f.setInt32([20, 23], [1, 1])
        f.setBoolean([30], [False])
        f.setFloat64([VR_ROTOR], [0.0])
        f.enterInitializationMode(startTime=0.0)
        f.exitInitializationMode()
        before = f.getFloat64([50, 51, 57])
        flags = [ctypes.c_bool(True) for _ in range(3)]
        last = ctypes.c_double(-1.0)
        log.take()
        assert (
            f.dll.fmi3DoStep(
                f.component,
                ctypes.c_double(0.0),
                ctypes.c_double(H),
                True,
                *[ctypes.byref(x) for x in flags],
                ctypes.byref(last),
            )
            == 2
        )  # fmi3Discard
        assert [x.value for x in flags] == [False, False, False] and last.value == 0.0
        assert [(s, c) for s, c, _ in log.take() if s != 0] == [(2, "logStatusDiscard")]
        assert f.getFloat64([50, 51, 57]) == before and f.getFloat64([VR_TIME]) == [0.0]
        f.setFloat64([VR_ROTOR], [5000.0])
        assert f.doStep(0.0, H) == (False, False, False, H)
    finally:
        f.freeInstance()


def test_messages_name_fmi3_functions(fmus) -> None:
    """The layer's messages name the face's functions (fmi3SerializedFMUStateSize), not FMI 2.0's."""
    log = _Log()
    f = _slave(fmus, log)
    try:
        f.enterInitializationMode()
        f.exitInitializationMode()
        s = f.getFMUState()
        buf = ctypes.create_string_buffer(8)
        log.take()
        assert f.dll.fmi3SerializeFMUState(f.component, s, _bytes(buf), ctypes.c_size_t(8)) == 3
        message = log.take()[-1][2]
        assert "(fmi3SerializedFMUStateSize)" in message and "fmi2" not in message
        f.freeFMUState(s)
    finally:
        f.freeInstance()


@pytest.mark.parametrize(
    "kw, fragment",
    [
        (dict(guid="{00000000-0000-0000-0000-000000000000}"), "instantiationToken {00000000"),
        (dict(eventModeUsed=True), "eventModeUsed = true is not supported"),
        (dict(requiredIntermediateVariables=[50]), "providesIntermediateUpdate = false"),
    ],
)
def test_instantiation_refused(fmus, kw: dict, fragment: str) -> None:
    log = _Log()
    with pytest.raises(Exception, match="Failed to instantiate FMU"):
        _slave(fmus, log, **kw)
    assert [(s, c) for s, c, _ in log.records] == [(3, "logStatusError")] and fragment in log.records[0][2]


def test_model_exchange_refused(fmus) -> None:
    _, _, md3, d3 = fmus
    log = _Log()
    lib = ctypes.CDLL(str(Path(d3) / "binaries" / "x86_64-linux" / "ShroudedBlade.so"))
    lib.fmi3InstantiateModelExchange.restype = ctypes.c_void_p
    inst = lib.fmi3InstantiateModelExchange(b"me", md3.guid.encode(), None, False, True, None, log.callback)
    assert inst is None and "fmi3InstantiateModelExchange: not supported" in log.records[0][2]
    # NULL instances are refused without a crash
    assert lib.fmi3DoStep(None, ctypes.c_double(0.0), ctypes.c_double(H), False, None, None, None, None) == 3
    assert lib.fmi3Reset(None) == 3
    lib.fmi3FreeInstance(None)


def test_ecos_bit_identical(fmu_path: Path, fmu3_path: Path) -> None:
    """Ecos (ecospy; its fmi4c loads FMI 3.0 co-simulation) runs both FMUs with the same step and
    the same held inputs: identical outputs (Jenkins element, run-up)."""
    pytest.importorskip("ecospy")
    from ecospy import EcosSimulation, EcosSimulationStructure

    aero, n = _signals((4000.0, 6000.0))
    names = ("tipDisplacement", "tipVelocity", "frictionForce", "dissipatedEnergy", "runningMaximum")

    def go(fmu: Path) -> np.ndarray:
        structure = EcosSimulationStructure()
        structure.add_model("blade", str(fmu))
        structure.add_parameter_set(
            "initial", {"blade::frictionModel": 3, "blade::aeroLoad": 0.0, "blade::rotorSpeed": 4000.0}
        )
        sim = EcosSimulation(structure=structure, step_size=H)
        rows = []
        try:
            assert sim.init(0.0, "initial")
            for k in range(int(round(STOP / H))):
                t = k * H
                sim.set_real("blade::aeroLoad", float(aero(t)))
                sim.set_real("blade::rotorSpeed", float(n(t)))
                sim.step()
                rows.append(
                    [sim.get_real(f"blade::{x}") for x in names] + [float(sim.get_integer("blade::contactState"))]
                )
            sim.terminate()
        finally:
            sim.free()
            structure.free()
        return np.array(rows)

    r2, r3 = go(fmu_path), go(fmu3_path)
    assert np.array_equal(_bits(r2), _bits(r3))
    assert np.max(np.abs(r2[:, 0])) > 3e-5 and np.any(r2[1:, -1] != r2[:-1, -1])


def test_undeclared_references_are_unknown(fmus) -> None:
    """The FMI 2.0 model exchange's locals (excitationPhase, sliderPosition, der(...)) are not in
    modelDescription3.xml: the FMI 3.0 binary refuses their value references like any unknown one."""
    md2, _, md3, _ = fmus
    declared3 = {v.valueReference for v in md3.modelVariables}
    undeclared = sorted(
        v.valueReference for v in md2.modelVariables if v.causality == "local" and v.valueReference not in declared3
    )
    assert len(undeclared) == 7 + 10  # the states and derivatives of model exchange
    assert undeclared, "modelDescription.xml has no locals missing from modelDescription3.xml"
    log = _Log()
    f = _slave(fmus, log)
    try:
        f.enterInitializationMode()
        f.exitInitializationMode()
        for vr in undeclared:
            _expect_error(log, lambda: f.getFloat64([vr]), f"fmi3GetFloat64: unknown value reference {vr}")
            _expect_error(log, lambda: f.setFloat64([vr], [0.0]), f"fmi3SetFloat64: unknown value reference {vr}")
            _expect_error(log, lambda: f.getInt64([vr]), f"fmi3GetInt64: unknown value reference {vr}")
        assert len(f.getFloat64([50, 51])) == 2  # the declared ones still answer
    finally:
        f.freeInstance()
