"""Tests 2-3 statistics: the paper's printed counts reproduce its statistics; synthetic records
with known answers; a smoke run on virtual-rig records."""

from __future__ import annotations

import numpy as np
import pandas as pd
import pytest
from statsmodels.stats.power import NormalIndPower
from statsmodels.stats.proportion import proportion_confint, proportion_effectsize

from graspcampaign.analysis import disturbance, hardware
from graspcampaign.rig import protocol
from graspcampaign.rig.plan import predict_trial
from graspcampaign.rig.virtual import virtual_trial


def _records(planner_counts: dict[str, tuple[int, int]], **extra) -> pd.DataFrame:
    """Executed records with ``k`` successes out of ``n`` per planner, objects cycled over 10."""
    rows = []
    for planner, (k, n) in planner_counts.items():
        for i in range(n):
            ok = i < k
            rows.append({"trial_id": f"{planner}-{i}", "planner": planner,
                         "object_id": f"obj-{i % 10}", "aborted": False, "success": ok,
                         "stable": ok, "outcome": "stable" if ok else "failure_slip",
                         "slip_flag": not ok, "drop_flag": False, "damage_flag": False,
                         "contact_loss_flag": False, **extra})
    return pd.DataFrame(rows)


def planner_summary(records: pd.DataFrame) -> pd.DataFrame:
    return hardware.planner_summary(records, seed=0)


def test_paper_test2_counts_reproduce_its_chi2():
    # §8.5: 637/819 proposed, 213/474 centroid, 79/282 random -> chi2 = 270.0 (Pearson)
    rec = _records({"heuristic": (637, 819), "centroid": (213, 474), "random": (79, 282)})
    out = hardware.planner_chi2(rec)
    assert out["chi2"].iloc[0] == pytest.approx(270.0, abs=0.05)
    assert out["dof"].iloc[0] == 2


def test_planner_summary_rates_and_intervals():
    rec = _records({"heuristic": (637, 819), "centroid": (213, 474)})
    rec = pd.concat([rec, _records({"heuristic": (0, 1)}).assign(aborted=True, trial_id="ab")])
    out = hardware.planner_summary(rec, n_resamples=200, seed=1).set_index("planner")
    assert out.loc["heuristic", "n"] == 819  # aborted attempts enter no statistic
    low, high = proportion_confint(637, 819, method="wilson")
    assert out.loc["heuristic", "success_pct"] == pytest.approx(100 * 637 / 819)
    assert out.loc["heuristic", "wilson_low_pct"] == pytest.approx(100 * low)
    assert out.loc["heuristic", "wilson_high_pct"] == pytest.approx(100 * high)
    assert out.loc["heuristic", "bootstrap_low_pct"] <= 100 * 637 / 819 <= \
        out.loc["heuristic", "bootstrap_high_pct"]
    total = out[["stable_pct", "partial_pct", "slip_pct", "drop_pct", "damage_pct",
                 "contact_loss_pct"]].sum(axis=1)
    np.testing.assert_allclose(total, 100.0)


