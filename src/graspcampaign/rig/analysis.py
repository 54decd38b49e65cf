"""Tests 2-3 statistics (paper §8.2-8.6, §9.2-9.5; Tables 6-9, Figs. 28-31, 33-36).

Every function takes ``records``: one row per trial attempt with the schedule columns
(:mod:`graspcampaign.rig.protocol`), the planner's predictions
(:func:`graspcampaign.rig.plan.predict_trial`) and the measured columns (the virtual rig or an
ingested file, :mod:`graspcampaign.rig.ingest`) -- see :func:`merge_records`. Aborted attempts are
dropped first: success denominators are executed trials (§8.1). Rates are in percent; signed
errors are measured - predicted; percentage errors are relative to the measured value.
Each function returns a pandas DataFrame (one row per planner, shape, block, ... as documented).

The statistics themselves come from :mod:`graspcampaign.stats` (Wilson 1927; Efron & Tibshirani
1993 cluster bootstrap over objects; McNemar 1947 on occurrence-matched pairs; Pearson chi2;
Kruskal & Wallis 1952; Bland & Altman 1986; logistic regression; Connor 1987 / Cohen 1988 power).
"""

from __future__ import annotations

import logging
import math
from collections.abc import Sequence

import numpy as np
import pandas as pd
from scipy import stats as sstats

from graspcampaign import stats
from graspcampaign.core.statics import GRAVITY

__all__ = [
    "PLANNER_ORDER",
    "block_summary",
    "coating_summary",
    "direction_summary",
    "executed",
    "failure_logistic",
    "first_finger_accuracy",
    "force_accuracy",
    "force_error_kruskal",
    "group_summary",
    "lateral_survival",
    "matched_mcnemar",
    "material_summary",
    "merge_records",
    "outcome_breakdown",
    "planner_chi2",
    "planner_summary",
    "power_analysis",
    "retention_classifier",
    "shape_summary",
    "slip_friction_kruskal",
    "stability_classifier",
    "threshold_agreement",
    "threshold_summary",
]

logger = logging.getLogger(__name__)

PLANNER_ORDER = ("heuristic", "centroid", "no_pso", "force_balance", "random")
"""Table 7 order (the proposed planner first)."""
PROPOSED = "heuristic"
FAILURE_CLASSES = ("failure_slip", "failure_drop", "failure_damage", "failure_contact_loss")


# --------------------------------------------------------------------------------------------
# Assembly
# --------------------------------------------------------------------------------------------
def merge_records(schedule: pd.DataFrame, predictions: pd.DataFrame,
                  measured: pd.DataFrame) -> pd.DataFrame:
    """Join schedule, predictions (same row order as the schedule) and measured (by trial_id).

    Parameters
    ----------
    schedule : DataFrame
        The study's schedule.
    predictions : DataFrame
        One row per schedule row, in schedule order (``predict_trial`` outputs).
    measured : DataFrame
        Measured columns with ``trial_id`` (virtual rig or :func:`validate_records`).

    Returns
    -------
    DataFrame
        One row per measured record (schedule rows without a record are left out).
    """
    if len(predictions) != len(schedule):
        raise ValueError(f"predictions must have one row per schedule row ({len(schedule)}), "
                         f"got {len(predictions)}")
    left = pd.concat([schedule.reset_index(drop=True), predictions.reset_index(drop=True)], axis=1)
    right = measured.drop(columns=[c for c in ("slot_id", "attempt") if c in measured])
    return left.merge(right, on="trial_id", how="inner", validate="one_to_one")


def executed(records: pd.DataFrame) -> pd.DataFrame:
    """Return the executed (non-aborted) trials with boolean outcome columns."""
    df = records[~records["aborted"].astype(bool)].copy()
    for c in ("success", "stable", "slip_flag", "drop_flag", "damage_flag", "contact_loss_flag",
              "predicted_stable", "retention_pred"):
        if c in df:
            df[c] = df[c].astype(bool)
    return df


def _pct(x) -> float:
    x = np.asarray(x, dtype=float)
    return float(100.0 * x.mean()) if x.size else math.nan


def _planners(df: pd.DataFrame) -> list[str]:
    present = set(df["planner"])
    return [p for p in PLANNER_ORDER if p in present] + sorted(present - set(PLANNER_ORDER))


