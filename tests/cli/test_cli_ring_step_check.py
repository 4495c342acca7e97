"""`python -m harness ring-step-check`: every bad value refused before any work, in one line naming
the option, the value and the accepted range."""

from __future__ import annotations

import pytest

from harness.cli.main import main


@pytest.mark.parametrize(
    "args, words",
    [
        (["--blades", "1"], ["--blades 1", "[2, "]),
        (["--speeds", "7000", "6000"], ["--speeds 7000 6000", "FROM must be below TO"]),
        (["--steps-per-period", "7"], ["--steps-per-period 7", "[8, 100000]"]),
        (["--finer", "320", "200"], ["--finer 320 200", "increasing from --steps-per-period 160"]),
        (["--finer", "160"], ["--finer 160", "increasing from --steps-per-period 160"]),
        (["--finer", "200000"], ["--finer 200000", "up to 100000"]),
        (["--every", "0"], ["--every 0", "[1, 1000000]"]),
        (["--above", "nan"], ["--above nan", "[0, 1]"]),
        (["--above", "-1e-5"], ["--above -1e-05", "[0, 1]"]),
        (["--pattern", "0.5", "0"], ["--pattern SIGMA '0.5'", "(0, 0.2]"]),
        (["--branches", "b.json"], ["--branches b.json", ".npz"]),
    ],
)
def test_bad_values_are_named(capsys, args, words):
    assert main(["ring-step-check", *args]) == 2
    err = capsys.readouterr().err
    assert err.startswith("error: ") and all(w in err for w in words), err
    assert err.count("\n") == 1, err
