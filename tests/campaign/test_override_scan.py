"""The quote-aware scans of an override's value (``override_scan.n_values``, ``mapping_keys``) against
Hydra's own parser: the values it splits a sweep into and the keys of the mapping it builds. The
scans exist because Hydra's parse keeps only the last of a repeated key and takes long on a huge
sweep; where neither happens they must read a value as Hydra does.
"""

from __future__ import annotations

import pytest
from hydra.core.override_parser.overrides_parser import OverridesParser

from graspcampaign.campaign.override import MAX_OVERRIDE_VALUES, check_overrides
from graspcampaign.campaign.override_scan import mapping_keys, n_values
from graspcampaign.errors import ConfigError

PARSER = OverridesParser.create()

#: Values whose quoted strings hold commas, colons, the other quote and escaped quotes.
SWEEPS = ["a", "a,b", "a,'b,c',d", r"'a\',b',c", r'"a\",b",c', "\"a',b\",c", "x,'y,z'"]
MAPPINGS = ["{a:1}", "{a:1,b:'p,q',c:[1,2]}", r"{a:'x\',y:1',y:2}", r'{a:"x\",y:1",y:2}',
            "{a:\"it's,b:1\",b:2}", "{a:b:c}", "{a:{b:1,c:2},d:[3,4]}", "{ a : 1 , b : [2] }"]


def _hydra(value: str):
    return PARSER.parse_override(f"x={value}")


@pytest.mark.parametrize("value", SWEEPS)
def test_the_values_counted_are_hydras(value):
    parsed = _hydra(value)
    assert n_values(value) == (len(parsed.value().list) if parsed.is_sweep_override() else 1)


@pytest.mark.parametrize("value", MAPPINGS)
def test_the_keys_of_a_mapping_are_hydras(value):
    assert mapping_keys(value) == list(_hydra(value).value())


def test_commas_inside_quoted_strings_do_not_count_toward_the_bound():
    """A sweep of exactly the most values an override holds, one a string holding commas: Hydra
    reads MAX_OVERRIDE_VALUES values, so it is accepted; one more value is refused."""
    value = ",".join(["1"] * (MAX_OVERRIDE_VALUES - 1) + ["'a,b,c'"])
    assert len(_hydra(value).value().list) == MAX_OVERRIDE_VALUES
    check_overrides([f"seeds={value}"])
    with pytest.raises(ConfigError, match=rf"holds {MAX_OVERRIDE_VALUES + 1:,} comma-separated values"):
        check_overrides([f"seeds=0,{value}"])


def test_a_key_after_an_escaped_quote_is_no_repeat():
    """``{a:'x\\',y:1',y:2}``: Hydra reads keys a and y (the first y is inside a's string)."""
    check_overrides([r"factors={a:'x\',y:1',y:2}"])


@pytest.mark.parametrize("item", ["pso.enabled=true", "model=default", "nodes=[144,0390]",
                                  "seeds=010", "pso.enabled=2"])
def test_check_overrides_parses_each_override_once(monkeypatch, item):
    # the value and its leading zero are read from one parse (they were two: a parse takes a time
    # quadratic in the values, up to ~1 s for the 2,000 an override may hold)
    calls = []
    real = OverridesParser.parse_overrides
    monkeypatch.setattr(OverridesParser, "parse_overrides",
                        lambda self, items: calls.append(items) or real(self, items))
    try:
        check_overrides([item])
    except ConfigError:  # the refusals of a leading zero and a bool are tests/cli's
        pass
    assert calls == [[item]]
