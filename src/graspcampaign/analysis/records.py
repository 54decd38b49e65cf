"""Records (docs/records.md) -> full-precision tables: executed trials, rates, paired outcomes,
design limit, validity gate. Success denominators are *executed* trials; errored trials and aborted
hardware attempts are counted apart (paper Sec. 11, 8.1). A statistic that cannot be computed is nan
with its reason in the matching ``*_why`` column. Groups are in :func:`~.vocabulary.ordered`'s order (the
vocabulary's; ``order``, the study's levels, for levels it lacks). The intervals and tests (and their
references) are :mod:`.rates`'.
"""

from __future__ import annotations

import math
from collections.abc import Iterator, Mapping, Sequence
from dataclasses import dataclass

import numpy as np
import pandas as pd

from graspcampaign.analysis import agreement, rates
from graspcampaign.analysis.vocabulary import ordered
from graspcampaign.core.verdict import FAILURE_CHECKS  # none, residual, torque, slip, geometry

#: The paper's per-contact penetration design limit [mm] (Sec. 4, Sec. 5.5; SPEC Sec. 2.7).
DESIGN_LIMIT_MM = 1.0
#: Outcome columns cast to plain bool on executed trials (nullable in the records). The readings
#: added after ``success`` (``success_unbounded``, ``success_vertical``, ``valid_geometry``, ...) stay
#: as recorded: an older file of a resumed run lacks them (null), and a rate reads them through
#: :func:`known`.
BOOLEAN_COLUMNS = ("success", "stable", "slip_flag", "drop_flag", "damage_flag", "contact_loss_flag",
                   "predicted_stable", "retention_pred", "exceeds_1mm", "loop_capped", "settled")


@dataclass(frozen=True)
class Estimate:
    """A value with an optional interval and sample size (a cell beside the paper's value)."""

    value: float
    low: float = math.nan
    high: float = math.nan
    n: int | None = None


def flag(frame: pd.DataFrame, column: str) -> pd.Series:
    """Return a nullable boolean column as bool, missing values False."""
    col = frame[column]
    return col if col.dtype == bool else col.astype("boolean").fillna(False).astype(bool)


def known(frame: pd.DataFrame, columns: Sequence[str]) -> pd.DataFrame:
    """Return the rows of ``frame`` whose outcome ``columns`` are all recorded, those columns as bool: a
    rate or a pair of outcomes is over the trials whose outcomes are known (``astype(bool)`` reads a
    NaN as True, a None as False). Sums of a flag count it with :func:`flag` (missing: not set)."""
    return frame[frame[list(columns)].notna().all(axis=1)].astype(dict.fromkeys(columns, bool))


def in_design_order(frame: pd.DataFrame) -> pd.DataFrame:
    """``frame``'s rows by ``trial_index`` then ``trial_id`` (where it has them; preparations, which
    have neither, by ``body_id``), each trial's rows in their stored order. A run's files hold rows
    in the order its tasks finished, which depends on ``n_jobs``, the task size and any resume (and
    a preparation computed again is stored last): a statistic read in that order would differ
    between two runs of the same trials, if only in its last digits (a sum's order)."""
    keys = [c for c in ("trial_index", "trial_id") if c in frame]
    if not keys and "body_id" in frame:
        keys = ["body_id"]
    return frame.sort_values(keys, kind="stable").reset_index(drop=True) if keys else frame


def executed(records: pd.DataFrame) -> pd.DataFrame:
    """Return the executed trials (``status == "ok"``, not ``aborted``), outcomes as bool (missing:
    False); an aborted hardware attempt enters no statistic (paper Sec. 8.1)."""
    keep = (records["status"] == "ok").fillna(False).to_numpy(bool) if "status" in records \
        else np.ones(len(records), bool)
    ok = records[keep & ~flag(records, "aborted").to_numpy()] if "aborted" in records else records[keep]
    return ok.assign(**{c: flag(ok, c) for c in BOOLEAN_COLUMNS if c in ok}).reset_index(drop=True)


