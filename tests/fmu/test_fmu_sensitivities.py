"""The FMU's sensitivities (parameter `sensitivities`, docs/model-notes.md s.8) against independent
computations:

- central differences of the FMU's own outputs with the sensitivities off, started from perturbed
  start values (and B), for every friction model, gated and not, fixed and tracked amplitude,
  over runs with contact, stick/slip, gate and period-end events;
- the closed-form monodromy expm(A t) of the linear blade (M, C0, K0 from the independent Python
  Galerkin reduction, harness.reference.blade);
and what goes with them: off, they read 0 and leave every other output bit-identical; model
exchange refuses them; FMU states carry them.

Tolerances. Differences: relative step 1e-6 of each parameter's scale, central, so truncation
~1e-12 and rounding ~1e-16 / 1e-6 of the output scale; the FMU's event location moves the event
by ~1e-15 s: the scaled difference between the two is below 2e-6 (measured <= 5e-7). Closed form:
RK4 at maxStep 2e-6 s, (omega_n h)^4 ~ 2e-9.
"""

from __future__ import annotations

import math

import numpy as np
import pytest
from scipy.linalg import expm

from tests.support.fmi2raw import ERROR, MODEL_EXCHANGE, OK, Instance

from harness.fmu.blade import BladeFMU, FMUError
from harness.model.excitation import AeroLoad, Constant
from harness.reference.blade import galerkin

SPEED = 6000.0  # [rpm]
EO = 3
T = 60.0 / (EO * SPEED)  # excitation period [s]
ROWS = ("tipDisplacement", "tipVelocity", "jenkinsForce", "runningMaximum", "amplitude")
COLS = ("Q0", "V0", "F0", "B")
START = {"Q0": "tipDisplacement", "V0": "tipVelocity", "F0": "jenkinsForce", "B": "B"}
SENS = [f"d{r[0].upper()}{r[1:]}_d{c}" for r in ROWS for c in COLS]
L_PER_M = 0.33 * 1e7 * math.cos(math.pi / 3)  # mu kn cos(gamma) [N/m]: L = L_PER_M (|q| - d)

# name: (parameters, periods); q0 > d = 3e-5 m starts in contact
CASES = {
    "linear (d = 1 m)": (dict(d=1.0, amplitudeMode=1, tipDisplacement=1e-5, tipVelocity=0.02), 2),
    "macroslip DF, gated, fixed B": (dict(amplitudeMode=1, B=6e-5, tipDisplacement=4e-5, tipVelocity=0.01), 2),
    "macroslip DF, ungated, fixed B": (dict(amplitudeMode=1, gating=False, B=6e-5, tipDisplacement=2e-5), 2),
    "macroslip DF, gated, tracked B": (dict(amplitudeMode=2, B=5e-5, tipDisplacement=4.5e-5, tipVelocity=-0.01), 3),
    "Coulomb DF, gated, tracked B": (dict(frictionModel=2, amplitudeMode=2, B=5e-5, tipDisplacement=4e-5), 3),
    "Jenkins element, stick start": (
        dict(frictionModel=3, tipDisplacement=5e-5, tipVelocity=0.01, jenkinsForce=0.4 * L_PER_M * 2e-5),
        2,
    ),
    "Jenkins element, open start": (dict(frictionModel=3, tipDisplacement=1e-5, tipVelocity=0.03), 2),
}


def run(fmu: BladeFMU, params: dict, periods: int, outputs: list[str]) -> dict[str, float]:
    p = dict(params, maxStep=2e-6)
    r = fmu.run(
        p,
        periods * T,
        T / 8,
        aero=AeroLoad(100.0, EO, Constant(SPEED)),
        speed_rpm=SPEED,
        outputs=outputs,
        input_fit="chebyshev",
        sample_every=10**9,
    )
    return {k: float(r[k][-1]) for k in outputs}


def scales(params: dict) -> dict[str, float]:
    """Scale of each parameter (the difference step is 1e-6 of it) and of each output row."""
    q = 3e-5
    return {
        "Q0": q,
        "V0": q * 2 * math.pi / T,
        "F0": L_PER_M * q,
        "B": params.get("B", 6e-5),
        "tipDisplacement": q,
        "tipVelocity": q * 2 * math.pi / T,
        "jenkinsForce": L_PER_M * q,
        "runningMaximum": q,
        "amplitude": q,
    }


def columns(params: dict) -> list[str]:
    if params.get("frictionModel") == 3:
        return ["Q0", "V0"] + (["F0"] if "jenkinsForce" in params else [])
    return ["Q0", "V0", "B"]


