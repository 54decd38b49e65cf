"""Quasi-static records -> Algorithm 2's mechanism, readings of success, grip need, epsilon.

Pure functions over ``quasi_static`` records (docs/records.md); ``order``: the study's levels.
References: paper Algorithm 2 line 7, Sec. 3.7, 6.1, 6.5; Ferrari & Canny (1992); Efron &
Tibshirani (1993), ch. 13, 16 (percentile and cluster bootstrap).
"""

from __future__ import annotations

import numpy as np
import pandas as pd
from scipy import stats

from graspcampaign.analysis import records as rec
from graspcampaign.analysis.rank_kernel import row_medians, sorted_pairs, tie_groups, weighted_rho
from graspcampaign.analysis.rates import BOOTSTRAP_RESAMPLES, CONFIDENCE_LEVEL
from graspcampaign.core.statics import GRAVITY
from graspcampaign.core.verdict import FAILURE_CHECKS

#: A pass rests on one fingertip when one contact gives >= this share of the vertical support
#: (``support_share_max``; descriptive, beside ``n_loaded == 1``; docs/decisions.md).
SINGLE_FINGERTIP_SHARE = 0.95
#: Trial-cluster resamples of the pooled H-epsilon rho (at most; docs/decisions.md, H against epsilon).
POOLED_RESAMPLES = 2000
#: Success as gated; without the validity gate; under |R_z|; with the torque check off.
READINGS = ("success", "success_unbounded", "success_vertical", "success_no_torque")


def algorithm_2(frame: pd.DataFrame) -> pd.DataFrame:
    """Return the rows (trials, or a table's groups) judged by Algorithm 2 (``grip_law`` absent or paper)."""
    return frame[frame["grip_law"] == "paper"] if "grip_law" in frame else frame


def paper_law(records: pd.DataFrame) -> pd.DataFrame:
    """Return the executed trials judged by Algorithm 2."""
    return algorithm_2(rec.executed(records))


def ferrari_canny_trials(records: pd.DataFrame) -> pd.DataFrame:
    """Return the paper-law trials of the ``ferrari_canny`` planner, whose candidates carry both H and ε.

    Raises
    ------
    ValueError
        If there is none.
    """
    if not len(rows := paper_law(records).query("planner == 'ferrari_canny'")):
        raise ValueError("no executed trial of the ferrari_canny planner")
    return rows


def _counts(frame: pd.DataFrame, by: list[str], counts: list[str], median: tuple[str, str],
            order: dict | None) -> pd.DataFrame:
    """Return per group ``n``, the sums of the boolean ``counts`` and ``median = (name, column)``."""
    rows = [{**key, "n": len(g), **g[counts].sum().astype(int), median[0]: g[median[1]].median()}
            for key, g in rec.groups(frame[[*by, *counts, median[1]]], by, order)]  # columns read
    return pd.DataFrame(rows, columns=[*by, "n", *counts, median[0]])


#: Each count of :func:`mechanism` and the record columns it reads: a trial missing one is out of
#: that count's n (``<count>_unread``), never counted as its negation; the ``single_`` counts are of
#: passes (a failed trial is in neither, read or not).
MECHANISM_READINGS = {"released": ["n_released"], "upper_released": ["n_released", "n_upper"],
                      "rho_passable": ["rho", "mass_kg"], "single_fingertip": ["support_share_max"],
                      "single_loaded": ["n_loaded"]}


def mechanism(records: pd.DataFrame, tau_f_n: float, order: dict | None = None,
              threshold: float = SINGLE_FINGERTIP_SHARE) -> pd.DataFrame:
    """Return per planner (paper-law rows) the counts ``released`` (a contact at delta = 0),
    ``upper_released`` (every upper contact released), ``rho_passable`` (rho m g < ``tau_f_n``),
    ``successes``, ``single_fingertip`` (passes whose largest contact gives >= ``threshold`` of
    the vertical support), ``single_loaded`` (passes with one loaded contact), ``rho_median``, and
    ``<count>_unread``: the trials (passes, of the last two) that count leaves out for a reading of
    :data:`MECHANISM_READINGS` not recorded; a count's n is ``n`` (``successes``) less them."""
    rows = paper_law(records)
    passes = rec.flag(rows, "success")
    frame = rows.assign(
        released=rows["n_released"] >= 1, upper_released=rows["n_released"] == rows["n_upper"],
        rho_passable=rows["rho"] * rows["mass_kg"] * GRAVITY < tau_f_n, successes=passes,
        single_fingertip=passes & (rows["support_share_max"] >= threshold),
        single_loaded=passes & (rows["n_loaded"] == 1), **{  # a missing value compares False: set apart
            f"{c}_unread": rows[read].isna().any(axis=1) & (passes | (not c.startswith("single_")))
            for c, read in MECHANISM_READINGS.items()})
    return _counts(frame, ["planner"], ["released", "upper_released", "rho_passable", "successes",
                                        "single_fingertip", "single_loaded",
                                        *(f"{c}_unread" for c in MECHANISM_READINGS)],
                   ("rho_median", "rho"), order)


