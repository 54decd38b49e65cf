"""The bound of every number in a ``paper:`` block, declared once per kind of quantity.

A paper dataclass field is typed with one of the kinds below (``class_balance_pct: Pct``), never
a bare ``float`` or ``int`` (tests/campaign/test_paper_bounds.py walks every field); a tuple of
two is a closed range of one kind, low end first (``PctRange``). ``campaign.paper._convert``
checks each value as given against its kind when a study is composed and refuses one outside it
with the sentence the campaign schema uses for its own out-of-range values
(:func:`graspcampaign.campaign.schema.check_value`): ``paper.class_balance_pct = 250 is out of
range; allowed: >= 0 and <= 100 (a percentage).`` The kind of each field follows what the paper
says the quantity is, not its name (docs/decisions.md, "Every paper value has a bound of its
kind").
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import Annotated, Any

from graspcampaign.core.plausible import PLAUSIBLE
from graspcampaign.errors import ConfigError


@dataclass(frozen=True)
class Bound:
    """Where a paper number may lie: validation metadata for ``schema.check_value`` (``gt``/``ge``,
    ``le``) and ``why``, what the quantity is, said in the refusal. Every bound refuses inf and nan."""

    meta: tuple[tuple[str, float], ...]
    why: str

    def check(self, given: Any, where: str) -> None:
        """Refuse ``given`` (the value as the file or override gives it) outside the bound.

        Raises
        ------
        ConfigError
            ``<where> = <given> is out of range; allowed: <bound> (<why>).``
        """
        from graspcampaign.campaign.schema import check_value

        check_value(where, given, {**dict(self.meta), "why": self.why})


def Between(low: float, high: float, why: str) -> Bound:  # noqa: N802 (reads as a type)
    """The closed interval [``low``, ``high``]."""
    return Bound((("ge", low), ("le", high)), why)


def AtLeast(low: float, why: str) -> Bound:  # noqa: N802
    """``low`` or more."""
    return Bound((("ge", low),), why)


def Above(low: float, why: str) -> Bound:  # noqa: N802
    """More than ``low``."""
    return Bound((("gt", low),), why)


def AtMost(high: float, why: str) -> Bound:  # noqa: N802
    """``high`` or less."""
    return Bound((("le", high),), why)


def Finite(why: str) -> Bound:  # noqa: N802
    """Any finite number (a signed quantity: its sign is part of what the paper reports)."""
    return Bound((), why)


@dataclass(frozen=True)
class Ordered:
    """A range the paper prints as "low-high": its low end may not lie above its high end."""

    def check(self, given: Any, where: str) -> None:
        """Refuse a range written high end first (``given``: the pair as the file or override gives
        it, its items checked already).

        Raises
        ------
        ConfigError
            ``<where> = [high, low] runs high to low; write a range low end first: [low, high].``
        """
        low, high = given
        if low > high:
            raise ConfigError(f"{where} = [{low!r}, {high!r}] runs high to low; write a range low "
                              f"end first: [{high!r}, {low!r}].")


ORDERED = Ordered()

# the kinds of quantity the paper reports (docs/decisions.md, "Every paper value has a bound of its kind")
Pct = Annotated[float, Between(0, 100, "a percentage")]
PctError = Annotated[float, AtLeast(0, "an error or a coefficient of variation in percent, which "
                                       "may exceed 100")]
PctOfWeight = Annotated[float, AtLeast(0, "a load in percent of the object's weight, which may "
                                          "exceed 100")]
Points = Annotated[float, Between(0, 100, "a width in percentage points")]
PointsDiff = Annotated[float, Between(-100, 100, "a difference of two percentages, in points")]
Score = Annotated[float, Between(0, 1, "a classifier's accuracy, precision, recall, F1 or AUC, "
                                       "from 0 to 1")]
Fraction = Annotated[float, Between(0, 1, "a part of a whole, from 0 to 1")]
PValue = Annotated[float, Between(0, 1, "a p-value")]
R2 = Annotated[float, AtMost(1, "a coefficient of determination, at most 1; below 0 when a fit "
                                "predicts worse than the mean")]
Friction = Annotated[float, Between(0, PLAUSIBLE["mu"].high, f"a friction coefficient: "
                                                             f"{PLAUSIBLE['mu'].why}")]
AngleDeg = Annotated[float, Between(0, 180, "an angle in degrees between two directions")]
Positive = Annotated[float, Above(0, "a time, force, torque, length, mass, stiffness, ratio or "
                                     "identified model coefficient, all positive")]
NonNegative = Annotated[float, AtLeast(0, "a magnitude: a residual, deviation, slip, energy, "
                                          "spread or test statistic")]
Signed = Annotated[float, Finite("a signed quantity: a margin, bias, slope or coefficient")]
Count = Annotated[int, AtLeast(0, "a count")]

PctRange = Annotated[tuple[Pct, Pct], ORDERED]
PctErrorRange = Annotated[tuple[PctError, PctError], ORDERED]
PositiveRange = Annotated[tuple[Positive, Positive], ORDERED]
NonNegativeRange = Annotated[tuple[NonNegative, NonNegative], ORDERED]
CountRange = Annotated[tuple[Count, Count], ORDERED]
