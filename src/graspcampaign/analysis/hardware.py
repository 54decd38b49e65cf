"""Test 2 statistics (paper §8.2-8.6; Tables 6-7, Figs. 28-31) and what Tests 2-3 share.

Every function takes ``records``: one row per trial attempt with the schedule columns, the
planner's predictions and the measured columns (the virtual rig or an ingested file) -- see
:func:`merge_records`. Only executed trials enter a statistic
(:func:`graspcampaign.analysis.records.executed`: aborted attempts and errored trials are
dropped, §8.1). Rates are in percent; signed errors are measured - predicted; percentage errors
are relative to the measured value. Each function returns a DataFrame at full precision.

References
----------
Wilson (1927); Efron & Tibshirani (1993) cluster bootstrap over objects; McNemar (1947) on
occurrence-matched pairs; Pearson chi2; Kruskal & Wallis (1952); Connor (1987) / Cohen (1988).
"""

from __future__ import annotations

import math
from collections.abc import Sequence

import numpy as np
import pandas as pd

from graspcampaign.analysis import agreement, association, rates
from graspcampaign.analysis.records import executed, rate_cells
from graspcampaign.analysis.vocabulary import PROPOSED, ordered

FAILURE_CLASSES = ("failure_slip", "failure_drop", "failure_damage", "failure_contact_loss")


def natural(df: pd.DataFrame) -> pd.Series:
    """Return the mask of trials at the surface's natural friction (no coating probe)."""
    return df["friction_level"] == "natural"


def planners_present(df: pd.DataFrame) -> list[str]:
    """Return the planners of ``df`` in the shared vocabulary's order."""
    return ordered("planner", df["planner"])


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


def percent(x) -> float:
    """Return the mean of a boolean array in percent (nan when empty)."""
    x = np.asarray(x, dtype=float)
    return float(100.0 * x.mean()) if x.size else math.nan


def planner_summary(records: pd.DataFrame, *, seed: int,
                    n_resamples: int = rates.BOOTSTRAP_RESAMPLES) -> pd.DataFrame:
    """Return success (Wilson and object-clustered bootstrap 95 % intervals) and outcome rates.

    Columns: ``planner, n, n_objects, success_pct, wilson_low_pct, wilson_high_pct,
    bootstrap_low_pct, bootstrap_high_pct`` (objects resampled, ``seed`` the study seed;
    nan with the reason in ``bootstrap_why`` below two objects), ``stable_pct, partial_pct,
    slip_pct, drop_pct, damage_pct, contact_loss_pct`` (primary outcome classes) and ``damage_any_pct`` (every
    damage flag, including co-occurring ones, §9.6). Table 7 (Test 2) / Table 9 (Test 3).
    """
    df = executed(records)
    rows = []
    for planner in planners_present(df):
        g = df[df["planner"] == planner]
        cells = rate_cells(g, "success", "object_id", seed, n_resamples)
        row = {"planner": planner, "n": len(g), "n_objects": cells["n_clusters"],
               "success_pct": cells["rate_pct"],
               **{k: cells[k] for k in ("wilson_low_pct", "wilson_high_pct", "bootstrap_low_pct",
                                        "bootstrap_high_pct", "bootstrap_why")}}
        row.update({
            "stable_pct": percent(g["outcome"] == "stable"),
            "partial_pct": percent(g["outcome"] == "partial"),
            "slip_pct": percent(g["outcome"] == "failure_slip"),
            "drop_pct": percent(g["outcome"] == "failure_drop"),
            "damage_pct": percent(g["outcome"] == "failure_damage"),
            "contact_loss_pct": percent(g["outcome"] == "failure_contact_loss"),
            "damage_any_pct": percent(g["damage_flag"]),
        })
        rows.append(row)
    return pd.DataFrame(rows)


def abs_pct_error(measured, predicted) -> np.ndarray:
    """Return ``100 |predicted - measured| / |measured|`` over the finite, non-zero pairs."""
    m = np.asarray(measured, dtype=float)
    p = np.asarray(predicted, dtype=float)
    ok = np.isfinite(m) & np.isfinite(p) & (m != 0.0)
    return 100.0 * np.abs(p[ok] - m[ok]) / np.abs(m[ok])


