"""Quasi-static records -> the numbers of the "what this shows" paragraph, grip laws, epsilon.

Pure functions over a records DataFrame of the ``quasi_static`` kind (``baseline_grid``,
``ablation``, ``grip_laws``, ``shapes``): they select, count and summarise; they never format.
Rates are returned with their counts (``k`` of ``n``) so the report attaches its own intervals.

Columns used (docs/records.md): ``status``, ``planner``, ``grip_law`` (factor; rows without it are
the ``paper`` law), ``success``, ``success_unbounded``, ``success_no_torque``, ``failure_check``,
``n_released``, ``n_upper``, ``n_loaded``, ``support_share_max``, ``rho``, ``epsilon_fc``,
``spearman_h_epsilon``; the ``candidates`` trace table (``trial_id``, ``h_total``,
``epsilon_fc``) for the pooled H-versus-epsilon figure.

References
----------
Paper Algorithm 2 line 7 (the sign step that releases upper contacts), §6.1, §6.5, §12; issue 13
item 2; Ferrari & Canny (1992); Fieller, Hartley & Pearson (1957), "Tests for rank correlation
coefficients. I", Biometrika 44:470-481 (variance 1.06/(n-3) of Fisher's z of Spearman's rho);
Efron & Tibshirani (1993) (percentile bootstrap).
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np
import pandas as pd
from scipy import stats

__all__ = [
    "SINGLE_FINGERTIP_SHARE",
    "CountShare",
    "SpearmanResult",
    "WhatThisShows",
    "epsilon_summary",
    "gate_removed",
    "h_epsilon_correlation",
    "median_rho_by_planner",
    "paper_law",
    "planner_grip_law_table",
    "released_contact_share",
    "single_fingertip_share",
    "spearman_interval",
    "what_this_shows",
]

SINGLE_FINGERTIP_SHARE = 0.95
"""A pass "rests on one fingertip" when one contact supplies at least this share of the vertical
normal support (``support_share_max``); a descriptive threshold (docs/decisions.md), reported
beside the stricter ``n_loaded == 1`` reading."""


@dataclass(frozen=True)
class CountShare:
    """``k`` of ``n`` rows, and the share ``k / n`` (NaN when n = 0)."""

    k: int
    n: int

    @property
    def share(self) -> float:
        """``k / n``."""
        return self.k / self.n if self.n else float("nan")


@dataclass(frozen=True)
class SpearmanResult:
    """Spearman's rank correlation with a confidence interval."""

    rho: float
    low: float
    high: float
    n: int
    confidence_level: float
    method: str


@dataclass(frozen=True)
class WhatThisShows:
    """The numbers of the paragraph explaining Algorithm 2's outcomes (paper law rows).

    Attributes
    ----------
    released : CountShare
        Triples with at least one contact released to delta = 0 by line 7's sign step.
    upper_released : CountShare
        Triples whose released contacts are exactly their upper contacts (n_out,z > 0).
    rho_median : pandas.Series
        Median ``rho = |R_xy| / W`` per planner.
    single_fingertip : CountShare
        Passes (``success``) with one contact carrying >= :data:`SINGLE_FINGERTIP_SHARE` of the
        vertical support.
    single_loaded : CountShare
        Passes with exactly one loaded contact.
    gate_removed : CountShare
        ``success_unbounded`` rows that the validity gate turned into failures.
    """

    released: CountShare
    upper_released: CountShare
    rho_median: pd.Series
    single_fingertip: CountShare
    single_loaded: CountShare
    gate_removed: CountShare


def _ok(records: pd.DataFrame) -> pd.DataFrame:
    return records[records["status"] == "ok"] if "status" in records else records


def paper_law(records: pd.DataFrame) -> pd.DataFrame:
    """Return the ``ok`` rows judged under Algorithm 2 (``grip_law`` absent or ``"paper"``)."""
    ok = _ok(records)
    return ok[ok["grip_law"] == "paper"] if "grip_law" in ok else ok


def _flag(frame: pd.DataFrame, column: str) -> pd.Series:
    return frame[column].astype("boolean").fillna(False).astype(bool)


