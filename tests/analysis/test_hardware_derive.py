"""Tests 2-3 columns the mutation run found unpinned: which trials the validity gate alone fails
(``gate_removed``), the block-B payload as a share of the object's weight, and the sign of the
belief gap (none − paper). Expected values come from the trials counted by hand and pandas."""

from __future__ import annotations

import numpy as np
import pandas as pd
import pytest
from hardware_records import planner_records

from graspcampaign.analysis import hardware, records


def test_gate_removed_is_a_success_only_without_the_validity_gate():
    rec = planner_records({"heuristic": (1, 3)})
    # trial 0 passes with the gate; 1 passes only without it; 2 fails both ways
    got = hardware.derive(rec.assign(success_unbounded=[True, True, False]))["gate_removed"]
    assert got.tolist() == [False, True, False]
    assert hardware.derive(rec)["gate_removed"].isna().all()  # a measured run knows no ungated success


def test_a_block_b_payload_is_a_share_of_the_objects_weight():
    """A 0.2 kg object weighs 0.2 · 9.81 N (SPEC §1): a pull of 0.981 N is 50 % of it."""
    rec = planner_records({"heuristic": (2, 2)}, block="B", disturbance_kind="down", mass_kg=0.2,
                   threshold_censored=False, threshold_pred_n=1.0, threshold_measured_nm=np.nan,
                   threshold_pred_nm=np.nan, first_finger_measured=0, first_finger_pred=1, peak_slip_mm=0.0)
    d = hardware.derive(rec.assign(threshold_measured_n=[0.981, 1.962]))
    assert d["payload_pct_w"].tolist() == pytest.approx([50.0, 100.0])


def test_the_belief_gap_is_exact_beliefs_minus_the_papers():
    """Under exact beliefs (none) 7 of 10 trials succeed, under the paper's 3: +40 pp."""
    paper = planner_records({"heuristic": (3, 10)})
    none = paper.assign(success=np.arange(10) < 7)
    long = pd.concat([paper.assign(belief_error="paper"), none.assign(belief_error="none")])
    row = hardware.belief_pairs(long).iloc[0]
    rate = long.groupby("belief_error")["success"].mean() * 100
    assert (row["success_paper_pct"], row["success_none_pct"]) == pytest.approx((rate["paper"], rate["none"]))
    assert row["difference_pp"] == pytest.approx(rate["none"] - rate["paper"]) == pytest.approx(40.0)


def test_a_flag_is_scored_against_the_success_rate_of_its_group():
    """4 of 6 trials succeed (base 4/6, Wilson interval from statsmodels); the flag marks 2 of
    them and nothing else (precision 2/2, recall 2/4). Flagging every trial has a precision equal
    to the base rate: no better than it, so not ``above_base``."""
    from statsmodels.stats.proportion import proportion_confint

    rec = pd.DataFrame({"planner": "heuristic", "success": [True, True, True, True, False, False],
                        "flag": [True, True, False, False, False, False], "every": True})
    out = hardware.classifier_table(rec, ["flag", "every"], ["planner"]).set_index("flag")
    low, high = proportion_confint(4, 6, method="wilson")
    assert out.loc["flag", ["base", "base_low", "base_high"]].tolist() == pytest.approx([4 / 6, low, high])
    assert (out.loc["flag", "precision"], out.loc["flag", "recall"]) == pytest.approx((1.0, 2 / 4))
    assert out.loc["every", "precision"] == pytest.approx(out.loc["every", "base"])
    assert not out.loc["every", "above_base"] and out.loc["flag", "above_base"]


def test_a_flag_is_scored_over_the_trials_where_it_and_the_outcome_are_recorded():
    """A flag or an outcome not recorded (NaN, None) is neither set nor unset: the trial leaves the
    score (``astype(bool)`` read a NaN flag as set, a None outcome as a failure). Against scikit-learn
    on the four trials with both recorded."""
    from sklearn.metrics import accuracy_score, precision_score, recall_score

    rec = pd.DataFrame({"planner": "heuristic",
                        "success": pd.Series([True, True, False, False, None, True], dtype=object),
                        "flag": [True, False, True, False, True, np.nan]})
    out = hardware.classifier_table(rec, ["flag"], ["planner"]).iloc[0]
    y, f = [True, True, False, False], [True, False, True, False]
    assert (out["n"], out["tp"] + out["fp"] + out["fn"] + out["tn"]) == (4, 4)
    assert [out["accuracy"], out["precision"], out["recall"]] == pytest.approx(
        [accuracy_score(y, f), precision_score(y, f), recall_score(y, f)])