def finite_median(x) -> float:
    """Return the median of the finite values of ``x`` (nan when there are none)."""
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
        nat = g[natural(g)]
        flagged = g[g["predicted_stable"]]
        rows.append({
            "shape": shape, "n": len(g), "success_pct": percent(g["success"]),
            "natural_n": len(nat), "natural_success_pct": percent(nat["success"]),
            "flagged_n": len(flagged), "flagged_success_pct": percent(flagged["success"]),
            "force_err_pct": finite_median(abs_pct_error(g["normal_force_mean_n"],
                                                  g["normal_force_pred_mean_n"])),
            "deformation_err_pct": finite_median(abs_pct_error(g["deformation_mean_mm"],
                                                        g["deformation_pred_mean_mm"])),
        })
    return pd.DataFrame(rows)


def material_summary(records: pd.DataFrame) -> pd.DataFrame:
    """Return success per material over all planners and for the proposed planner (Fig. 28b)."""
    df = executed(records)
    rows = []
    for material, g in df.groupby("material", sort=True):
        p = g[g["planner"] == PROPOSED]
        rows.append({"material": material, "n": len(g), "success_pct": percent(g["success"]),
                     "proposed_n": len(p), "proposed_success_pct": percent(p["success"])})
    return pd.DataFrame(rows)


def outcome_breakdown(records: pd.DataFrame) -> pd.DataFrame:
    """Return the fraction [%] of each outcome class per planner (Fig. 28c), one row per planner."""
    df = executed(records)
    table = pd.crosstab(df["planner"], df["outcome"], normalize="index") * 100.0
    order = ["stable", "success", "partial", *FAILURE_CLASSES]
    table = table.reindex(columns=[c for c in order if c in table.columns], fill_value=0.0)
    return table.reindex([p for p in planners_present(df)]).reset_index()


def group_summary(records: pd.DataFrame, planner: str = PROPOSED) -> pd.DataFrame:
    """Return the proposed planner's success per Test 2 group, the validation pool and group E.

    Rows: each group (A-E, M), ``ABD`` (the validation groups, §8.2: 86.5 % in the paper),
    ``all``, and group E by closing speed (``E closing 5`` ...) and lift speed.
    """
    df = executed(records)
    df = df[df["planner"] == planner]
    rows = []

    def add(label, g):
        rows.append({"group": label, "n": len(g), "success_pct": percent(g["success"]),
                     "stable_pct": percent(g["outcome"] == "stable")})

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
    for scope, g in [("all", df)] + [(p, df[df["planner"] == p]) for p in planners_present(df)]:
        ok = np.isfinite(g["normal_force_mean_n"].astype(float)) & \
            np.isfinite(g["normal_force_pred_mean_n"].astype(float))
        h = g[ok]
        row = {"scope": scope, "n": len(h)}
        if len(h) >= 2 and np.any(h["normal_force_pred_mean_n"] != 0):
            fit = agreement.parity_fit(h["normal_force_mean_n"], h["normal_force_pred_mean_n"])
            row.update(parity_slope=fit.slope_through_origin, parity_r2=fit.r2_uncentred,
                       parity_r2_centred=fit.r2_centred)
        row.update(
            force_err_pct=finite_median(abs_pct_error(h["normal_force_mean_n"],
                                               h["normal_force_pred_mean_n"])),
            deformation_err_pct=finite_median(abs_pct_error(h["deformation_mean_mm"],
                                                     h["deformation_pred_mean_mm"])),
            contact_point_err_mm=finite_median(h["contact_point_error_mm"]))
        rows.append(row)
    return pd.DataFrame(rows)


def classifier_row(scope: str, predicted, actual) -> dict:
    """Return the classifier scores of a boolean flag against measured success, as a row."""
    predicted = np.asarray(predicted, dtype=bool)
    actual = np.asarray(actual, dtype=bool)
    if predicted.size == 0:
        return {"scope": scope, "n": 0}
    m = agreement.classifier_metrics(predicted, actual)
    return {"scope": scope, "n": m.n, "accuracy": m.accuracy, "precision": m.precision,
            "recall": m.recall, "f1": m.f1, "tp": m.tp, "fp": m.fp, "fn": m.fn, "tn": m.tn,
            "certified": int(predicted.sum()), "false_certified": m.fp}