def status_counts(records: pd.DataFrame) -> dict[str, int]:
    """Return the number of executed, errored, aborted and otherwise excluded trials."""
    n_ok = int((records["status"] == "ok").sum()) if "status" in records else len(records)
    n_err = int((records["status"] == "error").sum()) if "status" in records else 0
    n_exec = len(executed(records))
    return {"executed": n_exec, "error": n_err, "aborted": n_ok - n_exec,
            "other": len(records) - n_ok - n_err}


def groups(frame: pd.DataFrame, by: Sequence[str], order: Mapping[str, Sequence] | None = None,
           keys_from: pd.DataFrame | None = None) -> Iterator[tuple[dict, pd.DataFrame]]:
    """Yield ``(key, rows)`` per group of ``by`` in display order (keys of ``keys_from``); a key
    with a missing value is no group (its rows match no key)."""
    source = (frame if keys_from is None else keys_from)[list(by)].drop_duplicates()
    keys = [k for k in zip(*(source[c] for c in by), strict=True) if not any(pd.isna(v) for v in k)]
    ranks = [{v: i for i, v in enumerate(ordered(c, [k[j] for k in keys], (order or {}).get(c, ())))}
             for j, c in enumerate(by)]
    index = _index(frame, by) if keys else {}
    for key in sorted(keys, key=lambda k: tuple(r[v] for r, v in zip(ranks, k, strict=True))):
        yield dict(zip(by, key, strict=True)), frame.iloc[index.get(key, [])]


def _index(frame: pd.DataFrame, by: Sequence[str]) -> dict:
    """Row positions per key tuple of ``by`` from one groupby (a missing value is in no group, as
    ``nan == nan`` is false)."""
    idx = frame.groupby(list(by), sort=False, observed=True).indices if len(frame) else {}
    return {k if len(by) > 1 else (k,): v for k, v in idx.items()}


def rate_table(records: pd.DataFrame, by: Sequence[str], *, outcome: str = "success",
               cluster: str | None = None, seed: int = 0,
               n_resamples: int = rates.BOOTSTRAP_RESAMPLES,
               order: Mapping[str, Sequence] | None = None) -> pd.DataFrame:
    """Return the rate [%] of ``outcome`` per group of ``by`` with Wilson and cluster intervals, over the
    executed trials with ``outcome`` recorded (:func:`known`; ``n``); ``cluster``: the object column
    whose values the bootstrap resamples (``shape``, ``object_id``)."""
    by = list(by)
    records = records[[c for c in dict.fromkeys([*by, outcome, cluster, "status", "aborted"])
                       if c in records]]  # every column read here (the rest: copies of no use)
    ok = executed(records)
    ok = known(ok, [outcome]) if outcome in ok else ok
    status = records["status"] if "status" in records else pd.Series("ok", records.index)
    err = records[status == "error"]
    aborted = records[(status == "ok") & flag(records, "aborted")] if "aborted" in records \
        else records.iloc[:0]
    e_index, a_index = (_index(err, by), _index(aborted, by)) if set(by) <= set(records) else ({}, {})
    rows = [{**key, "n": len(g), "n_error": len(e_index.get(tuple(key.values()), ())),
             "n_aborted": len(a_index.get(tuple(key.values()), ())),
             **rate_cells(g, outcome, cluster, seed, n_resamples)}
            for key, g in (groups(ok, by, order, records) if set(by) <= set(records) else ())]
    return pd.DataFrame(rows, columns=[
        *by, "n", "successes", "n_error", "n_aborted", "rate_pct", "wilson_low_pct",
        "wilson_high_pct", "bootstrap_low_pct", "bootstrap_high_pct", "n_clusters", "rate_why",
        "bootstrap_why"])