def test_the_planner_with_the_higher_success_ranks_first():
    """Under the paper's beliefs the proposed planner holds 6 of 10, centroid 3 of 10: ranks 1, 2;
    under exact beliefs centroid holds 9 of 10, the proposed one still 6: ranks 2, 1."""
    paper = pd.concat([planner_records({"heuristic": (6, 10)}), planner_records({"centroid": (3, 10)})])
    none = paper.assign(success=np.where(paper["planner"] == "centroid", np.arange(20) % 10 < 9,
                                         paper["success"]))
    long = pd.concat([paper.assign(belief_error="paper"), none.assign(belief_error="none")])
    out = hardware.belief_pairs(long).set_index("planner")
    assert out.loc[["heuristic", "centroid"], "rank_paper"].tolist() == [1, 2]
    assert out.loc[["heuristic", "centroid"], "rank_none"].tolist() == [2, 1]


def test_a_zero_measurement_has_no_percentage_error():
    """A force measured as 0 N has no relative error (nan, not inf): the median error of the
    others, |1.1 - 1| / 1 = 10 % and |1.3 - 1| / 1 = 30 %, is 20 %."""
    rec = planner_records({"heuristic": (3, 3)})
    rec = rec.assign(normal_force_mean_n=[0.0, 1.0, 1.0], normal_force_pred_mean_n=[0.5, 1.1, 1.3],
                     contact_point_error_mm=1.0)
    d = hardware.derive(rec)
    assert d["force_err_pct"].isna().tolist() == [True, False, False]
    acc = hardware.force_accuracy(d).set_index("scope")
    assert acc.loc["all", "force_err_pct"] == pytest.approx(20.0)


@pytest.mark.parametrize(("quantity", "unit"), [("deformation", "mm"), ("normal_force", "n")])
def test_an_error_compares_the_fingers_that_were_read(quantity, unit):
    """A buried finger has no deformation reading, and an ingested file may leave a finger's force
    empty (not measured; ingest checks the recorded mean against the fingers recorded): the measured
    mean is over fingers 1-2 (1.0, 1.2: 1.1), so the prediction is too (1.0, 1.0: 1.0),
    |1.0 - 1.1| / 1.1 = 100/11 %, not the three-finger 2.0's 900/11 % (at paper scale all 32 Test 2
    deformation errors above 1000 % were such trials). Three readings: 1.2 against 1.0, 20 %; none
    read beside a recorded mean (a measured file may give only the mean): the recorded prediction,
    0.6 against 0.5, 20 %."""
    def col(part: str) -> str:
        return f"{quantity}_{part}_{unit}"

    rec = planner_records({"heuristic": (3, 3)}).assign(**{
        col("1"): [1.0, 1.0, np.nan], col("2"): [1.2, 1.0, np.nan], col("3"): [np.nan, 1.0, np.nan],
        col("mean"): [1.1, 1.0, 0.5], col("pred_1"): [1.0, 1.2, 0.6], col("pred_2"): [1.0, 1.2, 0.6],
        col("pred_3"): [4.0, 1.2, 0.6], col("pred_mean"): [2.0, 1.2, 0.6]})
    got = hardware.derive(rec)[f"{quantity.removeprefix('normal_')}_err_pct"]
    assert got.tolist() == pytest.approx([100 / 11, 20.0, 20.0])


def test_the_force_parity_compares_the_fingers_that_were_read():
    """Fig. 29a and the parity slope pair the measured mean with the prediction over the same fingers,
    as the force error does. Trial 0 read fingers 1 and 2 only (measured 1.1 N, predicted 1.0 N over
    them, 2.0 N over all three); trials 1-2 read every finger. The slope through the origin is
    Σxy / Σx² by hand over the matched pairs (x predicted, y measured), numpy's least squares
    without an intercept agrees; the three-finger means give 16.2 / 19.25 = 0.84."""
    rec = planner_records({"heuristic": (3, 3)}).assign(
        normal_force_1_n=[1.0, 2.0, 3.0], normal_force_2_n=[1.2, 2.0, 3.0],
        normal_force_3_n=[np.nan, 2.0, 3.0], normal_force_mean_n=[1.1, 2.0, 3.0],
        normal_force_pred_1_n=[1.0, 2.5, 3.0], normal_force_pred_2_n=[1.0, 2.5, 3.0],
        normal_force_pred_3_n=[4.0, 2.5, 3.0], normal_force_pred_mean_n=[2.0, 2.5, 3.0],
        contact_point_error_mm=np.nan)
    x, y = np.array([1.0, 2.5, 3.0]), np.array([1.1, 2.0, 3.0])
    by_hand = (x @ y) / (x @ x)
    assert np.linalg.lstsq(x[:, None], y, rcond=None)[0][0] == pytest.approx(by_hand)
    row = hardware.force_accuracy(hardware.derive(rec)).set_index("scope").loc["all"]
    assert row["n_parity"] == 3 and row["parity_slope"] == pytest.approx(by_hand)
    assert by_hand == pytest.approx(15.1 / 16.25)


