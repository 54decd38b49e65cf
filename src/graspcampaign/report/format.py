"""The one way a report writes a number and sets it beside the paper's."""

from __future__ import annotations

import math
import numbers
import sys
from decimal import ROUND_HALF_EVEN, Context, Decimal
from typing import Any, NamedTuple

from graspcampaign.campaign.paper import Approximate
from graspcampaign.core.words import MISSING, listed  # noqa: F401 - fmt.listed: the one joiner

MINUS = "\u2212"
DASH = "\u2013"
P = "p"
"""The digits of a value that is a p-value (a :func:`~graspcampaign.report.spec.Claims` row's): printed
by :func:`p_value`, compared with the paper's at 3 decimals."""
EACH = "each value"  # a Col's digits: each value rounded alone (decimals of its own magnitude)


def is_missing(value: Any) -> bool:
    """Return whether ``value`` is None, nan or NA (absent, not an empty text)."""
    if value is None or isinstance(value, str):
        return value is None
    try:
        return bool(value != value)  # nan, pd.NA raise or compare unequal
    except (TypeError, ValueError):
        return True


def _nonzero(text: str) -> bool:
    return any(c in "123456789" for c in text) or "inf" in text


def number(value: Any, digits: int | None = None, *, sig: int | None = None,
           signed: bool = False, unit: str = "") -> str:
    """Return ``value`` rounded once to ``digits`` decimals or ``sig`` significant digits."""
    if isinstance(value, str):
        return value
    if is_missing(value):
        return MISSING
    if isinstance(value, bool):
        return "yes" if value else "no"
    alone = digits == EACH or sig is not None  # rounded to significant digits, not a column's decimals
    digits = decimals([value], sig or 3) if digits == EACH else digits
    if isinstance(value, numbers.Integral) and digits is None and sig is None:
        text = str(int(value))
    elif math.isinf(float(value)):
        text = "inf" if value > 0 else "-inf"
    elif alone and 0 < abs(float(value)) < SMALL:  # 7.02e-5, not 0.0000702: the digits it carries
        sign = MINUS if value < 0 else "+" if signed else ""  # the exponent's sign stays "-", as a p-value's
        return sign + _scientific(abs(float(value)), sig or 3) + unit
    else:
        exact, strip = Decimal(float(value)), digits is None and sig is None
        if digits is None:  # significant digits; negative "decimals" round left of the point
            digits = (sig or 4) - 1 - (exact.adjusted() if exact else 0)
        wide = Context(prec=max(28, exact.adjusted() + digits + 2))  # 1e30 to 2 decimals: 33 digits
        text = f"{exact.quantize(Decimal(1).scaleb(-int(digits)), rounding=ROUND_HALF_EVEN, context=wide):f}"
        text = text.rstrip("0").rstrip(".") if strip and "." in text else text
    text = text[1:] if text.startswith("-") and not _nonzero(text) else text  # no "-0.0"
    text = "+" + text if signed and not text.startswith("-") and _nonzero(text) else text
    return text.replace("-", MINUS) + unit


SMALL = 1e-3
"""Below this magnitude a value rounded to significant digits prints in scientific form (``7.02e-5``,
as a p-value does): written out, its leading zeros (``0.0000702``) read as digits it does not carry."""


def _scientific(value: float, sig: int) -> str:
    """``value`` to ``sig`` significant digits in scientific form, the exponent unpadded: ``7.02e-5``."""
    return f"{value:.{sig - 1}e}".replace("e-0", "e-").replace("e+0", "e")


SCALES = ((1.0, ""), (1e-3, "m"), (1e-6, "\u00b5"), (1e-9, "n"))
"""The SI prefixes :func:`scaled` writes: none, milli, micro, nano."""


def scaled(value: Any, unit: str, sig: int = 3) -> str:
    """Return ``value`` (in ``unit``, SI) to ``sig`` significant digits with the SI prefix that puts
    it between 1 and 1000: ``0.00164`` s is ``1.64 ms``, ``0.000185`` s ``185 µs`` (in µs alone a PSO
    call's 0.99 s printed as ``990000``, digits no one measured). Zero, a missing value and values
    of 1000 ``unit`` or more print without a prefix."""
    if is_missing(value) or isinstance(value, str) or not float(value) or not math.isfinite(float(value)):
        return number(value, sig=sig, unit=f" {unit}")
    rounded = float(f"{float(value):.{sig - 1}e}")  # the prefix of the value as printed: 0.0009996 s, 1.00 ms
    factor, prefix = next(((f, x) for f, x in SCALES if abs(rounded) >= f), SCALES[-1])
    return f"{number(rounded / factor, sig=sig)} {prefix}{unit}"


def p_value(p: Any) -> str:
    """Return a p-value by the one rule: two significant digits, written out from 0.001 up
    (``0.047``, ``0.50``, ``1.0``) and in scientific form below (``2.9e-16``); an underflow ``< 2e-308``."""
    if is_missing(p) or isinstance(p, str):
        return number(p)
    if float(p) >= 1e-3:
        return number(p, sig=2)
    return _scientific(float(p), 2) if p > 0 else f"< {sys.float_info.min:.0e}"


