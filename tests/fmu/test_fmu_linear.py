"""FMU against the closed form of the linear forced oscillator (contact out of reach).

With the gap d = 1 m no contact force ever acts and the amplitude is fixed (amplitudeMode 1, B < d),
so the FMU integrates M q'' + C0 q' + K0(Omega) q = G F sin(omega t), whose steady amplitude is
G F / |K0 - M omega^2 + i omega C0|. M, C0, K0 and G are computed here independently of blade.c
(scipy quadrature of the mode of eq. 20 with lambda from brentq on eq. 21, both formulations of
docs/model.md s.2) and checked against docs/model.md's printed check values. The load F sin(omega t) is passed
as value plus Taylor derivatives of orders 1..8 at every communication point (model-notes s.1), the
run lasts 18.5 decay times (envelope e^{-t C0 / (2 M)}), and the amplitude is a least-squares sine
fit over the last 10 whole periods. Tolerance 1e-6 relative, from the error budget: RK4 with
maxStep 5e-6 s, (omega_n h)^4 ~ 4e-9; Taylor truncation of the input, (omega h_c)^9/9! ~ 1e-10;
transient e^{-18.5} ~ 1e-8; quadrature ~1e-13.
"""

from __future__ import annotations

import math
from pathlib import Path

import numpy as np
import pytest
from tests.support.fmi2raw import aero_derivatives
from fmpy import extract, read_model_description
from fmpy.fmi2 import FMU2Slave
from scipy.integrate import quad
from scipy.optimize import brentq

# value references (modelDescription.xml)
VR_D, VR_B, VR_MAXSTEP, VR_FW0 = 11, 12, 13, 14
VR_FRICTION, VR_FORMULATION, VR_AMPMODE = 20, 21, 23
VR_AERO, VR_SPEED = 40, 41
VR_Q, VR_E, VR_FREQ, VR_KEQ = 50, 57, 58, 54

TABLE1 = dict(EI=343.0, rho=7800.0, A=4.2e-4, l=0.15, c=29.8, m0=0.025)  # docs/model.md s.1
FW0 = 100.0  # load amplitude [N/m]
MAX_STEP = 5e-6  # [s]
H_COMM = 2e-4  # communication step [s]
REL_TOL = 1e-6


def reduction(formulation: int, EI: float, rho: float, A: float, l: float, c: float, m0: float) -> dict:
    """M [kg], C0 [N s/m], K0 = K0s + K0w Omega^2 [N/m], G [m] of docs/model.md s.2, by quadrature."""
    R = m0 / (rho * A * l)

    def eq21(a: float) -> float:
        return 1 + math.cos(a) * math.cosh(a) + R * a * (math.cos(a) * math.sinh(a) - math.sin(a) * math.cosh(a))

    aL = brentq(eq21, 0.5, 1.8751041, xtol=1e-15, rtol=1e-15)  # first root, below the bare 1.8751
    lam = aL / l
    s = (math.sinh(aL) + math.sin(aL)) / (math.cosh(aL) + math.cos(aL))

    def phi(x: float) -> float:  # eq. 20
        return s * (math.cosh(lam * x) - math.cos(lam * x)) + math.sin(lam * x) - math.sinh(lam * x)

    def dphi(x: float) -> float:
        return lam * (s * (math.sinh(lam * x) + math.sin(lam * x)) + math.cos(lam * x) - math.cosh(lam * x))

    def ddphi(x: float) -> float:
        return lam**2 * (s * (math.cosh(lam * x) + math.cos(lam * x)) - math.sin(lam * x) - math.sinh(lam * x))

    def integral(f) -> float:
        return quad(f, 0.0, l, epsabs=0.0, epsrel=1e-13, limit=200)[0]

    u2 = phi(l)
    if formulation == 1:  # printed, eq. 24 and 26 with U2 = lambda^4 U1
        U1 = integral(lambda x: phi(x) ** 2)
        U3 = integral(lambda x: x * phi(x) * dphi(x))
        U4 = integral(lambda x: ddphi(x) * phi(x) * (l * l - x * x))
        U5 = integral(lambda x: phi(x) * ddphi(x))
        return dict(
            lambdaL=aL,
            M=rho * A * U1 / u2,
            C0=c * U1 / u2,
            K0s=EI * lam**4 * U1 / u2,
            K0w=(rho * A * U3 - 0.5 * rho * A * U4 - m0 * l * U5) / u2,
            G=integral(phi) / u2,
        )
    # consistent: phi normalised to phi(l) = 1
    n2 = integral(lambda x: (phi(x) / u2) ** 2)
    return dict(
        lambdaL=aL,
        M=rho * A * n2 + m0,
        C0=c * n2,
        K0s=EI * integral(lambda x: (ddphi(x) / u2) ** 2),
        K0w=integral(lambda x: (rho * A * (l * l - x * x) / 2 + m0 * l) * (dphi(x) / u2) ** 2),
        G=integral(phi) / u2,
    )


@pytest.fixture(scope="module")
def reductions() -> dict[int, dict]:
    return {f: reduction(f, **TABLE1) for f in (1, 2)}


def test_independent_reduction_matches_model_md(reductions: dict[int, dict]) -> None:
    """The test's own M, C0, K0 agree with docs/model.md s.2's check values to their printed digits."""
    printed, consistent = reductions[1], reductions[2]
    assert printed["lambdaL"] == pytest.approx(1.7898556, abs=1e-7)
    assert printed["M"] == pytest.approx(0.309149, abs=1e-6)
    assert printed["C0"] == pytest.approx(2.81216, abs=1e-5)
    assert printed["K0s"] == pytest.approx(656184, abs=1)
    assert printed["K0w"] == pytest.approx(0.355953, abs=1e-6)
    assert consistent["M"] == pytest.approx(0.146579, abs=1e-6)
    assert consistent["C0"] == pytest.approx(1.10594, abs=1e-5)
    assert consistent["K0s"] == pytest.approx(311121, abs=1)
    assert consistent["K0w"] == pytest.approx(0.174944, abs=1e-6)


