"""Tests 2-3 statistics (paper §8-9, Tables 6-9) over the executed trials of :func:`derive` (§8.1).

References: Wilson (1927); Efron & Tibshirani (1993); McNemar (1947); Pearson's χ²; Kruskal & Wallis (1952).
"""

from __future__ import annotations

from collections.abc import Mapping, Sequence

import numpy as np
import pandas as pd

from graspcampaign.analysis import agreement, association, rates
from graspcampaign.analysis.records import executed, flag, known, mcnemar_table, rate_table
from graspcampaign.analysis.vocabulary import label, ordered, things
from graspcampaign.core.statics import GRAVITY

CLASSES = {"stable": "stable", "marginal": "success", "partial": "partial", "slip": "failure_slip",
           "drop": "failure_drop", "damage": "failure_damage", "contact_loss": "failure_contact_loss"}
"""Short name -> primary outcome class (§8.1 grading precedence: one class per trial)."""
VISION_QUANTUM_MM = 0.1
"""The vision channel's quantisation [mm] (§8.1): a recorded mean deformation below it is within one step
of zero, a near-zero denominator of ``deformation_err_pct`` (`docs/decisions.md`,
*The deformation errors over a recorded mean below 0.1 mm are kept, counted and drawn apart*)."""
VIRTUAL_ONLY = ("mu_s_actual", "valid_geometry", "success_unbounded")
"""Record columns only the virtual rig knows (missing values on an ingested run)."""


def records_under_belief(records: pd.DataFrame, counterfactual: pd.DataFrame) -> pd.DataFrame:
    """Return the trace table ``belief_none`` shaped like the records (its columns replace theirs)."""
    replaced = [c for c in counterfactual.columns if c in records.columns and c != "trial_id"]
    return records.drop(columns=replaced).merge(counterfactual, on="trial_id", how="inner")


def beliefs(records: pd.DataFrame, counterfactual: pd.DataFrame | None = None) -> pd.DataFrame:
    """Return the records (``belief_error = paper``) and their ``none`` counterfactual, stacked."""
    parts = [records.assign(belief_error="paper")]
    if counterfactual is not None and len(counterfactual):
        parts.append(records_under_belief(records, counterfactual).assign(belief_error="none"))
    return pd.concat(parts, ignore_index=True)


def belief_pairs(long: pd.DataFrame) -> pd.DataFrame:
    """Return per planner its success and rank on the same trials under ``paper`` and ``none`` beliefs and
    McNemar's test of the pairs (:func:`~graspcampaign.analysis.records.mcnemar_table`, reference none)."""
    out = pd.concat([mcnemar_table(long[long["planner"] == p], "none", ["paper"], method="belief_error",
                                   pair_on="trial_id").assign(planner=p)
                     for p in ordered("planner", long["planner"])], ignore_index=True)
    for r, k in (("paper", "compared_only"), ("none", "reference_only")):
        out[f"success_{r}_pct"] = 100 * (out["both_success"] + out[k]) / out["pairs"]
    return out.assign(difference_pp=out["success_none_pct"] - out["success_paper_pct"], **{
        f"rank_{r}": out[f"success_{r}_pct"].rank(ascending=False, method="min") for r in ("paper", "none")})


def pct_error(measured: pd.Series, predicted: pd.Series) -> pd.Series:
    """Return ``100 |predicted - measured| / |measured|``, nan where measured is 0 or missing."""
    m, p = measured.astype(float), predicted.astype(float)
    return (100.0 * (p - m).abs() / m.abs()).where(m != 0)


def pred_read(df: pd.DataFrame, stem: str, unit: str) -> pd.Series:
    """Return the predicted trial mean of ``<stem>_pred_<j>_<unit>`` over the fingers with a measured
    ``<stem>_<j>_<unit>``, as the recorded ``<stem>_mean_<unit>`` is (ingest's mean counts the fingers
    recorded; a buried finger has no deformation reading); ``<stem>_pred_mean_<unit>`` where the
    records hold no per-finger values."""
    read, pred = ([f"{stem}_{p}{j}_{unit}" for j in (1, 2, 3)] for p in ("", "pred_"))
    every = df[f"{stem}_pred_mean_{unit}"].astype(float)
    if not set(read + pred) <= set(df):
        return every
    return df[pred].astype(float).where(df[read].notna().to_numpy()).mean(axis=1).fillna(every)


def below_quantum(df: pd.DataFrame) -> pd.Series:
    """Return whether each trial's ``deformation_err_pct`` divides by a recorded mean deformation below
    :data:`VISION_QUANTUM_MM` (within one vision step of zero); False where it has no error."""
    return df["deformation_err_pct"].notna() & (df["deformation_mean_mm"] < VISION_QUANTUM_MM)


