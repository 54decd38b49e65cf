"""The surrogate kind's finalize stage: Appendix A's models fitted, scored and timed by the run.

Checked on scenarios whose outcomes are known functions of the inputs (``surrogate_scenarios`` in
tests/conftest.py), so a correct fit must recover them; intervals against statsmodels.
"""

from __future__ import annotations

import numpy as np
import pandas as pd
import pytest
from statsmodels.stats.proportion import proportion_confint

pytest.importorskip("sklearn")

from graspcampaign.campaign.kinds.surrogate import LABELS  # noqa: E402


@pytest.fixture(scope="module")
def fitted(surrogate_scenarios, surrogate_finalize):
    return surrogate_finalize(surrogate_scenarios())


def test_classifiers_recover_the_known_structure(fitted):
    cls = fitted["surrogate_classification"].set_index(["label", "model"])
    assert set(cls.index.get_level_values("label")) == set(LABELS)
    assert (cls["roc_auc"] > 0.95).all()
    assert (cls["test_trials"] == 80).all()  # stratified 80/20 of 400
    for _, row in cls.iterrows():  # accuracy with its Wilson 95 % interval (statsmodels)
        k = round(row["accuracy_pct"] / 100 * row["test_trials"])
        low, high = proportion_confint(k, row["test_trials"], alpha=0.05, method="wilson")
        assert (row["accuracy_low_pct"], row["accuracy_high_pct"]) == pytest.approx((100 * low, 100 * high))
    importance = fitted["surrogate_importance"]
    assert importance.iloc[0]["feature"] == "mass_kg"  # the one input `success` depends on
    assert importance["importance"].sum() == pytest.approx(1.0)
    roc = fitted["surrogate_roc"]
    for _, g in roc.groupby(["label", "model"]):
        assert g["fpr"].is_monotonic_increasing and (g["fpr"].iloc[[0, -1]] == [0, 1]).all()


def test_regressors_and_parity_are_held_out(fitted, surrogate_scenarios):
    reg = fitted["surrogate_regression"].set_index(["target", "model"])
    assert reg.loc[("log10_residual_norm_n", "random_forest"), "r2"] > 0.95
    assert reg.loc[("log10_delta_max_mm", "random_forest"), "r2"] > 0.95
    parity = fitted["surrogate_parity"]
    assert len(parity) == 80
    # the simulated values are the held-out scenarios' own log10 ||R|| = 3 m (a closed form)
    held = np.sort(parity["simulated"].to_numpy())
    masses = np.sort(surrogate_scenarios()["mass_kg"].to_numpy())
    assert np.isin(np.round(held / 3, 12), np.round(masses, 12)).all()


def test_one_prediction_is_timed_beside_the_run_pso_call(fitted, surrogate_scenarios):
    t = fitted["surrogate_timing"].set_index("what")
    assert list(t.index) == ["pso_call", "mlp", "random_forest"]
    assert t.loc["pso_call", "time_s"] == pytest.approx(surrogate_scenarios()["pso_time_s"].median())
    assert t.loc["pso_call", "n_timed"] == 400 and t.loc["pso_call", "evaluations"] == 25
    assert (t.loc[["mlp", "random_forest"], "time_s"] > 0).all()
    assert (t.loc[["mlp", "random_forest"], "predicts"] == "success probability").all()
    assert (t["n_timed"] >= 5).all()


def test_fits_do_not_depend_on_the_call_only_timings_do(fitted, surrogate_scenarios, surrogate_finalize):
    again = surrogate_finalize(surrogate_scenarios())
    for name, table in fitted.items():
        if name != "surrogate_timing":
            pd.testing.assert_frame_equal(table, again[name])


@pytest.mark.slow  # starts loky workers: `make test-slow`
def test_models_fitted_in_two_processes_are_those_fitted_in_one(fitted, surrogate_scenarios,
                                                                surrogate_finalize):
    again = surrogate_finalize(surrogate_scenarios(), n_jobs=2)
    for name, table in fitted.items():
        if name != "surrogate_timing":
            pd.testing.assert_frame_equal(table, again[name])