@pytest.fixture(scope="module")
def unzipped(fmu_path: Path, tmp_path_factory: pytest.TempPathFactory) -> tuple[str, str]:
    md = read_model_description(str(fmu_path))
    return md.guid, extract(str(fmu_path), unzipdir=str(tmp_path_factory.mktemp("linear")))


def run_sine(
    unzipped: tuple[str, str], formulation: int, rpm: float, duration: float, friction: int = 1
) -> dict[str, np.ndarray]:
    """Drives aeroLoad = FW0 sin(omega t) with derivatives 1..8; returns sampled q and E."""
    guid, directory = unzipped
    slave = FMU2Slave(guid=guid, unzipDirectory=directory, modelIdentifier="ShroudedBlade", instanceName="linear")
    slave.instantiate()
    try:
        slave.setupExperiment(startTime=0.0)
        slave.setReal([VR_D, VR_MAXSTEP, VR_FW0], [1.0, MAX_STEP, 0.0])  # aeroLoad fed: built-in load off
        slave.setInteger([VR_FORMULATION, VR_AMPMODE, VR_FRICTION], [formulation, 1, friction])
        slave.enterInitializationMode()
        slave.setReal([VR_SPEED], [rpm])
        slave.exitInitializationMode()
        omega = 3 * 2 * math.pi * rpm / 60  # engineOrder 3
        n = int(math.ceil(duration / H_COMM))
        orders = list(range(1, 9))
        t = np.arange(n + 1) * H_COMM
        q = np.zeros(n + 1)
        E = np.zeros(n + 1)
        for k in range(n):
            tk = k * H_COMM
            load = aero_derivatives(tk, FW0, omega)  # value and derivatives 1..8 of FW0 sin(omega t)
            slave.setReal([VR_AERO], load[:1])
            slave.setRealInputDerivatives([VR_AERO] * 8, orders, load[1:])
            slave.doStep(tk, H_COMM)
            q[k + 1], E[k + 1] = slave.getReal([VR_Q, VR_E])
        freq, keq = slave.getReal([VR_FREQ, VR_KEQ])
        slave.terminate()
    finally:
        slave.freeInstance()
    return dict(t=t, q=q, E=E, freq=freq, keq=keq, omega=omega)


def sine_fit(t: np.ndarray, q: np.ndarray, omega: float, periods: int) -> tuple[float, float]:
    """(a, b) of the least-squares fit q = a sin(omega t) + b cos(omega t) + c over the last whole periods."""
    start = t[-1] - periods * 2 * math.pi / omega - 1e-12
    m = t >= start
    A = np.column_stack([np.sin(omega * t[m]), np.cos(omega * t[m]), np.ones(m.sum())])
    a, b, _ = np.linalg.lstsq(A, q[m], rcond=None)[0]
    return a, b


CASES = [
    (1, 3000.0, 1),
    (1, 5000.0, 1),
    (1, 7000.0, 1),
    (2, 3000.0, 1),
    (2, 5000.0, 1),
    (2, 7000.0, 1),
    (1, 5000.0, 2),
    (1, 5000.0, 3),
]


@pytest.mark.parametrize("formulation,rpm,friction", CASES)
def test_steady_amplitude_equals_closed_form(
    unzipped: tuple[str, str], reductions: dict[int, dict], formulation: int, rpm: float, friction: int
) -> None:
    r = reductions[formulation]
    tau = 2 * r["M"] / r["C0"]  # envelope decay time [s]: 0.22 s printed, 0.27 s consistent
    out = run_sine(unzipped, formulation, rpm, 18.5 * tau, friction)
    omega = out["omega"]
    Omega = 2 * math.pi * rpm / 60
    K0 = r["K0s"] + r["K0w"] * Omega**2
    X = r["G"] * FW0 / abs(K0 - r["M"] * omega**2 + 1j * omega * r["C0"])
    a, b = sine_fit(out["t"], out["q"], omega, periods=10)
    amp = math.hypot(a, b)
    assert amp == pytest.approx(X, rel=REL_TOL), f"amplitude {amp:.12e} m vs closed form {X:.12e} m"
    # viscous dissipation (model-notes s.2: E' = C0 q'^2) over the last 10 periods, with q' = omega X
    # cos(omega t + phi) of the closed-form X and the fitted phase: integral of C0 q'^2 in closed form
    k1 = len(out["t"]) - 1
    k0 = k1 - int(round(10 * 2 * math.pi / omega / H_COMM))
    t0, t1 = out["t"][k0], out["t"][k1]
    phase = math.atan2(b, a)
    expected = (
        0.5
        * r["C0"]
        * (omega * X) ** 2
        * (t1 - t0 + (math.sin(2 * (omega * t1 + phase)) - math.sin(2 * (omega * t0 + phase))) / (2 * omega))
    )
    assert out["E"][k1] - out["E"][k0] == pytest.approx(expected, rel=REL_TOL)
    # contact-free natural frequency output (model-notes s.4) and no contact stiffness
    assert out["freq"] == pytest.approx(math.sqrt(K0 / r["M"]) / (2 * math.pi), rel=1e-10)
    assert out["keq"] == 0.0