def _rate_row(df: pd.DataFrame, n_resamples: int, seed: int) -> dict:
    n = len(df)
    k = int(df["success"].sum())
    wilson = stats.wilson_interval(k, n)
    per_object = df.groupby("object_id")["success"].agg(["sum", "size"])
    boot = stats.cluster_bootstrap_interval(per_object["sum"].to_numpy(),
                                            per_object["size"].to_numpy(),
                                            n_resamples=n_resamples, rng=seed)
    return {"n": n, "success_pct": 100.0 * wilson.estimate,
            "wilson_low_pct": 100.0 * wilson.low, "wilson_high_pct": 100.0 * wilson.high,
            "bootstrap_low_pct": 100.0 * boot.low, "bootstrap_high_pct": 100.0 * boot.high,
            "n_objects": int(len(per_object))}


# --------------------------------------------------------------------------------------------
# Success, outcome classes (Tables 6, 7, 9; Fig. 28, 31a, 36a)
# --------------------------------------------------------------------------------------------
def planner_summary(records: pd.DataFrame, *, n_resamples: int = 2000, seed: int = 0
                    ) -> pd.DataFrame:
    """Return success (Wilson and object-clustered bootstrap 95 % intervals) and outcome rates.

    Columns: ``planner, n, n_objects, success_pct, wilson_low_pct, wilson_high_pct,
    bootstrap_low_pct, bootstrap_high_pct, stable_pct, partial_pct, slip_pct, drop_pct,
    damage_pct, contact_loss_pct`` (primary outcome classes) and ``damage_any_pct`` (every
    damage flag, including co-occurring ones, §9.6). Table 7 (Test 2) / Table 9 (Test 3).
    """
    df = executed(records)
    rows = []
    for planner in _planners(df):
        g = df[df["planner"] == planner]
        row = {"planner": planner, **_rate_row(g, n_resamples, seed)}
        row.update({
            "stable_pct": _pct(g["outcome"] == "stable"),
            "partial_pct": _pct(g["outcome"] == "partial"),
            "slip_pct": _pct(g["outcome"] == "failure_slip"),
            "drop_pct": _pct(g["outcome"] == "failure_drop"),
            "damage_pct": _pct(g["outcome"] == "failure_damage"),
            "contact_loss_pct": _pct(g["outcome"] == "failure_contact_loss"),
            "damage_any_pct": _pct(g["damage_flag"]),
        })
        rows.append(row)
    return pd.DataFrame(rows)


def _natural(df: pd.DataFrame) -> pd.Series:
    return df["friction_level"] == "natural"


def _abs_pct_err(measured, predicted) -> np.ndarray:
    m = np.asarray(measured, dtype=float)
    p = np.asarray(predicted, dtype=float)
    ok = np.isfinite(m) & np.isfinite(p) & (m != 0.0)
    return 100.0 * np.abs(p[ok] - m[ok]) / np.abs(m[ok])


def _median(x) -> float:
    x = np.asarray(x, dtype=float)
    x = x[np.isfinite(x)]
    return float(np.median(x)) if x.size else math.nan


def shape_summary(records: pd.DataFrame, planner: str = PROPOSED) -> pd.DataFrame:
    """Return Table 6: per shape, the proposed planner's success and prediction errors.

    Columns: ``shape, n, success_pct`` (all trials, incl. group C), ``natural_n,
    natural_success_pct`` (natural friction only), ``flagged_n, flagged_success_pct`` (trials the
    planner flagged ``predicted_stable``), ``force_err_pct`` and ``deformation_err_pct`` (median
    absolute errors of the trial-mean normal force and deformation).
    """
    df = executed(records)
    df = df[df["planner"] == planner]
    rows = []
    for shape, g in df.groupby("shape", sort=False):
        nat = g[_natural(g)]
        flagged = g[g["predicted_stable"]]
        rows.append({
            "shape": shape, "n": len(g), "success_pct": _pct(g["success"]),
            "natural_n": len(nat), "natural_success_pct": _pct(nat["success"]),
            "flagged_n": len(flagged), "flagged_success_pct": _pct(flagged["success"]),
            "force_err_pct": _median(_abs_pct_err(g["normal_force_mean_n"],
                                                  g["normal_force_pred_mean_n"])),
            "deformation_err_pct": _median(_abs_pct_err(g["deformation_mean_mm"],
                                                        g["deformation_pred_mean_mm"])),
        })
    return pd.DataFrame(rows)