def is_p_value(name: str) -> bool:
    """Whether the column ``name`` holds p-values: ``p``, ``p_<test>`` or ``<test>_p`` (docs/records.md)."""
    return name == "p" or name.startswith("p_") or name.endswith("_p")


def decimals(values: Any, sig: int = 3) -> int | str | None:
    """The one rounding of a column or a range: no decimals for whole numbers; :data:`EACH` value
    alone when its non-zero magnitudes lie more than two decades apart (one rounding would print the
    small ones as 0); else those giving its largest finite magnitude ``sig`` significant digits and
    its smallest non-zero one at least two (a column of 11.96 and 0.709 prints 0.71, not 0.7), the
    same for every value (None: no number)."""
    values = [abs(float(v)) for v in values if isinstance(v, numbers.Real) and not isinstance(v, bool)
              and not is_missing(v) and math.isfinite(float(v))]
    if not values or all(v.is_integer() for v in values):
        return 0 if values else None
    sizes = [v for v in values if v]
    if min(sizes) < 1e-2 * max(sizes):
        return EACH
    exponents = [math.floor(math.log10(v)) for v in sizes]
    return max(0, sig - 1 - max(exponents), 1 - min(exponents))


def interval(low: Any, high: Any, digits: int | None = None, *, sig: int | None = None) -> str:
    """Return ``"low–high"`` (``"low to high"`` when a bound is negative), each rounded once."""
    if is_missing(low) or is_missing(high):
        return MISSING
    sep = " to " if float(low) < 0 or float(high) < 0 else DASH
    return f"{number(low, digits, sig=sig)}{sep}{number(high, digits, sig=sig)}"


def span(values: Any, unit: str = "", digits: int | None = None) -> str:
    """Return the range ``"min–max"`` of ``values`` then ``unit`` (one value when both ends print alike):
    both ends at ``digits`` decimals if given (a percentage's 1), else rounded as a table column of
    ``values`` (:func:`decimals`); missing values are left out."""
    ends = [float(v) for v in values if not is_missing(v)]
    if not ends:
        return MISSING
    digits = decimals(ends) if digits is None else digits
    first, last = (number(v, digits) for v in (min(ends), max(ends)))
    return (first if first == last else interval(min(ends), max(ends), digits)) + unit


def estimate(value: Any, low: Any = None, high: Any = None, digits: int | None = None, *,
             sig: int | None = None, unit: str = "") -> str:
    """Return ``"value (low–high)"`` as the paper's tables print it (the value without interval);
    ``unit`` after the value and after the interval, as a sentence prints it (``5.7% (3.6–8.9%)``)."""
    text = number(value, digits, sig=sig, unit=unit)
    if is_missing(value) or is_missing(low) or is_missing(high):
        return text
    return f"{text} ({interval(low, high, digits, sig=sig)}{unit})"


def paper_text(paper: Any, digits: int | None = None) -> str:
    """Return the paper's value as printed: a number, a range ``lo–hi``, a one-sided bound (a range
    with a None end: ``≤ hi``, ``≥ lo``), yes/no or its text; a value the paper marks approximate
    (:class:`~graspcampaign.campaign.paper.Approximate`) with its own digits after ``≈`` (``≈ 86``)."""
    if isinstance(paper, Approximate):
        return f"≈ {number(float(paper))}"
    if not isinstance(paper, tuple | list):
        return number(paper, digits)
    if is_missing(paper[0]) or is_missing(paper[1]):
        return f"≤ {number(paper[1], digits)}" if is_missing(paper[0]) else f"≥ {number(paper[0], digits)}"
    return interval(paper[0], paper[1], digits)


def differing(frame: Any) -> tuple[int, int]:
    """How many rows of a verdict table (its ``differs`` column) differ from the paper's, of how many
    were compared (a row not compared, ``differs`` None, is no difference): the count a finding gives."""
    return int(frame["differs"].eq(True).sum()), int(frame["differs"].notna().sum())


class Verdict(NamedTuple):
    """How ours stands against the paper's value (:func:`verdict`): whether it differs (None: not
    compared), the short answer ``word`` ("differs by +0.3", "consistent (+0.02)") and why, if said."""

    differs: bool | None
    word: str
    why: str = ""

    @property
    def words(self) -> str:
        return f"{self.word}: {self.why}" if self.why else self.word