def test_a_label_with_too_few_positives_is_not_fitted(surrogate_scenarios, surrogate_finalize):
    df = surrogate_scenarios(120)
    df["success"] = df["success_unbounded"] = df["success_vertical"] = False
    df.loc[:4, "success_unbounded"] = True  # 5 < 10 positives
    out = surrogate_finalize(df)
    cls = out["surrogate_classification"]
    assert cls["note"].tolist() == ["not fitted: fewer than 10 trials of one class"] * 3
    assert "model" not in cls and out["surrogate_roc"].empty and out["surrogate_importance"].empty
    t = out["surrogate_timing"].set_index("what")  # the regressors of |R_z| are timed instead
    assert (t.loc[["mlp", "random_forest"], "predicts"] == "abs_residual_z_n").all()
    assert len(out["surrogate_regression"]) == 6


def test_r2_of_a_constant_held_out_target_is_missing_with_its_reason(surrogate_scenarios,
                                                                     surrogate_finalize):
    df = surrogate_scenarios(n=120)
    df["abs_residual_z_n"] = 1e-16 * (df.index % 2)  # force-closed grasps: |R_z| is round-off
    reg = surrogate_finalize(df)["surrogate_regression"].set_index(["target", "model"])
    flat = reg.loc["abs_residual_z_n"]
    assert flat["r2"].isna().all()
    assert (flat["note"] == "held-out target constant to round-off: R² undefined").all()
    assert reg.loc["log10_delta_max_mm", "r2"].notna().all()


def test_the_held_out_scores_are_stored_for_the_auc_interval(fitted):
    """The report bootstraps the AUC from these; they are the held-out trials the AUC was scored on."""
    from sklearn.metrics import roc_auc_score

    scores = fitted["surrogate_scores"]
    for (label, model), row in fitted["surrogate_classification"].set_index(["label", "model"]).iterrows():
        g = scores[(scores["label"] == label) & (scores["model"] == model)]
        assert len(g) == row["test_trials"] and g["positive"].sum() == row["test_positives"]
        assert roc_auc_score(g["positive"], g["score"]) == pytest.approx(row["roc_auc"])


def test_the_auc_interval_is_stored_beside_the_auc(fitted):
    """finalize stores each AUC's interval from its stored held-out scores (seed = the study's, 5
    here; the interval itself is checked in tests/analysis/test_auc_interval.py)."""
    from graspcampaign.analysis.agreement import auc_interval

    cls, scores = fitted["surrogate_classification"], fitted["surrogate_scores"]
    assert (cls["roc_auc_interval"] == "percentile").all() and (cls["roc_auc_resamples"] == 10_000).all()
    assert (cls["roc_auc_low"] <= cls["roc_auc"]).all() and (cls["roc_auc"] <= cls["roc_auc_high"]).all()
    assert (cls["roc_auc_interval_note"] == "").all()
    row = cls.set_index(["label", "model"]).loc[("success_vertical", "mlp")]
    g = scores[(scores["label"] == "success_vertical") & (scores["model"] == "mlp")]
    ci = auc_interval(g.loc[g["positive"], "score"], g.loc[~g["positive"], "score"], seed=5)
    assert (row["roc_auc_low"], row["roc_auc_high"]) == (ci.low, ci.high)
    assert row["roc_auc_low"] < row["roc_auc_high"]  # not a degenerate interval


def test_a_split_holding_out_one_positive_stores_the_auc_without_an_interval(surrogate_scenarios,
                                                                              surrogate_finalize):
    """10 positives (the fitting minimum) with a 10% held-out share leave 1 held-out positive, which
    no bootstrap can resample: finalize stored nothing and crashed after every trial had run."""
    df = surrogate_scenarios(200)
    df["success_unbounded"] = df.index < 10
    out = surrogate_finalize(df, test_fraction=0.1)
    cls = out["surrogate_classification"].set_index(["label", "model"]).loc["success_unbounded"]
    assert (cls["test_positives"] == 1).all() and cls["roc_auc"].between(0, 1).all()
    assert cls[["roc_auc_low", "roc_auc_high"]].isna().all().all()
    assert (cls["roc_auc_interval_note"] == "only 1 held-out positive, too few for an interval").all()
    assert (cls["roc_auc_resamples"] == 0).all() and (cls["roc_auc_interval"] == "").all()


