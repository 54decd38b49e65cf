"""Records -> tables: executed trials, rates with their reasons, McNemar pairing, design limit."""

from __future__ import annotations

import math

import numpy as np
import pandas as pd
import pytest
from hypothesis import given
from hypothesis import strategies as st
from statsmodels.stats.proportion import proportion_confint

from graspcampaign.analysis import records as rec


def test_preparations_read_by_body_whatever_order_they_were_stored_in():
    """A preparation computed again is stored after the others: read in stored order, a mean of
    three identifications differed in its last digits (0.8748875612767799 against
    0.87488756127678, a report table) from the run that stored them in one go."""
    values = [0.6427790385687973, 0.8301810361062393, 1.1516975690553032]
    first = pd.DataFrame({"body_id": ["a1", "b2", "c3"], "b": values})
    again = first.iloc[[1, 2, 0]]  # a1's computed again: stored last
    assert sum(again["b"]) != sum(first["b"])  # the order a sum is taken in shows
    for frame in (first, again):
        ordered = rec.in_design_order(frame)
        assert ordered["body_id"].tolist() == ["a1", "b2", "c3"]
        assert ordered["b"].mean() == first["b"].mean()


def test_executed_drops_errors_and_aborted_attempts():
    records = pd.DataFrame({"status": ["ok", "ok", "error", "ok"],
                            "aborted": [False, True, False, None],
                            "success": [True, None, None, pd.NA]})
    ok = rec.executed(records)
    assert len(ok) == 2 and ok["success"].tolist() == [True, False]
    assert rec.status_counts(records) == {"executed": 2, "error": 1, "aborted": 1, "other": 0}


def test_rate_table_wilson_and_the_reasons_it_gives():
    records = pd.DataFrame({"status": "ok", "planner": ["a"] * 10 + ["b"] * 3,
                            "shape": ["s1"] * 5 + ["s2"] * 5 + ["s1"] * 3,
                            "success": [True] * 7 + [False] * 3 + [True, False, False]})
    records = pd.concat([records, pd.DataFrame({"status": ["error"], "planner": ["c"],
                                                "shape": ["s1"]})], ignore_index=True)
    table = rec.rate_table(records, ["planner"], cluster="shape", seed=1, n_resamples=500)
    table = table.set_index("planner")
    low, high = proportion_confint(7, 10, method="wilson")  # statsmodels reference
    assert table.loc["a", ["n", "successes", "rate_pct"]].tolist() == [10, 7, 70.0]
    assert table.loc["a", "wilson_low_pct"] == pytest.approx(100 * low)
    assert table.loc["a", "wilson_high_pct"] == pytest.approx(100 * high)
    assert table.loc["a", "n_clusters"] == 2 and table.loc["a", "bootstrap_why"] == ""
    assert math.isnan(table.loc["b", "bootstrap_low_pct"])
    assert table.loc["b", "bootstrap_why"] == "needs \u2265 2 shape values, has 1"
    assert (table.loc["c", "n"], table.loc["c", "n_error"]) == (0, 1)
    assert table.loc["c", "rate_why"] == "no executed trial"


def test_rate_without_an_outcome_column_says_so():
    records = pd.DataFrame({"status": ["error", "error"], "planner": ["a", "a"]})
    table = rec.rate_table(records, ["planner"])
    assert table["rate_why"].tolist() == ["no executed trial"]
    with pytest.raises(ValueError, match="no executed trial"):
        rec.rate(records)


def test_mcnemar_pairs_occurrences_and_skips_errors():
    # scene s1 has two occurrences per planner; scene s3 misses its baseline (errored)
    records = pd.DataFrame({
        "scene_id": ["s1", "s1", "s1", "s1", "s2", "s2", "s3", "s3"],
        "trial_index": range(8),
        "planner": ["a", "b", "a", "b", "a", "b", "a", "b"],
        "status": ["ok"] * 7 + ["error"],
        "success": [True, False, True, True, False, True, True, None]})
    row = rec.mcnemar_table(records, "a", ["b"]).iloc[0]
    assert (row["pairs"], row["reference_only"], row["compared_only"], row["unpaired"]) == \
        (3, 1, 1, 1)
    assert row["chi2_cc"] == 0.0 and row["p_exact"] == 1.0


