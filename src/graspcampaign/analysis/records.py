"""Records -> full-precision tables: executed trials, rates, paired outcomes, design limit.

Every function takes a run's records (one row per trial, docs/records.md) and returns a
DataFrame at full precision, or a small frozen result; nothing here formats or words a number.
Success denominators are *executed* trials (:func:`executed`); errored trials and aborted
hardware attempts are counted in their own columns and enter no denominator (paper Sec. 11,
Sec. 8.1). A statistic that cannot be computed for a group (no executed trial, fewer than two
clusters) is nan, with the reason in the matching ``*_why`` column.

References
----------
Wilson, E. B. (1927). Probable inference, the law of succession, and statistical inference.
J. Am. Stat. Assoc. 22(158), 209-212.
Efron, B. & Tibshirani, R. J. (1993). An Introduction to the Bootstrap, ch. 13 (clusters).
McNemar, Q. (1947). Note on the sampling error of the difference between correlated
proportions or percentages. Psychometrika 12(2), 153-157.
"""

from __future__ import annotations

import math
from collections.abc import Mapping, Sequence
from dataclasses import dataclass

import numpy as np
import pandas as pd

from graspcampaign.analysis import rates
from graspcampaign.analysis.vocabulary import ordered

#: The paper's per-contact penetration design limit [mm] (Sec. 4, Sec. 5.5; SPEC Sec. 2.7).
DESIGN_LIMIT_MM = 1.0
#: First failing check of Algorithm 1, in the order the checks run.
FAILURE_CHECKS = ("none", "residual", "torque", "slip")
#: Outcome columns cast to plain bool on executed trials (nullable in the records).
BOOLEAN_COLUMNS = ("success", "success_vertical", "stable", "slip_flag", "drop_flag",
                   "damage_flag", "contact_loss_flag", "predicted_stable", "retention_pred",
                   "exceeds_1mm", "loop_capped", "settled")


@dataclass(frozen=True)
class Estimate:
    """A value with an optional interval and sample size (a cell beside the paper's value)."""

    value: float
    low: float = math.nan
    high: float = math.nan
    n: int | None = None


def executed(records: pd.DataFrame) -> pd.DataFrame:
    """Return the executed trials: ``status == "ok"`` and not ``aborted``; outcomes as bool.

    An aborted hardware attempt is kept in the records for provenance and enters no statistic
    (paper Sec. 8.1; docs/records.md). Missing outcome values of executed trials read False.
    """
    ok = records[records["status"] == "ok"] if "status" in records else records
    if "aborted" in ok:
        ok = ok[~ok["aborted"].astype("boolean").fillna(False).astype(bool)]
    cast = {c: ok[c].astype("boolean").fillna(False).astype(bool)
            for c in BOOLEAN_COLUMNS if c in ok}
    return ok.assign(**cast).reset_index(drop=True)


def data_source(records: pd.DataFrame, declared: str | None) -> str:
    """Return the data's source label: ``virtual`` as soon as one record says so.

    A run declared ``measured`` but filled with virtual-rig exports is virtual-rig data, never
    hardware data (SPEC §4); otherwise the declared source (``simulation`` by default).
    """
    if "source" in records and (records["source"] == "virtual").any():
        return "virtual"
    return str(declared or "simulation")


def status_counts(records: pd.DataFrame) -> dict[str, int]:
    """Return the number of executed, errored, aborted and otherwise excluded trials."""
    n_ok = int((records["status"] == "ok").sum()) if "status" in records else len(records)
    n_exec = len(executed(records))
    n_err = int((records["status"] == "error").sum()) if "status" in records else 0
    return {"executed": n_exec, "error": n_err, "aborted": n_ok - n_exec,
            "other": len(records) - n_ok - n_err}


def _keys(df: pd.DataFrame, by: Sequence[str], order: Mapping[str, Sequence]) -> list[tuple]:
    keys = list(dict.fromkeys(zip(*(df[c] for c in by), strict=True))) if len(df) else []
    ranks = [{v: i for i, v in enumerate(ordered(c, [k[j] for k in keys], order.get(c, ())))}
             for j, c in enumerate(by)]
    return sorted(keys, key=lambda k: tuple(r[v] for r, v in zip(ranks, k, strict=True)))


