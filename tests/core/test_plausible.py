"""The plausible ranges read one way by their two readers: ``PlausibleRange.contains`` (``plan``)
and the campaign schema's ``check_value`` on ``meta()`` (study configs). Mutation round 6."""

from __future__ import annotations

import math

import pytest

from graspcampaign.campaign.schema import check_value
from graspcampaign.core.plausible import OBJECT_SIZE_MM, PLAUSIBLE
from graspcampaign.errors import ConfigError

RANGES = {**PLAUSIBLE, "object_size_mm": OBJECT_SIZE_MM}


def _schema_accepts(rng, value):
    try:
        check_value("x", value, rng.meta())
    except ConfigError:
        return False
    return True


@pytest.mark.parametrize("name", RANGES)
def test_both_readers_agree_at_each_bound_and_just_beyond(name):
    rng = RANGES[name]
    for value in (rng.low, math.nextafter(rng.low, -math.inf), math.nextafter(rng.low, math.inf),
                  rng.high, math.nextafter(rng.high, math.inf), math.nextafter(rng.high, -math.inf)):
        assert rng.contains(value) == _schema_accepts(rng, value), (name, value)
    # the top is in the range, as its text says ("<= 3"); the bottom when the text says ">="
    assert rng.contains(rng.high) and f"<= {rng.high:g}" in rng.text()
    assert rng.contains(rng.low) == (not rng.low_open) == rng.text().startswith(">=")
