"""``errors.shorten``: a long quoted value is cut to its start and length, never the prose around
it, whose apostrophes are no quotes."""

from __future__ import annotations

import shlex

from hypothesis import given
from hypothesis import strategies as st

from graspcampaign.errors import LONG_VALUE, shorten


def test_a_long_quoted_value_is_cut_to_its_start_and_length():
    value = "x" * 100_000
    assert shorten(f"override 'seed={value}' is not a number.") == (
        "override 'seed=" + "x" * 55 + "... (100005 characters)' is not a number.")


def test_an_apostrophe_in_the_prose_opens_no_quoted_value():
    """The sentence of a damaged run: its prose holds apostrophes ("the run's"), its advice a command
    quoted by shlex; the cut took the 300 characters between the apostrophe and the command's first
    quote, the file's reason with them (found when the resume advice grew its overrides)."""
    command = shlex.join(["graspcampaign", "run", "baseline_grid", "mu=[0.3]", "shape=[sphere,pear]",
                          "--root", "/tmp/results"])
    message = (f"run baseline_grid/default has a damaged file (its account of the run's other parts "
               f"is not one the tool writes: {'trial t-1 has rows in text; ' * 8}); resume the run "
               f"({command}) to quarantine the file and run its trials again.")
    assert len(message.split("run's", 1)[1].split("'mu=")[0]) > LONG_VALUE
    assert shorten(message) == message


@given(st.text(alphabet=st.characters(blacklist_characters="'\n", blacklist_categories=("Cs",)),
               min_size=LONG_VALUE + 1, max_size=400))
def test_a_cut_value_keeps_its_start_and_says_its_length(value):
    assert shorten(f"key '{value}' is unknown.") == (
        f"key '{value[:60]}... ({len(value)} characters)' is unknown.")
