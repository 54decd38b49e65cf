"""The tick labels of every figure (report.style.tick) and its rate bars (report.style.bars)."""

import re

import matplotlib as mpl
import numpy as np
from hypothesis import given
from hypothesis import strategies as st
from matplotlib.figure import Figure

from graspcampaign.analysis.vocabulary import VOCABULARIES, label
from graspcampaign.report.style import RC, bars, tick

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


def test_a_missing_rate_draws_no_whisker():
    """A group without a value (a dynamic_check shape whose grasps are all not settled by t_max, or
    not yet run) has no bar and no whisker; its caption says so. The whisker used to be drawn from
    0 to 0 with its caps, a mark at 0% on the axis that read as a measured 0%."""
    with mpl.rc_context(RC):  # the report's caps
        ax = Figure().subplots()
        bars(ax, [0, 1], [50.0, np.nan], [40.0, np.nan], [60.0, np.nan], ["C0", "C1"])
    points = np.vstack([line.get_xydata() for line in ax.lines]
                       + [seg for c in ax.collections for seg in c.get_segments()])
    drawn = points[np.isfinite(points).all(axis=1)]
    assert set(drawn[:, 0].round(1)) <= {-0.1, 0.0, 0.1}, drawn  # only the measured group's whisker
    assert drawn[:, 1].min() == 40.0 and drawn[:, 1].max() == 60.0