def test_mcnemar_without_a_discordant_pair_has_no_p():
    """Every pair concordant: no test, so no statistic and no p (was p = 1.0 beside "undefined")."""
    records = pd.DataFrame({"scene_id": ["s1", "s1", "s2", "s2"], "trial_index": range(4),
                            "planner": ["a", "b"] * 2, "status": "ok", "success": [True, True, False, False]})
    row = rec.mcnemar_table(records, "a", ["b"]).iloc[0]
    assert row["pairs"] == 2 and row["test_why"]
    assert all(math.isnan(row[c]) for c in ("chi2_cc", "p_chi2", "p_exact", "odds_ratio"))


def test_design_limit_counts_exceedances_strictly():
    d = np.array([0.2, 0.9, 1.0, 1.01, 5.0])
    records = pd.DataFrame({"status": "ok", "planner": "a", "delta_max_mm": d,
                            "success": [True, True, False, True, False]})
    row = rec.design_limit_table(records, ["planner"], radius_mm=5.0).iloc[0]
    assert (row["exceeds"], row["successes_exceeding"]) == (2, 1)  # 1.0 is not above 1 mm
    assert row["delta_max_median_mm"] == 1.0


def test_gate_table_counts_the_successes_the_validity_gate_removed():
    # 6 executed trials of planner a: 4 pass the checks, 1 of them with a contact deeper than r
    records = pd.DataFrame({"status": ["ok"] * 7 + ["error"], "planner": ["a"] * 6 + ["b", "a"],
                            "success_unbounded": [True, True, True, True, False, False, False, None],
                            "valid_geometry": [True, True, False, True, False, True, True, None],
                            "success": [True, True, False, True, False, False, False, None]})
    table = rec.gate_table(records, ["planner"]).set_index("planner")
    assert table.loc["a", ["n", "success_unbounded", "removed", "success", "invalid_geometry"]
                     ].tolist() == [6, 4, 1, 3, 2]
    low, high = proportion_confint(1, 4, method="wilson")  # statsmodels reference
    assert table.loc["a", ["removed_pct", "removed_low_pct", "removed_high_pct"]].tolist() == \
        pytest.approx([25.0, 100 * low, 100 * high])
    assert table.loc["b", "removed_why"] == "no success without the gate"
    with pytest.raises(KeyError, match="success_unbounded"):
        rec.gate_table(records.drop(columns="success_unbounded"), ["planner"])


def test_at_bound_reads_booleans_or_the_comma_joined_names():
    booleans = pd.DataFrame({"at_bound_n": [True, None, False]})
    assert rec.at_bound(booleans, "n_exp").tolist() == [True, False, False]  # n_exp is n
    joined = pd.DataFrame({"pso_at_bound": ["lambda1,n", "", None, "lambda2"]})
    assert rec.at_bound(joined, "lambda1").tolist() == [True, False, False, False]
    assert rec.at_bound(joined, "n").tolist() == [True, False, False, False]


@given(st.lists(st.tuples(st.sampled_from(["a", "b", None]), st.sampled_from([0.1, 0.3, math.nan]),
                          st.integers(0, 2)), max_size=40),
       st.sampled_from([["planner"], ["mu"], ["planner", "mu"], ["mu", "seed"]]))
def test_groups_partition_the_rows_with_a_complete_key(rows, by):
    """Each group holds exactly the rows whose key columns equal its key, in record order; a row
    with a missing key value is in no group (as NaN equals nothing); no key repeats."""
    frame = pd.DataFrame(rows, columns=["planner", "mu", "seed"]).assign(row=lambda f: range(len(f)))
    seen, keys = [], []
    for key, g in rec.groups(frame, by):
        assert all(g[c].eq(v).all() for c, v in key.items())
        assert g["row"].is_monotonic_increasing
        seen += g["row"].tolist()
        keys.append(tuple(key.values()))
    complete = frame[by].notna().all(axis=1)
    assert sorted(seen) == frame.loc[complete, "row"].tolist() and len(set(keys)) == len(keys)


