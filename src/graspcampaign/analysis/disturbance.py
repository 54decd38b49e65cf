"""Test 3 statistics (paper §9.2-9.5; Tables 8-9, Figs. 33-36): thresholds and retention.

Thresholds are compared only where a ramp ended in slip: a ramp that reached its cap or its
commanded level gives a lower bound (censored), never a number (:func:`thresholds`). Conventions
as in :mod:`graspcampaign.analysis.hardware`.

References
----------
Bland & Altman (1986); Kaplan & Meier (1958) (uncensored survival); logistic regression.
"""

from __future__ import annotations

import math
from collections.abc import Sequence

import numpy as np
import pandas as pd
from scipy import stats as sstats

from graspcampaign.analysis import agreement, association
from graspcampaign.analysis.hardware import (
    abs_pct_error,
    classifier_row,
    finite_median,
    natural,
    percent,
    planners_present,
)
from graspcampaign.analysis.records import executed
from graspcampaign.analysis.vocabulary import PROPOSED
from graspcampaign.core.statics import GRAVITY


def thresholds(df: pd.DataFrame, block: str) -> tuple[np.ndarray, np.ndarray, pd.DataFrame]:
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
    for p in planners_present(df):
        m, pr, _ = thresholds(df[df["planner"] == p], "A")
        rows.append({"planner": p, "n": int(m.size), "lat_threshold_median_n": finite_median(m),
                     "lat_threshold_err_pct": finite_median(abs_pct_error(m, pr)),
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
    df = df[(df["planner"] == planner) & natural(df)]
    rows = []
    for block, g in df.groupby("block", sort=True):
        m, p, h = thresholds(g, block)
        if block == "A":
            headline, unit = finite_median(m), "N"
        elif block == "B":
            down = h[h["disturbance_kind"] == "down"]
            weight = down["mass_kg"].astype(float) * GRAVITY
            headline = finite_median(100.0 * down["threshold_measured_n"].astype(float) / weight)
            unit = "% W"
        elif block == "C":
            headline, unit = finite_median(m), "N m"
        else:
            headline, unit = finite_median(g["peak_slip_mm"]), "mm slip"
        r2 = math.nan
        if m.size >= 3 and np.any(p != 0):
            r2 = agreement.parity_fit(m, p).r2_centred
        rows.append({"block": block, "disturbance": str(g["disturbance"].iloc[0]), "n": len(g),
                     "success_pct": percent(g["success"]), "headline": headline,
                     "headline_unit": unit, "n_thresholds": int(m.size),
                     "threshold_err_pct": finite_median(abs_pct_error(m, p)),
                     "parity_r2_centred": r2})
    rows.append({"block": "all", "disturbance": "natural-friction blocks", "n": len(df),
                 "success_pct": percent(df["success"])})
    return pd.DataFrame(rows)


def threshold_agreement(records: pd.DataFrame, planner: str = PROPOSED) -> pd.DataFrame:
    """Return Bland-Altman and parity of predicted vs measured lateral thresholds (Fig. 34).

    Over the planner's block-A trials (natural and coating probes) with an uncensored measured
    threshold. One row: ``n, bias_n, sd_n, loa_low_n, loa_high_n`` (measured - predicted),
    ``ols_slope, ols_intercept, ols_r2, ols_p`` (measured on predicted, with intercept),
    ``parity_slope, parity_r2`` (through the origin), ``median_err_pct``, ``n_err_over_50pct``.
    """
    df = executed(records)
    m, p, _ = thresholds(df[df["planner"] == planner], "A")
    row: dict = {"planner": planner, "n": int(m.size)}
    if m.size >= 3:
        ba = agreement.bland_altman(m, p)
        lin = sstats.linregress(p, m)
        row.update(bias_n=ba.bias, sd_n=ba.sd, loa_low_n=ba.lower, loa_high_n=ba.upper,
                   ols_slope=float(lin.slope), ols_intercept=float(lin.intercept),
                   ols_r2=float(lin.rvalue**2), ols_p=float(lin.pvalue))
        if np.any(p != 0):
            fit = agreement.parity_fit(m, p)
            row.update(parity_slope=fit.slope_through_origin, parity_r2=fit.r2_uncentred)
        err = abs_pct_error(m, p)
        row.update(median_err_pct=finite_median(err), n_err_over_50pct=int(np.sum(err > 50.0)))
    return pd.DataFrame([row])


def first_finger_accuracy(records: pd.DataFrame) -> pd.DataFrame:
    """Return how often the predicted first finger to slip is the measured one (§9.3).

    Over trials whose measured first finger is known (1-3). Rows ``all`` and per planner:
    ``n, correct, accuracy_pct``.
    """
    df = executed(records)
    df = df[df["first_finger_measured"].fillna(0).astype(int) > 0]
    rows = []
    for scope, g in [("all", df)] + [(p, df[df["planner"] == p]) for p in planners_present(df)]:
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
    df = df[(df["block"] == "A") & natural(df)]
    grid = np.asarray(levels if levels is not None else np.arange(0.0, 8.01, 0.25), dtype=float)
    rows = []
    for p in planners:
        g = df[df["planner"] == p]
        if g.empty:
            continue
        thr = g["threshold_measured_n"].astype(float).fillna(0.0).to_numpy()
        curve = agreement.survival_curve(thr, grid)
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
    res = association.logistic_regression(df, "failed", ["load", "mass", "mu", "proposed"])
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
        m, p, _ = thresholds(g, "A")
        rows.append({"friction_level": level, "n": len(g), "success_pct": percent(g["success"]),
                     "threshold_median_n": finite_median(m),
                     "threshold_err_pct": finite_median(abs_pct_error(m, p))})
    return pd.DataFrame(rows)


def direction_summary(records: pd.DataFrame, planner: str = PROPOSED) -> pd.DataFrame:
    """Return the median natural-friction lateral threshold per pull direction (Fig. 33b)."""
    df = executed(records)
    df = df[(df["planner"] == planner) & (df["block"] == "A") & natural(df)]
    rows = []
    for direction, g in df.groupby("direction_deg", sort=True):
        m, _, _ = thresholds(g, "A")
        rows.append({"direction_deg": float(direction), "n": len(g),
                     "threshold_median_n": finite_median(m), "success_pct": percent(g["success"])})
    return pd.DataFrame(rows)


def retention_classifier(records: pd.DataFrame) -> pd.DataFrame:
    """Return the pre-disturbance retention flag scored against measured success (§9.5, Fig. 36c).

    Rows ``all`` and one per planner; columns as :func:`stability_classifier`.
    """
    df = executed(records)
    rows = [classifier_row("all", df["retention_pred"], df["success"])]
    for p in planners_present(df):
        g = df[df["planner"] == p]
        rows.append(classifier_row(p, g["retention_pred"], g["success"]))
    return pd.DataFrame(rows)