def rate_table(records: pd.DataFrame, by: Sequence[str], *, outcome: str = "success",
               cluster: str | None = None, seed: int = 0,
               n_resamples: int = rates.BOOTSTRAP_RESAMPLES,
               order: Mapping[str, Sequence] | None = None) -> pd.DataFrame:
    """Return the rate of ``outcome`` per group of ``by``, with Wilson and cluster intervals.

    Parameters
    ----------
    records : DataFrame
        All trial rows of a run (executed, errored and aborted).
    by : sequence of str
        Grouping columns; groups are ordered by ``order`` (e.g. the study's factor levels),
        then by the shared vocabulary (:mod:`graspcampaign.analysis.vocabulary`).
    outcome : str
        Boolean record column whose rate is computed.
    cluster : str or None
        Column naming the object (``shape`` in simulation, ``object_id`` on the rig): a
        percentile bootstrap resampling objects, not trials, per group.
    seed, n_resamples : int
        Bootstrap generator seed (the study seed) and resample count.

    Returns
    -------
    DataFrame
        ``by``, ``n``, ``successes``, ``n_error``, ``n_aborted``, ``rate_pct``,
        ``wilson_low_pct``, ``wilson_high_pct``, ``bootstrap_low_pct``, ``bootstrap_high_pct``,
        ``n_clusters``, ``rate_why``, ``bootstrap_why`` (rates in percent).
    """
    by = list(by)
    ok = executed(records)
    err = records[records["status"] == "error"] if "status" in records else records.iloc[:0]
    aborted = records[(records["status"] == "ok") & records["aborted"].astype("boolean")
                      .fillna(False).astype(bool)] if {"status", "aborted"} <= set(records) \
        else records.iloc[:0]
    known = [c for c in by if c in records]
    rows = []
    for key in _keys(records, known, order or {}) if len(known) == len(by) else []:
        sel = dict(zip(by, key, strict=True))

        def part(df: pd.DataFrame, sel=sel) -> pd.DataFrame:
            mask = np.ones(len(df), bool)
            for c, v in sel.items():
                mask &= (df[c] == v).to_numpy()
            return df[mask]

        g = part(ok)
        row = {**sel, "n": len(g), "n_error": len(part(err)), "n_aborted": len(part(aborted)),
               **rate_cells(g, outcome, cluster, seed, n_resamples)}
        rows.append(row)
    cols = [*by, "n", "successes", "n_error", "n_aborted", "rate_pct", "wilson_low_pct",
            "wilson_high_pct", "bootstrap_low_pct", "bootstrap_high_pct", "n_clusters",
            "rate_why", "bootstrap_why"]
    return pd.DataFrame(rows, columns=cols)


def rate_cells(g: pd.DataFrame, outcome: str, cluster: str | None, seed: int,
                n_resamples: int) -> dict:
    nan = math.nan
    out = {"successes": 0, "rate_pct": nan, "wilson_low_pct": nan, "wilson_high_pct": nan,
           "bootstrap_low_pct": nan, "bootstrap_high_pct": nan, "n_clusters": 0,
           "rate_why": "", "bootstrap_why": "" if cluster else "no object clustering here"}
    if not len(g):
        return {**out, "rate_why": "no executed trial", "bootstrap_why": "no executed trial"}
    if outcome not in g:
        why = f"no `{outcome}` column in the records"
        return {**out, "rate_why": why, "bootstrap_why": why}
    k = int(g[outcome].sum())
    w = rates.wilson_interval(k, len(g))
    out.update(successes=k, rate_pct=100 * w.estimate, wilson_low_pct=100 * w.low,
               wilson_high_pct=100 * w.high)
    if cluster and cluster in g:
        per = g.groupby(cluster, sort=True)[outcome].agg(["sum", "size"])
        out["n_clusters"] = len(per)
        if len(per) < 2:
            out["bootstrap_why"] = f"needs \u2265 2 {cluster} values, has {len(per)}"
        else:
            b = rates.cluster_bootstrap_interval(per["sum"].to_numpy(), per["size"].to_numpy(),
                                                 n_resamples=n_resamples, rng=seed)
            out.update(bootstrap_low_pct=100 * b.low, bootstrap_high_pct=100 * b.high)
    elif cluster:
        out["bootstrap_why"] = f"no `{cluster}` column in the records"
    return out


def rate(records: pd.DataFrame, mask=None, outcome: str = "success") -> Estimate:
    """Return the rate [%] of ``outcome`` over the executed trials selected by ``mask``.

    ``mask`` is a callable taking the executed trials and returning a boolean Series (or None
    for all). Raises ``ValueError`` naming the reason when no executed trial is selected.
    """
    ok = executed(records)
    g = ok[mask(ok)] if mask is not None and len(ok) else ok
    if not len(g):
        raise ValueError("no executed trial")
    if outcome not in g:
        raise ValueError(f"no `{outcome}` column in the records")
    w = rates.wilson_interval(int(g[outcome].sum()), len(g))
    return Estimate(100 * w.estimate, 100 * w.low, 100 * w.high, len(g))


def paired_outcomes(records: pd.DataFrame, method: str = "planner", pair_on: str = "scene_id",
                    outcome: str = "success") -> pd.DataFrame:
    """Return executed outcomes wide: one row per matched occurrence, one column per method.

    The k-th executed row of a method within a ``pair_on`` group pairs with the k-th row of
    every other method there (k counts rows in trial order, paper Sec. 11); an errored trial
    leaves its pair incomplete (nan) and it is dropped from that comparison.
    """
    ok = executed(records)
    if "trial_index" in ok:
        ok = ok.sort_values("trial_index", kind="stable")
    occurrence = ok.groupby([pair_on, method], sort=False).cumcount()
    return (ok.assign(_occurrence=occurrence)
            .pivot(index=[pair_on, "_occurrence"], columns=method, values=outcome))