def test_design_limit_counts_depths_beyond_the_fingertip_radius_apart():
    # 860 m, 85 km: a fingertip of r = 5 mm buried that deep is no contact (issue 13)
    d = np.array([0.4, 2.0, 5.0, 8.6e5, 8.53e7])
    records = pd.DataFrame({"status": "ok", "planner": ["a"] * 4 + ["b"], "delta_max_mm": d,
                            "success": [True, True, False, False, False]})
    table = rec.design_limit_table(records, ["planner"], radius_mm=5.0).set_index("planner")
    assert table.loc["a", ["exceeds", "beyond_radius"]].tolist() == [3, 1]  # 5.0 is within r
    assert table.loc["a", ["delta_max_median_mm", "delta_max_max_mm"]].tolist() == [2.0, 5.0]
    assert table.loc["a", "delta_max_p95_mm"] == pytest.approx(np.quantile([0.4, 2.0, 5.0], 0.95))
    assert table.loc["b", "beyond_radius"] == 1 and np.isnan(table.loc["b", "delta_max_max_mm"])


def test_failure_checks_show_geometry_for_gated_records_even_at_zero():
    records = pd.DataFrame({"status": "ok", "planner": "a", "failure_check": ["none", "residual"],
                            "valid_geometry": [True, True]})
    table = rec.failure_check_table(records, ["planner"])
    assert table[["none", "residual", "torque", "slip", "geometry"]].iloc[0].tolist() == [1, 1, 0, 0, 0]
    # a run recorded before the validity gate has no geometry column
    assert "geometry" not in rec.failure_check_table(records.drop(columns="valid_geometry"), ["planner"])


def test_mcnemar_pairs_by_trial_order_not_row_order():
    """Rows stored out of trial order (shards are read in any order): scene s1's first a (trial 0,
    a success) pairs with its first b (trial 1, a failure), its second a (trial 2, a failure)
    with its second b (trial 3, a success). By hand: a won one pair, b one, none both."""
    records = pd.DataFrame({"scene_id": "s1", "trial_index": [2, 1, 0, 3], "planner": ["a", "b", "a", "b"],
                            "status": "ok", "success": [False, False, True, True]})
    row = rec.mcnemar_table(records, "a", ["b"]).iloc[0]
    assert (row["pairs"], row["reference_only"], row["compared_only"], row["both_success"],
            row["both_fail"]) == (2, 1, 1, 0, 0)


def test_mcnemar_counts_the_concordant_pairs_apart():
    """Three pairs both succeed, one both fail, one a alone (counted by hand)."""
    records = pd.DataFrame({"scene_id": [f"s{i // 2}" for i in range(10)], "trial_index": range(10),
                            "planner": ["a", "b"] * 5, "status": "ok",
                            "success": [True, True] * 3 + [False, False] + [True, False]})
    row = rec.mcnemar_table(records, "a", ["b"]).iloc[0]
    assert (row["both_success"], row["both_fail"], row["reference_only"]) == (3, 1, 1)


def test_a_median_of_two_values_has_no_interval_three_have_one():
    """docs/decisions.md: a median's bootstrap interval from MIN_TRIALS = 3 values on, none below."""
    two, three = rec.median(pd.Series([1.0, 2.0]), seed=0), rec.median(pd.Series([1.0, 2.0, 4.0]), 0)
    assert two.value == 1.5 and math.isnan(two.low) and math.isnan(two.high) and two.n == 2
    assert three.value == 2.0 and three.low <= 2.0 <= three.high


def test_failure_checks_of_a_gated_run_without_the_column_show_geometry():
    """Records whose first failing check reads "geometry" come from the gate even where the
    ``valid_geometry`` column is missing (a trimmed export): the geometry column is shown."""
    records = pd.DataFrame({"status": "ok", "planner": "a", "failure_check": ["none", "geometry"]})
    table = rec.failure_check_table(records, ["planner"])
    assert table[["none", "geometry", "geometry_pct"]].iloc[0].tolist() == [1, 1, 50.0]


def _older_file_records() -> pd.DataFrame:
    """Records as RunStore.read gives a run resumed across the release that added the later readings:
    the first file's rows have no ``success_vertical`` or ``success_unbounded`` (null, read as None), and
    one trial errored (no outcome at all)."""
    import pyarrow as pa

    return pa.table({
        "trial_id": [f"t{i}" for i in range(6)], "planner": ["heuristic"] * 6,
        "status": ["ok"] * 5 + ["error"], "success": [True, False, True, False, True, None],
        "success_vertical": [None, None, True, False, True, None],
        "success_unbounded": [None, None, True, True, True, None]}).to_pandas()


