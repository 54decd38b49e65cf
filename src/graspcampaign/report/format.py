"""The one way a report writes a number and puts it beside the paper's.

* **Rounding once.** A value is rounded a single time, from its exact binary value, half to even
  (:mod:`decimal`), to a number of decimals or of significant digits; an interval's bounds and
  its estimate are each rounded once (17/100 prints 10.9–25.5, not the doubly rounded 25.6).
* **One missing mark** (:data:`MISSING`) and one minus sign (:data:`MINUS`).
* **One verdict rule** (:func:`verdict`), used by every table that sets ours beside the paper.

References
----------
Wilson, E. B. (1927), for the intervals whose bounds are printed here; IEEE 754 /
Python ``decimal`` for exact rounding.
"""

from __future__ import annotations

import math
import numbers
from decimal import ROUND_HALF_EVEN, Decimal
from typing import Any

MISSING = "\u2014"
"""The mark of a value that is missing or could not be computed (its reason stands beside it)."""
MINUS = "\u2212"
DASH = "\u2013"


def is_missing(value: Any) -> bool:
    """Return whether ``value`` is None, nan or NA (a value that is absent, not an empty text)."""
    if value is None:
        return True
    if isinstance(value, str):
        return False
    try:
        return bool(value != value)  # nan, pd.NA raise or compare unequal
    except (TypeError, ValueError):
        return True


def number(value: Any, digits: int | None = None, *, sig: int | None = None,
           signed: bool = False, unit: str = "") -> str:
    """Return ``value`` rounded once: ``digits`` decimals, or ``sig`` significant digits.

    Integers print as they are; with neither ``digits`` nor ``sig`` a float keeps 4 significant
    digits without trailing zeros (0.1, 2, 0.003142). ``signed`` prefixes ``+`` to a non-zero
    positive value; ``unit`` is appended as given (e.g. ``" pp"``). Missing values print
    :data:`MISSING`.
    """
    if isinstance(value, str):
        return value
    if is_missing(value):
        return MISSING
    if isinstance(value, bool):
        return "yes" if value else "no"
    if isinstance(value, numbers.Integral) and digits is None and sig is None:
        text = str(int(value))
    elif math.isinf(float(value)):
        text = "inf" if value > 0 else "-inf"
    else:
        exact = Decimal(float(value))
        strip = digits is None and sig is None
        if digits is None:  # significant digits; negative "decimals" round left of the point
            digits = (sig or 4) - 1 - (exact.adjusted() if exact else 0)
        text = f"{exact.quantize(Decimal(1).scaleb(-digits), rounding=ROUND_HALF_EVEN):f}"
        if strip and "." in text:
            text = text.rstrip("0").rstrip(".")
    if text.startswith("-"):
        text = text[1:] if not any(c in "123456789" for c in text) else text
    if signed and not text.startswith("-") and any(c in "123456789" for c in text):
        text = "+" + text
    return text.replace("-", MINUS) + unit


def interval(low: Any, high: Any, digits: int | None = None, *, sig: int | None = None) -> str:
    """Return ``"low–high"`` (``"low to high"`` when a bound is negative), each rounded once."""
    if is_missing(low) or is_missing(high):
        return MISSING
    sep = " to " if float(low) < 0 or float(high) < 0 else DASH
    return f"{number(low, digits, sig=sig)}{sep}{number(high, digits, sig=sig)}"


def estimate(value: Any, low: Any = None, high: Any = None, digits: int | None = None, *,
             sig: int | None = None) -> str:
    """Return ``"value (low–high)"`` in the style of the paper's tables (just the value when
    there is no interval)."""
    text = number(value, digits, sig=sig)
    if is_missing(value) or is_missing(low) or is_missing(high):
        return text
    return f"{text} ({interval(low, high, digits, sig=sig)})"


def paper_text(paper: Any, digits: int | None = None) -> str:
    """Return the paper's value as printed: a number, a range ``lo–hi``, yes/no or its text."""
    if isinstance(paper, tuple | list):
        return interval(paper[0], paper[1], digits)
    return number(paper, digits)


def verdict(ours: Any, paper: Any, *, low: Any = None, high: Any = None, digits: int = 1,
            unit: str = "") -> tuple[bool | None, str]:
    """Say how ours stands against the paper's value: ``(differs, words)``.

    The one rule of every report:

    * no paper value, or ours not computed: ``differs`` is None;
    * the paper gives a range ``(lo, hi)``: ours inside it agrees;
    * the paper gives a yes/no or a word: equality agrees;
    * ours has a 95 % interval: the paper's value inside it is consistent, outside it differs;
    * otherwise ours matches when it is within one unit of the last printed digit of the
      paper's value (``10**-digits``; the paper both rounds and truncates), else it differs.

    The difference (ours − paper) is stated, rounded once to ``digits`` decimals.
    """
    if is_missing(paper):
        return None, "the paper reports no value"
    if is_missing(ours):
        return None, "not computed"
    if isinstance(paper, tuple | list):
        lo, hi = float(paper[0]), float(paper[1])
        if lo <= float(ours) <= hi:
            return False, f"inside the paper's range {interval(lo, hi, digits)}{unit}"
        side = "below" if float(ours) < lo else "above"
        return True, f"differs: {side} the paper's range {interval(lo, hi, digits)}{unit}"
    if isinstance(paper, bool | str) or isinstance(ours, bool | str):
        if str(ours) == str(paper):
            return False, f"as in the paper ({number(paper)})"
        return True, f"differs: the paper reports {number(paper)}, ours is {number(ours)}"
    diff = number(float(ours) - float(paper), digits, signed=True, unit=unit)
    if not is_missing(low) and not is_missing(high):
        if float(low) <= float(paper) <= float(high):
            return False, f"consistent: the paper's value lies inside our 95% interval ({diff})"
        return True, f"differs by {diff}: the paper's value lies outside our 95% interval"
    if abs(float(ours) - float(paper)) < 10.0 ** -digits:
        return False, "matches to the paper's printed precision"
    return True, f"differs by {diff}"
