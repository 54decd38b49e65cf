"""The one verdict rule at the ends of the intervals it reads: both ends belong to them.

A paper value equal to an end of our 95 % interval is inside it (statsmodels' Wilson interval
gives the ends); ours equal to an end of the paper's range is inside that range, whatever its
printed precision.
"""

from __future__ import annotations

from hypothesis import given, settings
from hypothesis import strategies as st
from statsmodels.stats.proportion import proportion_confint

from graspcampaign.report import format as fmt


@settings(deadline=None)  # values checked, not time: a loaded machine stalls an example
@given(st.integers(1, 99), st.sampled_from([0, 1]))
def test_a_paper_value_at_an_end_of_our_interval_is_inside_it(successes, end):
    low, high = (100 * v for v in proportion_confint(successes, 100, alpha=0.05, method="wilson"))
    paper = (low, high)[end]
    judged = fmt.verdict(successes, paper, low=low, high=high, unit="%")
    assert judged.differs is False
    assert judged.words.endswith("paper inside our 95% CI")


@settings(deadline=None)  # values checked, not time: a loaded machine stalls an example
@given(st.floats(0.1, 0.9), st.floats(1e-6, 1e-3), st.sampled_from([0, 1]))
def test_ours_at_an_end_of_the_paper_range_is_inside_it(low, width, end):
    paper = (low, low + width)
    judged = fmt.verdict(paper[end], paper, digits=1)
    assert judged.differs is False
    assert judged.words == f"inside the paper's range {fmt.paper_text(paper, 1)}"


def test_a_paper_value_marked_approximate_prints_as_the_paper_prints_it_and_is_judged_as_before():
    """Table 1's "∼86%" printed as "86.0", a digit the paper never gave: it prints "≈ 86"; the verdict
    is the one of the plain number (the paper's 86 against our Wilson interval 11.7–16.7)."""
    from graspcampaign.campaign.paper import Approximate

    assert fmt.paper_text(Approximate(86.0), 1) == "≈ 86" and fmt.paper_text(86.0, 1) == "86.0"
    assert fmt.paper_text(Approximate(0.5), 3) == "≈ 0.5"
    judged = fmt.verdict(14.1, Approximate(86.0), low=11.7, high=16.7, unit="%")
    assert judged == fmt.verdict(14.1, 86.0, low=11.7, high=16.7, unit="%")
    assert judged.words == "differs by −71.9 pp: paper outside our 95% CI"  # 14.1 − 86, by hand
