"""Tests of analysis.dynamic_check: confusion matrix, Cohen's kappa, agreement per group.

Outside references: statsmodels (``cohens_kappa``, ``proportion_confint``) on the constructed
tables, scikit-learn's ``cohen_kappa_score`` on the labels, and kappa worked by hand from its
definition (Cohen 1960).
"""

from __future__ import annotations

import numpy as np
import pandas as pd
import pytest
from sklearn.metrics import cohen_kappa_score
from statsmodels.stats.inter_rater import cohens_kappa as sm_kappa
from statsmodels.stats.proportion import proportion_confint

from graspcampaign.analysis import dynamic_check as dc


def _records(both, qs_only, dyn_only, neither, **columns):
    qs = [True] * both + [True] * qs_only + [False] * dyn_only + [False] * neither
    dyn = [True] * both + [False] * qs_only + [True] * dyn_only + [False] * neither
    status = ["stable" if d else "penetration_limit" for d in dyn]  # every grasp determined
    return pd.DataFrame({"qs_success": qs, "success": dyn, "status": "ok", "dynamic_status": status,
                         **columns})


def test_confusion_matrix_orientation_and_error_rows():
    records = _records(20, 5, 10, 15)
    errors = pd.DataFrame({"qs_success": [True, False], "success": [None, None],
                           "status": ["error", "error"], "dynamic_status": [None, None]})
    table = dc.confusion_matrix(pd.concat([records, errors], ignore_index=True))
    # rows: quasi-static success / failure; columns: dynamic success / failure
    np.testing.assert_array_equal(table, [[20, 5], [10, 15]])
    with pytest.raises(KeyError, match="dynamic_check records have no column 'qs_preset_success'"):
        dc.confusion_matrix(records, "qs_preset_success")
    with pytest.raises(KeyError, match="dynamic_check records have no column 'dynamic_status'"):
        dc.confusion_matrix(records.drop(columns="dynamic_status"))


def test_kappa_matches_the_definition_and_statsmodels():
    # By hand: p_o = (20 + 15) / 50 = 0.7; marginals 25/25 (rows) and 30/20 (columns), so
    # p_e = (25 * 30 + 25 * 20) / 50^2 = 0.5 and kappa = (0.7 - 0.5) / (1 - 0.5) = 0.4.
    table = np.array([[20, 5], [10, 15]])
    result = dc.cohens_kappa(table)
    assert result.n == 50
    assert result.observed_agreement == pytest.approx(0.7)
    assert result.expected_agreement == pytest.approx(0.5)
    assert result.kappa == pytest.approx(0.4)
    reference = sm_kappa(table)
    assert result.std_error == pytest.approx(reference.std_kappa)
    assert (result.ci_low, result.ci_high) == pytest.approx((reference.kappa_low,
                                                             reference.kappa_upp))
    # a 90 % interval is narrower by z(0.95) / z(0.975) = 1.6449 / 1.9600
    narrow = dc.cohens_kappa(table, confidence_level=0.90)
    assert narrow.ci_high - narrow.ci_low == pytest.approx(
        (reference.kappa_upp - reference.kappa_low) * 1.6448536 / 1.9599640, rel=1e-6)


@pytest.mark.parametrize("table", [[[7, 0], [0, 3]], [[3, 4], [2, 41]], [[0, 12], [9, 0]]])
def test_kappa_on_other_tables_matches_statsmodels(table):
    result = dc.cohens_kappa(table)
    reference = sm_kappa(np.array(table))
    assert result.kappa == pytest.approx(reference.kappa)
    assert (result.ci_low, result.ci_high) == pytest.approx((reference.kappa_low,
                                                             reference.kappa_upp))


@pytest.mark.filterwarnings("ignore:invalid value:RuntimeWarning")  # statsmodels' z at std 0
def test_kappa_is_undefined_when_both_labels_are_constant():
    # every grasp fails both ways: p_o = p_e = 1, kappa = 0 / 0
    result = dc.cohens_kappa([[0, 0], [0, 40]])
    assert result.observed_agreement == 1.0 and result.expected_agreement == 1.0
    assert np.isnan(result.kappa) and np.isnan(result.ci_low)
    assert result.why == "undefined: every trial has one label in both columns"
    assert dc.cohens_kappa([[0, 0], [0, 0]]).why == "no trial to compare"
    # one label constant, the other not: p_e = p_o, so kappa = 0 (defined)
    one = dc.cohens_kappa([[0, 0], [3, 37]])
    assert one.kappa == pytest.approx(sm_kappa(np.array([[0, 0], [3, 37]])).kappa) == 0.0
    assert one.why == "0 by construction: the quasi-static label is constant"
    assert np.isnan(one.ci_low) and np.isnan(one.std_error)
    with pytest.raises(ValueError, match=r"table must be a \(2, 2\) array of counts, got \[1, 2\]"):
        dc.cohens_kappa([1, 2])