def derive(records: pd.DataFrame) -> pd.DataFrame:
    """Return the executed trials with the columns every Tests 2-3 table reads.

    ``is_<class>``, ``natural`` (success at natural friction), ``normal_force_pred_read_n`` (the prediction
    over the fingers whose force was read, :func:`pred_read`), ``force_err_pct``, ``deformation_err_pct``,
    ``g_geo_gap``/``mu_s_gap`` (believed - actual), ``gate_removed`` (a success only without the δ ≤ r
    gate), ``match_key``; Test 3: ``threshold``/``threshold_pred`` (uncensored ramps; N·m in block C),
    ``threshold_err_pct``, ``lat_threshold_n``/``_err_pct`` (block A), ``payload_pct_w`` (block B down),
    ``headline`` (Table 8: A, C threshold, B payload, D, E peak slip [mm]), ``first_finger_correct``.
    """
    df = executed(records)
    df = df.assign(**{c: np.nan for c in VIRTUAL_ONLY if c not in df})
    unbounded = df["success_unbounded"].astype("boolean")
    force = pred_read(df, "normal_force", "n")
    new = {**{f"is_{k}": df["outcome"] == v for k, v in CLASSES.items()},
           "natural": df["success"].where(df["friction_level"] == "natural"),
           "normal_force_pred_read_n": force, "force_err_pct": pct_error(df["normal_force_mean_n"], force),
           "deformation_err_pct": pct_error(df["deformation_mean_mm"], pred_read(df, "deformation", "mm")),
           "g_geo_gap": df["g_geo_believed"].astype(float) - df["g_geo_actual"].astype(float),
           "mu_s_gap": df["mu_s_believed"].astype(float) - df["mu_s_actual"].astype(float),
           "gate_removed": (unbounded & ~df["success"]).where(unbounded.notna()),
           "match_key": df[["object_id", "condition", "repeat"]].astype(str).agg("|".join, axis=1)}
    if "block" in df:
        a, c = df["block"] == "A", df["block"] == "C"
        m = df["threshold_measured_nm"].where(c, df["threshold_measured_n"]).astype(float)
        p = df["threshold_pred_nm"].where(c, df["threshold_pred_n"]).astype(float)
        ok = np.isfinite(m) & np.isfinite(p) & (m > 0) & ~flag(df, "threshold_censored")
        err = pct_error(m, p).where(ok)
        payload = (100 * m / (df["mass_kg"] * GRAVITY)).where(ok & (df["disturbance_kind"] == "down"))
        ff = df["first_finger_measured"].fillna(0).astype(int)
        new.update(threshold=m.where(ok), threshold_pred=p.where(ok), threshold_err_pct=err,
                   lat_threshold_n=m.where(ok & a), lat_threshold_err_pct=err.where(a),
                   payload_pct_w=payload, headline=m.where(ok & (a | c)).combine_first(payload).combine_first(
                       df["peak_slip_mm"].astype(float).where(df["block"].isin(["D", "E"]))),
                   first_finger_correct=(df["first_finger_pred"].astype(int) == ff).where(ff > 0))
    return df.assign(**new)


def scoped(df: pd.DataFrame, parts: Mapping[str, pd.Series]) -> pd.DataFrame:
    """Return the rows each mask of ``parts`` selects, stacked with their ``scope`` name."""
    return pd.concat([df[mask].assign(scope=name) for name, mask in parts.items()], ignore_index=True)


def summary(df: pd.DataFrame, by: Sequence[str], rates: Sequence[str] = (), medians: Sequence[str] = (),
            *, cluster: str | None = None, seed: int = 0, order: Mapping | None = None) -> pd.DataFrame:
    """Return per group of ``by`` the success :func:`~.records.rate_table` (``success_pct``, ``_low_pct``,
    ``_high_pct``), each boolean column of ``rates`` likewise as ``<name>_pct``, ... and the count
    ``n_<name>`` of its non-missing rows (``is_`` dropped; 0 for a group with none), and the median and
    count ``n_<things>`` of ``medians`` (the column without its unit suffix: a count of ``lat_threshold_n``
    is ``n_lat_threshold``, not newtons)."""
    by = list(by)
    out = rate_table(df, by, cluster=cluster, seed=seed, order=order).rename(columns=lambda c: c.replace(
        "rate_pct", "success_pct").replace("wilson", "success"))
    for col in rates:
        name = col.removeprefix("is_")
        t = rate_table(known(df, [col]), by, outcome=col, order=order)
        t = t[[*by, "n", "rate_pct", "wilson_low_pct", "wilson_high_pct"]]
        out = out.merge(t.set_axis([*by, f"n_{name}", f"{name}_pct", f"{name}_low_pct", f"{name}_high_pct"],
                                   axis=1), on=by, how="left")
        out[f"n_{name}"] = out[f"n_{name}"].fillna(0).astype(int)
    if medians:
        g = df.groupby(by, sort=False)[list(medians)]
        counts = g.count().rename(columns=lambda c: f"n_{things(c)}")
        out = out.merge(g.median().join(counts).reset_index(), on=by, how="left")
    return out