def test_matched_mcnemar_reproduces_the_papers_33_to_3():
    # §8.5: on 90 matched pairs the proposed planner won 33 and lost 3 -> chi2 = 23.4, OR = 11.0
    rows = []
    for i in range(90):
        a = i < 33 or 36 <= i < 60  # won 0-32, both succeed 36-59
        b = 33 <= i < 60             # lost 33-35
        for planner, ok in (("heuristic", a), ("centroid", b)):
            rows.append({"trial_id": f"{planner}-{i}", "planner": planner, "aborted": False,
                         "success": ok, "matched": True, "object_id": f"o{i % 10}",
                         "condition": f"c{i // 30}", "repeat": (i // 10) % 3})
    out = hardware.matched_mcnemar(pd.DataFrame(rows)).iloc[0]
    assert (out["won"], out["lost"], out["n_pairs"]) == (33, 3, 90)
    assert out["chi2"] == pytest.approx(23.4, abs=0.05)
    assert out["odds_ratio"] == pytest.approx(11.0)


def test_threshold_agreement_and_summary():
    rng = np.random.default_rng(0)
    pred = rng.uniform(1.0, 6.0, 300)
    meas = 1.2 * pred + 0.1 + rng.normal(0, 0.05, 300)
    rec = pd.DataFrame({"trial_id": [f"t{i}" for i in range(300)], "planner": "heuristic",
                        "aborted": False, "success": True, "block": "A",
                        "friction_level": "natural", "threshold_measured_n": meas,
                        "threshold_pred_n": pred, "threshold_censored": False,
                        "object_id": "o", "direction_deg": 0.0})
    out = disturbance.threshold_agreement(rec).iloc[0]
    assert out["n"] == 300
    assert out["bias_n"] == pytest.approx(np.mean(meas - pred))
    assert out["ols_slope"] == pytest.approx(1.2, abs=0.01)
    assert out["median_err_pct"] == pytest.approx(
        100 * np.median(np.abs(pred - meas) / meas))
    rec.loc[:9, "threshold_censored"] = True
    assert disturbance.threshold_agreement(rec).iloc[0]["n"] == 290
    summary = disturbance.threshold_summary(rec).iloc[0]
    assert summary["lat_threshold_median_n"] == pytest.approx(np.median(meas[10:]))


def test_lateral_survival_counts_failures_as_zero():
    rec = pd.DataFrame({"trial_id": list("abcd"), "planner": "heuristic", "aborted": False,
                        "success": True, "block": "A", "friction_level": "natural",
                        "threshold_measured_n": [1.0, 2.0, 3.0, np.nan]})
    out = disturbance.lateral_survival(rec, levels=[0.0, 1.5, 2.5, 3.5], planners=["heuristic"])
    assert out["surviving_fraction"].tolist() == [1.0, 0.5, 0.25, 0.0]


def test_classifiers():
    rec = pd.DataFrame({"trial_id": [f"t{i}" for i in range(6)], "planner": "heuristic",
                        "aborted": False, "group": ["A", "A", "C", "C", "B", "B"],
                        "predicted_stable": [True, True, True, False, False, True],
                        "retention_pred": [True, False, True, False, False, True],
                        "success": [True, False, False, False, True, True]})
    out = hardware.stability_classifier(rec).set_index("scope")
    assert out.loc["all", ["tp", "fp", "fn", "tn"]].tolist() == [2, 2, 1, 1]
    assert out.loc["group C", "n"] == 2 and out.loc["outside C", "n"] == 4
    ret = disturbance.retention_classifier(rec).set_index("scope")
    assert ret.loc["all", "precision"] == pytest.approx(2 / 3)


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


def test_power_analysis_matches_statsmodels():
    out = hardware.power_analysis(0.778, 0.467, powers=(0.8,)).set_index("design")
    h = proportion_effectsize(0.778, 0.467)
    n = NormalIndPower().solve_power(effect_size=abs(h), alpha=0.05, power=0.8)
    assert out.loc["independent", "n_per_arm"] == int(np.ceil(n))
    assert out.loc["paired", "n_per_arm"] > 0


def test_every_statistic_runs_on_virtual_records():
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
        tables[maker.__name__] = hardware.merge_records(rows, preds, meas)
    t2, t3 = tables["test2_schedule"], tables["test3_schedule"]
    for fn in (planner_summary, hardware.shape_summary, hardware.material_summary,
               hardware.outcome_breakdown, hardware.group_summary, hardware.force_accuracy,
               hardware.stability_classifier, hardware.matched_mcnemar, hardware.planner_chi2,
               hardware.force_error_kruskal, hardware.slip_friction_kruskal):
        out = fn(t2)
        assert isinstance(out, pd.DataFrame) and len(out) > 0, fn.__name__
    mc = hardware.matched_mcnemar(t2)
    assert set(mc["baseline"]) == {"centroid", "no_pso", "force_balance", "random"}
    assert ((mc["n_pairs"] > 0) & (mc["n_pairs"] <= 90)).all()
    for fn in (planner_summary, disturbance.threshold_summary, disturbance.block_summary,
               disturbance.threshold_agreement, disturbance.first_finger_accuracy,
               disturbance.lateral_survival, disturbance.retention_classifier,
               disturbance.failure_logistic, disturbance.coating_summary,
               disturbance.direction_summary, hardware.matched_mcnemar, hardware.planner_chi2):
        out = fn(t3)
        assert isinstance(out, pd.DataFrame) and len(out) > 0, fn.__name__
    assert (hardware.matched_mcnemar(t3)["n_pairs"] <= 100).all()
