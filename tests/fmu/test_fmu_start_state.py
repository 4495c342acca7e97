"""Start values of the state (docs/model-notes.md s.7): a run restarted at t1 from the
state an earlier run had at t1 continues that run.

Every continuous state of the FMU has a settable start value (tipDisplacement q, tipVelocity q',
dissipatedEnergy E, jenkinsForce = k_d (Delta_u - w) for the Jenkins element, runningMaximum for the
tracked amplitude), so a master (a periodic-orbit shooting code) can start anywhere. The check: run
from rest, read the state at t1, start a fresh run at t1 from those start values under the same
load, and compare it with the original run continued past t1. Both integrate the same ODE from the
same state on the same communication grid, so they agree to rounding; only the event at the
restart differs. The reference is the FMU's own continued run; which discrete mode the restart
picks (stick, slip on the cone) is checked against the rule of model-notes s.7 evaluated here in
Python from the parameters. The refusals of bad start values are in the invalid-input catalogue
(tests/fmu/test_fmu_errors.py, docs/invalid-inputs.md), not repeated here.
"""

from __future__ import annotations

import math

import numpy as np
import pytest

from harness.fmu.blade import BladeFMU, FMUError
from harness.model.params import ParameterError

RPM = 5000.0  # rotorSpeed [rpm] (the default)
EO = 3  # engineOrder (the default)
T = 60.0 / (EO * RPM)  # excitation period 2 pi / omega [s]
H = 1e-4  # communication step [s]
OUT = [
    "tipDisplacement",
    "tipVelocity",
    "jenkinsForce",
    "dissipatedEnergy",
    "runningMaximum",
    "amplitude",
    "contactState",
]
REL = 1e-9  # agreement of the restarted run, relative to the amplitude

# the defaults, for the independent friction limit L = mu kn cos(gamma) (|q| - d) (eq. 3)
MU, KN, GAMMA, D, KD_RATIO = 0.33, 1e7, math.pi / 3, 3e-5, 0.608695652173913


def friction_limit(q: float) -> float:
    """L [N] at q [m] for the default contact parameters (0 when the contact is open)."""
    return MU * KN * math.cos(GAMMA) * max(abs(q) - D, 0.0)


def state_at(row: np.void, jenkins: bool) -> dict[str, float]:
    """The start values that reproduce the state of an output row."""
    st = {
        "tipDisplacement": float(row["tipDisplacement"]),
        "tipVelocity": float(row["tipVelocity"]),
        "dissipatedEnergy": float(row["dissipatedEnergy"]),
    }
    if jenkins:
        st["jenkinsForce"] = float(row["jenkinsForce"])
    return st


def assert_same_run(rest: np.ndarray, orig: np.ndarray, names: tuple[str, ...]) -> dict[str, float]:
    """rest and orig on the same grid; each output within REL of its largest magnitude (q and the
    amplitude-like outputs: of the amplitude). Returns the relative differences."""
    assert len(rest) == len(orig)
    np.testing.assert_allclose(rest["time"], orig["time"], rtol=0, atol=1e-15)
    amp = float(np.max(np.abs(orig["tipDisplacement"])))
    diffs = {}
    for n in names:
        scale = amp if n in ("tipDisplacement", "amplitude", "runningMaximum") else float(np.max(np.abs(orig[n])))
        diffs[n] = float(np.max(np.abs(rest[n] - orig[n]))) / scale
    assert all(d <= REL for d in diffs.values()), diffs
    return diffs


def pick(res: np.ndarray, state: int, after: float) -> int:
    """First sample after `after` s in contact state `state` with both neighbours in it too (not
    at a transition)."""
    cs = res["contactState"]
    for i in np.nonzero(res["time"] > after)[0][:-1]:
        if cs[i - 1] == cs[i] == cs[i + 1] == state:
            return int(i)
    raise AssertionError(f"no sample in contact state {state} after {after} s")


# ---------------------------------------------------------------------------------------------
# the Jenkins element (frictionModel 3): restart in stick and in slip