def test_the_deformation_errors_over_a_sub_quantum_measurement_are_counted_per_scope():
    """Measured means 0.05, 0, 0.2, missing and 0.099 mm against 1 mm predicted (heuristic), 1 mm
    (centroid): three heuristic errors (0 mm has none), two of them over a mean below the 0.1 mm vision
    step (0.05, 0.099; §8.1); none of the centroid's."""
    rec = pd.concat([planner_records({"heuristic": (5, 5)}).assign(
        deformation_mean_mm=[0.05, 0.0, 0.2, np.nan, 0.099]), planner_records({"centroid": (1, 1)})])
    acc = hardware.force_accuracy(hardware.derive(rec.assign(contact_point_error_mm=1.0))).set_index("scope")
    assert acc["n_deformation_err"].to_dict() == {"all": 4, "heuristic": 3, "centroid": 1}
    assert acc["n_deformation_below_quantum"].to_dict() == {"all": 2, "heuristic": 2, "centroid": 0}


def test_three_pairs_get_a_parity_fit():
    """Three (predicted, measured) pairs (1, 2), (2, 3), (3, 7): the slope through the origin is
    sum(xy) / sum(x^2) = (2 + 6 + 21) / 14 (Eisenhauer 2003)."""
    df = pd.DataFrame({"scope": "all", "m": [2.0, 3.0, 7.0], "p": [1.0, 2.0, 3.0]})
    out = hardware.parity_by(df, "scope", "m", "p").iloc[0]
    assert out["n_parity"] == 3 and out["parity_slope"] == pytest.approx(29 / 14)


def test_a_threshold_measured_as_zero_is_no_threshold():
    """Block A: a pull that read 0 N held nothing (no uncensored ramp reached a load): it enters
    neither the threshold nor its error; 2 N against 2.5 N predicted is a 25 % error."""
    rec = planner_records({"heuristic": (2, 2)}, block="A", disturbance_kind="lateral", mass_kg=0.2,
                   threshold_censored=False, threshold_pred_n=2.5, threshold_measured_nm=np.nan,
                   threshold_pred_nm=np.nan, first_finger_measured=0, first_finger_pred=1, peak_slip_mm=0.0)
    d = hardware.derive(rec.assign(threshold_measured_n=[0.0, 2.0]))
    assert d["threshold"].isna().tolist() == [True, False]
    assert d["lat_threshold_n"].isna().tolist() == [True, False]
    assert d["threshold_err_pct"].tolist() == pytest.approx([np.nan, 25.0], nan_ok=True)


def test_the_headline_of_block_c_is_its_torque_threshold():
    """Table 8 reads block C by its sustained torque [N·m] (0.3 and 0.45 here), not missing."""
    rec = planner_records({"heuristic": (2, 2)}, block="C", disturbance_kind="yaw", mass_kg=0.2,
                   threshold_censored=False, threshold_measured_n=np.nan, threshold_pred_n=np.nan,
                   threshold_pred_nm=0.4, first_finger_measured=0, first_finger_pred=1, peak_slip_mm=0.0)
    d = hardware.derive(rec.assign(threshold_measured_nm=[0.3, 0.45]))
    assert d["headline"].tolist() == pytest.approx([0.3, 0.45])


def test_a_ramp_censored_is_no_threshold_and_a_missing_mark_is_no_censoring():
    """Block A, 2 N held against 2.5 N predicted on four ramps marked censored, not, and missing
    (None, NaN: a records file written before the column): only the censored one loses its
    threshold and error (25 %). The mark is read by ``records.flag``, the one reading of a flag
    (missing: not set), which derive typed out again."""
    rec = planner_records({"heuristic": (4, 4)}, block="A", disturbance_kind="lateral", mass_kg=0.2,
                   threshold_pred_n=2.5, threshold_measured_n=2.0, threshold_measured_nm=np.nan,
                   threshold_pred_nm=np.nan, first_finger_measured=0, first_finger_pred=1, peak_slip_mm=0.0)
    d = hardware.derive(rec.assign(threshold_censored=pd.Series([True, False, None, np.nan], dtype=object)))
    assert d["threshold"].isna().tolist() == [True, False, False, False]
    assert d["threshold_err_pct"].tolist() == pytest.approx([np.nan, 25.0, 25.0, 25.0], nan_ok=True)
    assert hardware.flag is records.flag
