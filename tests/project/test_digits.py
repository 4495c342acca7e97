"""The digits results are written with (harness/digits.py): 6 significant digits of a column's
largest magnitude, half-even on the exact binary value; the CSV writers (write_csv, the branch
CSV) and the JSON summary go through it, so that rounding noise below the 6th digit (1e-13 to 1e-7
relative between two machines) leaves the written text unchanged."""

from __future__ import annotations

import math
from decimal import Decimal

import numpy as np
from hypothesis import given, settings
from hypothesis import strategies as st

from harness import digits
from harness.files.tables import read_csv, write_csv
from harness.analysis.periodic.continuation import Branch, BranchPoint, write_branches_csv


def _significant(text: str) -> int:
    """Significant digits of a number's text (trailing zeros of the mantissa not counted)."""
    mant = text.lstrip("-").split("e")[0].replace(".", "").lstrip("0").rstrip("0")
    return len(mant)


def test_the_quantum_follows_the_column_maximum() -> None:
    col = digits.column([8698.52598, 8698.52505, 1.2e-3, -0.0, float("nan"), -312.123456])
    assert col == ["8698.53", "8698.53", "0.0", "0.0", "nan", "-312.12"]
    # a state component that is noise next to its column is written 0
    assert digits.column([5.489502741815819e-05, 1e-20, -3.3e-06]) == ["5.4895e-05", "0.0", "-3.3e-06"]
    assert digits.column([]) == [] and digits.column([0.0, 0.0]) == ["0.0", "0.0"]


def test_half_even_on_the_exact_binary_value() -> None:
    # 0.125 and 0.375 are exact in binary: ties go to the even digit
    assert digits.text(0.125, -2) == "0.12" and digits.text(0.375, -2) == "0.38"
    # 2.675 is 2.67499999... in binary: below the tie, down (a decimal-string rounding would go up)
    assert Decimal(2.675) < Decimal("2.675") and digits.text(2.675, -2) == "2.67"


@settings(max_examples=300, deadline=None)
@given(
    st.lists(
        st.floats(min_value=-1e12, max_value=1e12, allow_nan=False, allow_subnormal=False), min_size=1, max_size=20
    )
)
def test_rounded_text_is_within_half_a_quantum_and_has_at_most_6_digits(values) -> None:
    texts = digits.column(values)
    top = max(abs(v) for v in values)
    if top == 0.0:
        assert set(texts) == {"0.0"}
        return
    q = 10.0 ** (math.floor(math.log10(top)) - digits.SIGNIFICANT + 1)
    for v, t in zip(values, texts):
        assert abs(float(t) - v) <= 0.5 * q * (1 + 1e-9) + 1e-15 * abs(v), (v, t)
        assert _significant(t) <= digits.SIGNIFICANT + 1, t  # the column's top digit may carry: 999999.7 -> 1000000


def test_noise_below_the_6th_digit_leaves_the_text_unchanged() -> None:
    # 2000 values of amplitudes, speeds and states, each perturbed by 1e-10 relative (the size of the
    # differences between two machines): the same text unless a value lies within the noise of a
    # rounding boundary (probability ~2e-5 each here: none of these)
    rng = np.random.default_rng(3)
    for scale in (5e-5, 8698.5, 1.0):
        v = scale * rng.uniform(-1, 1, 2000)
        noisy = v * (1 + 1e-10 * rng.standard_normal(v.size))
        assert digits.column(v) == digits.column(noisy)


def test_write_csv_rounds_float_columns_only(tmp_path) -> None:
    tab = np.zeros(
        3, dtype=[("speed_rpm", "f8"), ("amplitude_m", "f8"), ("branches", "i4"), ("ok", "?"), ("model", "U8")]
    )
    tab["speed_rpm"] = [10671.728944996667, 9981.280074317272, 6352.027780771505]
    tab["amplitude_m"] = [5.489502741815819e-05, 1e-19, 3.024311493679535e-05]
    tab["branches"] = [1, 12345678, 3]
    tab["ok"] = [True, False, True]
    tab["model"] = ["jenkins", "fixedPt", "x"]
    write_csv(tmp_path / "t.csv", tab, "a comment")
    lines = (tmp_path / "t.csv").read_text().splitlines()
    assert lines[0] == "# a comment"
    # quanta 0.1 rpm and 1e-10 m: 6 digits of each column's largest value
    assert lines[2:] == ["10671.7,5.4895e-05,1,1,jenkins", "9981.3,0.0,12345678,0,fixedPt", "6352.0,3.02431e-05,3,1,x"]
    back = read_csv(tmp_path / "t.csv")
    assert back["speed_rpm"][0] == 10671.7


def test_branch_csv_rounds_its_columns(tmp_path) -> None:
    pts = [
        BranchPoint(
            8698.52598123,
            np.array([5.4895027418e-05, -0.0123456789, 1e-21]),
            5.4895027418e-05,
            np.array([0.9876543 + 1e-12j, 0.5 - 0.25j]),
        ),
        BranchPoint(9000.0, np.array([1e-5, 0.01, 0.0]), 1.1e-05, np.array([0.3 + 0j, 0.1 + 0j])),
    ]
    write_branches_csv(tmp_path / "b.csv", [Branch("jenkins", pts)], {"d_mm": [0.04]})
    rows = [r.split(",") for r in (tmp_path / "b.csv").read_text().splitlines()]
    head, first = rows[0], dict(zip(rows[0], rows[1]))
    assert head[:3] == ["d_mm", "branch", "kind"]
    assert (first["d_mm"], first["speed_rpm"], first["amplitude_m"]) == ("0.04", "8698.53", "5.4895e-05")
    assert (first["q0_m"], first["v0_m_s"]) == ("5.4895e-05", "-0.0123457")
    # the multipliers to 1e-5 (6 digits of the unit circle), |mu|max to 6 digits of its column
    assert first["multipliers"] == "0.98765+0.0j 0.5-0.25j" and first["mu_abs_max"] == "0.987654"
    assert [complex(z) for z in first["multipliers"].split()] == [0.98765, 0.5 - 0.25j]


def test_json_values_keep_6_significant_digits() -> None:
    out = digits.rounded(
        {
            "speed": 8698.52598,
            "n": 3,
            "flag": True,
            "none": None,
            "list": [1 / 3, np.float64(2 / 3), (1e-300, -7.123456789e12)],
            "arr": np.array([0.1234567]),
        }
    )
    assert out == {
        "speed": 8698.53,
        "n": 3,
        "flag": True,
        "none": None,
        "list": [0.333333, 0.666667, [1e-300, -7.12346e12]],
        "arr": [0.123457],
    }
    assert isinstance(out["n"], int) and isinstance(out["flag"], bool)
