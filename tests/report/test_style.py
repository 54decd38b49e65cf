"""The tick labels of every figure (report.style.tick)."""

import re

from hypothesis import given
from hypothesis import strategies as st

from graspcampaign.analysis.vocabulary import VOCABULARIES, label
from graspcampaign.report.style import tick

WORDS = st.text(alphabet="abcdefghijklmnopqrstuvwxyz–-()2ε", min_size=1, max_size=14)


@given(st.lists(WORDS, min_size=1, max_size=5))
def test_tick_keeps_every_character_and_wraps_at_nine(words):
    text = " ".join(words)
    wrapped = tick(text)
    assert "".join(wrapped.split()) == "".join(text.split())  # nothing lost, nothing added
    for line in wrapped.split("\n"):  # a line over the width is one word that has no dash to break at
        assert len(line) <= 9 or (" " not in line and not re.search(r"[–-]\w", line)), line


def test_every_planner_label_fits_its_bar():
    """Labels of the vocabulary wrap to lines of at most nine characters or one unbreakable word
    (the Ferrari–Canny label ran into its neighbour in Fig. 18a)."""
    assert tick("Ferrari–Canny ε") == "Ferrari–\nCanny ε"
    for column, values in VOCABULARIES.items():
        for value in values:
            for line in tick(label(column, value)).split("\n"):
                assert len(line) <= 9 or " " not in line, (column, value, line)
