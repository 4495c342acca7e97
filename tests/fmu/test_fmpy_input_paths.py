"""fmpy's own `simulate_fmu` as the master, both input paths, against the independent reference.

An input table (time, aeroLoad, rotorSpeed) drives the FMU through `fmpy.simulate_fmu` (co-simulation,
communication step = output_interval h) once with the inputs held over each step (fmpy's default:
value at the left end of the step) and once with `set_input_derivatives=True`, where fmpy also sets
the first time derivative of the table's linear interpolation (the slope of the table segment at
t_k), so the FMU sees u(t_k) + u'(t_k) (t - t_k) inside the step (docs/model-notes.md s.1). Both are
compared with `harness.reference.simulate` driven by the exact continuous signals. Expected error
orders in h: held inputs act like a delay of h/2, error O(h) (~ omega h / 2 of the amplitude);
linear inputs leave the Taylor remainder u'' (t - t_k)^2 / 2, error O(h^2) (~ (omega h)^2 / 6), so
the derivative path is closer by ~3 / (omega h) (8..10 at h = 2e-4 s, 4000..6000 rpm). fmpy 0.3.32
cannot do the second run unless the FMU has exactly 9 continuous inputs (a fixed-size buffer, see
`_InputWithSizedDerivatives`); the test works around it only while the unpatched call still fails.
"""

from __future__ import annotations

import math
import warnings
from pathlib import Path

import fmpy.simulation
import numpy as np
import pytest
from fmpy import extract, instantiate_fmu, read_model_description, simulate_fmu

from harness import reference
from harness.model.excitation import AeroLoad, Constant, LinearRamp
from harness.model.params import fmu_parameters, validate

STOP = 0.03  # run length [s]: contact starts after ~7 ms, several hundred switching events
H_FINE, H_COARSE = 1e-4, 2e-4  # communication steps [s]; omega h = 0.31..0.38 at H_COARSE
# 5e-4 s (omega h ~ 0.8..0.95) is too coarse for either path to be in its asymptotic range:
# there the linear extrapolation error (omega h)^2 / 2 ~ 0.4 of the load is no longer small.
TABLE_DT = 1e-6  # input table spacing [s]: fmpy's slope at t_k is that of the table segment next
# to t_k (left or right, depending on rounding of t_k), u'(t_k) +- u'' dt / 2: relative slope
# error omega dt / 2 ~ 1e-3, negligible against the O(h^2) remainder.
FMPY_BUG = "Can only assign sequence of same size"

SCENARIOS = {
    # no contact (d = 1 m), speed run-up through the 4966 rpm resonance: both inputs vary
    "no contact, run-up 4000-6000 rpm": (dict(d=1.0, amplitudeMode=1), LinearRamp(4000.0, 6000.0, 0.0, STOP)),
    # describing-function contact switched on/off at |q| = d (gating), fixed B
    "gated DF contact, 6000 rpm": (dict(amplitudeMode=1), Constant(6000.0)),
    # time-domain Jenkins element (impacts, stick/slip events), speed run-up
    "Jenkins element, run-up 4000-6000 rpm": (dict(frictionModel=3), LinearRamp(4000.0, 6000.0, 0.0, STOP)),
}
# Acceptance bands. No contact (a linear system): orders 1 and 2 to within 0.15, ratio at
# H_COARSE >= 5 (predicted ~9). With contact the switching adds nonlinear sensitivity (measured
# orders 1.02..1.07 held, 1.8..1.85 derivative; ratio 6..7): held in [0.8, 1.3], derivative in
# [1.5, 2.5], ratio >= 3.
BANDS = {
    True: dict(held=(0.85, 1.15), deriv=(1.85, 2.15), ratio=5.0),
    False: dict(held=(0.8, 1.3), deriv=(1.5, 2.5), ratio=3.0),
}


class _InputWithSizedDerivatives(fmpy.simulation.Input):
    """WORKAROUND for an fmpy 0.3.32 bug (fmpy/simulation.py, class Input): `__init__` allocates the
    derivative buffer of each group of continuous inputs as `(value_type * 9)()` whatever the number
    of inputs, and `apply()` then assigns an array of len(vrs) to it (`derivatives[:] = d`), which
    raises `ValueError: Can only assign sequence of same size` unless there are exactly 9 inputs.
    The only change: re-allocate that buffer with len(vrs) entries. Used only while the unpatched
    call still raises (see `fmpy_needs_patch`); delete this class once fmpy is fixed."""

    def __init__(self, *args, **kwargs) -> None:  # noqa: ANN002, ANN003 (same signature as fmpy's)
        super().__init__(*args, **kwargs)
        if self.t is not None:
            self.continuous = [
                info._replace(derivatives=(info.derivatives._type_ * len(info.vrs))()) for info in self.continuous
            ]


def _table(aero: AeroLoad, speed, stop: float) -> np.ndarray:  # noqa: ANN001
    t = np.linspace(0.0, stop, int(round(stop / TABLE_DT)) + 1)
    table = np.zeros(t.size, dtype=[("time", float), ("aeroLoad", float), ("rotorSpeed", float)])
    table["time"], table["aeroLoad"], table["rotorSpeed"] = t, aero(t), speed(t)
    return table


@pytest.fixture(scope="module")
def unzipped(fmu_path: Path, tmp_path_factory: pytest.TempPathFactory) -> str:
    """The FMU extracted once (simulate_fmu then neither extracts nor leaves temp dirs behind)."""
    return extract(str(fmu_path), unzipdir=str(tmp_path_factory.mktemp("fmpy_inputs")))


