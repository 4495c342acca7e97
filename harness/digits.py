"""The digits the harness writes results with (CSV and JSON files: `make run`'s results/, the
studies, the command-line tools' tables).

SIGNIFICANT = 6 significant digits, counted from the largest magnitude of a column (CSV) or of the
value itself (JSON). Why 6: the least accurate quantities written are accurate to about 1e-6
relative (the time integration, RK4 at the default maxStep 1e-5 s; the peaks and folds, located
along the branches to their speed tolerance; the settled amplitudes of the sweeps), so a 7th digit
says nothing about the model. The digits beyond carry rounding noise that differs from machine to
machine and with the BLAS thread count (measured between two machines: 1e-13 to 1e-7 relative),
which would leave `git status` full of changed result files after `make run`.

Counting from the column's largest magnitude, not from each value, also rounds the values that are
noise around zero (a state component of 1e-20 m in a column of 1e-5 m is written 0), and every
value of a column shares one quantum. Rounding is half-even on the exact binary value (decimal
arithmetic), so the written text depends on the value only; a value that happens to lie within
the noise of a rounding boundary can still flip its last digit.

Kept outside the layers (like harness.outputs): every layer's writer shares it.
"""

from __future__ import annotations

import math
from decimal import ROUND_HALF_EVEN, Decimal
from typing import Any, Iterable

SIGNIFICANT = 6


def exponent(scale: float, digits: int = SIGNIFICANT) -> int | None:
    """The decimal exponent e of the quantum 10^e that keeps `digits` significant digits of `scale`
    (None for a zero or non-finite scale: nothing to round to)."""
    if not (math.isfinite(scale) and scale != 0.0):
        return None
    return math.floor(math.log10(abs(scale))) - digits + 1


def text(value: float, e: int | None) -> str:
    """`value` rounded to a multiple of 10^e, as the shortest text that reads back as that number
    ('nan', 'inf' as Python writes them; e None: the value's own shortest text)."""
    v = float(value)
    if v == 0.0:
        return "0.0"  # -0.0 too: the sign of a zero is rounding noise
    if e is None or not math.isfinite(v):
        return repr(v)
    d = Decimal(v).quantize(Decimal(1).scaleb(e), rounding=ROUND_HALF_EVEN)
    r = float(d)
    return "0.0" if r == 0.0 else repr(r)


def column(values: Iterable[float], digits: int = SIGNIFICANT) -> list[str]:
    """The texts of one column: every value rounded to the quantum of the column's largest
    finite magnitude."""
    vals = [float(v) for v in values]
    finite = [abs(v) for v in vals if math.isfinite(v)]
    e = exponent(max(finite), digits) if finite else None
    return [text(v, e) for v in vals]


def number(value: float, digits: int = SIGNIFICANT) -> float:
    """One value rounded to `digits` significant digits of itself."""
    v = float(value)
    return float(text(v, exponent(v, digits)))


def rounded(obj: Any, digits: int = SIGNIFICANT) -> Any:
    """A JSON-able structure with every float rounded to `digits` significant digits of itself
    (ints, bools, strings and None unchanged; tuples become lists)."""
    if isinstance(obj, bool) or obj is None or isinstance(obj, (int, str)):
        return obj
    if isinstance(obj, float):
        return number(obj, digits)
    if isinstance(obj, dict):
        return {k: rounded(v, digits) for k, v in obj.items()}
    if isinstance(obj, (list, tuple)):
        return [rounded(v, digits) for v in obj]
    if hasattr(obj, "tolist") and hasattr(obj, "dtype"):  # a numpy scalar or array
        return rounded(obj.tolist(), digits)
    return obj
