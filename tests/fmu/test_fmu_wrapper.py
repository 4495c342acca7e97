"""harness.fmu.blade.BladeFMU: lifecycle, validation before the FMU is touched, reset and continuation,
FMU state round trips, sampling, errors with partial results, and the held-input path against
fmpy's own simulate_fmu (an independent master)."""

from __future__ import annotations

import math
from pathlib import Path

import numpy as np
import pytest
from fmpy import simulate_fmu
from fmpy.validation import validate_fmu

from harness.model.excitation import AeroLoad, Constant, ExcitationError, LinearRamp, Stepped
from harness.fmu.blade import BladeFMU, FMUError, FMUNotFoundError, input_error, step_inputs
from harness.model.params import ParameterError

FAST = {"gating": False}  # smooth runs


@pytest.fixture(scope="module")
def fmu(fmu_path):
    assert validate_fmu(str(fmu_path)) == []
    with BladeFMU(fmu_path) as f:
        yield f


def test_result_layout_and_grid(fmu):
    res = fmu.run(None, 0.01, 1e-4)
    assert res.dtype.names[0] == "time"
    assert set(fmu.output_names) <= set(res.dtype.names)
    assert res.dtype["regime"].kind == "i"
    np.testing.assert_allclose(res["time"], np.arange(101) * 1e-4, rtol=0, atol=1e-15)
    assert res["tipDisplacement"][0] == 0.0 and np.max(np.abs(res["tipDisplacement"])) > 0
    # a stop time that is not a multiple of the step: the last step is shorter and lands on it
    res2 = fmu.run(None, 0.01005, 1e-4, outputs=["tipDisplacement"])
    assert res2.dtype.names == ("time", "tipDisplacement")
    assert res2["time"][-1] == 0.01005 and len(res2) == 102


def test_reset_gives_identical_runs_and_continuation_equals_one_run(fmu):
    a = fmu.run(FAST, 0.02, 1e-4)
    b = fmu.run(FAST, 0.02, 1e-4)
    np.testing.assert_array_equal(a, b)
    first = fmu.run(FAST, 0.01, 1e-4)
    rest = fmu.run(None, 0.02, 1e-4, reset=False)
    assert rest["time"][0] == pytest.approx(0.01)
    # the continued grid is 0.01 + k h instead of (100 + k) h: times differ by rounding (1e-18 s),
    # so the inputs and results agree to rounding, not bitwise
    q = a["tipDisplacement"]
    np.testing.assert_allclose(
        np.concatenate([first, rest[1:]])["tipDisplacement"], q, rtol=0, atol=1e-11 * np.max(np.abs(q))
    )


def test_bad_parameters_rejected_before_the_fmu_is_touched(fmu):
    fmu.run(FAST, 0.01, 1e-4)
    with pytest.raises(ParameterError, match="unknown parameter 'gap'"):
        fmu.run({"gap": 1e-5}, 0.02, 1e-4)
    with pytest.raises(ParameterError, match="out of range"):
        fmu.run({"d": -1e-5}, 0.02, 1e-4)
    with pytest.raises(ExcitationError, match="outside"):
        fmu.run(FAST, 0.02, 1e-4, speed_rpm=LinearRamp(5000, 40000, 0, 0.01))
    # the FMU was not reset or stepped by the failed calls: the run continues where it was
    cont = fmu.run(None, 0.02, 1e-4, reset=False)
    ref = fmu.run(FAST, 0.02, 1e-4)["tipDisplacement"]
    np.testing.assert_allclose(cont["tipDisplacement"], ref[100:], rtol=0, atol=1e-11 * np.max(np.abs(ref)))


def test_state_roundtrip_same_and_fresh_instance(fmu, fmu_path):
    fmu.run(None, 0.01, 1e-4)
    state = fmu.get_state()
    a = fmu.run(None, 0.02, 1e-4, reset=False)
    fmu.set_state(state)
    b = fmu.run(None, 0.02, 1e-4, reset=False)
    np.testing.assert_array_equal(a, b)
    with BladeFMU(fmu_path) as other:
        other.set_state(bytes(state))  # plain bytes: the time must then be given
        c = other.run(None, 0.02, 1e-4, reset=False, start_time=0.01)
    np.testing.assert_array_equal(a, c)


def test_sample_every(fmu):
    full = fmu.run(FAST, 0.0205, 1e-4)
    sub = fmu.run(FAST, 0.0205, 1e-4, sample_every=10)
    idx = list(range(0, len(full) - 1, 10)) + [len(full) - 1]
    np.testing.assert_array_equal(sub, full[idx])