def parity_by(df: pd.DataFrame, by: str, measured: str, predicted: str) -> pd.DataFrame:
    """Return per group of ``by`` the parity fit of measured on predicted through the origin (≥ 3 pairs)."""
    rows = []
    for key, g in df.dropna(subset=[measured, predicted]).groupby(by, sort=False):
        fit = agreement.parity_fit(g[measured], g[predicted]) if len(g) >= 3 else None
        rows.append({by: key, "n_parity": len(g), **({} if fit is None else {
            "parity_slope": fit.slope_through_origin, "parity_r2": fit.r2_uncentred,
            "parity_r2_centred": fit.r2_centred})})
    return pd.DataFrame(rows, columns=[by, "n_parity", "parity_slope", "parity_r2", "parity_r2_centred"])


def force_accuracy(df: pd.DataFrame) -> pd.DataFrame:
    """Return per scope (all, each planner) the normal-force parity (the measured mean on the prediction
    over the same fingers, ``normal_force_pred_read_n``) and median errors (§8.3, Fig. 29), each median
    with its count ``n_<things>`` (a trial may lack a deformation or a contact point), and the count
    ``n_deformation_below_quantum`` of errors over a recorded mean below :data:`VISION_QUANTUM_MM`
    (:func:`below_quantum`)."""
    df = df.dropna(subset=["normal_force_mean_n", "normal_force_pred_read_n"])
    long = scoped(df, {"all": df["planner"].notna(), **{p: df["planner"] == p for p in
                                                        ordered("planner", df["planner"])}})
    g = long.groupby("scope", sort=False)[["force_err_pct", "deformation_err_pct", "contact_point_error_mm"]]
    errors = g.median().join(g.count().rename(columns=lambda c: f"n_{things(c)}")).reset_index()
    low = below_quantum(long)
    errors["n_deformation_below_quantum"] = low.groupby(long["scope"], sort=False).sum().to_numpy()
    return parity_by(long, "scope", "normal_force_mean_n", "normal_force_pred_read_n").merge(errors)


def classifier_table(df: pd.DataFrame, flags: Sequence[str], by: Sequence[str]) -> pd.DataFrame:
    """Return each flag scored against measured success per group of ``by``, over the trials with both
    recorded (:func:`known`): counts, accuracy, f1, the base success rate, precision and recall with Wilson
    95 % bounds (``_low``, ``_high``), ``above_base``."""
    rows = []
    for column in flags:
        for key, g in df.groupby(list(by), sort=False):
            g = known(g, [column, "success"])
            m = agreement.classifier_metrics(g[column], g["success"])
            row = {"flag": column, **dict(zip(by, key, strict=True)), "n": m.n, "flagged": m.tp + m.fp,
                   "tp": m.tp, "fp": m.fp, "fn": m.fn, "tn": m.tn, "accuracy": m.accuracy, "f1": m.f1}
            for name, k, n in (("base", m.tp + m.fn, m.n), ("precision", m.tp, m.tp + m.fp),
                               ("recall", m.tp, m.tp + m.fn)):
                w = rates.wilson_interval(k, n) if n else None
                row.update({name + s: getattr(w, a, np.nan) for s, a in (("", "estimate"), ("_low", "low"),
                                                                         ("_high", "high"))})
            rows.append({**row, "above_base": row["precision"] > row["base"]})
    return pd.DataFrame(rows)


def chi2_planners(df: pd.DataFrame, planners: Sequence[str] = ("heuristic", "centroid", "random"), *,
                  seed: int = 0) -> dict:
    """Return the chi2 test of planner × success over ``planners`` (§8.5, §9.5) by the small-count rule of
    :func:`association.equal_rates_test` (Monte Carlo p from ``seed`` below an expected count of 5); the
    ``test`` text names the method."""
    g = df[df["planner"].isin(planners)]
    counts = g.groupby("planner")["success"].agg(["sum", "size"])
    res = association.equal_rates_test(counts["sum"], counts["size"], seed=seed)
    names = ", ".join(label("planner", p) for p in planners if p in counts.index)
    if not res.method:  # every trial has one outcome: nothing was tested
        return {"test": f"no test: every trial has one outcome ({names})", "n": len(g),
                "statistic": np.nan, "dof": res.groups - 1, "p": np.nan}
    return {"test": f"{res.method} planner × success ({names})", "n": len(g),
            "statistic": res.statistic, "dof": res.groups - 1, "p": res.pvalue}


def kruskal(df: pd.DataFrame, value: str, by: str) -> dict:
    """Return Kruskal-Wallis of ``value`` across the groups of ``by``, with each group's median."""
    groups = {k: x.to_numpy(float) for k, x in df.dropna(subset=[value]).groupby(by, sort=True)[value]}
    res = association.kruskal_wallis(*groups.values())
    return {"test": f"Kruskal–Wallis {value} by {by}", "n": res.n, "statistic": res.statistic,
            "dof": res.n_groups - 1, "p": res.pvalue, **{f"median_{k}": np.median(x) for k, x in
                                                         groups.items()}}