def material_summary(records: pd.DataFrame) -> pd.DataFrame:
    """Return success per material over all planners and for the proposed planner (Fig. 28b)."""
    df = executed(records)
    rows = []
    for material, g in df.groupby("material", sort=True):
        p = g[g["planner"] == PROPOSED]
        rows.append({"material": material, "n": len(g), "success_pct": _pct(g["success"]),
                     "proposed_n": len(p), "proposed_success_pct": _pct(p["success"])})
    return pd.DataFrame(rows)


def outcome_breakdown(records: pd.DataFrame) -> pd.DataFrame:
    """Return the fraction [%] of each outcome class per planner (Fig. 28c), one row per planner."""
    df = executed(records)
    table = pd.crosstab(df["planner"], df["outcome"], normalize="index") * 100.0
    order = ["stable", "success", "partial", *FAILURE_CLASSES]
    table = table.reindex(columns=[c for c in order if c in table.columns], fill_value=0.0)
    return table.reindex([p for p in _planners(df)]).reset_index()


def group_summary(records: pd.DataFrame, planner: str = PROPOSED) -> pd.DataFrame:
    """Return the proposed planner's success per Test 2 group, the validation pool and group E.

    Rows: each group (A-E, M), ``ABD`` (the validation groups, §8.2: 86.5 % in the paper),
    ``all``, and group E by closing speed (``E closing 5`` ...) and lift speed.
    """
    df = executed(records)
    df = df[df["planner"] == planner]
    rows = []

    def add(label, g):
        rows.append({"group": label, "n": len(g), "success_pct": _pct(g["success"]),
                     "stable_pct": _pct(g["outcome"] == "stable")})

    for group, g in df.groupby("group", sort=True):
        add(group, g)
    add("ABD", df[df["group"].isin(["A", "B", "D"])])
    add("all", df)
    e = df[df["group"] == "E"]
    for speed, g in e.groupby("closing_speed_mm_per_s"):
        add(f"E closing {speed:g} mm/s", g)
    for speed, g in e.groupby("lift_speed_mm_per_s"):
        add(f"E lift {speed:g} mm/s", g)
    return pd.DataFrame(rows)


# --------------------------------------------------------------------------------------------
# Prediction accuracy (Fig. 29) and the stability classifier (Fig. 31c)
# --------------------------------------------------------------------------------------------
def force_accuracy(records: pd.DataFrame) -> pd.DataFrame:
    """Return parity and median errors of the force and deformation predictions (§8.3).

    One row for all executed trials with a measured force (``all``), then one per planner.
    Columns: ``scope, n, parity_slope`` (measured on predicted trial-mean normal force, through
    the origin), ``parity_r2`` (uncentred, as through-origin software reports), ``parity_r2_centred``,
    ``force_err_pct``, ``deformation_err_pct`` (medians of absolute % errors) and
    ``contact_point_err_mm`` (median).
    """
    df = executed(records)
    rows = []
    for scope, g in [("all", df)] + [(p, df[df["planner"] == p]) for p in _planners(df)]:
        ok = np.isfinite(g["normal_force_mean_n"].astype(float)) & \
            np.isfinite(g["normal_force_pred_mean_n"].astype(float))
        h = g[ok]
        row = {"scope": scope, "n": len(h)}
        if len(h) >= 2 and np.any(h["normal_force_pred_mean_n"] != 0):
            fit = stats.parity_fit(h["normal_force_mean_n"], h["normal_force_pred_mean_n"])
            row.update(parity_slope=fit.slope_through_origin, parity_r2=fit.r2_uncentred,
                       parity_r2_centred=fit.r2_centred)
        row.update(
            force_err_pct=_median(_abs_pct_err(h["normal_force_mean_n"],
                                               h["normal_force_pred_mean_n"])),
            deformation_err_pct=_median(_abs_pct_err(h["deformation_mean_mm"],
                                                     h["deformation_pred_mean_mm"])),
            contact_point_err_mm=_median(h["contact_point_error_mm"]))
        rows.append(row)
    return pd.DataFrame(rows)


def _classifier_row(scope: str, predicted, actual) -> dict:
    predicted = np.asarray(predicted, dtype=bool)
    actual = np.asarray(actual, dtype=bool)
    if predicted.size == 0:
        return {"scope": scope, "n": 0}
    m = stats.classifier_metrics(predicted, actual)
    return {"scope": scope, "n": m.n, "accuracy": m.accuracy, "precision": m.precision,
            "recall": m.recall, "f1": m.f1, "tp": m.tp, "fp": m.fp, "fn": m.fn, "tn": m.tn,
            "certified": int(predicted.sum()), "false_certified": m.fp}