def test_agreement_per_group():
    records = pd.concat([
        _records(20, 5, 10, 15, planner="heuristic", model_preset="firm"),
        _records(0, 0, 0, 40, planner="centroid", model_preset="firm"),
    ], ignore_index=True)
    table = dc.agreement_table(records, by="planner").set_index("planner")
    heuristic, centroid = table.loc["heuristic"], table.loc["centroid"]
    assert heuristic["n"] == 50 and heuristic["kappa"] == pytest.approx(0.4)
    assert (heuristic["both_success"], heuristic["qs_only"], heuristic["dynamic_only"],
            heuristic["both_failure"]) == (20, 5, 10, 15)
    assert heuristic["qs_success_rate"] == 0.5 and heuristic["dynamic_success_rate"] == 0.6
    low, high = proportion_confint(35, 50, alpha=0.05, method="wilson")
    assert (heuristic["agreement_low"], heuristic["agreement_high"]) == pytest.approx((low, high))
    assert centroid["agreement"] == 1.0 and np.isnan(centroid["kappa"])
    assert centroid["kappa_why"] == "undefined: every trial has one label in both columns"
    assert heuristic["kappa_why"] == ""
    overall = dc.agreement_table(records)
    assert len(overall) == 1 and overall.loc[0, "n"] == 90
    assert overall.loc[0, "kappa"] == pytest.approx(sm_kappa(np.array([[20, 5], [10, 55]])).kappa)
    two = dc.agreement_table(records, by=["model_preset", "planner"])
    assert list(two.columns[:2]) == ["model_preset", "planner"] and len(two) == 2


def test_a_grasp_not_settled_by_t_max_is_left_out_not_a_failure():
    """A dynamic grasp stopped by the time budget is undetermined: the agreement and kappa are those
    of the determined trials alone (scikit-learn on them), the rest counted in ``not_settled``."""
    rng = np.random.default_rng(7)
    n = 60
    qs, dyn = rng.random(n) < 0.4, rng.random(n) < 0.5
    status = np.where(dyn, "stable", rng.choice(["penetration_limit", "dropped", "not_settled"], n))
    records = pd.DataFrame({"status": "ok", "qs_success": qs, "success": dyn, "dynamic_status": status,
                            "planner": np.where(np.arange(n) < 40, "heuristic", "centroid")})
    records.loc[records.planner == "centroid", ["success", "dynamic_status"]] = [False, "not_settled"]
    table = dc.agreement_table(records, by="planner").set_index("planner")
    for planner, group in records.groupby("planner"):
        kept = group[group.dynamic_status != "not_settled"]
        row = table.loc[planner]
        assert row["not_settled"] == len(group) - len(kept)
        assert row["n"] == len(kept)
        if len(kept):
            assert row["agreement"] == pytest.approx((kept.qs_success == kept.success).mean())
            assert row["kappa"] == pytest.approx(cohen_kappa_score(kept.qs_success, kept.success))
            assert row["dynamic_success_rate"] == pytest.approx(kept.success.mean())
    assert 0 < table.loc["heuristic", "not_settled"] < 40
    # every centroid grasp timed out: nothing to compare, no rate and no kappa (not 100 % "both fail")
    centroid = table.loc["centroid"]
    assert centroid["n"] == 0 and centroid["not_settled"] == 20
    assert np.isnan(centroid[["agreement", "agreement_low", "agreement_high", "kappa",
                              "qs_success_rate", "dynamic_success_rate"]].astype(float)).all()
    assert centroid["kappa_why"] == "no trial to compare"


@pytest.mark.parametrize("missing", [np.nan, None])
def test_a_trial_missing_a_label_enters_no_table_and_is_counted_apart(missing):
    """``astype(bool)`` read a missing quasi-static label as a success (NaN) or a failure (None), and
    ``executed`` read a missing dynamic label as a failure: each missing label made a pair. Such a
    trial is now no pair (as McNemar's unpaired rows), counted in ``unlabelled``; the table and kappa
    are those of the labelled trials alone (scikit-learn on them)."""
    labelled = _records(20, 5, 10, 15, planner="heuristic")
    gaps = pd.DataFrame({"qs_success": [missing, missing, True, False],
                         "success": [True, False, missing, missing], "status": "ok", "planner": "heuristic",
                         "dynamic_status": ["stable", "dropped", "stable", "dropped"]})
    records = pd.concat([labelled, gaps], ignore_index=True)
    np.testing.assert_array_equal(dc.confusion_matrix(records), [[20, 5], [10, 15]])
    row = dc.agreement_table(records, by="planner").iloc[0]
    assert (row["n"], row["unlabelled"], row["not_settled"]) == (50, 4, 0)
    assert row["kappa"] == pytest.approx(cohen_kappa_score(labelled.qs_success, labelled.success))
    assert row["qs_success_rate"] == 0.5 and row["dynamic_success_rate"] == 0.6


def test_a_group_without_an_executed_trial_is_no_row_and_its_labels_are_read_once():
    """``agreement_table`` groups the stored rows and leaves the labels to ``confusion_matrix``: a
    planner whose trials all errored is no row (as when the groups were of the executed trials), and
    an errored trial with both labels enters no count of its planner's row."""
    records = pd.concat([
        _records(3, 1, 2, 4, planner="heuristic"),
        pd.DataFrame({"qs_success": [True, False], "success": [True, False], "status": "error",
                      "dynamic_status": "stable", "planner": ["heuristic", "centroid"]})],
        ignore_index=True)
    table = dc.agreement_table(records, by="planner")
    assert list(table.planner) == ["heuristic"]
    row = table.iloc[0]
    assert (row["n"], row["unlabelled"], row["not_settled"], row["both_success"]) == (10, 0, 0, 3)
    overall = dc.agreement_table(records[records.status == "error"])  # no executed trial at all
    assert len(overall) == 1 and overall.loc[0, "n"] == 0
    assert overall.loc[0, "kappa_why"] == "no trial to compare"