def released_contact_share(records: pd.DataFrame) -> CountShare:
    """Return the paper-law triples with at least one contact released (``n_released >= 1``)."""
    rows = paper_law(records)
    return CountShare(int((rows["n_released"] >= 1).sum()), len(rows))


def median_rho_by_planner(records: pd.DataFrame) -> pd.Series:
    """Return the median ``rho`` (horizontal normal-only residual over the weight) per planner."""
    return paper_law(records).groupby("planner", sort=False)["rho"].median()


def single_fingertip_share(records: pd.DataFrame, threshold: float = SINGLE_FINGERTIP_SHARE,
                           grip_law: str = "paper") -> tuple[CountShare, CountShare]:
    """Return the passes resting on one fingertip: by support share, and by ``n_loaded == 1``."""
    ok = _ok(records)
    rows = ok[ok["grip_law"] == grip_law] if "grip_law" in ok else ok
    passes = rows[_flag(rows, "success")]
    by_share = int((passes["support_share_max"] >= threshold).sum())
    return CountShare(by_share, len(passes)), CountShare(int((passes["n_loaded"] == 1).sum()),
                                                         len(passes))


def gate_removed(records: pd.DataFrame, by: tuple[str, ...] = ()) -> pd.DataFrame | CountShare:
    """Return how many ``success_unbounded`` rows the validity gate removed (``k`` of ``n``).

    With ``by`` (e.g. ``("planner", "grip_law")``) a DataFrame with columns ``removed``,
    ``unbounded`` and ``n`` per group.
    """
    ok = _ok(records)
    removed = _flag(ok, "success_unbounded") & ~_flag(ok, "success")
    if not by:
        return CountShare(int(removed.sum()), int(_flag(ok, "success_unbounded").sum()))
    frame = ok.assign(_removed=removed, _unbounded=_flag(ok, "success_unbounded"))
    grouped = frame.groupby(list(by), sort=False)
    return pd.DataFrame({"removed": grouped["_removed"].sum(),
                         "unbounded": grouped["_unbounded"].sum(),
                         "n": grouped.size()})


def what_this_shows(records: pd.DataFrame,
                    threshold: float = SINGLE_FINGERTIP_SHARE) -> WhatThisShows:
    """Return every number of the "what this shows" paragraph from paper-law records."""
    rows = paper_law(records)
    single, loaded = single_fingertip_share(rows, threshold)
    removed = gate_removed(rows)
    return WhatThisShows(
        released=released_contact_share(rows),
        upper_released=CountShare(int((rows["n_released"] == rows["n_upper"]).sum()), len(rows)),
        rho_median=median_rho_by_planner(rows),
        single_fingertip=single,
        single_loaded=loaded,
        gate_removed=removed,
    )


def planner_grip_law_table(records: pd.DataFrame) -> pd.DataFrame:
    """Return successes per planner x grip law under each reading, with ``n``.

    Columns: ``n``, ``success``, ``success_unbounded``, ``success_no_torque`` (counts), and the
    first failing check counted per label (``fail_<label>``); rows indexed by
    (``planner``, ``grip_law``).
    """
    ok = _ok(records)
    if "grip_law" not in ok:
        ok = ok.assign(grip_law="paper")
    flags = {c: _flag(ok, c) for c in ("success", "success_unbounded", "success_no_torque")}
    frame = ok.assign(**flags)
    grouped = frame.groupby(["planner", "grip_law"], sort=False)
    table = grouped[list(flags)].sum().astype(int)
    table.insert(0, "n", grouped.size())
    checks = pd.crosstab([frame["planner"], frame["grip_law"]], frame["failure_check"])
    checks.columns = [f"fail_{c}" for c in checks.columns]
    return table.join(checks).fillna(0)


def epsilon_summary(records: pd.DataFrame) -> pd.DataFrame:
    """Return per planner the force-closure share (``epsilon_fc > 0``) and epsilon statistics.

    Columns: ``n``, ``force_closure`` (count), ``epsilon_median``, ``epsilon_mean``,
    ``epsilon_max`` (over the planner's chosen triples, paper-law rows: epsilon is geometric).
    """
    rows = paper_law(records)
    grouped = rows.groupby("planner", sort=False)["epsilon_fc"]
    return pd.DataFrame({"n": grouped.size(),
                         "force_closure": grouped.apply(lambda e: int((e > 0.0).sum())),
                         "epsilon_median": grouped.median(),
                         "epsilon_mean": grouped.mean(),
                         "epsilon_max": grouped.max()})


