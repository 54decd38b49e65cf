"""Mutation round 9: ``errors.shorten`` at its edges (docs/decisions.md, mutation round 9): the
longest value kept whole, a value's length counted by ``len``, the punctuation and apostrophes
around a value, a quoted value on one line."""

from __future__ import annotations

import pytest

from graspcampaign.errors import LONG_VALUE, shorten

PROSE = " ".join(["word"] * 60)  # 299 characters, no word longer than 4


def _cut(value: str) -> str:
    return f"{value[:60]}... ({len(value)} characters)"


@pytest.mark.parametrize("template", ["key '{}' is unknown.", "path {} is missing.", "no file {}"])
def test_a_value_of_the_longest_length_kept_is_kept_whole_and_one_more_is_cut(template):
    kept, cut = "k" * LONG_VALUE, "c" * (LONG_VALUE + 1)
    assert shorten(template.format(kept)) == template.format(kept)
    assert shorten(template.format(cut)) == template.format(_cut(cut))


def test_the_punctuation_after_a_long_word_stays_outside_its_count():
    """The colon after a path (``PATH: it is too long``) is the sentence's, not the path's: the
    count is the path's own length."""
    path = "/tmp/" + "d" * 295
    assert len(path) == 300
    for after in (":", ";", ",", "."):
        assert shorten(f"file {path}{after} gone") == f"file {_cut(path)}{after} gone"


def test_a_long_word_before_an_apostrophe_is_cut():
    """``'NAME's records``: the quote after the name, followed by a letter, closes no quoted value
    (it is a possessive's), so the name is cut as a word ending at the apostrophe."""
    name = "r" * 300
    assert shorten(f"the run '{name}'s records are gone.") == f"the run '{_cut(name)}'s records are gone."


def test_an_apostrophe_before_a_letter_closes_no_quoted_value():
    """No word of this message is longer than 4 characters and its one quoted value is short: the
    prose from the quote after ``]`` to the apostrophe of "study's" is no value."""
    message = f"override 'mu=[0.3]' is refused: {PROSE} in the study's factors."
    assert shorten(message) == message


def test_a_quoted_value_with_spaces_is_cut_whole():
    """A quoted value holding a long word and more is one value: cut to its start and the length of
    the whole, not the long word's alone."""
    value = "v" * 250 + " and more"
    assert shorten(f"key '{value}' is unknown.") == f"key '{_cut(value)}' is unknown."


def test_a_quoted_value_lies_on_one_line():
    """Two quoted paths on two lines: the prose between them, across the line breaks, is no value."""
    message = f"files '/data/a/' and\n{PROSE}\n'/data/b/' differ."
    assert shorten(message) == message


def test_an_apostrophe_after_a_letter_opens_no_quoted_value():
    """The apostrophe of "run's", then prose longer than a value, then a quoted path (its quote
    followed by ``/``, no letter): the prose between them is no value."""
    message = f"the run's {PROSE} '/data/x' is missing."
    assert shorten(message) == message