@pytest.mark.parametrize("state", [1, 2], ids=["stick", "slip"])
def test_jenkins_restart_continues_the_run(fmu: BladeFMU, state: int) -> None:
    p = {"frictionModel": 3, "amplitudeMode": 1}  # fixed B: the element needs no amplitude
    stop, h = 0.1, H / 4  # stick lasts ~1e-4 s at a time: sample finer
    orig = fmu.run(p, stop, h, speed_rpm=RPM, outputs=OUT)
    i1 = pick(orig, state, 0.05)
    row, t1 = orig[i1], float(orig["time"][i1])
    F1, q1 = float(row["jenkinsForce"]), float(row["tipDisplacement"])
    # the output is the spring force: inside the cone in stick, on it in slip (L from the parameters)
    L = friction_limit(q1)
    assert L > 0 and F1 != 0.0
    if state == 1:
        assert abs(F1) < L
    else:
        assert abs(abs(F1) - L) <= 1e-9 * L
    st = state_at(row, jenkins=True)
    rest = fmu.run({**p, **st}, stop, h, speed_rpm=RPM, start_time=t1, outputs=OUT)
    # the restart starts in the same mode with the given state (the force up to the rounding of
    # w = sin(g) q - F / kd)
    assert rest["contactState"][0] == state
    for n in ("tipDisplacement", "tipVelocity", "dissipatedEnergy"):
        assert rest[n][0] == st[n]
    assert abs(rest["jenkinsForce"][0] - F1) <= 1e-12 * L
    assert np.array_equal(rest["contactState"], orig["contactState"][i1:])
    assert_same_run(rest, orig[i1:], ("tipDisplacement", "tipVelocity", "jenkinsForce", "dissipatedEnergy"))
    assert rest["time"][-1] - t1 >= 5 * T  # several periods
    # the test can fail: without the spring force (start value 0: unloaded) the run differs
    if state == 1:
        st0 = {**st, "jenkinsForce": 0.0}
        other = fmu.run({**p, **st0}, stop, h, speed_rpm=RPM, start_time=t1, outputs=OUT)
        amp = float(np.max(np.abs(orig["tipDisplacement"][i1:])))
        assert float(np.max(np.abs(other["tipDisplacement"] - orig["tipDisplacement"][i1:]))) > 1e-4 * amp


def test_jenkins_start_mode_follows_the_cone_rule(fmu: BladeFMU) -> None:
    """Stick strictly inside the cone; on it, slip in direction s = sign(F0) iff the slip rate
    cs v0 >= 0, cs = s kd sin(g) - sigma mu kn cos(g) (model-notes s.7); the unloaded default
    starts in stick even where an arriving contact would slip (kdRatio 2: kd tan(g) > mu kn)."""
    q0 = 5e-5
    L = friction_limit(q0)
    kd = KD_RATIO * KN

    def expected(F: float, v: float) -> int:  # the rule, sigma = sign(q0) = +1
        if abs(F) < L * (1 - 1e-12):
            return 1
        s = 1.0 if F > 0 else -1.0
        cs = s * kd * math.sin(GAMMA) - MU * KN * math.cos(GAMMA)
        return 2 if cs * v >= 0 else 1

    cases = [(F, v) for F in (0.0, 0.5 * L, -0.9 * L, L, -L, L * (1 + 1e-13)) for v in (0.01, 0.0, -0.01)]
    cases = [({"jenkinsForce": F, "tipVelocity": v}, expected(F, v)) for F, v in cases]
    assert {e for _, e in cases} == {1, 2}
    assert [e for s, e in cases if s["jenkinsForce"] == L] == [2, 2, 1]  # cs > 0 at the defaults
    for starts, expected in cases:
        r = fmu.run({"frictionModel": 3, "tipDisplacement": q0, **starts}, 2 * H, H, outputs=OUT)
        assert r["contactState"][0] == expected, (starts, r["contactState"][0])
        F = starts["jenkinsForce"]
        if expected == 2:  # slip: w set so that the force is s L exactly
            assert abs(r["jenkinsForce"][0] - math.copysign(L, F)) <= 1e-12 * L
        else:
            assert abs(r["jenkinsForce"][0] - F) <= 1e-12 * L
    # the unloaded start with kd tan(g) > mu kn: stick, as before the start value existed
    r = fmu.run({"frictionModel": 3, "kdRatio": 2.0, "tipDisplacement": q0, "tipVelocity": 0.01}, 2 * H, H, outputs=OUT)
    assert r["contactState"][0] == 1 and r["jenkinsForce"][0] == 0.0


def test_describing_function_reports_no_jenkins_force(fmu: BladeFMU) -> None:
    for fm in (1, 2):
        r = fmu.run({"frictionModel": fm, "amplitudeMode": 1}, 0.02, H, outputs=OUT)
        assert np.max(np.abs(r["tipDisplacement"])) > D  # the contact closed
        assert np.all(r["jenkinsForce"] == 0.0)


# ---------------------------------------------------------------------------------------------
# the tracked amplitude (amplitudeMode 2): restart at a period end with B and runningMaximum