def stability_classifier(records: pd.DataFrame) -> pd.DataFrame:
    """Return the ``predicted_stable`` flag scored against measured success (§8.4, Fig. 31c).

    Rows: ``all``, ``baselines``, each planner, ``group C`` and ``outside C`` (proposed planner),
    with ``n, accuracy, precision, recall, f1, tp, fp, fn, tn, certified, false_certified``.
    """
    df = executed(records)
    rows = [_classifier_row("all", df["predicted_stable"], df["success"])]
    base = df[df["planner"] != PROPOSED]
    rows.append(_classifier_row("baselines", base["predicted_stable"], base["success"]))
    for p in _planners(df):
        g = df[df["planner"] == p]
        rows.append(_classifier_row(p, g["predicted_stable"], g["success"]))
    prop = df[df["planner"] == PROPOSED]
    if "group" in prop:
        for scope, g in (("group C", prop[prop["group"] == "C"]),
                         ("outside C", prop[prop["group"] != "C"])):
            rows.append(_classifier_row(scope, g["predicted_stable"], g["success"]))
    return pd.DataFrame(rows)


def retention_classifier(records: pd.DataFrame) -> pd.DataFrame:
    """Return the pre-disturbance retention flag scored against measured success (§9.5, Fig. 36c).

    Rows ``all`` and one per planner; columns as :func:`stability_classifier`.
    """
    df = executed(records)
    rows = [_classifier_row("all", df["retention_pred"], df["success"])]
    for p in _planners(df):
        g = df[df["planner"] == p]
        rows.append(_classifier_row(p, g["retention_pred"], g["success"]))
    return pd.DataFrame(rows)


# --------------------------------------------------------------------------------------------
# Paired and contingency tests (§8.5, §9.5)
# --------------------------------------------------------------------------------------------
def _match_key(df: pd.DataFrame) -> pd.Series:
    return df["object_id"].astype(str) + "|" + df["condition"].astype(str) + "|" + \
        df["repeat"].astype(str)


def matched_mcnemar(records: pd.DataFrame, baselines: Sequence[str] | None = None
                    ) -> pd.DataFrame:
    """Return McNemar tests of the proposed planner against each baseline on the matched set.

    Pairs are occurrence-matched: the same object, condition and repeat index (one executed
    attempt per slot), so every pair faced the same scene. Columns: ``baseline, n_pairs,
    proposed_success_pct, baseline_success_pct, difference_pp, won`` (proposed succeeded,
    baseline failed), ``lost, chi2, p_chi2, p_exact, odds_ratio, odds_ratio_low,
    odds_ratio_high``.
    """
    df = executed(records)
    df = df[df["matched"].astype(bool)].copy()
    df["key"] = _match_key(df)
    prop = df[df["planner"] == PROPOSED].set_index("key")["success"]
    rows = []
    for b in baselines or [p for p in _planners(df) if p != PROPOSED]:
        base = df[df["planner"] == b].set_index("key")["success"]
        common = prop.index.intersection(base.index)
        a, c = prop.loc[common].to_numpy(bool), base.loc[common].to_numpy(bool)
        n01, n10 = stats.discordant_pairs(a, c) if len(common) else (0, 0)
        res = stats.mcnemar(n01, n10)
        rows.append({"baseline": b, "n_pairs": len(common),
                     "proposed_success_pct": _pct(a), "baseline_success_pct": _pct(c),
                     "difference_pp": _pct(a) - _pct(c), "won": n10, "lost": n01,
                     "chi2": res.statistic, "p_chi2": res.pvalue_chi2, "p_exact": res.pvalue_exact,
                     "odds_ratio": res.odds_ratio, "odds_ratio_low": res.odds_ratio_low,
                     "odds_ratio_high": res.odds_ratio_high})
    return pd.DataFrame(rows)


