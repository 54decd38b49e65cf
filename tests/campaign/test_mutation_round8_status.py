"""Mutation round 8: how `show`/`status` write a duration and wrap the paper block, checked by
hand (docs/decisions.md, mutation round 8)."""

from __future__ import annotations

import pytest

from graspcampaign.campaign import status
from graspcampaign.campaign.compose import compose_study


@pytest.mark.parametrize(("seconds", "text"), [
    (0, "0 s"), (0.25, "250 ms"), (119, "119 s"), (120, "2 min"), (7199, "120 min"), (7200, "2.0 h"),
    (9000, "2.5 h"), (5580, "93 min")])
def test_a_duration_is_written_in_the_unit_its_size_calls_for(seconds, text):
    """Seconds below 2 min, minutes below 2 h, then hours to a tenth (9000 s is 2.5 h, not 2 h)."""
    assert status._fmt_seconds(seconds) == text


def test_the_paper_block_wraps_at_about_100_characters_and_never_inside_a_pair():
    """Test 2's paper block: each line at most 100 characters, each key=value pair on one line, and
    no line that could have taken the next pair (it would still fit in 100)."""
    study = compose_study("test2_grasp")
    text = status.design_text(study)
    block = text[text.index("\npaper: ") + 1:].splitlines()
    assert len(block) > 10 and all(len(line) <= 100 for line in block)
    pairs = status._paper_pairs(study.paper)
    joined = " ".join(line.strip() for line in block)
    assert joined == "paper: " + ", ".join(pairs)
    for line, after in zip(block, block[1:], strict=False):
        assert len(line) + 1 + len(after.strip()) > 100  # the next pair did not fit
