"""Mutation round 9: ``analysis.records``' reading of missing outcomes (``known``, ``flag``) and of
the design order (``in_design_order``), checked against pandas' own semantics and counts by hand
(docs/decisions.md, mutation round 9)."""

from __future__ import annotations

import numpy as np
import pandas as pd

from graspcampaign.analysis import records as rec


def test_a_missing_flag_is_not_set_whatever_its_missing_value():
    """None, NaN and pd.NA in a flag column each count as not set (pandas reads NaN as True and None
    as False in ``astype(bool)``; a NaN read as a set flag would count a missing slip as a slip)."""
    frame = pd.DataFrame({"slip_flag": pd.Series([True, None, np.nan, pd.NA, False], dtype=object)})
    assert bool(pd.Series([np.nan]).astype(bool)[0]) is True  # what pandas alone does
    assert rec.flag(frame, "slip_flag").tolist() == [True, False, False, False, False]
    assert rec.flag(frame, "slip_flag").dtype == bool
    assert int(rec.flag(frame, "slip_flag").sum()) == 1


def test_a_pair_of_outcomes_is_over_the_rows_where_both_are_recorded():
    """Rows 0, 3 have both outcomes; row 1 lacks the second, row 2 the first: two rows, as bool
    (counted by hand: one success of two for each)."""
    frame = pd.DataFrame({"success": pd.Series([True, False, np.nan, False], dtype=object),
                          "predicted_stable": pd.Series([False, None, True, True], dtype=object)})
    both = rec.known(frame, ["success", "predicted_stable"])
    assert both.index.tolist() == [0, 3]
    assert both["success"].tolist() == [True, False] and both["predicted_stable"].tolist() == [False, True]
    assert both["success"].dtype == bool and both["predicted_stable"].dtype == bool
    assert (both["success"] & ~both["predicted_stable"]).tolist() == [True, False]  # bool algebra works


def test_rows_of_one_key_keep_their_stored_order():
    """Many rows share each key (a trial's steps, a preparation computed again and stored after the
    others): sorted by the key, each key's rows stay in the order stored. A table keyed by
    ``trial_index`` alone is sorted on integers, where numpy's quicksort (pandas' default, above 16
    rows) does not keep that order."""
    for key, values in (("trial_index", [3, 1, 2] * 40), ("body_id", ["c3", "a1", "b2"] * 40)):
        frame = pd.DataFrame({key: values, "stored": range(len(values))})
        ordered = rec.in_design_order(frame)
        assert ordered[key].tolist() == sorted(values)
        for _, rows in ordered.groupby(key):
            assert rows["stored"].is_monotonic_increasing, key


def test_trials_are_in_their_design_index_order_not_their_ids():
    """``trial_index`` is the design's order; a trial id is text (t10 sorts before t2) and only
    breaks ties; a table that has both trials and bodies is sorted by its trials. The rows are
    numbered anew: a column computed in that order (a fresh Series) lines up with them, where
    pandas, aligning by label, would give each row the value computed for its stored position."""
    frame = pd.DataFrame({"trial_index": [10, 2, 2, 1], "trial_id": ["t10", "t2b", "t2a", "t1"],
                          "body_id": ["a", "c", "b", "z"]})
    ordered = rec.in_design_order(frame)
    assert ordered["trial_id"].tolist() == ["t1", "t2a", "t2b", "t10"]
    computed = pd.Series(["t1", "t2a", "t2b", "t10"])  # e.g. a label per row, in design order
    assert (ordered.assign(label=computed)["label"] == ordered["trial_id"]).all()
