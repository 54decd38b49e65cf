"""Test 2's shares of the residual flag (§8.1's certified shares in and outside group C, §8.4's counts as
shares) over the trials whose flag is recorded. ``astype(bool)`` read a missing flag held as NaN (a frame
concatenated in pandas) as certified, and one held as None (a Parquet null: a records file written before
the column existed) as not certified, so a trial nobody flagged entered every share."""

from __future__ import annotations

import math

import pandas as pd
import pytest
from statsmodels.stats.proportion import proportion_confint

NAN = float("nan")


def _run():
    """Six trials of the proposed planner and two of the centroid planner, two of them without the flag
    (NaN, None), as ``report.studies.opening.frames`` gives the executed trials (success as bool)."""
    from graspcampaign.campaign.paper import study_paper
    from graspcampaign.report.render import Run

    trials = pd.DataFrame({
        "belief_error": "paper", "planner": ["heuristic"] * 6 + ["centroid"] * 2,
        "group": ["C", "C", "A", "A", "A", "C", "A", "A"],
        "success": [True, False, True, False, True, False, True, True],
        "predicted_stable_residual": pd.Series([True, NAN, True, False, None, True, NAN, False],
                                               dtype=object)})
    run = Run(trials, {}, study_paper("test2_grasp"))
    run.memo("hardware", lambda: trials)
    return run


@pytest.mark.parametrize(("quantity", "k", "n"), [
    ("proposed planner's group C trials certified by the residual flag (paper 71 of 144)", 2, 2),
    ("proposed planner's trials outside group C certified by the residual flag (paper ≈ 90%)", 1, 2),
    ("successes, all planners (paper 1008 of 1755)", 5, 8),
    ("successes labelled unstable by the residual flag (paper 24 of 1008)", 1, 3),
    ("proposed planner's trials certified by the residual flag (paper 677 of 819)", 3, 4),
    ("proposed planner's certified grasps that failed (paper 50 of 677)", 1, 3)])
def test_a_trial_without_the_residual_flag_enters_no_share_of_it(quantity, k, n):
    """Counted by hand from the eight trials above: the flag recorded on t0, t2, t3, t5 of the proposed
    planner (certified t0, t2, t5; t5 failed) and on the second centroid trial (a success, not
    certified). The old code gave 2 of 5 successes labelled unstable (None read as not certified), 4 of
    6 proposed trials certified and 2 of 4 of them failing (NaN read as certified)."""
    from graspcampaign.report.spec import Claims
    from graspcampaign.report.studies.test2 import residual_flag_rows

    row = Claims("flags", "", residual_flag_rows).compute(_run()).set_index("quantity").loc[quantity]
    low, high = proportion_confint(k, n, method="wilson")
    assert row["why"] == "" and row["n"] == n
    assert [row["value"], row["low"], row["high"]] == pytest.approx([100 * k / n, 100 * low, 100 * high])
    assert not math.isnan(row["value"])