def mcnemar_table(records: pd.DataFrame, reference: str, others: Sequence[str], *,
                  method: str = "planner", pair_on: str = "scene_id") -> pd.DataFrame:
    """Return McNemar's test of ``reference`` against each of ``others`` on matched pairs.

    Orientation as :func:`graspcampaign.stats.mcnemar`: A = ``reference``, so
    ``reference_only`` (n10) counts pairs it won and an odds ratio above 1 favours it.
    """
    wide = paired_outcomes(records, method, pair_on)
    rows = []
    for other in others:
        if reference not in wide or other not in wide:
            continue
        both = wide[[reference, other]]
        complete = both.notna().all(axis=1)
        a = both.loc[complete, reference].astype(bool).to_numpy()
        b = both.loc[complete, other].astype(bool).to_numpy()
        n01, n10 = rates.discordant_pairs(a, b) if a.size else (0, 0)
        res = rates.mcnemar(n01, n10)
        rows.append({
            "reference": reference, "compared": other, "pairs": int(a.size),
            "reference_only": n10, "compared_only": n01, "both_success": int(np.sum(a & b)),
            "both_fail": int(np.sum(~a & ~b)), "unpaired": int((~complete).sum()),
            "chi2_cc": res.statistic, "p_chi2": res.pvalue_chi2, "p_exact": res.pvalue_exact,
            "odds_ratio": res.odds_ratio, "odds_ratio_low": res.odds_ratio_low,
            "odds_ratio_high": res.odds_ratio_high,
            "test_why": "" if n01 + n10 else "no discordant pair: the test is undefined"})
    return pd.DataFrame(rows, columns=[
        "reference", "compared", "pairs", "reference_only", "compared_only", "both_success",
        "both_fail", "unpaired", "chi2_cc", "p_chi2", "p_exact", "odds_ratio", "odds_ratio_low",
        "odds_ratio_high", "test_why"])


def design_limit_table(records: pd.DataFrame, by: Sequence[str], *,
                       limit_mm: float = DESIGN_LIMIT_MM,
                       order: Mapping[str, Sequence] | None = None) -> pd.DataFrame:
    """Return how often ``delta_max_mm`` exceeds the design limit, per group (Wilson 95 %).

    The paper keeps every contact within 1 mm (Sec. 4, 5.5); SPEC Sec. 2.7 requires the report
    to show how often our SI evaluation exceeds it. Strictly above the limit counts.
    """
    by = list(by)
    ok = executed(records)
    ok = ok[ok["delta_max_mm"].notna()] if "delta_max_mm" in ok else ok.iloc[:0]
    rows = []
    for key in _keys(ok, by, order or {}):
        g = ok[np.logical_and.reduce([(ok[c] == v).to_numpy() for c, v in zip(by, key,
                                                                              strict=True)])]
        d = g["delta_max_mm"].to_numpy(dtype=float)
        over = d > limit_mm
        w = rates.wilson_interval(int(over.sum()), len(g))
        success = g["success"].to_numpy(bool) if "success" in g else np.zeros(len(g), bool)
        rows.append({**dict(zip(by, key, strict=True)), "n": len(g), "exceeds": int(over.sum()),
                     "exceeds_pct": 100 * w.estimate, "wilson_low_pct": 100 * w.low,
                     "wilson_high_pct": 100 * w.high,
                     "successes_exceeding": int((over & success).sum()),
                     "delta_max_median_mm": float(np.median(d)),
                     "delta_max_p95_mm": float(np.quantile(d, 0.95)),
                     "delta_max_max_mm": float(d.max())})
    return pd.DataFrame(rows, columns=[
        *by, "n", "exceeds", "exceeds_pct", "wilson_low_pct", "wilson_high_pct",
        "successes_exceeding", "delta_max_median_mm", "delta_max_p95_mm", "delta_max_max_mm"])


def failure_check_table(records: pd.DataFrame, by: Sequence[str],
                        order: Mapping[str, Sequence] | None = None) -> pd.DataFrame:
    """Return the count and share [%] of each first failing check (none/residual/torque/slip)."""
    by = list(by)
    ok = executed(records)
    if "failure_check" not in ok:
        ok = ok.assign(failure_check="unknown")
    found = [c for c in ok["failure_check"].dropna().unique() if c not in FAILURE_CHECKS]
    checks = [*FAILURE_CHECKS, *sorted(map(str, found))]
    rows = []
    for key in _keys(ok, by, order or {}):
        g = ok[np.logical_and.reduce([(ok[c] == v).to_numpy() for c, v in zip(by, key,
                                                                              strict=True)])]
        counts = g["failure_check"].value_counts()
        row = {**dict(zip(by, key, strict=True)), "n": len(g)}
        for c in checks:
            row[c] = int(counts.get(c, 0))
            row[f"{c}_pct"] = 100 * row[c] / len(g)
        rows.append(row)
    return pd.DataFrame(rows, columns=[*by, "n", *(x for c in checks for x in (c, f"{c}_pct"))])