@pytest.fixture(scope="module")
def fmpy_needs_patch(unzipped: str) -> bool:
    """True while fmpy's unpatched `set_input_derivatives=True` still raises the known ValueError on
    this FMU (two continuous inputs); False once fmpy is fixed: then every run goes unpatched. The
    probe uses our own instance (freed here) because fmpy does not free it when the call raises."""
    speed = Constant(5000.0)
    table = _table(AeroLoad(100.0, 3, speed), speed, 1e-3)
    inst = instantiate_fmu(unzipped, read_model_description(unzipped), "CoSimulation")
    try:
        simulate_fmu(
            unzipped,
            stop_time=1e-3,
            output_interval=1e-4,
            input=table,
            set_input_derivatives=True,
            fmu_instance=inst,
            output=["tipDisplacement"],
        )
    except ValueError as exc:
        assert FMPY_BUG in str(exc), f"fmpy failed differently than the known 0.3.32 bug: {exc}"
        return True
    finally:
        inst.freeInstance()
    warnings.warn(
        f"fmpy's set_input_derivatives works unpatched now: delete _InputWithSizedDerivatives in {Path(__file__).name}",
        stacklevel=1,
    )
    return False


def _simulate(
    unzipped: str,
    params: dict,
    table: np.ndarray,
    h: float,
    derivatives: bool,
    patch: bool,
    monkeypatch: pytest.MonkeyPatch,
) -> np.ndarray:
    kwargs = dict(
        stop_time=STOP,
        output_interval=h,
        input=table,
        start_values=fmu_parameters(params),
        output=["tipDisplacement"],
        set_input_derivatives=derivatives,
    )
    if derivatives and patch:
        with monkeypatch.context() as m:
            m.setattr(fmpy.simulation, "Input", _InputWithSizedDerivatives)
            return simulate_fmu(unzipped, **kwargs)
    return simulate_fmu(unzipped, **kwargs)


def test_unpatched_fmpy_status(unzipped: str, fmpy_needs_patch: bool, record_property) -> None:  # noqa: ANN001
    """Records whether the workaround is active; while it is, the unpatched call must fail with
    exactly the known error (checked again here, outside the fixture, on a full-size table); once
    fmpy is fixed there is nothing to assert: skipped with the reason."""
    record_property("fmpy_input_derivatives_patched", fmpy_needs_patch)
    if not fmpy_needs_patch:
        pytest.skip("fmpy's set_input_derivatives works unpatched now: nothing to check (delete the workaround)")
    speed = Constant(5000.0)
    table = _table(AeroLoad(100.0, 3, speed), speed, 2e-3)
    inst = instantiate_fmu(unzipped, read_model_description(unzipped), "CoSimulation")
    try:
        with pytest.raises(ValueError, match=FMPY_BUG):
            simulate_fmu(
                unzipped,
                stop_time=2e-3,
                output_interval=1e-4,
                input=table,
                set_input_derivatives=True,
                fmu_instance=inst,
            )
    finally:
        inst.freeInstance()


@pytest.mark.parametrize("name", list(SCENARIOS))
def test_input_derivatives_closer_to_reference(
    unzipped: str,
    fmpy_needs_patch: bool,
    name: str,  # noqa: ANN001
    monkeypatch: pytest.MonkeyPatch,
    record_property,
) -> None:
    options, speed = SCENARIOS[name]
    p = validate(options)
    aero = AeroLoad(p["Fw0"], p["engineOrder"], speed)
    table = _table(aero, speed, STOP)
    n_fine = int(round(STOP / H_FINE))
    grid = np.minimum(np.arange(n_fine + 1) * H_FINE, STOP)
    ref = reference.simulate(p, STOP, aero, speed, t_eval=grid)["tipDisplacement"]
    amp = float(np.max(np.abs(ref)))
    no_contact = p["d"] >= 1.0
    assert (amp < p["d"]) if no_contact else (amp > 1.1 * p["d"]), (amp, p["d"])  # the contact really acts

    errors: dict[tuple[float, bool], float] = {}
    for h in (H_FINE, H_COARSE):
        stride = int(round(h / H_FINE))
        for deriv in (False, True):
            res = _simulate(unzipped, p, table, h, deriv, fmpy_needs_patch, monkeypatch)
            np.testing.assert_allclose(res["time"], grid[::stride], rtol=0, atol=1e-12)
            errors[h, deriv] = float(np.max(np.abs(res["tipDisplacement"] - ref[::stride]))) / amp
    order_held = math.log2(errors[H_COARSE, False] / errors[H_FINE, False])
    order_deriv = math.log2(errors[H_COARSE, True] / errors[H_FINE, True])
    ratio = errors[H_COARSE, False] / errors[H_COARSE, True]
    report = (
        f"{name}: max|q - q_ref| / max|q_ref| held {errors[H_FINE, False]:.3e} (h = {H_FINE:g} s), "
        f"{errors[H_COARSE, False]:.3e} (h = {H_COARSE:g} s), order {order_held:.2f}; with derivatives "
        f"{errors[H_FINE, True]:.3e}, {errors[H_COARSE, True]:.3e}, order {order_deriv:.2f}; "
        f"held / derivatives at h = {H_COARSE:g} s: {ratio:.1f}; fmpy patched: {fmpy_needs_patch}"
    )
    print(report)
    record_property("fmpy_input_paths", report)
    band = BANDS[no_contact]
    assert errors[H_COARSE, True] < errors[H_COARSE, False] / band["ratio"], report
    assert band["held"][0] <= order_held <= band["held"][1], report
    assert band["deriv"][0] <= order_deriv <= band["deriv"][1], report