def planner_chi2(records: pd.DataFrame,
                 planners: Sequence[str] = ("heuristic", "centroid", "random")) -> pd.DataFrame:
    """Return Pearson's chi2 of planner x success over all executed trials of ``planners``.

    The paper's three-way tests: Test 2 proposed/centroid/random (chi2 = 270.0), Test 3 retention
    across the same arms (chi2 = 221). One row: ``planners, n, chi2, dof, p``.
    """
    df = executed(records)
    df = df[df["planner"].isin(planners)]
    table = pd.crosstab(df["planner"], df["success"]).reindex(columns=[True, False], fill_value=0)
    res = stats.chi2_contingency_test(table.to_numpy())
    return pd.DataFrame([{"planners": ",".join(planners), "n": len(df), "chi2": res.statistic,
                          "dof": res.dof, "p": res.pvalue}])


def _kruskal_row(samples: dict[str, np.ndarray], median_prefix: str) -> pd.DataFrame:
    """Kruskal-Wallis over the non-empty finite samples, with each sample's median."""
    groups = {label: x for label, x in samples.items() if x.size}
    res = stats.kruskal_wallis(*groups.values())
    medians = {f"{median_prefix}{label}": float(np.median(x)) for label, x in groups.items()}
    return pd.DataFrame([{"n": res.n, "n_groups": res.n_groups, "H": res.statistic,
                          "p": res.pvalue, **medians}])


def force_error_kruskal(records: pd.DataFrame) -> pd.DataFrame:
    """Return Kruskal-Wallis of the absolute force-prediction error across planners (§8.5).

    Columns: ``n, n_groups, H, p`` and the per-planner medians ``median_err_pct_<planner>``.
    """
    df = executed(records)
    samples = {}
    for p in _planners(df):
        g = df[df["planner"] == p]
        samples[p] = _abs_pct_err(g["normal_force_mean_n"], g["normal_force_pred_mean_n"])
    return _kruskal_row(samples, "median_err_pct_")


def slip_friction_kruskal(records: pd.DataFrame) -> pd.DataFrame:
    """Return Kruskal-Wallis of peak slip across friction levels over all executed trials (§8.6).

    Columns: ``n, n_groups, H, p`` and ``median_slip_mm_<level>``.
    """
    df = executed(records)
    samples = {}
    for level, g in df.groupby("friction_level", sort=True):
        slip = g["peak_slip_mm"].astype(float).to_numpy()
        samples[level] = slip[np.isfinite(slip)]
    return _kruskal_row(samples, "median_slip_mm_")


# --------------------------------------------------------------------------------------------
# Test 3: thresholds, blocks, first finger, survival, logistic (Tables 8-9, Figs. 33-36)
# --------------------------------------------------------------------------------------------
def _thresholds(df: pd.DataFrame, block: str) -> tuple[np.ndarray, np.ndarray, pd.DataFrame]:
    """Measured and predicted thresholds of a block's uncensored trials (N, or N m for C)."""
    g = df[df["block"] == block]
    col = ("threshold_measured_nm", "threshold_pred_nm") if block == "C" else \
        ("threshold_measured_n", "threshold_pred_n")
    censored = g["threshold_censored"].astype(bool) if "threshold_censored" in g else False
    m = g[col[0]].astype(float)
    p = g[col[1]].astype(float)
    ok = np.isfinite(m) & np.isfinite(p) & (m > 0) & ~censored
    return m[ok].to_numpy(), p[ok].to_numpy(), g[ok]


def threshold_summary(records: pd.DataFrame) -> pd.DataFrame:
    """Return per planner the median lateral threshold and its prediction error (Table 9).

    Over all block-A trials (natural and coating probes) with a measured, uncensored threshold.
    Columns: ``planner, n, lat_threshold_median_n, lat_threshold_err_pct`` (median absolute %
    error), ``lat_bias_n`` (mean measured - predicted).
    """
    df = executed(records)
    rows = []
    for p in _planners(df):
        m, pr, _ = _thresholds(df[df["planner"] == p], "A")
        rows.append({"planner": p, "n": int(m.size), "lat_threshold_median_n": _median(m),
                     "lat_threshold_err_pct": _median(_abs_pct_err(m, pr)),
                     "lat_bias_n": float(np.mean(m - pr)) if m.size else math.nan})
    return pd.DataFrame(rows)