def verdict(ours: Any, paper: Any, *, low: Any = None, high: Any = None, digits: int = 1,
            unit: str = "", ratio: str = "", commanded: str = "", because: str = "",
            pinned: str = "", bound: str = "the paper's target") -> Verdict:
    """Say how ours stands against the paper's value, the one rule: a range agrees
    inside it and a one-sided bound (a range with a None end) when ours keeps it: "within" an upper one
    (``(None, hi)``: at most hi), "meets" a lower one (``(lo, None)``: at least lo)
    (ours rounded to ``digits``, as printed; ours ``inf`` lies above every range); a word when equal;
    ours with a 95 % interval when it holds the paper's value, or its nearest end is within one unit
    of the paper's last printed digit (``10**-digits``), as a point value is (so a zero-width interval
    reads as the value).
    ``unit`` is the values' unit: a value or range of percentages prints ``%``, a difference of two
    percentages ``pp``. ``ratio`` (e.g. "faster"): the
    values are ratios, said as ratios ("ours 9.17× faster, the paper's 17000× (1850 times ours)"; no ratio
    of the two when either is 0, compared by their difference alone).
    ``commanded``: ours is the run's own command, reached by construction (the words say how), so it
    is not compared. ``because``: why ours is not compared (the words are that reason).
    ``pinned``: ours is a CV over runs that all ended on a search bound, at these values (as printed):
    the words add that it measures the bound. ``bound``: what a one-sided bound is and whose, in its words
    ("the paper's bound" for a limit the paper observed; "this tool's speed target", one not the paper's)."""
    if because:
        return Verdict(None, because)
    if pinned:
        judged = verdict(ours, paper, low=low, high=high, digits=digits, unit=unit, ratio=ratio,
                         commanded=commanded, bound=bound)
        return Verdict(judged.differs, f"{judged.words}; on its search bound ({pinned}) in every run, "
                       f"so CV {number(ours, digits)}{unit.strip()} measures the bound, not repeatability")
    if commanded:
        return Verdict(None, "commanded, not a result", commanded)
    if is_missing(paper):
        return Verdict(None, "no paper value")
    if is_missing(ours):
        return Verdict(None, "not computed")
    unit = unit.strip()
    if isinstance(paper, tuple | list):
        bounded = not is_missing(paper[0]) and not is_missing(paper[1])
        lo = float(paper[0]) if not is_missing(paper[0]) else -math.inf
        hi = float(paper[1]) if not is_missing(paper[1]) else math.inf
        # an upper bound is kept within ("within the paper's design limit ≤ 1.00 mm"), a lower one met
        what, word = ("the paper's range", "inside") if bounded else (
            bound, "within" if is_missing(paper[0]) else "meets")
        where = f"{what} {paper_text(paper, digits)}{'' if unit in ('', '%', '°') else ' '}{unit}"
        if lo <= float(ours) <= hi:
            return Verdict(False, f"{word} {where}")
        if lo <= round(float(ours), digits) <= hi:  # ours as printed (0.4252 -> 0.43 in 0.43-0.48)
            return Verdict(False, f"{word} {where} at its printed precision")
        return Verdict(True, "differs", f"{'below' if float(ours) < lo else 'above'} {where}")
    if isinstance(paper, bool | str) or isinstance(ours, bool | str):
        if str(ours) == str(paper):
            return Verdict(False, f"as in the paper ({number(paper)})")
        return Verdict(True, "differs", f"the paper reports {number(paper)}, ours is {number(ours)}")
    unit = "pp" if unit == "%" else unit
    nearest = float(ours) if is_missing(low) or is_missing(high) else \
        min(max(float(paper), float(low)), float(high))
    gap, step = float(ours) - float(paper), 10.0 ** -digits
    differs = abs(nearest - float(paper)) >= step
    tol = number(step, digits, unit=f" {unit}" if unit else "")
    # a difference printed as the tolerance but not equal to it gets one more digit (−0.012, not −0.01)
    fine = differs and number(abs(gap), digits) == number(step, digits) and not math.isclose(abs(gap), step)
    diff = number(gap, digits + 1 if fine else digits, signed=True, unit=f" {unit}" if unit else "")
    if not is_missing(low) and not is_missing(high):
        if float(low) <= float(paper) <= float(high):
            return Verdict(False, f"consistent ({diff})", "paper inside our 95% CI")
        if not differs:  # e.g. 1/3 in every seed against the paper's 0.33
            return Verdict(False, f"consistent ({diff})",
                           f"paper within one printed digit ({tol}) of our 95% CI")
        return Verdict(True, f"differs by {diff}", "paper outside our 95% CI")
    if ratio:
        zero = "ours" if not float(ours) else "the paper's" if not float(paper) else ""
        times = (f"{number(float(paper) / float(ours), sig=3)} times ours" if not zero
                 else f"no ratio: {zero} is 0")
        return Verdict(differs, "differs" if differs else "as in the paper",
                       f"ours {number(ours, sig=3)}× {ratio}, the paper's {number(paper)}× ({times})")
    if differs:
        return Verdict(True, f"differs by {diff}")
    if round(float(ours), digits) == round(float(paper), digits):
        return Verdict(False, "matches as printed")
    return Verdict(False, "matches", f"within one printed digit ({tol}) of the paper's value")
