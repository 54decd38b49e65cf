"""Test 1 bench summaries of the per-event fits (paper §7; Tables 4-5, Figs. 23-25).

Each function takes the fits (one record per event) or the PSO run log and returns a
full-precision DataFrame, units in the column names. Damage depths and transfer errors need the
traces: the run's finalize stage computes them (``rig.test1_summary``, ``summary/``).
"""

from __future__ import annotations

import numpy as np
import pandas as pd
from scipy import stats

from graspcampaign.analysis.records import at_bound, flag
from graspcampaign.core import bench
from graspcampaign.core.bench import FAMILIES
from graspcampaign.core.identify import PARAMETER_COLUMNS, PARAMETER_NAMES

MATERIALS = tuple(FAMILIES)
"""Material families in Table 4 order."""
KEY = ["material", "specimen", "environment"]


def fitted(records: pd.DataFrame) -> pd.DataFrame:
    """Completed events of executed trials, ``fit_ok``/``accepted``/``slipped_measured`` as bool."""
    ok = records[records["status"] == "ok"]
    ok = ok[ok["event_status"] == "completed"] if "event_status" in ok else ok
    return ok.assign(**{c: flag(ok, c) for c in (
        "fit_ok", "accepted", "slipped_measured") if c in ok}).reset_index(drop=True)


def oblique_summary(fits: pd.DataFrame) -> pd.DataFrame:
    """Oblique events (§7.3) with ``mu_s_calibrated`` (median breakaway of the specimen's slides
    in that environment), ``margin_n`` = μs fn − ft at the dwell, the Coulomb prediction
    ``predicted_slip`` = tan(angle) > μs, and whether it matches the margin's sign and the
    measured slip."""
    mu = fits[fits["block"] == "sliding"].groupby(KEY)["mu_s"].median().rename("mu_s_calibrated")
    ob = fits[fits["block"] == "oblique"].join(mu, on=KEY)
    ob["margin_n"] = bench.slip_margin(ob["mu_s_calibrated"], ob["peak_normal_force_n"],
                                       ob["peak_tangential_force_n"])
    ob["predicted_slip"] = np.tan(np.radians(ob["angle_deg"])) > ob["mu_s_calibrated"]
    ob["margin_negative"] = ob["margin_n"] < 0
    ob["classification_matches_margin"] = ob["predicted_slip"] == ob["margin_negative"]
    ob["classification_matches_measured"] = ob["predicted_slip"] == ob["slipped_measured"].astype(bool)
    return ob.reset_index(drop=True)


def cyclic_summary(fits: pd.DataFrame) -> pd.DataFrame:
    """Fatigue cycles (§7.4) with ``k_ratio`` = f0.5 / cycle 1's (K/K1) and ``permanent_set_mm`` =
    shift of the shifted-law contact onset from cycle 1's."""
    cy = fits[fits["block"] == "cyclic"].sort_values(["material", "specimen", "cycle_index"])
    first = cy.groupby(KEY)[["f05_n", "onset_mm"]].transform("first")
    return cy.assign(k_ratio=cy["f05_n"] / first["f05_n"],
                     permanent_set_mm=cy["onset_mm"] - first["onset_mm"]).reset_index(drop=True)


def table4(fits: pd.DataFrame, truths: pd.DataFrame | None = None) -> pd.DataFrame:
    """Per-family means in Table 4's layout: accepted normal fits (n, K, f0.5, their count; C their
    median, a mean being ruled by a few wild per-event C, and ``c_negative`` the fits whose C < 0,
    non-physical), fitted slides (μs, μk, kt) and holds (ρ, τ); E (mean, SD over specimens) from
    the virtual bench's ``truths`` when given (the bench measures no modulus)."""
    fits = fits[fits["fit_ok"].astype(bool)]
    nf = fits[(fits["block"] == "normal") & fits["accepted"].astype(bool)]
    c, nf = nf["c_n_s_per_m"].groupby(nf["material"]), nf.groupby("material")
    sl, rl = (fits[fits["block"] == b].groupby("material") for b in ("sliding", "relaxation"))
    out = pd.concat([nf[["n_exp", "k_n_per_mm_n", "f05_n"]].mean(), c.median(),
                     c.agg(lambda v: int((v < 0).sum())).rename("c_negative"),
                     nf.size().rename("n_accepted_fits"), sl[["mu_s", "mu_k", "k_t_n_per_mm"]].mean(),
                     rl[["rho", "tau_s"]].mean()], axis=1)
    if truths is not None and len(truths):
        e = truths.drop_duplicates(["material", "specimen"]).groupby("material")["modulus_kpa"]
        out = pd.concat([e.mean(), e.std().rename("modulus_sd_kpa"), out], axis=1).reindex(out.index)
    return out.loc[[m for m in MATERIALS if m in out.index]].rename_axis("material").reset_index()