def _named_rate(records: pd.DataFrame, by: list[str], outcome: str, order: dict | None) -> pd.DataFrame:
    """Return :func:`~.records.rate_table`'s ``n``, count and Wilson rate of ``outcome`` per group of
    ``by`` under the outcome's name: ``<outcome>``, ``<outcome>_pct``, ``<outcome>_low_pct`` and
    ``<outcome>_high_pct``."""
    t = rec.rate_table(records, by, outcome=outcome, order=order)
    return t[[*by, "n", "successes", "rate_pct", "wilson_low_pct", "wilson_high_pct"]].set_axis(
        [*by, "n", outcome, f"{outcome}_pct", f"{outcome}_low_pct", f"{outcome}_high_pct"], axis=1)


def readings(records: pd.DataFrame, by: list[str], order: dict | None = None) -> pd.DataFrame:
    """Return per group each reading's count ``r`` and rate ``r_pct`` (Wilson ``r_low_pct``,
    ``r_high_pct``), ``gate_removed`` and ``torque_binds`` (the passes the gate, the torque check remove),
    over the ``n`` trials with every reading recorded (:func:`~.records.known`): the removed passes are
    differences of two readings of one trial, and a reading not recorded (a file written before its
    column existed reads null) is no failure. ``n_unread``: the executed trials left out for a reading
    missing (a group whose every trial lacks one has ``n`` 0 and no rate)."""
    flags = rec.known(records, READINGS)
    ok = rec.executed(records[[c for c in (*by, "status", "aborted") if c in records]])
    frame = pd.DataFrame([{**key, "executed": len(g)} for key, g in rec.groups(ok, by, order)],
                         columns=[*by, "executed"])
    for r in READINGS:
        t = _named_rate(flags, by, r, order)
        frame = frame.merge(t if r == READINGS[0] else t.drop(columns="n"), on=by, how="left")
    counts = ["n", *READINGS]  # a group with no trial read: 0 of 0, its rates missing
    frame = frame.assign(**{c: frame[c].fillna(0).astype(int) for c in counts})
    frame.insert(len(by) + 1, "n_unread", frame.pop("executed") - frame["n"])
    return frame.assign(gate_removed=frame["success_unbounded"] - frame["success"],
                        torque_binds=frame["success_no_torque"] - frame["success"])


def loop_at_n_max_pct(trials: pd.DataFrame) -> float:
    """Return the share [%] of ``trials`` whose Algorithm 2 was still moving at its N_max iterations
    (``loop_capped``, a flag: missing, not set); nan without a trial."""
    return 100 * rec.flag(trials, "loop_capped").mean()


def grip_need(records: pd.DataFrame, order: dict | None = None) -> pd.DataFrame:
    """Return per grip law (``slip``, ``oracle``) and planner the counts ``holdable`` (needed grip
    within the cap), ``no_equal_grip`` (``grip_needed_n`` infinite), ``capped_passes`` and
    ``steepest_normal_z_median`` (median max_j |n_out,z|; 0: horizontal)."""
    ok = rec.executed(records)
    ok = ok[ok["grip_law"] != "paper"]
    capped = rec.flag(ok, "grip_capped")
    frame = ok.assign(holdable=~capped, no_equal_grip=np.isinf(ok["grip_needed_n"].astype(float)),
                      capped_passes=capped & rec.flag(ok, "success"),
                      steepest=ok.filter(like="contact_normal_z_").abs().max(axis=1))
    return _counts(frame, ["grip_law", "planner"], ["holdable", "no_equal_grip", "capped_passes"],
                   ("steepest_normal_z_median", "steepest"), order)


def law_outcomes(records: pd.DataFrame, order: dict | None = None) -> pd.DataFrame:
    """Return per grip law other than ``paper`` the counts ``n``, ``successes``, ``capped`` (the
    grip at its cap), ``no_equal_grip`` (``grip_needed_n`` infinite), the smallest and largest
    ``delta_max_mm`` of the capped trials, and the count of each first failing check."""
    ok = rec.executed(records)
    rows = []
    for key, g in rec.groups(ok[ok["grip_law"] != "paper"] if "grip_law" in ok else ok.iloc[:0],
                             ["grip_law"], order):
        capped, checks = rec.flag(g, "grip_capped"), g["failure_check"].value_counts()
        depth = g.loc[capped, "delta_max_mm"]
        rows.append({**key, "n": len(g), "successes": int(g["success"].sum()),
                     "capped": int(capped.sum()),
                     "no_equal_grip": int(np.isinf(g["grip_needed_n"].astype(float)).sum()),
                     "capped_delta_min_mm": depth.min(), "capped_delta_max_mm": depth.max(),
                     **{c: int(checks.get(c, 0)) for c in FAILURE_CHECKS}})
    return pd.DataFrame(rows, columns=["grip_law", "n", "successes", "capped", "no_equal_grip",
                                       "capped_delta_min_mm", "capped_delta_max_mm", *FAILURE_CHECKS])


