"""`python -m harness ring-completeness`: every bad value refused before any work, in one line
naming the option, the value and the accepted range."""

from __future__ import annotations

import pytest

from harness.cli.main import main


@pytest.mark.parametrize(
    "args, words",
    [
        (["--blades", "1"], ["--blades 1", "[2, "]),
        (["--speeds", "5000", "40000"], ["--speeds 40000", "(0, 30000]"]),
        (["--speeds", "7000", "6000"], ["--speeds 7000 6000", "FROM must be below TO"]),
        (["--speeds", "5000", "nan"], ["--speeds nan", "(0, 30000]"]),
        (["--spacing", "0"], ["--spacing 0", "[0.1, TO - FROM = 2500]"]),
        (["--spacing", "3000"], ["--spacing 3000", "[0.1, TO - FROM = 2500]"]),
        (["--random", "-1"], ["--random -1", "[0, 100]"]),
        (["--seed", "-3"], ["--seed -3", "[0, 2^63)"]),
        (["--seed", "2"], ["--seed 2", "engine's own"]),
        (["--settle", "0.5"], ["--settle 0.5", "[1e-12, 1e-2]"]),
        (["--max-periods", "5"], ["--max-periods 5", "[10, 1000000]"]),
        (["--steps-per-period", "7"], ["--steps-per-period 7", "[8, 100000]"]),
        (["--jobs", "0"], ["--jobs 0", "[1, 64]"]),
        (["--pattern", "0", "1"], ["--pattern SIGMA '0'", "(0, 0.2]"]),
        (["--pattern", "0.05", "x"], ["--pattern INDEX 'x'", "[0, 999999]"]),
        (["--branches", "b.json"], ["--branches b.json", ".npz"]),
        (["--out", "/proc/version/x"], ["--out /proc/version/x", "cannot write there"]),
    ],
)
def test_bad_values_are_named(capsys, args, words):
    assert main(["ring-completeness", *args]) == 2
    err = capsys.readouterr().err
    assert err.startswith("error: ") and all(w in err for w in words), err
    assert err.count("\n") == 1, err