@pytest.mark.parametrize("case", list(CASES))
def test_sensitivities_equal_central_differences(fmu: BladeFMU, case: str) -> None:
    params, periods = CASES[case]
    sc = scales(params)
    got = run(fmu, dict(params, sensitivities=True), periods, SENS)
    worst = 0.0
    for col in columns(params):
        h = 1e-6 * sc[col]
        name = START[col]
        base = params.get(name, 6e-5 if name == "B" else 0.0)
        plus = run(fmu, dict(params, **{name: base + h}), periods, list(ROWS))
        minus = run(fmu, dict(params, **{name: base - h}), periods, list(ROWS))
        for row in ROWS:
            fd = (plus[row] - minus[row]) / (2 * h)
            s = got[f"d{row[0].upper()}{row[1:]}_d{col}"]
            err = abs(s - fd) * sc[col] / sc[row]
            worst = max(worst, err)
            assert err <= 2e-6, f"{case}: d{row}/d{col} = {s:.9g}, central difference {fd:.9g} (scaled error {err:.2e})"
    assert worst >= 0.0


def test_linear_sensitivities_equal_the_closed_form_monodromy(fmu: BladeFMU) -> None:
    """d(q, q')/d(q0, q0') = expm(A t), A = [[0, 1], [-K0/M, -C0/M]] of the linear blade."""
    g = galerkin({})
    Omega = 2 * math.pi * SPEED / 60
    A = np.array([[0.0, 1.0], [-g.K0(Omega) / g.M, -g.C0 / g.M]])
    for periods in (1, 3):
        got = run(fmu, dict(CASES["linear (d = 1 m)"][0], sensitivities=True), periods, SENS)
        S = np.array(
            [
                [got["dTipDisplacement_dQ0"], got["dTipDisplacement_dV0"]],
                [got["dTipVelocity_dQ0"], got["dTipVelocity_dV0"]],
            ]
        )
        E = expm(A * periods * T)
        D = np.diag([1.0, 2 * math.pi / T])  # scaled: q ~ 1, q' ~ omega
        err = np.max(np.abs(np.linalg.inv(D) @ (S - E) @ D))
        assert err <= 1e-8, f"{periods} periods: {S} vs closed form {E} (scaled error {err:.2e})"


def test_off_they_read_zero_and_change_nothing(fmu: BladeFMU) -> None:
    params, periods = CASES["macroslip DF, gated, tracked B"]
    plain = ["tipDisplacement", "tipVelocity", "amplitude", "runningMaximum", "dissipatedEnergy", "normalForce"]
    off = run(fmu, params, periods, plain + SENS)
    on = run(fmu, dict(params, sensitivities=True), periods, plain + SENS)
    assert all(off[k] == 0.0 for k in SENS)
    assert all(off[k] == on[k] for k in plain), "the sensitivities changed the state"
    assert any(on[k] != 0.0 for k in SENS)


def test_model_exchange_refuses_them(lib) -> None:
    with Instance(lib, fmu_type=MODEL_EXCHANGE) as c:
        assert c.set_boolean(["sensitivities"], [1]) == OK  # a parameter: settable before initialization
        assert c.setup() == OK
        assert c.enter_init() == OK
        assert c.exit_init() == ERROR
        assert "sensitivities = true is for co-simulation only" in c.log_text()


def test_fmu_states_carry_them(fmu: BladeFMU) -> None:
    params, _ = CASES["Jenkins element, stick start"]
    p = dict(params, sensitivities=True, maxStep=2e-6)
    aero = AeroLoad(100.0, EO, Constant(SPEED))
    fmu.run(p, T, T / 8, aero=aero, speed_rpm=SPEED, outputs=["tipDisplacement"], input_fit="chebyshev")
    state = fmu.get_state()
    a = fmu.run(p, 2 * T, T / 8, aero=aero, speed_rpm=SPEED, outputs=SENS, input_fit="chebyshev", reset=False)
    fmu.set_state(state)
    b = fmu.run(p, 2 * T, T / 8, aero=aero, speed_rpm=SPEED, outputs=SENS, input_fit="chebyshev", reset=False)
    for k in SENS:
        assert a[k][-1] == b[k][-1], k


def test_a_bad_value_is_refused(fmu: BladeFMU) -> None:
    with pytest.raises((FMUError, ValueError), match="sensitivities"):
        run(fmu, dict(sensitivities=2), 1, ["tipDisplacement"])