def block_summary(records: pd.DataFrame, planner: str = PROPOSED) -> pd.DataFrame:
    """Return Table 8: the proposed planner's natural-friction blocks.

    Columns: ``block, disturbance, n, success_pct, headline`` (A: median lateral threshold [N];
    B: median downward threshold as % of W; C: median torque [N m]; D, E: median peak slip
    [mm]), ``headline_unit``, ``n_thresholds`` (uncensored thresholds measured),
    ``threshold_err_pct`` (median absolute % error), ``parity_r2_centred``.
    """
    df = executed(records)
    df = df[(df["planner"] == planner) & _natural(df)]
    rows = []
    for block, g in df.groupby("block", sort=True):
        m, p, h = _thresholds(g, block)
        if block == "A":
            headline, unit = _median(m), "N"
        elif block == "B":
            down = h[h["disturbance_kind"] == "down"]
            weight = down["mass_kg"].astype(float) * GRAVITY
            headline = _median(100.0 * down["threshold_measured_n"].astype(float) / weight)
            unit = "% W"
        elif block == "C":
            headline, unit = _median(m), "N m"
        else:
            headline, unit = _median(g["peak_slip_mm"]), "mm slip"
        r2 = math.nan
        if m.size >= 3 and np.any(p != 0):
            r2 = stats.parity_fit(m, p).r2_centred
        rows.append({"block": block, "disturbance": str(g["disturbance"].iloc[0]), "n": len(g),
                     "success_pct": _pct(g["success"]), "headline": headline,
                     "headline_unit": unit, "n_thresholds": int(m.size),
                     "threshold_err_pct": _median(_abs_pct_err(m, p)),
                     "parity_r2_centred": r2})
    rows.append({"block": "all", "disturbance": "natural-friction blocks", "n": len(df),
                 "success_pct": _pct(df["success"])})
    return pd.DataFrame(rows)


def threshold_agreement(records: pd.DataFrame, planner: str = PROPOSED) -> pd.DataFrame:
    """Return Bland-Altman and parity of predicted vs measured lateral thresholds (Fig. 34).

    Over the planner's block-A trials (natural and coating probes) with an uncensored measured
    threshold. One row: ``n, bias_n, sd_n, loa_low_n, loa_high_n`` (measured - predicted),
    ``ols_slope, ols_intercept, ols_r2, ols_p`` (measured on predicted, with intercept),
    ``parity_slope, parity_r2`` (through the origin), ``median_err_pct``, ``n_err_over_50pct``.
    """
    df = executed(records)
    m, p, _ = _thresholds(df[df["planner"] == planner], "A")
    row: dict = {"planner": planner, "n": int(m.size)}
    if m.size >= 3:
        ba = stats.bland_altman(m, p)
        lin = sstats.linregress(p, m)
        row.update(bias_n=ba.bias, sd_n=ba.sd, loa_low_n=ba.lower, loa_high_n=ba.upper,
                   ols_slope=float(lin.slope), ols_intercept=float(lin.intercept),
                   ols_r2=float(lin.rvalue**2), ols_p=float(lin.pvalue))
        if np.any(p != 0):
            fit = stats.parity_fit(m, p)
            row.update(parity_slope=fit.slope_through_origin, parity_r2=fit.r2_uncentred)
        err = _abs_pct_err(m, p)
        row.update(median_err_pct=_median(err), n_err_over_50pct=int(np.sum(err > 50.0)))
    return pd.DataFrame([row])


def first_finger_accuracy(records: pd.DataFrame) -> pd.DataFrame:
    """Return how often the predicted first finger to slip is the measured one (§9.3).

    Over trials whose measured first finger is known (1-3). Rows ``all`` and per planner:
    ``n, correct, accuracy_pct``.
    """
    df = executed(records)
    df = df[df["first_finger_measured"].fillna(0).astype(int) > 0]
    rows = []
    for scope, g in [("all", df)] + [(p, df[df["planner"] == p]) for p in _planners(df)]:
        correct = int((g["first_finger_pred"].astype(int)
                       == g["first_finger_measured"].astype(int)).sum())
        rows.append({"scope": scope, "n": len(g), "correct": correct,
                     "accuracy_pct": 100.0 * correct / len(g) if len(g) else math.nan})
    return pd.DataFrame(rows)