@pytest.mark.parametrize("k", [11, 16])  # the update at t1 applied by t1 / just after it (both happen)
def test_tracked_amplitude_restart_at_a_period_end(fmu: BladeFMU, k: int) -> None:
    """The tracked period clock psi restarts at 0 at the start time, so t1 = k T is a period end
    of the original run and both runs then have the same period ends. The continuation grid has
    T / 37.3 steps, so no later period end falls on a communication point (where either run may
    report B just before or just after the update)."""
    p = {"frictionModel": 1, "amplitudeMode": 2}
    t1, h2, stop = k * T, T / 37.3, (k + 6.5) * T
    head = fmu.run(p, t1, T / 40, speed_rpm=RPM, outputs=OUT)
    tail = fmu.run(None, stop, h2, speed_rpm=RPM, outputs=OUT, reset=False)
    row = head[-1]
    assert row["time"] == t1 == tail["time"][0]
    st = state_at(row, jenkins=False)
    if tail["amplitude"][1] == row["amplitude"]:
        # the period-end event was applied by t1: B and the new window are in the outputs at t1
        st.update(B=float(row["amplitude"]), runningMaximum=float(row["runningMaximum"]))
    else:
        # psi reached 2 pi k a rounding error after t1: the update happens just after t1. Its
        # result by model-notes s.3: B = max |q| over the period that ends, the window restarts
        # at |q(t1)| (runningMaximum start value 0: the initial window is |q0|)
        B = max(float(row["runningMaximum"]), abs(float(row["tipDisplacement"])))
        assert abs(tail["amplitude"][1] - B) <= 1e-9 * B
        st.update(B=B, runningMaximum=0.0)
    rest = fmu.run({**p, **st}, stop, h2, speed_rpm=RPM, start_time=t1, outputs=OUT)
    assert rest["runningMaximum"][0] == max(abs(st["tipDisplacement"]), st["runningMaximum"])
    assert_same_run(
        rest[1:], tail[1:], ("tipDisplacement", "tipVelocity", "dissipatedEnergy", "amplitude", "runningMaximum")
    )
    # the test can fail: the default B (the start of the tracked amplitude) gives another run, as
    # the contact closes in the first period (B acts only then; it is replaced at its end)
    assert np.max(np.abs(tail["tipDisplacement"][tail["time"] < t1 + T])) > D
    other = fmu.run(
        {**p, **{n: v for n, v in st.items() if n != "B"}}, stop, h2, speed_rpm=RPM, start_time=t1, outputs=OUT
    )
    amp = float(np.max(np.abs(tail["tipDisplacement"])))
    assert float(np.max(np.abs(other["tipDisplacement"] - tail["tipDisplacement"]))) > 1e-6 * amp


def test_running_maximum_start_value_feeds_the_first_period(fmu: BladeFMU) -> None:
    """The first tracked amplitude is max(|q| over the first period, start value): a start value
    above every |q| of the first period is what B becomes at its end."""
    p = {"amplitudeMode": 2, "gating": False, "tipDisplacement": 1e-6}
    big = 7e-4  # [m] far above the response to the default load
    r = fmu.run({**p, "runningMaximum": big}, 1.5 * T, T / 40, outputs=OUT)
    assert r["runningMaximum"][0] == big and r["amplitude"][0] == 6e-5  # B starts at parameter B
    after = r["time"] > T * (1 + 1e-9)
    assert np.all(r["amplitude"][after] == big)
    plain = fmu.run(p, 1.5 * T, T / 40, outputs=OUT)
    assert plain["runningMaximum"][0] == 1e-6 and np.all(plain["amplitude"][after] < big / 10)


# ---------------------------------------------------------------------------------------------
# defaults and the harness


def test_zero_start_values_equal_the_default_run(fmu: BladeFMU) -> None:
    zeros = {
        "tipDisplacement": 0.0,
        "tipVelocity": 0.0,
        "dissipatedEnergy": 0.0,
        "jenkinsForce": 0.0,
        "runningMaximum": 0.0,
    }
    for p in ({"frictionModel": 3}, {}):
        a = fmu.run(p, 0.02, H, outputs=OUT)
        b = fmu.run({**p, **zeros}, 0.02, H, outputs=OUT)
        assert all(np.array_equal(a[n], b[n]) for n in OUT)


def test_bad_start_values_through_the_harness(fmu: BladeFMU) -> None:
    with pytest.raises(ParameterError, match=r"runningMaximum = -1e-05 m .*\[0, inf\) m"):
        fmu.run({"runningMaximum": -1e-5}, 0.01, H)
    with pytest.raises(ParameterError, match="jenkinsForce = nan"):
        fmu.run({"jenkinsForce": math.nan}, 0.01, H)
    # the cone is a cross-field rule: the FMU refuses it at initialization, BladeFMU raises its word
    with pytest.raises(FMUError) as err:
        fmu.run({"frictionModel": 3, "tipDisplacement": 5e-5, "jenkinsForce": 40.0}, 0.01, H)
    assert any("jenkinsForce = 40 N" in m and "[-33, 33] N" in m for m in err.value.messages), err.value.messages
    assert len(fmu.run(None, 0.001, H)) == 11  # usable again after the refusal