def test_a_trial_without_a_label_is_no_training_example(surrogate_scenarios, surrogate_finalize):
    """100 of 400 scenarios have no ``success_vertical`` (null, as a Parquet file written before the
    reading reads): that label's classifiers are trained and scored on the 300 recorded, as on a run of
    those 300 alone (same split of their positions, same fits), where the 100 were negatives (400
    trials). The other labels are unchanged."""
    import pyarrow as pa

    full = surrogate_scenarios()
    unread = full.index % 4 == 0
    df = pa.Table.from_pandas(full.assign(success_vertical=full["success_vertical"].where(~unread)),
                              preserve_index=False).to_pandas()
    assert df["success_vertical"].isna().sum() == 100
    out = surrogate_finalize(df)["surrogate_classification"].set_index(["label", "model"])
    alone = surrogate_finalize(full[~unread].reset_index(drop=True))["surrogate_classification"]
    row = out.loc["success_vertical"]
    assert (row["trials"] == 300).all() and (row["test_trials"] == 60).all()
    assert (row["positives"] == int((full["mu"][~unread] > 0.3).sum())).all()
    pd.testing.assert_frame_equal(row.reset_index(drop=True), alone.set_index(["label", "model"]).loc[
        "success_vertical"].reset_index(drop=True))
    whole = surrogate_finalize(full)["surrogate_classification"].set_index(["label", "model"])
    pd.testing.assert_frame_equal(out.loc["success"], whole.loc["success"])


def _held_out(y: np.ndarray | None, n: int = 400, seed: int = 5) -> np.ndarray:
    """scikit-learn's own held-out 20 % of ``n`` positions: stratified on ``y`` (StratifiedShuffleSplit,
    which train_test_split(stratify=) draws from), or unstratified (ShuffleSplit) when ``y`` is None."""
    from sklearn.model_selection import ShuffleSplit, StratifiedShuffleSplit

    cv = (ShuffleSplit if y is None else StratifiedShuffleSplit)(n_splits=1, test_size=0.2,
                                                                 random_state=seed)
    return next(cv.split(np.zeros((n, 1)), y))[1]


def _diverging_labels(surrogate_scenarios):
    """Scenarios whose three labels differ: the configured check is rarer than Algorithm 1's label."""
    df = surrogate_scenarios()
    df["success"] = (df["mass_kg"] < 0.3) & (df["mu"] > 0.2)
    return df


def test_each_label_is_held_out_by_its_own_stratified_split(surrogate_scenarios, surrogate_finalize):
    """Every classifier is scored on the split stratified on its own label (seed recorded): its held-out
    classes, in order, are those of scikit-learn's StratifiedShuffleSplit on that label."""
    df = _diverging_labels(surrogate_scenarios)
    out = surrogate_finalize(df)
    cls, scores = out["surrogate_classification"], out["surrogate_scores"]
    assert (cls["split_label"] == cls["label"]).all() and (cls["split_seed"] == 5).all()
    for label in LABELS:
        y = df[label].to_numpy(bool)
        for model in ("mlp", "random_forest"):
            g = scores[(scores["label"] == label) & (scores["model"] == model)]
            assert g["positive"].tolist() == y[_held_out(y)].tolist()


def test_the_regressors_hold_out_appendix_as_split_on_the_papers_label(surrogate_scenarios,
                                                                       surrogate_finalize):
    """Appendix A: 'An 80/20 train/test split is used with stratification on the binary label' (one
    split): the regressors are scored on the split of Algorithm 1 as published, not of whichever label
    was fitted first (the configured check, whose split they used). The parity table's simulated
    values are the held-out trials' log10 ||R|| = 3 m, in held-out order."""
    df = _diverging_labels(surrogate_scenarios)
    out = surrogate_finalize(df)
    test = _held_out(df["success_unbounded"].to_numpy(bool))
    assert not np.array_equal(test, _held_out(df["success"].to_numpy(bool)))  # the old split differs
    held = out["surrogate_parity"]["simulated"].to_numpy()
    assert held == pytest.approx(3 * df["mass_kg"].to_numpy()[test])
    reg = out["surrogate_regression"]
    assert (reg["split_label"] == "success_unbounded").all() and (reg["split_seed"] == 5).all()
    assert (reg["test_trials"] == len(test)).all()


def test_without_the_papers_label_the_regressors_split_is_unstratified(surrogate_scenarios,
                                                                       surrogate_finalize):
    """Algorithm 1's label with too few positives to stratify on: the regressors are held out by an
    unstratified split of every trial (seed recorded), not by another label's."""
    df = _diverging_labels(surrogate_scenarios)
    df["success_unbounded"] = df.index < 5
    out = surrogate_finalize(df)
    test = _held_out(None, n=len(df))
    held = out["surrogate_parity"]["simulated"].to_numpy()
    assert held == pytest.approx(3 * df["mass_kg"].to_numpy()[test])
    reg = out["surrogate_regression"]
    assert (reg["split_label"] == "").all() and (reg["split_seed"] == 5).all()