def epsilon_table(records: pd.DataFrame, order: dict | None = None) -> pd.DataFrame:
    """Return per planner the force-closure share (epsilon > 0) and the median, mean and max
    epsilon of its chosen triples (paper-law rows: epsilon is geometric)."""
    rows = paper_law(records)
    out = _named_rate(rows.assign(force_closure=rows["epsilon_fc"] > 0), ["planner"], "force_closure", order)
    eps = rows.groupby("planner")["epsilon_fc"].agg(["median", "mean", "max"])
    return out.join(eps.add_prefix("epsilon_"), on="planner")


def weighted_spearman(x, y, w) -> float:
    """Return Spearman's rho of the sample in which the pair (x_i, y_i) occurs ``w_i`` times
    (NaN for a constant sample; :func:`graspcampaign.analysis.rank_kernel.weighted_rho`)."""
    w = np.asarray(w, dtype=float)
    return float(weighted_rho(*sorted_pairs(x, y, w, np.zeros(len(w), dtype=np.int64)),
                              np.ones((1, 1)))[0])


def h_epsilon_correlation(records: pd.DataFrame, candidates: pd.DataFrame, *,
                          confidence: float = CONFIDENCE_LEVEL, n_resamples: int = BOOTSTRAP_RESAMPLES,
                          seed: int = 0) -> pd.DataFrame:
    """Return Spearman's rho of H(G) and epsilon (rho < 0: agreement) with bootstrap intervals.

    Rows: the median over the paper-law ``ferrari_canny`` trials of each trial's rho over all (and
    force-closure) candidates; rho over those trials' pooled ``candidates``, its percentile
    interval resampling trials (a trial's candidates share a body; at most
    :data:`POOLED_RESAMPLES` resamples), none where ``candidates`` holds none of those trials (an
    empty frame: the run stored no candidate table)."""
    rng, alpha, rows = np.random.default_rng(seed), (1 - confidence) / 2, ferrari_canny_trials(records)
    out = []
    for reading, column in (("median per trial", "spearman_h_epsilon"),
                            ("median per trial, force closure", "spearman_h_epsilon_fc")):
        v = rows[column].dropna().to_numpy(float)
        if len(v) >= 2:
            # v's tie groups (int32: half the bytes scipy copies per resample) are resampled,
            # their medians counted (row_medians); in batches of ~4·10^6 values (16 MB): the same
            # draws as one call, which at 2·10^4 trials allocates ~3 GB and runs 3x slower
            group, n_groups = tie_groups(v)
            distinct = np.empty(n_groups)
            distinct[group] = v
            ci = stats.bootstrap((group.astype(np.int32),), lambda g, axis, d=distinct: row_medians(g, d),
                                 confidence_level=confidence, method="percentile",
                                 n_resamples=n_resamples, rng=rng,
                                 batch=max(1, 2**22 // len(v))).confidence_interval
            out.append((reading, float(np.median(v)), ci.low, ci.high, len(v), np.nan))
    # an empty ``candidates`` (a run that stored no candidate table; it may have no column): no pooled row
    pooled = candidates[candidates["trial_id"].isin(rows["trial_id"])] if len(candidates) else candidates
    trial = pooled["trial_id"].astype("category").cat.codes.to_numpy() if len(pooled) else np.empty(0, int)
    if (k := len(np.unique(trial))) >= 2:
        ranks = sorted_pairs(pooled["h_total"].to_numpy(float),
                             pooled["epsilon_fc"].to_numpy(float), np.ones(len(trial)), trial)
        draws, n_boot = [], min(n_resamples, POOLED_RESAMPLES)
        for start in range(0, n_boot, 64):  # each resample's trial counts, drawn in turn, 64 a call
            draws.append(weighted_rho(*ranks, np.array(
                [np.bincount(rng.integers(0, k, k), minlength=k)
                 for _ in range(min(64, n_boot - start))], dtype=float)))
        low, high = np.nanquantile(np.concatenate(draws), [alpha, 1 - alpha])
        out.append(("pooled", float(weighted_rho(*ranks, np.ones((1, k)))[0]), low, high, k, len(trial)))
    return pd.DataFrame(out, columns=["reading", "rho", "low", "high", "n_trials", "n_pairs"])
