"""Mutation round 9: the quote-aware scans of an override's value (``override_scan``) against Hydra's
own parser and OmegaConf's own reading (docs/decisions.md, mutation round 9): a value of several
quoted strings, a string escaping a line break, numbers with an underscore Hydra reads as numbers,
and the functions of sweeps Hydra calls (its function registry records each call).
"""

from __future__ import annotations

from dataclasses import dataclass

import pytest
from hydra._internal.grammar.functions import Functions
from hydra.core.override_parser.overrides_parser import OverridesParser
from hydra.core.override_parser.types import ChoiceSweep
from omegaconf import OmegaConf

from graspcampaign.campaign.override_scan import (
    SWEEP_FUNCTIONS,
    mapping_keys,
    n_values,
    sweep_function,
    underscored_numbers,
)

PARSER = OverridesParser.create()


def _hydra(value: str):
    """Hydra's value of the override ``x=value`` (a sweep as its ChoiceSweep)."""
    return PARSER.parse_override(f"x={value}").value()


def _elements(value) -> int:
    """The elements Hydra reads in a parsed value, at any depth (a sweep's, a list's, a dict's)."""
    if isinstance(value, ChoiceSweep):
        value = value.list
    if isinstance(value, dict):
        value = list(value.values())
    return sum(map(_elements, value)) if isinstance(value, list) else 1


@pytest.mark.parametrize("value", [
    "'a','b'", "'a,b','c,d'", "\"a\",'b,c',d", "['x','y,z']", "'a','b','c'",
    "'a\\\n,b',c",  # a backslash escapes the line break: the string runs on to its quote
])
def test_the_elements_of_several_quoted_strings_are_hydras(value):
    """The closing quote of one string opens no other: ``'a','b'`` is two values to Hydra (the scan
    restarted at the closing quote read ``,'`` as a string and counted one)."""
    assert n_values(value) == _elements(_hydra(value))


@pytest.mark.parametrize("value", ["{a:'x',b:'y',c:1}", "{a:'p,q',b:\"r\",c:'s'}",
                                   "{k:'a\\\n,b:1',b:2}"])
def test_the_keys_after_several_quoted_values_are_hydras(value):
    assert mapping_keys(value) == list(_hydra(value))


@pytest.mark.parametrize("value", [" {a:1,b:2}", "  {a:[1,2],b:{c:3}}"])
def test_a_mapping_after_spaces_is_one_to_hydra(value):
    """Hydra's grammar skips the spaces before a value: ``x= {a:1}`` is the mapping {a: 1}."""
    assert mapping_keys(value) == list(_hydra(value))


@pytest.mark.parametrize("value", ["{a:sort([2,1]),b:1}", "{a:str(1),b:[1,2],c:3}",
                                   "{k:${oc.select:a,b}:c}", "{k:${oc.select:a,b}:c,j:2}"])
def test_a_call_or_an_interpolation_inside_a_mapping_hides_no_key(value):
    """A call's parentheses and an interpolation's braces are brackets: a comma inside them
    separates no keys (so the colon after ``${oc.select:a,b}``, in the value ``${...}:c``, ends no
    key), and the key after the closing one is the mapping's."""
    assert mapping_keys(value) == list(_hydra(value))


@pytest.mark.parametrize("word", ["1_0", "+1_0", "-0.1_5", "0.1_5", ".5_0", "1_0.", "1e1_0", "1_0e1",
                                  "-1_0e-1_0"])
def test_a_number_hydra_reads_with_its_digits_grouped_is_found(word):
    read = _hydra(word)
    assert isinstance(read, int | float) and not isinstance(read, bool)  # Hydra's reading
    assert underscored_numbers(word) == [word]
    for value in (f"[144,{word}]", f"{{a:{word}}}", f"{{a: {word},b:2}}", f"[{word}, 3]"):
        assert underscored_numbers(value) == [word], value


def test_a_quoted_number_is_text_to_hydra_and_a_number_to_omegaconf():
    """``'1_0'`` unquoted is not scanned (Hydra reads the text '1_0'); ``quoted`` scans it, as a
    key taking a number reads it: OmegaConf's int() turns the text into 10."""

    @dataclass
    class Numbers:
        n: int = 0

    assert _hydra("'1_0'") == "1_0" and _hydra('"1_0"') == "1_0"
    assert underscored_numbers("'1_0'") == [] and underscored_numbers('["1_0",2]') == []
    numbers = OmegaConf.structured(Numbers)
    numbers.n = "1_0"
    assert numbers.n == 10
    assert underscored_numbers("'1_0'", quoted=True) == ["1_0"]
    assert underscored_numbers("[1_0, '2_0']", quoted=True) == ["1_0", "2_0"]
    assert underscored_numbers("[1_0, '2_0']") == ["1_0"]


@pytest.mark.parametrize("value", ["1'a'_0", "[1'x'_5,2]", "1\"b\"_0", "{a:1'q'_0}"])
def test_a_number_found_is_one_typed(value):
    """A refusal names the number as typed: a quoted string is no part of the words beside it, so
    ``1'a'_0`` (a value Hydra's grammar cannot parse, whose parse error it reports) holds no
    ``1_0``. Every word found is a piece of the value as typed."""
    assert all(word in value for word in underscored_numbers(value) + underscored_numbers(value, True))


@pytest.fixture
def hydra_calls(monkeypatch):
    """The functions Hydra's grammar evaluates while parsing, by name."""
    called: list[str] = []
    real = Functions.eval

    def recording(self, func):
        called.append(func.name)
        return real(self, func)

    monkeypatch.setattr(Functions, "eval", recording)
    return called


@pytest.mark.parametrize("value", [
    "shuffle([1,2])", "sort (3)", "str(sort([b,a]))", "str(value=sort([b,a]))", "{a:sort([2,1]),b:1}",
    "{a: shuffle([1,2])}", "[a, interval(0,1)]", "[ sort([1])]", "x,sort([1])", "sort(shuffle([1,2]))",
    # Hydra calls none of them: a quoted string is text, and a name after a space is no call
    "'sort(x)'", "'a, sort(b)'", "x,'y,shuffle(z)'", "{a:'b: sort(c)'}", "b sort([1])", "str(1)", "a_sort",
])
def test_a_function_of_sweeps_is_named_where_hydra_calls_it(hydra_calls, value):
    """``sweep_function`` names a function exactly where Hydra's grammar calls one of
    :data:`SWEEP_FUNCTIONS` (recorded by Hydra's function registry), and none where it calls none."""
    try:
        PARSER.parse_override(f"x={value}")
    except Exception:  # noqa: BLE001  (a value Hydra cannot parse calls nothing)
        pass
    called = [name for name in hydra_calls if name in SWEEP_FUNCTIONS]
    found = sweep_function(value)
    assert (found is None) == (not called), (value, called)
    assert found is None or found in called


def test_every_function_of_sweeps_is_one_hydra_registers():
    """The grammar's sweeps (choice, range, interval, glob) and its functions of sweeps (tag, sort,
    shuffle): every function Hydra registers but its casts (int, float, str, bool)."""
    casts = {"int", "float", "str", "bool"}
    assert sorted(SWEEP_FUNCTIONS) == sorted(set(PARSER.functions.functions) - casts)
