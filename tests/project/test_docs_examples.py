"""The examples of README.md and the user guide run and do what they say: the fmpy example feeds
the load (the FMU's aeroLoad starts at 0) and gives the response of the harness's own held-input
run; the Python examples print what their results hold. README.md holds its two files verbatim.
(docs/examples/quickstart.py has its own test, tests/cli/test_quickstart.py.)"""

from __future__ import annotations

import re
import runpy
import subprocess
import sys
from pathlib import Path

import numpy as np
import pytest
from fmpy.util import read_csv

from harness.fmu.blade import BladeFMU
from harness.model.excitation import Stepped

REPO = Path(__file__).resolve().parents[2]
EXAMPLES = REPO / "docs" / "examples"


def _run(name: str, monkeypatch, capsys) -> tuple[dict, str]:
    monkeypatch.chdir(REPO)  # the examples name build/ShroudedBlade.fmu as a user in the repository would
    names = runpy.run_path(str(EXAMPLES / name), run_name="__main__")
    return names, capsys.readouterr().out


def _printed(out: str, label: str) -> float:
    m = re.search(re.escape(label) + r" ([-\d.e+]+) m", out)
    assert m, f"the example did not print {label!r}: {out!r}"
    return float(m.group(1))


def test_fmpy_example_equals_the_held_input_run(fmu_path, monkeypatch, capsys):
    names, out = _run("fmpy_simulate.py", monkeypatch, capsys)
    res = names["res"]
    with BladeFMU(fmu_path) as fmu:  # the same load and speed, inputs held over each step as fmpy does
        ref = fmu.run(
            {"Fw0": 100.0, "engineOrder": 3},
            0.3,
            1e-4,
            speed_rpm=5000.0,
            derivative_order=0,
            outputs=["tipDisplacement"],
        )
    q, q_ref = res["tipDisplacement"], ref["tipDisplacement"]
    assert len(q) == len(q_ref) and np.allclose(res["time"], ref["time"], rtol=0, atol=1e-12)
    scale = np.abs(q_ref).max()
    assert scale > 3e-5  # loaded: beyond the gap d = 0.03 mm (an unloaded blade stays at 0)
    # the load table is interpolated by fmpy, not evaluated: rounding differences only, which the
    # tracked-amplitude response amplifies ~10x per 50 ms (measured 8e-8 of the amplitude)
    assert np.abs(q - q_ref).max() <= 1e-6 * scale
    assert _printed(out, "max |q| over 0.3 s:") == pytest.approx(np.abs(q).max(), rel=1e-4)


def test_python_example_prints_its_result(fmu_path, monkeypatch, capsys):
    names, out = _run("python_api.py", monkeypatch, capsys)
    result = names["out"]
    assert len(result) == 3001 and result["time"][-1] == pytest.approx(0.3, abs=1e-12)
    assert out.startswith("3001 rows: time, tipDisplacement,")
    amplitude = np.abs(result["tipDisplacement"][result["time"] > 0.25]).max()
    assert _printed(out, "amplitude over the last 50 ms:") == pytest.approx(amplitude, rel=1e-4)
    assert amplitude > 4e-5  # the example's gap: the shrouds are in contact


def test_blade_fmu_example(fmu_path, monkeypatch, capsys):
    names, out = _run("blade_fmu.py", monkeypatch, capsys)
    held, runup = names["held"], names["runup"]
    assert _printed(out, "held inputs: max |q| =") == pytest.approx(np.abs(held["tipDisplacement"]).max(), rel=1e-4)
    assert _printed(out, "run-up: max |q| =") == pytest.approx(np.abs(runup["tipDisplacement"]).max(), rel=1e-4)
    # the run-up did reach the FMU: the contact-free natural frequency follows the speed up
    f = runup["naturalFrequency"]
    assert f[-1] > f[0] and np.all(np.diff(f) >= -1e-9 * f[0])
    # the held-input run is the run the fmpy example makes (same load, same steps; see above)
    names_fmpy, _ = _run("fmpy_simulate.py", monkeypatch, capsys)
    q = names_fmpy["res"]["tipDisplacement"]
    assert np.abs(q - held["tipDisplacement"]).max() <= 1e-6 * np.abs(q).max()


@pytest.mark.parametrize("name", ["fmpy_builtin.py", "fmpy_simulate.py", "python_api.py"])
def test_readme_holds_the_example(name):
    code = (EXAMPLES / name).read_text().strip()
    assert f"```python\n{code}\n```" in (REPO / "README.md").read_text()


SAMPLE_COMMAND = (
    "python -m fmpy simulate build/ShroudedBlade.fmu --input-file docs/examples/speed_steps_in.csv"
    " --output-interval 1e-4 --stop-time 0.3 --output-file speed_steps_out.csv"
)


def test_sample_input_csv_runs_in_fmpy_simulate(fmu_path, tmp_path):
    """The guide's sample input table (rotorSpeed steps 4000 -> 5000 -> 6000 rpm at 0.1 and 0.2 s,
    aeroLoad 0: the built-in load) through fmpy's command line, as the guide shows it, against the
    harness's own run of the same speed history with the load fed through aeroLoad with its
    derivatives (measured 1.6e-10 m on a 5.6e-5 m response; tolerance 1e-8 m)."""
    assert SAMPLE_COMMAND in (REPO / "docs" / "guide" / "importers.md").read_text()  # the guide shows this run
    args = SAMPLE_COMMAND.split()[1:]
    args[args.index("build/ShroudedBlade.fmu")] = str(fmu_path)
    args[args.index("docs/examples/speed_steps_in.csv")] = str(EXAMPLES / "speed_steps_in.csv")
    proc = subprocess.run([sys.executable, *args], cwd=tmp_path, capture_output=True, text=True, timeout=300)
    assert proc.returncode == 0 and not proc.stderr.strip(), proc.stderr  # no "missing input" warning either
    res = read_csv(str(tmp_path / "speed_steps_out.csv"))
    with BladeFMU(fmu_path) as fmu:
        ref = fmu.run(
            {},
            0.3,
            1e-4,
            speed_rpm=Stepped([4000.0, 5000.0, 6000.0], [0.1, 0.1, 0.1]),
            outputs=["tipDisplacement", "naturalFrequency"],
        )
    assert len(res) == len(ref) and np.allclose(res["time"], ref["time"], rtol=0, atol=1e-12)
    assert np.abs(ref["tipDisplacement"]).max() > 3e-5  # loaded: the built-in load is on
    assert np.abs(res["tipDisplacement"] - ref["tipDisplacement"]).max() <= 1e-8
    # the speed steps reached the FMU (contact-free frequency follows the speed)
    assert np.abs(res["naturalFrequency"] - ref["naturalFrequency"]).max() <= 1e-9