def rate_cells(g: pd.DataFrame, outcome: str, cluster: str | None, seed: int,
               n_resamples: int = rates.BOOTSTRAP_RESAMPLES) -> dict:
    """Return one row of :func:`rate_table` (no group or counts) over the executed trials ``g``."""
    out = {"successes": 0, **dict.fromkeys(("rate_pct", "wilson_low_pct", "wilson_high_pct",
                                            "bootstrap_low_pct", "bootstrap_high_pct"), math.nan),
           "n_clusters": 0, "rate_why": "", "bootstrap_why": "" if cluster else "no object clustering here"}
    why = "no executed trial" if not len(g) else "" if outcome in g else \
        f"no `{outcome}` column in the records"
    if why:
        return {**out, "rate_why": why, "bootstrap_why": why}
    w = rates.wilson_interval(int(g[outcome].sum()), len(g))
    out.update(successes=w.successes, rate_pct=100 * w.estimate, wilson_low_pct=100 * w.low,
               wilson_high_pct=100 * w.high)
    if cluster and cluster not in g:
        out["bootstrap_why"] = f"no `{cluster}` column in the records"
    elif cluster:
        per = g.groupby(cluster, sort=True)[outcome].agg(["sum", "size"])
        out["n_clusters"] = len(per)
        if len(per) < 2:
            out["bootstrap_why"] = f"needs \u2265 2 {cluster} values, has {len(per)}"
        else:
            b = rates.cluster_bootstrap_interval(per["sum"].to_numpy(), per["size"].to_numpy(),
                                                 n_resamples=n_resamples, rng=seed)
            out.update(bootstrap_low_pct=100 * b.low, bootstrap_high_pct=100 * b.high)
    return out


def rate(records: pd.DataFrame, mask=None, outcome: str = "success") -> Estimate:
    """Return the rate [%] of ``outcome`` over the executed trials ``mask(ok)`` selects (None:
    all) with ``outcome`` recorded (:func:`known`; ``n``); raise ValueError naming why there is none."""
    ok = executed(records)
    g = ok[mask(ok)] if mask is not None and len(ok) else ok
    g = known(g, [outcome]) if outcome in g else g
    cells = rate_cells(g, outcome, None, 0)
    if cells["rate_why"]:
        raise ValueError(cells["rate_why"])
    return Estimate(cells["rate_pct"], cells["wilson_low_pct"], cells["wilson_high_pct"], len(g))


#: Values a median's bootstrap interval needs (agreement.median_interval); fewer: no interval.
MIN_TRIALS = 3


def median(values: pd.Series, seed: int) -> Estimate:
    """Return the median of ``values`` with its percentile-bootstrap 95 % interval
    (:func:`~graspcampaign.analysis.agreement.median_interval`) from :data:`MIN_TRIALS` values on."""
    low, high = agreement.median_interval(values, seed=seed) if len(values) >= MIN_TRIALS \
        else (math.nan, math.nan)
    return Estimate(float(values.median()), low, high, n=len(values))