def test_a_reading_an_older_file_lacks_enters_no_rate():
    """Five executed trials, three with an |R_z| reading (two of them pass): the rate is 2 of 3 with
    statsmodels' Wilson interval, not 2 of 5 (a missing reading read as a failure); its n is 3, the
    errored trial counted apart as before. The reading ``success`` is recorded for all five."""
    records = _older_file_records()
    assert records["success_vertical"].isna().sum() == 3  # the frame is what a Parquet null reads as
    row = rec.rate_table(records, ["planner"], outcome="success_vertical").iloc[0]
    low, high = proportion_confint(2, 3, method="wilson")
    assert (row["n"], row["successes"], row["n_error"]) == (3, 2, 1)
    assert [row["rate_pct"], row["wilson_low_pct"], row["wilson_high_pct"]] == pytest.approx(
        [200 / 3, 100 * low, 100 * high])
    one = rec.rate(records, outcome="success_vertical")
    assert (one.n, one.value) == (3, pytest.approx(200 / 3))
    assert rec.rate(records).n == 5  # success: every executed trial has it
    assert rec.executed(records)["success_vertical"].isna().sum() == 2  # kept missing, not False


def test_a_trial_without_the_ungated_reading_is_no_gate_removal():
    """``gate_removed`` (a pass only without the validity gate) of a trial without ``success_unbounded``
    is unknown: Test 2's belief table rate of it is over the three trials read (one removed: t3, which
    passed without the gate and failed with it), where the missing two counted as not removed (1 of 5)."""
    from graspcampaign.analysis import hardware

    records = _older_file_records().assign(outcome="stable", friction_level="natural", object_id="o",
                                           condition="c", repeat=0, aborted=False)
    d = hardware.derive(records.assign(**{c: 1.0 for c in (
        "normal_force_mean_n", "normal_force_pred_mean_n", "deformation_mean_mm", "deformation_pred_mean_mm",
        "g_geo_believed", "g_geo_actual", "mu_s_believed")}))
    assert d["gate_removed"].tolist()[2:] == [False, True, False] and d["gate_removed"][:2].isna().all()
    row = hardware.summary(d, ["planner"], ["gate_removed"]).iloc[0]
    assert (row["n_gate_removed"], row["gate_removed_pct"]) == (3, pytest.approx(100 / 3))
    gate = rec.gate_table(records.assign(valid_geometry=True), ["planner"]).iloc[0]
    assert (gate["n"], gate["success_unbounded"], gate["removed"]) == (5, 3, 1)


def test_a_trial_without_a_geometry_reading_is_not_counted_invalid():
    """``valid_geometry`` came with the validity gate, after ``success``: a trial of an older file has none
    (null, read as None). The gate table counts the one recorded False (t3, counted by hand), where the
    two trials without a reading counted as invalid too (3 of 5); ``executed()`` keeps them missing, so a
    rate of it (Test 2's belief table) is over the three read: 2 of 3, statsmodels' Wilson interval."""
    import pyarrow as pa

    from graspcampaign.analysis import hardware

    records = pa.Table.from_pandas(_older_file_records()).append_column(
        "valid_geometry", pa.array([None, None, True, False, True, None])).to_pandas()
    assert records["valid_geometry"].isna().sum() == 3
    gate = rec.gate_table(records, ["planner"]).iloc[0]
    assert (gate["n"], gate["n_valid_geometry"], gate["invalid_geometry"]) == (5, 3, 1)  # of the 3 read
    assert rec.executed(records)["valid_geometry"].isna().sum() == 2  # kept missing, not False
    row = hardware.summary(rec.executed(records), ["planner"], ["valid_geometry"]).iloc[0]
    low, high = proportion_confint(2, 3, method="wilson")
    assert row["n_valid_geometry"] == 3
    assert [row[f"valid_geometry{end}_pct"] for end in ("", "_low", "_high")] == pytest.approx(
        [200 / 3, 100 * low, 100 * high])