@pytest.mark.parametrize("spp", [2, 4])
def test_step_polynomials_stay_within_their_error_bound(spp):
    # The polynomial the FMU evaluates over each step (value + sum_j u^(j) (t - t_k)^j / j!) against
    # the load itself on 41 points per step: within input_error (Taylor (w h)^9/9!, Chebyshev
    # 2 (w h / 4)^9 / 9!, closed-form bounds) of the amplitude 100 N/m; "taylor" is the signal's
    # own derivatives.
    aero = AeroLoad(100.0, 3, Constant(5000.0))
    T = 60.0 / (3 * 5000.0)
    grid = np.arange(4 * spp + 1) * T / spp
    assert np.array_equal(step_inputs(aero, grid, 8, "taylor"), aero.derivatives(grid[:-1], 8))
    for fit in ("taylor", "chebyshev"):
        u = step_inputs(aero, grid, 8, fit)
        worst = 0.0
        for k in range(len(grid) - 1):
            x = np.linspace(0.0, grid[k + 1] - grid[k], 41)
            poly = sum(u[j, k] * x**j / math.factorial(j) for j in range(9))
            worst = max(worst, float(np.max(np.abs(poly - aero(grid[k] + x)))))
        assert worst <= 100.0 * input_error(2 * math.pi / spp, 8, fit) * (1 + 1e-6), (fit, worst)


def test_two_steps_per_period_with_fitted_carried_inputs_match_fine_steps(fmu):
    # 2 steps per period, Chebyshev-fitted load (6.3e-7 of its amplitude), values carried over by
    # the FMU (at most twice that at a step start) against 32 steps per period with the exact
    # Taylor derivatives (error (2 pi/32)^9/9! = 1e-11): the trajectories at the common times agree
    # within 1e-5 of the amplitude (the load error bound 1.3e-6, times 8 for its amplification in
    # the response: the linear, contact-free blade, whose resonant gain at 3x the excitation
    # frequency is below that of the fundamental here).
    p = {"d": 1e-2}
    T = 60.0 / (3 * 5000.0)
    fine = fmu.run(p, 100 * T, T / 32, outputs=["tipDisplacement"])["tipDisplacement"][::16]
    for carry in (False, True):
        big = fmu.run(p, 100 * T, T / 2, outputs=["tipDisplacement"], input_fit="chebyshev", carry_values=carry)
        err = np.max(np.abs(big["tipDisplacement"] - fine)) / np.max(np.abs(fine))
        assert err <= 1e-5, (carry, err)
    with pytest.raises(ParameterError, match="breakpoint"):
        fmu.run(p, 10 * T, T / 2, speed_rpm=Stepped([5000.0, 5100.0], [5 * T, 5 * T]), carry_values=True)


def test_held_inputs_match_fmpy_simulate_fmu(fmu, fmu_path):
    # derivative_order=0 is what fmpy does without input derivatives: the same run through
    # fmpy.simulate_fmu (input table at the communication points, held over each step) must agree
    # to rounding.
    params = {"gating": False, "d": 4e-5}
    speed = LinearRamp(4000.0, 6000.0, 0.0, 0.02)
    ours = fmu.run(params, 0.02, 2e-4, speed_rpm=speed, derivative_order=0)
    grid = ours["time"]
    aero = AeroLoad(100.0, 3, speed)
    table = np.zeros(len(grid), dtype=[("time", float), ("aeroLoad", float), ("rotorSpeed", float)])
    table["time"], table["aeroLoad"], table["rotorSpeed"] = grid, aero(grid), speed(grid)
    theirs = simulate_fmu(
        str(fmu_path),
        start_time=0.0,
        stop_time=0.02,
        output_interval=2e-4,
        input=table,
        start_values={**params, "Fw0": 0.0},
        output=["tipDisplacement"],
    )  # load fed: built-in off
    assert len(theirs) == len(ours)
    np.testing.assert_allclose(
        theirs["tipDisplacement"], ours["tipDisplacement"], rtol=0, atol=1e-12 * np.max(np.abs(ours["tipDisplacement"]))
    )


def test_fmu_error_carries_messages_time_and_partial_result(fmu):
    # a static load pushes q past the gap at zero speed: the describing functions need omega > 0,
    # so the FMU discards the step (docs/model-notes.md s.2)
    with pytest.raises(FMUError) as info:
        fmu.run({"Fw0": 100.0}, 0.05, 1e-4, speed_rpm=0.0, aero=Constant(2000.0))
    err = info.value
    assert 0 < err.time < 0.05 and err.status in (2, 3)
    assert err.messages, "the FMU's log messages must be captured"
    assert len(err.partial) > 1 and err.partial["time"][-1] <= err.time + 1e-12
    assert np.max(np.abs(err.partial["tipDisplacement"])) <= 4e-5  # stopped near the gap
    with pytest.raises(RuntimeError):
        fmu.run(None, 0.06, 1e-4, reset=False)
    assert len(fmu.run(None, 0.001, 1e-4)) == 11  # a reset run works again


def test_cleanup_and_missing_fmu(fmu_path, tmp_path):
    f = BladeFMU(fmu_path)
    unzip = Path(f._unzip)
    assert unzip.is_dir()
    f.run(None, 0.001, 1e-4)
    f.close()
    assert not unzip.exists()
    f.close()  # idempotent
    with pytest.raises(FMUNotFoundError):
        BladeFMU(tmp_path / "missing.fmu")
    with pytest.raises(ParameterError):
        BladeFMU._grid(0.0, math.nan, 1e-4)
