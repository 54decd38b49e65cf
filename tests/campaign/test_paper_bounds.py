"""Every number of every paper block has a bound of its kind; a value is taken iff it lies in it;
every shipped study file composes with its paper values in bounds."""

from __future__ import annotations

import dataclasses
import math
import types
import typing

import pytest
from hypothesis import given
from hypothesis import strategies as st

from graspcampaign.campaign import paper_bounds as pb
from graspcampaign.campaign.compose import compose_study, list_studies
from graspcampaign.campaign.paper import _convert, paper_types
from graspcampaign.errors import ConfigError

#: each kind of quantity and the interval the paper's quantity of that kind lives in, written here
#: from what the quantity is (low, high, low end excluded): a percentage 0-100, a score 0-1, ...
KINDS = {
    "Pct": (0.0, 100.0, False), "PctError": (0.0, math.inf, False),
    "PctOfWeight": (0.0, math.inf, False), "Points": (0.0, 100.0, False),
    "PointsDiff": (-100.0, 100.0, False), "Score": (0.0, 1.0, False), "Fraction": (0.0, 1.0, False),
    "PValue": (0.0, 1.0, False), "R2": (-math.inf, 1.0, False), "Friction": (0.0, 3.0, False),
    "AngleDeg": (0.0, 180.0, False), "Positive": (0.0, math.inf, True),
    "NonNegative": (0.0, math.inf, False), "Signed": (-math.inf, math.inf, False),
}
finite = st.floats(allow_nan=False, allow_infinity=False, min_value=-1e6, max_value=1e6)
edges = st.sampled_from([-100.0, -1.0, -1e-9, 0.0, 1e-9, 1.0, 3.0, 3.0000001, 100.0, 100.0001, 180.0, 181.0])


def taken(typ, value) -> bool:
    try:
        _convert(typ, value, "paper.x")
    except ConfigError:
        return False
    return True


def test_every_kind_is_declared_once_and_listed_here():
    declared = {name for name, v in vars(pb).items()
                if typing.get_origin(v) is typing.Annotated and typing.get_args(v)[0] is float}
    assert declared == set(KINDS)


def near(*ends: float) -> st.SearchStrategy[float]:
    """Each finite end, and the floats just either side of it (nothing for a kind with no end)."""
    points = [x for end in ends if math.isfinite(end)
              for x in (math.nextafter(end, -math.inf), end, math.nextafter(end, math.inf))]
    return st.sampled_from(points) if points else st.nothing()


@pytest.mark.parametrize("kind", sorted(KINDS))
@given(data=st.data())
def test_a_value_is_taken_iff_it_lies_in_its_kind(kind, data):
    low, high, open_low = KINDS[kind]
    value = data.draw(finite | edges | near(low, high))
    inside = (value > low if open_low else value >= low) and value <= high
    assert taken(getattr(pb, kind), value) is inside


@given(kind=st.sampled_from(sorted(KINDS)), value=st.sampled_from([math.inf, -math.inf, math.nan]))
def test_no_kind_takes_inf_or_nan(kind, value):
    assert not taken(getattr(pb, kind), value)


@given(value=st.integers(-10**6, 10**6) | st.sampled_from([-1, 0, 1]))
def test_a_count_is_taken_iff_it_is_zero_or_more(value):
    assert taken(pb.Count, value) is (value >= 0)


@given(low=finite, width=st.floats(0, 1e6), value=finite | edges)
def test_a_bound_between_two_numbers_takes_what_lies_between(low, width, value):
    high = low + width
    bound = typing.Annotated[float, pb.Between(low, high, "w")]
    assert taken(bound, value) is (low <= value <= high)
    assert taken(typing.Annotated[float, pb.Above(low, "w")], value) is (value > low)
    assert taken(typing.Annotated[float, pb.AtLeast(low, "w")], value) is (value >= low)
    assert taken(typing.Annotated[float, pb.AtMost(high, "w")], value) is (value <= high)


@given(a=st.floats(0, 100), b=st.floats(0, 100))
def test_a_range_is_taken_iff_it_is_written_low_end_first(a, b):
    assert taken(pb.PctRange, [a, b]) is (a <= b)


def test_a_refusal_names_the_key_the_value_as_given_and_the_bound():
    with pytest.raises(ConfigError, match=r"^paper\.x = 250 is out of range; allowed: >= 0 and <= 100 "
                                          r"\(a percentage\)\.$"):
        _convert(pb.Pct, 250, "paper.x")
    with pytest.raises(ConfigError, match=r"^paper\.x = \[91, 89\.5\] runs high to low; write a range "
                                          r"low end first: \[89\.5, 91\]\.$"):
        _convert(pb.PctRange, [91, 89.5], "paper.x")
    with pytest.raises(ConfigError, match=r"^paper\.x\[1\] = 101 is out of range; allowed: >= 0 and "):
        _convert(pb.PctRange, [91, 101], "paper.x")  # each end first, then the order
    with pytest.raises(ConfigError, match=r"^paper\.x must be a number; got 'fifty'\.$"):
        _convert(pb.Pct, "fifty", "paper.x")  # the type first, then the bound


def unbounded_numbers(typ, where: str, ordered: bool = False) -> list[str]:
    """The places under the type ``typ`` where a number has no bound (a bare float or int), or a
    pair has no order (a tuple not marked ``Ordered``; ``ordered``: this one is)."""
    if typing.get_origin(typ) is typing.Annotated:
        base, *marks = typing.get_args(typ)
        if any(isinstance(m, pb.Bound) for m in marks):
            return []
        return unbounded_numbers(base, where, any(isinstance(m, pb.Ordered) for m in marks))
    if dataclasses.is_dataclass(typ):
        hints = typing.get_type_hints(typ, include_extras=True)
        return [w for f in dataclasses.fields(typ)
                for w in unbounded_numbers(hints[f.name], f"{typ.__name__}.{f.name}")]
    origin = typing.get_origin(typ)
    if origin in (typing.Union, types.UnionType):
        return [w for a in typing.get_args(typ) if a is not type(None) for w in unbounded_numbers(a, where)]
    if origin is dict:
        return unbounded_numbers(typing.get_args(typ)[1], f"{where}[key]")
    if origin is tuple:
        return ([] if ordered else [f"{where} (a pair with no order)"]) + [
            w for a in typing.get_args(typ) if a is not Ellipsis for w in unbounded_numbers(a, f"{where}[i]")]
    return [where] if typ in (int, float) else []


def test_every_number_of_every_paper_dataclass_has_a_bound():
    """A new field typed ``float`` fails here: it must say which kind of quantity it is."""
    missing = [w for cls in paper_types().values() for w in unbounded_numbers(cls, cls.__name__)]
    assert missing == []


@dataclasses.dataclass(frozen=True)
class Nested:
    ok: pb.Pct
    bare: float
    bare_dict: dict[str, int]
    bare_range: tuple[pb.Pct, pb.Pct]
    optional: float | None = None


@dataclasses.dataclass(frozen=True)
class Outer:
    inner: Nested
    fine: pb.CountRange


def test_the_walk_finds_a_field_without_a_bound():
    assert unbounded_numbers(Outer, "Outer") == [
        "Nested.bare", "Nested.bare_dict[key]", "Nested.bare_range (a pair with no order)",
        "Nested.optional"]


@pytest.mark.parametrize("study", list_studies())
def test_every_shipped_study_file_composes_with_its_paper_values_in_bounds(study):
    """Composing checks the paper block (studycheck.check_paper_block) against its bounds."""
    assert compose_study(study, []).name == study