def table5(runs: pd.DataFrame) -> pd.DataFrame:
    """Mean (with its 95% Student-t interval ``mean_low``/``mean_high``), SD, CV (%) of each
    identified parameter over the converged runs (Table 5; ``parameter`` its name, as §4's), and
    ``n_at_bound``: converged runs that ended with that parameter on a search bound."""
    ok, p = runs[runs["converged"].astype(bool)], list(PARAMETER_COLUMNS)
    out = pd.DataFrame({"parameter": list(PARAMETER_NAMES), "mean": ok[p].mean().to_numpy(),
                        "sd": ok[p].std(ddof=1).to_numpy(), "n_runs": len(ok)})
    half = stats.t.ppf(0.975, len(ok) - 1) * out["sd"] / np.sqrt(len(ok)) if len(ok) > 1 else np.nan
    out["mean_low"], out["mean_high"] = out["mean"] - half, out["mean"] + half
    out["cv_pct"] = 100.0 * out["sd"] / out["mean"].where(out["mean"] != 0)
    out["n_at_bound"] = [int(at_bound(ok, q).sum()) if "at_bound" in ok else None for q in p]
    return out


ORDER = {"quantity": ("normal_force", "friction", "relaxation", "flat_to_curved"), "split": (
    "train", "unseen_specimen", "unseen_speed", "unseen_load", "extended_relaxation", "flat_to_curved")}
"""§7.6 quantities and splits in the paper's order."""


def transfer_summary(errors: pd.DataFrame) -> pd.DataFrame:
    """Transfer errors (``rig.test1_summary.transfer_errors``) per quantity and split: events, mean,
    median and 95th percentile of ``error_pct``, in :data:`ORDER`; ``<quantity|split>_label`` in words."""
    if not len(errors):
        return errors
    t = errors.groupby(["quantity", "split"])["error_pct"].agg(
        events="size", mean_error_pct="mean", median_error_pct="median",
        p95_error_pct=lambda e: e.quantile(0.95)).reset_index()
    t["quantity_label"], t["split_label"] = (t[c].str.replace("_", " ") for c in ("quantity", "split"))
    return t.sort_values(["quantity", "split"], key=lambda c: c.map(ORDER[c.name].index))


def damage_summary(depths: pd.DataFrame, truths: pd.DataFrame | None, radius_mm: float) -> pd.DataFrame:
    """Damage depths (``rig.test1_summary.damage_depths``) per family: specimens, mean/min/max depth,
    how many were set-limited, extrapolated (beyond the deepest cycled level) or beyond the
    fingertip radius ``radius_mm`` (``beyond_radius``: deeper is not a contact), the criteria, and
    with the virtual bench's ``truths`` the median absolute error against each specimen's true
    threshold."""
    if not len(d := depths):
        return d
    d = d.assign(beyond_radius=d["damage_depth_mm"] > radius_mm)
    if truths is not None and len(truths):
        d = d.merge(truths[[*KEY, "damage_depth_mm"]], "left", KEY, suffixes=("", "_true"))
        d["abs_error_median_mm"] = (d["damage_depth_mm"] - d["damage_depth_mm_true"]).abs()
    g = d.assign(set_limited=d["criterion"] == "set", extrapolated=d["extrapolated"].astype(bool)) \
        .sort_values("material", key=lambda m: m.map(MATERIALS.index)).groupby("material", sort=False)
    depth = g["damage_depth_mm"].agg(damage_depth_mean_mm="mean", damage_depth_min_mm="min",
                                     damage_depth_max_mm="max")
    return pd.concat([g.size().rename("specimens"), depth,
                      g[["set_limited", "extrapolated", "beyond_radius"]].sum(),
                      g[["abs_error_median_mm"]].median() if "abs_error_median_mm" in d else None,
                      g[["stiffness_target", "set_limit_mm"]].first() if "set_limit_mm" in d else None],
                     axis=1).reset_index()