def stability_classifier(records: pd.DataFrame) -> pd.DataFrame:
    """Return the ``predicted_stable`` flag scored against measured success (§8.4, Fig. 31c).

    Rows: ``all``, ``baselines``, each planner, ``group C`` and ``outside C`` (proposed planner),
    with ``n, accuracy, precision, recall, f1, tp, fp, fn, tn, certified, false_certified``.
    """
    df = executed(records)
    rows = [classifier_row("all", df["predicted_stable"], df["success"])]
    base = df[df["planner"] != PROPOSED]
    rows.append(classifier_row("baselines", base["predicted_stable"], base["success"]))
    for p in planners_present(df):
        g = df[df["planner"] == p]
        rows.append(classifier_row(p, g["predicted_stable"], g["success"]))
    prop = df[df["planner"] == PROPOSED]
    if "group" in prop:
        for scope, g in (("group C", prop[prop["group"] == "C"]),
                         ("outside C", prop[prop["group"] != "C"])):
            rows.append(classifier_row(scope, g["predicted_stable"], g["success"]))
    return pd.DataFrame(rows)


# --------------------------------------------------------------------------------------------
# Paired and contingency tests (§8.5, §9.5)
# --------------------------------------------------------------------------------------------
def match_key(df: pd.DataFrame) -> pd.Series:
    """Return the matched-set key of each trial: object, condition and repeat index."""
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
    df["key"] = match_key(df)
    prop = df[df["planner"] == PROPOSED].set_index("key")["success"]
    rows = []
    for b in baselines or [p for p in planners_present(df) if p != PROPOSED]:
        base = df[df["planner"] == b].set_index("key")["success"]
        common = prop.index.intersection(base.index)
        a, c = prop.loc[common].to_numpy(bool), base.loc[common].to_numpy(bool)
        n01, n10 = rates.discordant_pairs(a, c) if len(common) else (0, 0)
        res = rates.mcnemar(n01, n10)
        rows.append({"baseline": b, "n_pairs": len(common),
                     "proposed_success_pct": percent(a), "baseline_success_pct": percent(c),
                     "difference_pp": percent(a) - percent(c), "won": n10, "lost": n01,
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
    res = association.chi2_contingency_test(table.to_numpy())
    return pd.DataFrame([{"planners": ",".join(planners), "n": len(df), "chi2": res.statistic,
                          "dof": res.dof, "p": res.pvalue}])


def kruskal_row(samples: dict[str, np.ndarray], median_prefix: str) -> pd.DataFrame:
    """Kruskal-Wallis over the non-empty finite samples, with each sample's median."""
    groups = {label: x for label, x in samples.items() if x.size}
    res = association.kruskal_wallis(*groups.values())
    medians = {f"{median_prefix}{label}": float(np.median(x)) for label, x in groups.items()}
    return pd.DataFrame([{"n": res.n, "n_groups": res.n_groups, "H": res.statistic,
                          "p": res.pvalue, **medians}])


def force_error_kruskal(records: pd.DataFrame) -> pd.DataFrame:
    """Return Kruskal-Wallis of the absolute force-prediction error across planners (§8.5).

    Columns: ``n, n_groups, H, p`` and the per-planner medians ``median_err_pct_<planner>``.
    """
    df = executed(records)
    samples = {}
    for p in planners_present(df):
        g = df[df["planner"] == p]
        samples[p] = abs_pct_error(g["normal_force_mean_n"], g["normal_force_pred_mean_n"])
    return kruskal_row(samples, "median_err_pct_")


def slip_friction_kruskal(records: pd.DataFrame) -> pd.DataFrame:
    """Return Kruskal-Wallis of peak slip across friction levels over all executed trials (§8.6).

    Columns: ``n, n_groups, H, p`` and ``median_slip_mm_<level>``.
    """
    df = executed(records)
    samples = {}
    for level, g in df.groupby("friction_level", sort=True):
        slip = g["peak_slip_mm"].astype(float).to_numpy()
        samples[level] = slip[np.isfinite(slip)]
    return kruskal_row(samples, "median_slip_mm_")


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
            res = rates.power_two_proportions(
                p1, p2, alpha=alpha, power=power, paired=paired,
                discordant=paired_discordant if paired else None)
            rows.append({"design": "paired" if paired else "independent", "p1": p1, "p2": p2,
                         "alpha": alpha, "power": power, "n_per_arm": res.n_per_arm,
                         "effect_size": res.effect_size, "effect_size_kind": res.effect_size_kind})
    return pd.DataFrame(rows)
