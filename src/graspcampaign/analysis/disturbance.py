"""Test 3 statistics (paper §9.3-9.5; Figs. 34, 36) over the frame of :func:`.hardware.derive`.

References: Bland & Altman (1986); Kaplan & Meier (1958), uncensored case; logistic regression (Wald).
"""

from __future__ import annotations

from collections.abc import Sequence

import numpy as np
import pandas as pd
from scipy import stats

from graspcampaign.analysis import agreement, association
from graspcampaign.analysis.vocabulary import PROPOSED


def threshold_agreement(df: pd.DataFrame, planner: str = PROPOSED) -> dict:
    """Return Bland-Altman of measured - predicted, the OLS of measured on predicted and the median
    error over the planner's uncensored block-A lateral thresholds (§9.3, Fig. 34)."""
    g = df[df["planner"] == planner].dropna(subset=["lat_threshold_n"])
    m, p, err = (g[c].to_numpy(float) for c in ("lat_threshold_n", "threshold_pred", "lat_threshold_err_pct"))
    if m.size < 3:
        return {"planner": planner, "n": m.size}
    ba, lin = agreement.bland_altman(m, p), stats.linregress(p, m)
    return {"planner": planner, "n": m.size, "bias_n": ba.bias, "sd_n": ba.sd, "loa_low_n": ba.lower,
            "loa_high_n": ba.upper, "loa_half_n": (ba.upper - ba.lower) / 2, "ols_slope": lin.slope,
            "ols_intercept_n": lin.intercept, "ols_r2": lin.rvalue**2, "ols_p": lin.pvalue,
            "median_err_pct": np.median(err), "n_err_over_50pct": int(np.sum(err > 50.0))}


def lateral_survival(df: pd.DataFrame, levels: Sequence[float],
                     planners: Sequence[str] = (PROPOSED, "centroid")) -> pd.DataFrame:
    """Return the share of each planner's natural-friction block-A trials sustaining at least each level
    (Fig. 36b): a grasp lost before the pull counts as 0 N, a censored ramp at its cap."""
    a = df[(df["block"] == "A") & (df["friction_level"] == "natural")]
    rows = []
    for p in planners:
        thr = a.loc[a["planner"] == p, "threshold_measured_n"].astype(float).fillna(0.0).to_numpy()
        if thr.size:
            c = agreement.survival_curve(thr, levels)
            rows += [{"planner": p, "level_n": lv, "surviving_fraction": f, "n": c.n}
                     for lv, f in zip(c.levels, c.surviving_fraction, strict=True)]
    return pd.DataFrame(rows)


def failure_logistic(df: pd.DataFrame) -> pd.DataFrame:
    """Return the logistic regression of failure over the fixed-load blocks B, D, E (§9.5) on the applied
    load [N], mass [kg], believed μ_s and the proposed-planner indicator."""
    g = df[df["block"].isin(["B", "D", "E"])]
    g = pd.DataFrame({"failed": (~g["success"]).astype(int), "load": g["load_n"].astype(float),
                      "mass": g["mass_kg"].astype(float), "mu": g["mu_s_believed"].astype(float),
                      "proposed": (g["planner"] == PROPOSED).astype(int)})
    res = association.logistic_regression(g, "failed", ["load", "mass", "mu", "proposed"])
    return res.coefficients.rename_axis("term").reset_index().assign(
        n=res.n, converged=res.converged, separation=res.separation_kind)
