"""Tests 2-3 statistics: the paper's printed counts reproduce its statistics; synthetic records
with known answers; a smoke run on virtual-rig records."""

from __future__ import annotations

import functools

import numpy as np
import pandas as pd
import pytest
from hardware_records import PREDICTED, planner_records
from statsmodels.stats.proportion import proportion_confint

from graspcampaign.analysis import disturbance, hardware
from graspcampaign.analysis.records import mcnemar_table
from graspcampaign.rig import protocol
from graspcampaign.rig.plan import predict_trial
from graspcampaign.rig.virtual import virtual_trial


def _merge(schedule: pd.DataFrame, preds: pd.DataFrame, meas: pd.DataFrame) -> pd.DataFrame:
    """The records of a virtual run: schedule rows with their predictions, joined to the measured."""
    left = pd.concat([schedule.reset_index(drop=True), preds.reset_index(drop=True)], axis=1)
    return left.merge(meas.drop(columns=["slot_id", "attempt"], errors="ignore"), on="trial_id")


def test_paper_test2_counts_reproduce_its_chi2():
    # §8.5: 637/819 proposed, 213/474 centroid, 79/282 random -> chi2 = 270.0 (Pearson)
    rec = planner_records({"heuristic": (637, 819), "centroid": (213, 474), "random": (79, 282)})
    out = hardware.chi2_planners(hardware.derive(rec))
    assert out["statistic"] == pytest.approx(270.0, abs=0.05)
    assert (out["dof"], out["n"]) == (2, 819 + 474 + 282)


def test_chi2_planners_says_no_test_ran_when_every_trial_has_one_outcome():
    # 6/6 and 4/4 succeed: scipy has no table to test; the row had read "χ² planner × success
    # (proposed H(G), centroid, random)" with p 1.0, naming a planner with no trial
    rec = planner_records({"heuristic": (6, 6), "centroid": (4, 4)})
    out = hardware.chi2_planners(hardware.derive(rec))
    assert out["test"] == "no test: every trial has one outcome (proposed H(G), centroid)"
    assert np.isnan(out["p"]) and np.isnan(out["statistic"]) and out["n"] == 10


def test_chi2_planners_takes_the_monte_carlo_p_below_five_expected():
    # 6/8, 2/6, 1/5: every expected failure count < 5, so the asymptotic p is not trusted; the p is
    # scipy's Monte Carlo p of the same table from the given seed, as equal_rates_test's (the old
    # code reported the chi-square distribution's p regardless)
    from scipy import stats

    rec = planner_records({"heuristic": (6, 8), "centroid": (2, 6), "random": (1, 5)})
    out = hardware.chi2_planners(hardware.derive(rec), seed=7)
    table = np.array([[2, 4], [6, 2], [1, 4]])  # planners sorted: centroid, heuristic, random
    ref = stats.chi2_contingency(table, correction=False, method=stats.MonteCarloMethod(
        n_resamples=9999, rng=np.random.default_rng(7)))
    assert out["p"] == pytest.approx(ref.pvalue, rel=1e-12)
    assert out["statistic"] == pytest.approx(ref.statistic, rel=1e-12) and out["dof"] == 2
    assert out["test"].startswith("Monte Carlo χ² planner × success")


def test_planner_summary_rates_and_intervals():
    rec = planner_records({"heuristic": (637, 819), "centroid": (213, 474)})
    rec = pd.concat([rec, planner_records({"heuristic": (0, 1)}).assign(aborted=True, trial_id="ab")])
    d = hardware.derive(rec)
    out = hardware.summary(d, ["planner"], [f"is_{k}" for k in hardware.CLASSES], cluster="object_id",
                           seed=1).set_index("planner")
    assert out.loc["heuristic", "n"] == 819  # aborted attempts enter no statistic
    low, high = proportion_confint(637, 819, method="wilson")
    assert out.loc["heuristic", "success_pct"] == pytest.approx(100 * 637 / 819)
    assert out.loc["heuristic", "success_low_pct"] == pytest.approx(100 * low)
    assert out.loc["heuristic", "success_high_pct"] == pytest.approx(100 * high)
    assert out.loc["heuristic", "bootstrap_low_pct"] <= 100 * 637 / 819 <= \
        out.loc["heuristic", "bootstrap_high_pct"]
    total = out[[f"{k}_pct" for k in hardware.CLASSES]].sum(axis=1)  # one class per trial
    np.testing.assert_allclose(total, 100.0)