def lateral_survival(records: pd.DataFrame, levels: Sequence[float] | None = None,
                     planners: Sequence[str] = ("heuristic", "centroid")) -> pd.DataFrame:
    """Return the survival curve of the lateral threshold at natural friction (Fig. 36b).

    The fraction of each planner's natural-friction block-A trials that sustain at least each
    level (a trial that dropped or failed before the pull counts as 0 N; a censored threshold
    counts at the cap). Long format: ``planner, level_n, surviving_fraction, n``.
    """
    df = executed(records)
    df = df[(df["block"] == "A") & _natural(df)]
    grid = np.asarray(levels if levels is not None else np.arange(0.0, 8.01, 0.25), dtype=float)
    rows = []
    for p in planners:
        g = df[df["planner"] == p]
        if g.empty:
            continue
        thr = g["threshold_measured_n"].astype(float).fillna(0.0).to_numpy()
        curve = stats.survival_curve(thr, grid)
        rows += [{"planner": p, "level_n": float(lv), "surviving_fraction": float(f), "n": curve.n}
                 for lv, f in zip(curve.levels, curve.surviving_fraction, strict=True)]
    return pd.DataFrame(rows)


def failure_logistic(records: pd.DataFrame) -> pd.DataFrame:
    """Return the logistic regression of failure over the fixed-load blocks B, D, E (§9.5).

    Predictors: applied load [N] (``load_n``, the sinusoid amplitude for E), object mass [kg],
    the believed friction coefficient of the surface, and the proposed-planner indicator.
    Columns: ``term, coef, se, z, p, ci_low, ci_high`` plus ``n, converged, separation``.
    """
    df = executed(records)
    df = df[df["block"].isin(["B", "D", "E"])].copy()
    df["failed"] = (~df["success"]).astype(int)
    df["load"] = df["load_n"].astype(float)
    df["mass"] = df["mass_kg"].astype(float)
    df["mu"] = df["mu_s_believed"].astype(float)
    df["proposed"] = (df["planner"] == PROPOSED).astype(int)
    res = stats.logistic_regression(df, "failed", ["load", "mass", "mu", "proposed"])
    table = res.coefficients.reset_index().rename(columns={"index": "term"})
    table["n"] = res.n
    table["converged"] = res.converged
    table["separation"] = res.separation_kind
    return table


def coating_summary(records: pd.DataFrame, planner: str = PROPOSED) -> pd.DataFrame:
    """Return block-A success and median lateral threshold per friction level (Fig. 33a)."""
    df = executed(records)
    df = df[(df["planner"] == planner) & (df["block"] == "A")]
    rows = []
    for level, g in df.groupby("friction_level", sort=False):
        m, p, _ = _thresholds(g, "A")
        rows.append({"friction_level": level, "n": len(g), "success_pct": _pct(g["success"]),
                     "threshold_median_n": _median(m),
                     "threshold_err_pct": _median(_abs_pct_err(m, p))})
    return pd.DataFrame(rows)


def direction_summary(records: pd.DataFrame, planner: str = PROPOSED) -> pd.DataFrame:
    """Return the median natural-friction lateral threshold per pull direction (Fig. 33b)."""
    df = executed(records)
    df = df[(df["planner"] == planner) & (df["block"] == "A") & _natural(df)]
    rows = []
    for direction, g in df.groupby("direction_deg", sort=True):
        m, _, _ = _thresholds(g, "A")
        rows.append({"direction_deg": float(direction), "n": len(g),
                     "threshold_median_n": _median(m), "success_pct": _pct(g["success"])})
    return pd.DataFrame(rows)


# --------------------------------------------------------------------------------------------
# Power (§11: the ablation lacked power)
# --------------------------------------------------------------------------------------------
def power_analysis(p1: float, p2: float, *, alpha: float = 0.05,
                   powers: Sequence[float] = (0.8, 0.9), paired_discordant: float | None = None
                   ) -> pd.DataFrame:
    """Return the trials per arm needed to detect success rates ``p1`` vs ``p2``.

    One row per (design, power): ``design`` ``independent`` (two arms, Cohen's h) and
    ``paired`` (matched pairs with McNemar, Connor 1987; ``paired_discordant`` is the expected
    discordant fraction, default the independence value), with ``n_per_arm``.
    """
    rows = []
    for power in powers:
        for paired in (False, True):
            res = stats.power_two_proportions(
                p1, p2, alpha=alpha, power=power, paired=paired,
                discordant=paired_discordant if paired else None)
            rows.append({"design": "paired" if paired else "independent", "p1": p1, "p2": p2,
                         "alpha": alpha, "power": power, "n_per_arm": res.n_per_arm,
                         "effect_size": res.effect_size, "effect_size_kind": res.effect_size_kind})
    return pd.DataFrame(rows)