def mcnemar_table(records: pd.DataFrame, reference: str, others: Sequence[str], *,
                  method: str = "planner", pair_on: str = "scene_id") -> pd.DataFrame:
    """Return McNemar's test of ``reference`` against each of ``others`` on matched pairs;
    ``reference_only`` counts the pairs it won, an odds ratio above 1 favours it.

    The k-th executed trial of a method within a ``pair_on`` group (trial order, paper Sec. 11)
    pairs with the k-th of every other method there; an errored trial leaves its pair unpaired.
    Without a discordant pair the test is undefined: no statistic, no p, the reason in ``test_why``."""
    ok = executed(records)
    ok = ok.sort_values("trial_index", kind="stable") if "trial_index" in ok else ok
    wide = (ok.assign(_occurrence=ok.groupby([pair_on, method], sort=False).cumcount())
            .pivot(index=[pair_on, "_occurrence"], columns=method, values="success"))
    rows = []
    for other in [o for o in others if reference in wide and o in wide]:
        paired = known(wide, [reference, other])
        a, b = (paired[c].to_numpy() for c in (reference, other))
        n01, n10 = rates.discordant_pairs(a, b) if a.size else (0, 0)
        res = rates.mcnemar(n01, n10)
        p = (res.pvalue_chi2, res.pvalue_exact) if n01 + n10 else (math.nan, math.nan)  # no test, no p
        rows.append([reference, other, a.size, n10, n01, int(np.sum(a & b)), int(np.sum(~a & ~b)),
                     len(wide) - len(paired), res.statistic, *p,
                     res.odds_ratio, res.odds_ratio_low, res.odds_ratio_high,
                     "" if n01 + n10 else "no discordant pair: the test is undefined"])
    return pd.DataFrame(rows, columns=[
        "reference", "compared", "pairs", "reference_only", "compared_only", "both_success",
        "both_fail", "unpaired", "chi2_cc", "p_chi2", "p_exact", "odds_ratio", "odds_ratio_low",
        "odds_ratio_high", "test_why"])


def beyond_radius(records: pd.DataFrame, radius_mm: float) -> pd.Series:
    """Return whether each record's deepest contact lies deeper than the fingertip radius
    ``radius_mm`` (``delta_max_mm`` > r): the fingertip's centre inside the object, a non-physical
    state (issue 13). The one rule of the reports; a missing ``delta_max_mm`` is not beyond.

    The validity gate's ``valid_geometry`` column is the same condition on the same depths (every
    contact within r, :func:`graspcampaign.core.verdict.geometry_valid`; a released contact has
    δ = 0), so the two agree on every gated record; this rule reads ``delta_max_mm`` because every
    kind records it, while records written before the gate have no ``valid_geometry``."""
    return records["delta_max_mm"] > radius_mm


def design_limit_table(records: pd.DataFrame, by: Sequence[str], *, radius_mm: float,
                       order: Mapping[str, Sequence] | None = None) -> pd.DataFrame:
    """Return per group how often ``delta_max_mm`` exceeds (strictly) the 1 mm design limit
    (paper Sec. 4, 5.5; SPEC Sec. 2.7), with Wilson 95 %, and the median, 95th percentile and
    maximum of ``delta_max_mm``; ``beyond_radius`` counts the trials deeper than the fingertip radius
    ``radius_mm`` (non-physical: the fingertip's centre inside the object, issue 13) and the three
    statistics are over the other, physical trials (nan when there are none)."""
    ok = executed(records)
    ok = ok[ok["delta_max_mm"].notna()] if "delta_max_mm" in ok else ok.iloc[:0]
    rows, used = [], [c for c in (*by, "delta_max_mm", "success") if c in ok]  # copied per group
    for key, g in groups(ok[used], list(by), order):
        d = g["delta_max_mm"].to_numpy(float)
        over = d > DESIGN_LIMIT_MM
        beyond = beyond_radius(g, radius_mm).to_numpy()
        w = rates.wilson_interval(int(over.sum()), len(g))
        success = g["success"].to_numpy(bool) if "success" in g else np.zeros(len(g), bool)
        shown = d[~beyond]
        stats = (np.median(shown), np.quantile(shown, 0.95), shown.max()) if len(shown) \
            else (math.nan,) * 3
        rows.append({**key, "n": len(g), "exceeds": w.successes, "exceeds_pct": 100 * w.estimate,
                     "wilson_low_pct": 100 * w.low, "wilson_high_pct": 100 * w.high,
                     "successes_exceeding": int((over & success).sum()),
                     "beyond_radius": int(beyond.sum()),
                     **dict(zip(("delta_max_median_mm", "delta_max_p95_mm", "delta_max_max_mm"),
                                map(float, stats), strict=True))})
    return pd.DataFrame(rows, columns=[
        *by, "n", "exceeds", "exceeds_pct", "wilson_low_pct", "wilson_high_pct",
        "successes_exceeding", "beyond_radius", "delta_max_median_mm", "delta_max_p95_mm",
        "delta_max_max_mm"])


