"""Test 1 summaries of ``analysis.calibration`` on small hand-made tables.

Expected values are computed with numpy on the raw rows (``np.percentile`` with its default
linear interpolation for the 95th percentile; ``np.std(..., ddof=1)`` for the SD).
"""

from __future__ import annotations

import numpy as np
import pandas as pd
import pytest
from statsmodels.stats.weightstats import DescrStatsW

from graspcampaign.analysis.calibration import damage_summary, table4, table5, transfer_summary


def test_transfer_summary_per_quantity_and_split_in_the_papers_order():
    errors = pd.DataFrame({"quantity": ["friction"] * 4 + ["normal_force"] * 3,
                           "split": ["unseen_load", "train", "train", "unseen_load", "unseen_speed",
                                     "train", "unseen_speed"],
                           "error_pct": [4.0, 1.0, 3.0, 8.0, 2.0, 0.5, 6.0]})
    t = transfer_summary(errors)
    assert list(zip(t["quantity"], t["split"], strict=True)) == [
        ("normal_force", "train"), ("normal_force", "unseen_speed"), ("friction", "train"),
        ("friction", "unseen_load")]
    row = t.set_index(["quantity", "split"]).loc[("friction", "unseen_load")]
    assert row["events"] == 2 and row["mean_error_pct"] == 6.0 and row["median_error_pct"] == 6.0
    assert row["p95_error_pct"] == pytest.approx(np.percentile([4.0, 8.0], 95))  # 7.8
    assert transfer_summary(errors.iloc[:0]).empty


def test_damage_summary_per_family_with_the_error_against_the_truth():
    key = {"material": ["gel", "gel", "gel"], "specimen": [1, 2, 3], "environment": ["normal_lab"] * 3}
    depths = pd.DataFrame({**key, "damage_depth_mm": [2.0, 3.0, 4.5],
                           "criterion": ["set", "stiffness", "set"], "extrapolated": [False, True, False],
                           "stiffness_target": 0.85, "set_limit_mm": 0.5})
    truths = pd.DataFrame({**key, "damage_depth_mm": [2.5, 2.0, 4.0], "modulus_kpa": 100.0})
    row = damage_summary(depths, truths, 5.0).set_index("material").loc["gel"]
    assert row["specimens"] == 3 and row["set_limited"] == 2 and row["extrapolated"] == 1
    assert (row["damage_depth_mean_mm"], row["damage_depth_min_mm"], row["damage_depth_max_mm"]) == \
        pytest.approx((np.mean([2.0, 3.0, 4.5]), 2.0, 4.5))
    assert row["abs_error_median_mm"] == pytest.approx(np.median([0.5, 1.0, 0.5]))
    assert "abs_error_median_mm" not in damage_summary(depths, None, 5.0)  # ingested: no truths
    # 5.5 mm is deeper than the 5 mm fingertip radius: no contact is that deep
    deep = depths.assign(damage_depth_mm=[2.0, 5.5, 6.0])
    assert damage_summary(deep, None, 5.0)["beyond_radius"].tolist() == [2]


def test_table4_damping_is_the_median_with_the_negative_fits_counted():
    """A few wild per-event C (here -5 N s/m) ruled the family mean: Table 4 printed C = -1.2 beside
    the paper's 0.06; the median and the count of non-physical negative C say what the fits hold."""
    c = [-5.0, 0.05, 0.06, 0.07, -0.01]
    fits = pd.DataFrame({"material": "gel", "block": "normal", "fit_ok": True, "accepted": True,
                         "n_exp": 0.5, "k_n_per_mm_n": 0.3, "f05_n": 0.2, "c_n_s_per_m": c,
                         **dict.fromkeys(["mu_s", "mu_k", "k_t_n_per_mm", "rho", "tau_s"], np.nan)})
    row = table4(fits).iloc[0]
    assert row["c_n_s_per_m"] == pytest.approx(np.median(c)) and row["c_negative"] == 2
    assert row["n_accepted_fits"] == 5


def test_table5_over_the_converged_runs_and_their_bounds():
    runs = pd.DataFrame({"converged": [True, True, True, False], "lambda1": [1.0, 2.0, 4.0, 99.0],
                         "lambda2": [0.1, 0.1, 0.1, 0.0], "n_exp": [0.4, 0.5, 0.6, 3.0], "b": 0.0, "k": 1.0,
                         "c": [1.0, 2.0, 3.0, 0.0], "at_bound": ["lambda2", "lambda2,b", None, "n"]})
    t = table5(runs).set_index("parameter")
    assert t.loc["lambda1", "mean"] == pytest.approx(7 / 3)
    assert t.loc["lambda1", "cv_pct"] == pytest.approx(100 * np.std([1, 2, 4], ddof=1) / (7 / 3))
    assert np.isnan(t.loc["b", "cv_pct"])  # mean 0: CV undefined
    assert t.loc["lambda2", "sd"] == pytest.approx(0, abs=1e-15)
    assert t["n_runs"].eq(3).all()
    # the mean's 95% interval: Student t over the 3 converged runs (statsmodels)
    assert (t.loc["lambda1", "mean_low"], t.loc["lambda1", "mean_high"]) == pytest.approx(
        DescrStatsW(np.array([1.0, 2.0, 4.0])).tconfint_mean(0.05))
    assert t["n_at_bound"].to_dict() == {"lambda1": 0, "lambda2": 2, "n": 0, "b": 1, "k": 0, "c": 0}