def test_matched_mcnemar_reproduces_the_papers_33_to_3():
    # §8.5: on 90 matched pairs the proposed planner won 33 and lost 3 -> chi2 = 23.4, OR = 11.0
    rows = []
    for i in range(90):
        a = i < 33 or 36 <= i < 60  # won 0-32, both succeed 36-59
        b = 33 <= i < 60             # lost 33-35
        for planner, ok in (("heuristic", a), ("centroid", b)):
            rows.append({"planner": planner, "success": ok, "object_id": f"o{i % 10}",
                         "condition": f"c{i // 30}", "repeat": (i // 10) % 3})
    d = planner_records({}).iloc[:0]
    d = hardware.derive(pd.concat([d, pd.DataFrame(rows)]).assign(
        trial_id=lambda x: np.arange(len(x)).astype(str), status="ok", aborted=False,
        outcome="stable", friction_level="natural", **{c: 1.0 for c in PREDICTED}))
    out = mcnemar_table(d, "heuristic", ["centroid"], pair_on="match_key").iloc[0]
    assert (out["reference_only"], out["compared_only"], out["pairs"]) == (33, 3, 90)
    assert out["chi2_cc"] == pytest.approx(23.4, abs=0.05)
    assert out["odds_ratio"] == pytest.approx(11.0)


def test_threshold_agreement_and_summary():
    rng = np.random.default_rng(0)
    pred = rng.uniform(1.0, 6.0, 300)
    meas = 1.2 * pred + 0.1 + rng.normal(0, 0.05, 300)
    rec = planner_records({"heuristic": (300, 300)}, block="A", threshold_censored=False, mass_kg=0.2,
                   threshold_measured_nm=np.nan, threshold_pred_nm=np.nan, disturbance_kind="lateral",
                   first_finger_measured=0, first_finger_pred=1, peak_slip_mm=0.0)
    rec = rec.assign(threshold_measured_n=meas, threshold_pred_n=pred)
    out = disturbance.threshold_agreement(hardware.derive(rec))
    assert out["n"] == 300
    assert out["bias_n"] == pytest.approx(np.mean(meas - pred))
    assert out["ols_slope"] == pytest.approx(1.2, abs=0.01)
    assert out["median_err_pct"] == pytest.approx(100 * np.median(np.abs(pred - meas) / meas))
    rec.loc[:9, "threshold_censored"] = True  # a ramp that reached its cap is a lower bound only
    d = hardware.derive(rec)
    assert disturbance.threshold_agreement(d)["n"] == 290
    assert d["first_finger_correct"].isna().all()  # no finger slipped: nothing to score
    summary = hardware.summary(d, ["block"], medians=["lat_threshold_n"]).iloc[0]
    assert summary["lat_threshold_n"] == pytest.approx(np.median(meas[10:]))
    assert summary["n_lat_threshold"] == 290


def test_threshold_agreement_of_three_pulls_by_hand():
    """Predicted 2, 4, 3 N, measured 4, 2, 3 N: differences 2, -2, 0 (mean 0, SD 2), so the limits
    are -/+ 1.96 * 2 and their half-width 3.92 N; errors |p - m| / m are 50 %, 100 %, 0 %, of
    which one is *over* 50 %. Two pulls fit any line exactly: no statistics, only the count."""
    rec = planner_records({"heuristic": (3, 3)}, block="A", threshold_censored=False, mass_kg=0.2,
                   threshold_measured_nm=np.nan, threshold_pred_nm=np.nan, disturbance_kind="lateral",
                   first_finger_measured=0, first_finger_pred=1, peak_slip_mm=0.0)
    d = hardware.derive(rec.assign(threshold_measured_n=[4.0, 2.0, 3.0], threshold_pred_n=[2.0, 4.0, 3.0]))
    out = disturbance.threshold_agreement(d)
    assert (out["bias_n"], out["sd_n"], out["loa_half_n"]) == pytest.approx((0.0, 2.0, 3.92))
    assert out["n_err_over_50pct"] == 1 and out["median_err_pct"] == pytest.approx(50.0)
    assert disturbance.threshold_agreement(d.iloc[:2]) == {"planner": "heuristic", "n": 2}


def test_lateral_survival_counts_failures_as_zero():
    rec = pd.DataFrame({"trial_id": list("abcd"), "planner": "heuristic", "aborted": False,
                        "success": True, "block": "A", "friction_level": "natural",
                        "threshold_measured_n": [1.0, 2.0, 3.0, np.nan]})
    out = disturbance.lateral_survival(rec, levels=[0.0, 1.5, 2.5, 3.5], planners=["heuristic"])
    assert out["surviving_fraction"].tolist() == [1.0, 0.5, 0.25, 0.0]


def test_classifiers():
    rec = pd.DataFrame({"planner": "heuristic", "group": ["A", "A", "C", "C", "B", "B"],
                        "predicted_stable": [True, True, True, False, False, True],
                        "retention_pred": [True, False, True, False, False, True],
                        "success": [True, False, False, False, True, True]})
    out = hardware.classifier_table(hardware.scoped(rec, {"all": rec["planner"].notna(), "group C": rec[
        "group"] == "C"}), ["predicted_stable", "retention_pred"], ["scope"]).set_index(["flag", "scope"])
    assert out.loc[("predicted_stable", "all"), ["tp", "fp", "fn", "tn"]].tolist() == [2, 2, 1, 1]
    assert out.loc[("predicted_stable", "group C"), "n"] == 2
    ret = out.loc[("retention_pred", "all")]
    low, high = proportion_confint(2, 3, method="wilson")
    assert (ret["precision"], ret["precision_low"], ret["precision_high"]) == \
        pytest.approx((2 / 3, low, high))
    assert ret["base"] == pytest.approx(0.5) and bool(ret["above_base"])


def test_failure_logistic_recovers_known_coefficients():
    rng = np.random.default_rng(1)
    n = 4000
    load = rng.uniform(0.5, 5.0, n)
    mass = rng.uniform(0.05, 0.6, n)
    mu = rng.uniform(0.3, 0.8, n)
    proposed = rng.integers(0, 2, n)
    eta = -1.0 + 0.5 * load + 2.5 * mass + 0.4 * mu - 3.0 * proposed
    failed = rng.random(n) < 1 / (1 + np.exp(-eta))
    rec = pd.DataFrame({"trial_id": np.arange(n).astype(str), "aborted": False,
                        "block": rng.choice(["B", "D", "E"], n), "success": ~failed,
                        "load_n": load, "mass_kg": mass, "mu_s_believed": mu,
                        "planner": np.where(proposed == 1, "heuristic", "random")})
    out = disturbance.failure_logistic(rec).set_index("term")
    np.testing.assert_allclose(out.loc[["load", "mass", "proposed"], "coef"], [0.5, 2.5, -3.0],
                               atol=0.35)
    assert bool(out["converged"].iloc[0])


@functools.cache
def _virtual_tables() -> dict[str, pd.DataFrame]:
    """Tests 2-3's derived tables of 150 unmatched trials plus the matched and faulted ones, each run
    on the virtual rig."""
    tables = {}
    for maker, n in ((protocol.test2_schedule, 150), (protocol.test3_schedule, 150)):
        schedule = maker(0)
        rows = schedule[schedule["matched"] | schedule["rig_fault"]]
        rows = pd.concat([rows, schedule[~schedule["matched"]].head(n)]).drop_duplicates("trial_id")
        preds = pd.DataFrame([predict_trial(r) for r in rows.to_dict("records")])
        meas = pd.DataFrame([virtual_trial(r, p, np.random.default_rng(i)) for i, (r, p) in
                             enumerate(zip(rows.to_dict("records"), preds.to_dict("records"),
                                           strict=True))])
        meas.insert(0, "trial_id", rows["trial_id"].to_numpy())
        tables[maker.__name__] = hardware.derive(_merge(rows, preds, meas).assign(status="ok"))
    return tables


def test_every_statistic_runs_on_virtual_records():
    tables = _virtual_tables()
    t2, t3 = tables["test2_schedule"], tables["test3_schedule"]
    for d in (t2, t3):
        for out, col in ((hardware.summary(d, ["planner"], ["is_stable"], ["force_err_pct"]), "n"),
                         (hardware.force_accuracy(d), "parity_slope"),
                         (hardware.classifier_table(d, ["predicted_stable"], ["planner"]), "accuracy"),
                         (pd.DataFrame([hardware.chi2_planners(d), hardware.kruskal(d, "force_err_pct",
                                                                                   "planner")]), "p")):
            assert len(out) > 0 and out[col].notna().all(), col
        mc = mcnemar_table(d[d["matched"].astype(bool)], "heuristic", ["centroid", "random"],
                           pair_on="match_key")
        assert ((mc["pairs"] > 0) & (mc["pairs"] <= 100)).all()
    for out in (pd.DataFrame([disturbance.threshold_agreement(t3)]), disturbance.failure_logistic(t3),
                disturbance.lateral_survival(t3, [0.0, 1.0, 2.0])):
        assert len(out) > 0
    assert t3["headline"].notna().any() and t3["first_finger_correct"].notna().any()


def test_each_median_error_carries_the_count_it_is_over():
    """A trial may measure its force but not its deformation: the median deformation error was shown
    with the parity pairs' n (1272 where 1255 trials measured a deformation, in the paper-scale Test 2)."""
    d = _virtual_tables()["test2_schedule"]
    before = hardware.force_accuracy(d).set_index("scope").loc["all"]
    measured = d[["deformation_err_pct", "normal_force_mean_n",
                  "normal_force_pred_mean_n"]].notna().all(axis=1)
    lost = d.assign(deformation_err_pct=d["deformation_err_pct"].mask(measured & (measured.cumsum() <= 7)))
    after = hardware.force_accuracy(lost).set_index("scope").loc["all"]
    assert after["n_parity"] == before["n_parity"] and after["n_force_err"] == before["n_parity"]
    assert after["n_deformation_err"] == before["n_deformation_err"] - 7
    assert before["n_deformation_err"] == measured.sum()


def test_a_group_with_no_reading_of_a_rate_counts_zero_rows_not_nan():
    """The count n_stable of a planner none of whose trials recorded is_stable was NaN (the
    merge of a rate table lacking the group), and made every n_ column a float."""
    d = planner_records({"a": (1, 2), "b": (2, 2)}).assign(is_stable=[True, False, None, None])
    out = hardware.summary(d, ["planner"], ["is_stable"]).set_index("planner")
    assert out["n_stable"].to_dict() == {"a": 2, "b": 0}
    assert out["n_stable"].dtype.kind == "i" and np.isnan(out.loc["b", "stable_pct"])