def failure_check_table(records: pd.DataFrame, by: Sequence[str],
                        order: Mapping[str, Sequence] | None = None) -> pd.DataFrame:
    """Return per group the count and share [%] of each first failing check: every check of
    ``FAILURE_CHECKS`` (0 where it never failed first); ``geometry`` only for records of the
    validity gate (``valid_geometry``; runs recorded before it have none)."""
    ok = executed(records)
    ok = ok if "failure_check" in ok else ok.assign(failure_check="unknown")
    found = sorted(map(str, set(ok["failure_check"].dropna().unique()) - set(FAILURE_CHECKS)))
    gated = "valid_geometry" in ok or (ok["failure_check"] == "geometry").any()  # runs with the gate
    names, rows = [*(c for c in FAILURE_CHECKS if gated or c != "geometry"), *found], []
    for key, g in groups(ok[[*by, "failure_check"]], list(by), order):  # the columns read
        counts, row = g["failure_check"].value_counts(), {**key, "n": len(g)}
        for c in names:
            row[c] = int(counts.get(c, 0))
            row[f"{c}_pct"] = 100 * row[c] / len(g)
        rows.append(row)
    return pd.DataFrame(rows, columns=[*by, "n", *(x for c in names for x in (c, f"{c}_pct"))])


def gate_table(records: pd.DataFrame, by: Sequence[str],
               order: Mapping[str, Sequence] | None = None) -> pd.DataFrame:
    """Return per group the ``success_unbounded`` trials the validity gate ``removed`` (a contact
    deeper than the fingertip radius), with Wilson 95 %, and the ``invalid_geometry`` trials (a recorded
    ``valid_geometry`` False) of the ``n_valid_geometry`` with the reading (a trial without it is in
    ``n`` only)."""
    ok = executed(records)
    for column in ("success_unbounded", "valid_geometry", "success"):
        if column not in ok:
            raise KeyError(column)
    rows = []
    for key, g in groups(ok, list(by), order):
        unbounded = g[flag(g, "success_unbounded")]  # recorded as passing without the gate
        cells = rate_cells(unbounded.assign(removed=~unbounded["success"]), "removed", None, 0)
        read = known(g, ["valid_geometry"])  # the trials with a depth reading
        rows.append({**key, "n": len(g), "success_unbounded": len(unbounded),
                     "removed": cells["successes"], "removed_pct": cells["rate_pct"],
                     "removed_low_pct": cells["wilson_low_pct"],
                     "removed_high_pct": cells["wilson_high_pct"],
                     "removed_why": "no success without the gate" if cells["rate_why"] else "",
                     "success": int(g["success"].sum()), "n_valid_geometry": len(read),
                     "invalid_geometry": int((~read["valid_geometry"]).sum())})
    return pd.DataFrame(rows, columns=[*by, "n", "success_unbounded", "removed", "removed_pct",
                                       "removed_low_pct", "removed_high_pct", "removed_why",
                                       "success", "n_valid_geometry", "invalid_geometry"])


def at_bound(frame: pd.DataFrame, parameter: str) -> pd.Series:
    """Return whether ``parameter`` ended on a PSO search bound: column ``at_bound_<parameter>``,
    else the comma-joined ``at_bound`` / ``pso_at_bound``."""
    parameter = {"n_exp": "n"}.get(parameter, parameter)
    if f"at_bound_{parameter}" in frame:
        return flag(frame, f"at_bound_{parameter}")
    column = next((c for c in ("at_bound", "pso_at_bound") if c in frame), None)
    if column is None:
        raise KeyError("at_bound")
    return frame[column].fillna("").astype(str).str.split(",").map(lambda names: parameter in names)