def spearman_interval(x, y, confidence: float = 0.95) -> SpearmanResult:
    """Return Spearman's rho of paired samples with a Fisher-z interval.

    ``z = atanh(rho)`` with standard error ``sqrt(1.06 / (n - 3))`` (Fieller, Hartley & Pearson
    1957), back-transformed with tanh. Pairs must be independent; for candidates clustered in
    trials use :func:`h_epsilon_correlation`, which resamples trials.
    """
    x, y = np.asarray(x, dtype=float), np.asarray(y, dtype=float)
    keep = np.isfinite(x) & np.isfinite(y)
    x, y = x[keep], y[keep]
    n = len(x)
    if n < 4 or np.ptp(x) == 0.0 or np.ptp(y) == 0.0:
        return SpearmanResult(float("nan"), float("nan"), float("nan"), n, confidence,
                              "fisher-z (Fieller 1957)")
    rho = float(stats.spearmanr(x, y).statistic)
    half = stats.norm.ppf(0.5 + confidence / 2.0) * np.sqrt(1.06 / (n - 3))
    z = np.arctanh(np.clip(rho, -1 + 1e-15, 1 - 1e-15))
    return SpearmanResult(rho, float(np.tanh(z - half)), float(np.tanh(z + half)), n, confidence,
                          "fisher-z (Fieller 1957)")


def h_epsilon_correlation(records: pd.DataFrame, candidates: pd.DataFrame | None = None, *,
                          confidence: float = 0.95, n_resamples: int = 10_000,
                          seed: int = 0) -> dict[str, SpearmanResult]:
    """Return how H(G) ranks the candidates against epsilon, as Spearman correlations.

    ``per_trial``: the median over ``ferrari_canny`` trials of each trial's Spearman rho over its
    N_cand candidates (``spearman_h_epsilon``), with a percentile-bootstrap interval resampling
    trials (independent scene draws). ``pooled`` (when the ``candidates`` table is given): rho
    over the pooled subsample, its interval from a bootstrap that resamples *trials* (the
    candidates of one trial share a body). Negative rho means agreement (H lower is better,
    epsilon higher is better).
    """
    rng = np.random.default_rng(seed)
    rows = paper_law(records)
    rows = rows[rows["planner"] == "ferrari_canny"]
    values = rows["spearman_h_epsilon"].to_numpy(dtype=float)
    values = values[np.isfinite(values)]
    out = {}
    if len(values) >= 2:
        boot = stats.bootstrap((values,), np.median, confidence_level=confidence,
                               n_resamples=n_resamples, method="percentile", random_state=rng)
        out["per_trial"] = SpearmanResult(float(np.median(values)),
                                          float(boot.confidence_interval.low),
                                          float(boot.confidence_interval.high), len(values),
                                          confidence, "median of per-trial rho, trial bootstrap")
    if candidates is not None and len(candidates):
        pooled = candidates[candidates["trial_id"].isin(rows["trial_id"])] if "trial_id" in rows \
            else candidates
        groups = [g[["h_total", "epsilon_fc"]].to_numpy(dtype=float)
                  for _, g in pooled.groupby("trial_id", sort=True)]
        if len(groups) >= 2:
            def pooled_rho(index):
                block = np.concatenate([groups[i] for i in index])
                return stats.spearmanr(block[:, 0], block[:, 1]).statistic

            whole = float(pooled_rho(range(len(groups))))
            draws = np.array([pooled_rho(rng.integers(0, len(groups), len(groups)))
                              for _ in range(min(n_resamples, 2000))])
            alpha = (1.0 - confidence) / 2.0
            low, high = np.nanquantile(draws, [alpha, 1.0 - alpha])
            out["pooled"] = SpearmanResult(whole, float(low), float(high),
                                           int(sum(len(g) for g in groups)), confidence,
                                           "pooled rho, trial-cluster bootstrap (2000 resamples)")
    return out
