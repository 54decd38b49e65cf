"""Report tables: success rates beside the paper's value, paired tests, design-limit counts.

Every table here comes as a pair of DataFrames: ``full`` keeps full precision (written to CSV and
JSON, what a test or a notebook checks) and ``display`` holds the same rows rounded once from full
precision for Markdown/HTML (:func:`graspcampaign.stats.format_interval`). Rates are computed over
*executed* trials only (``status == "ok"``); errored trials are counted in their own column and
never enter a denominator (paper Sec. 11, "Software and data").

Intervals: Wilson (1927) at trial level for every rate; where trials cluster within objects (in
simulation the shape is the object) a percentile bootstrap that resamples objects, not trials
(Efron & Tibshirani 1993, ch. 13), with its seed and resample count stated in the caption.
Paired comparisons use McNemar (1947) on occurrence-matched pairs: rows of one scene draw share a
``scene_id`` (docs/records.md), and the k-th executed row of a planner in a scene pairs with the
k-th of the other planner.
"""

from __future__ import annotations

import math
from collections.abc import Callable, Mapping, Sequence
from dataclasses import dataclass
from decimal import ROUND_HALF_EVEN, Decimal

import numpy as np
import pandas as pd

from graspcampaign import stats
from graspcampaign.report import format as fmt

CONFIDENCE_LEVEL = 0.95
BOOTSTRAP_RESAMPLES = 10_000
#: The paper's per-contact penetration design limit [mm] (Sec. 4, Sec. 5.5; SPEC Sec. 2.7).
DESIGN_LIMIT_MM = 1.0
FAILURE_CHECKS = ("none", "residual", "torque", "slip")
MINUS = "\u2212"


@dataclass(frozen=True)
class TablePair:
    """A report table at full precision (CSV/JSON) and as displayed (Markdown/HTML)."""

    full: pd.DataFrame
    display: pd.DataFrame


@dataclass(frozen=True)
class BootstrapSpec:
    """How object-clustered bootstrap intervals are drawn (stated beside every table)."""

    cluster: str  # record column naming the object (``shape`` in simulation)
    seed: int
    n_resamples: int = BOOTSTRAP_RESAMPLES

    def note(self) -> str:
        return (f"{self.cluster}-clustered percentile bootstrap: objects ({self.cluster}) "
                f"resampled, not trials; {self.n_resamples} resamples, seed {self.seed}")


# --------------------------------------------------------------------------------------------
# Formatting (each number rounded once from full precision)
# --------------------------------------------------------------------------------------------


def format_number(value: float | None, digits: int = 1, percent: bool = False) -> str:
    """Return ``value`` rounded once (ties to even) from its exact binary value; "—" if missing."""
    if value is None or (isinstance(value, float) and math.isnan(value)):
        return "\u2014"
    if math.isinf(value):
        return "inf" if value > 0 else f"{MINUS}inf"
    exact = Decimal(float(value)) * (100 if percent else 1)
    text = f"{exact.quantize(Decimal(1).scaleb(-digits), rounding=ROUND_HALF_EVEN):f}"
    if text.startswith("-"):
        text = text[1:] if not any(c in "123456789" for c in text) else MINUS + text[1:]
    return text


def difference_pp(ours_fraction: float, paper_pct: float | None) -> float:
    """Return ours minus the paper's value in percentage points (nan without a paper value)."""
    if paper_pct is None:
        return math.nan
    return float(Decimal(float(ours_fraction)) * 100 - Decimal(str(paper_pct)))


def format_signed(value: float, digits: int = 1, unit: str = " pp") -> str:
    """Return a signed number (``+1.2 pp``, ``−21.4 pp``), rounded once."""
    if value is None or math.isnan(value):
        return "\u2014"
    text = format_number(value, digits)
    sign = "" if text.startswith(MINUS) or text.lstrip("0.") == "" else "+"
    return f"{sign}{text}{unit}"


def verdict(paper_pct: float | None, ours_fraction: float, low: float, high: float,
            boot_low: float | None = None, boot_high: float | None = None) -> str:
    """Say in words how our rate stands against the paper's.

    E.g. ``"differs from the paper by −21.4 pp; outside our 95% Wilson interval"``.
    """
    if paper_pct is None or (isinstance(paper_pct, float) and math.isnan(paper_pct)):
        return "the paper reports no value for this row"
    diff = difference_pp(ours_fraction, paper_pct)
    paper = float(paper_pct) / 100.0
    where = "inside" if low <= paper <= high else "outside"
    text = f"paper's value {where} our 95% Wilson interval"
    if boot_low is not None and not math.isnan(boot_low):
        inside = boot_low <= paper <= boot_high
        text += f" ({'inside' if inside else 'outside'} the object-bootstrap interval)"
    if format_number(diff, 1) in ("0.0", f"{MINUS}0.0"):
        return f"matches the paper (difference 0.0 pp); {text}"
    return f"differs from the paper by {format_signed(diff)}; {text}"


# --------------------------------------------------------------------------------------------
# Executed trials
# --------------------------------------------------------------------------------------------


def executed(records: pd.DataFrame) -> pd.DataFrame:
    """Return the executed trials with ``success`` as a plain bool column.

    Executed: ``status == "ok"`` and, for the hardware protocols, not ``aborted`` (an aborted
    attempt is kept for provenance and enters no statistic, paper Sec. 8.1; docs/records.md).
    """
    ok = records[records["status"] == "ok"]
    if "aborted" in ok:
        ok = ok[~ok["aborted"].astype("boolean").fillna(False).astype(bool)]
    if "success" in ok:
        ok = ok.assign(success=ok["success"].astype("boolean").fillna(False).astype(bool))
    return ok


def rate_cell(successes: int, n: int) -> str:
    """Return ``"k/n = e % (low–high)"`` with its Wilson 95 % interval; ``"–"`` for no trials."""
    if n == 0:
        return "–"
    ci = stats.wilson_interval(int(successes), int(n), CONFIDENCE_LEVEL)
    return (f"{successes}/{n} = {100 * ci.estimate:.1f} % "
            f"({fmt.interval(100 * ci.low, 100 * ci.high, 1)})")


def status_note(records: pd.DataFrame) -> str:
    """Return one sentence stating executed and errored trial counts."""
    n_ok = int((records["status"] == "ok").sum())
    n_err = int((records["status"] == "error").sum())
    other = len(records) - n_ok - n_err
    text = (f"{n_ok} trials executed; {n_err} errored trial{'s' if n_err != 1 else ''} counted "
            "separately and excluded from every success denominator")
    return text + (f"; {other} with another status, also excluded." if other else ".")


# --------------------------------------------------------------------------------------------
# Success rates
# --------------------------------------------------------------------------------------------


def _group_keys(df: pd.DataFrame, by: Sequence[str]) -> pd.Series:
    return pd.Series(list(zip(*(df[c] for c in by), strict=True)), index=df.index, dtype=object)


def rate_table(records: pd.DataFrame, by: Sequence[str], *,
               paper_pct: Callable[[tuple], float | None] | None = None,
               bootstrap: BootstrapSpec | None = None,
               order: Mapping[str, Sequence] | None = None) -> TablePair:
    """Return success rates per group with n, errors, Wilson and bootstrap intervals, the paper.

    Parameters
    ----------
    records : DataFrame
        All trial rows of a run (executed and errored).
    by : sequence of str
        Grouping columns (e.g. ``["planner"]`` or ``["shape", "planner"]``).
    paper_pct : callable or None
        Maps a group key (tuple of ``by`` values) to the paper's rate in percent, or None.
    bootstrap : BootstrapSpec or None
        Object-clustered bootstrap per group; skipped for groups with fewer than two objects.
    order : mapping or None
        Display order of the levels of some ``by`` columns (others sorted).

    Returns
    -------
    TablePair
        ``full`` columns: ``by``, ``paper_pct``, ``ours_pct``, ``difference_pp``, ``n``,
        ``successes``, ``n_error``, ``wilson_low_pct``, ``wilson_high_pct``,
        ``bootstrap_low_pct``, ``bootstrap_high_pct``, ``n_clusters``, ``verdict``.
    """
    by = list(by)
    ok = executed(records)
    err = records[records["status"] == "error"]
    keys = sorted(set(_group_keys(records, by)), key=lambda k: _sort_key(k, by, order))
    succ = ok.groupby(by, sort=False, dropna=False)["success"].agg(["sum", "size"])
    n_err = err.groupby(by, sort=False, dropna=False).size()
    per_cluster = None
    if bootstrap is not None and bootstrap.cluster in ok:
        per_cluster = ok.groupby([*by, bootstrap.cluster], sort=False)["success"].agg(["sum", "size"])
    rows = []
    for key in keys:
        index = key if len(by) > 1 else key[0]
        s, n = (int(succ.loc[index, "sum"]), int(succ.loc[index, "size"])) if index in succ.index \
            else (0, 0)
        paper = paper_pct(key) if paper_pct else None
        row = dict(zip(by, key, strict=True))
        row.update(paper_pct=paper, n=n, successes=s, n_error=int(n_err.get(index, 0)))
        boot = (math.nan, math.nan, 0)
        if n:
            w = stats.wilson_interval(s, n, CONFIDENCE_LEVEL)
            if per_cluster is not None:
                boot = _bootstrap(per_cluster, index, len(by), bootstrap)
            row.update(ours_pct=100 * w.estimate, difference_pp=difference_pp(w.estimate, paper),
                       wilson_low_pct=100 * w.low, wilson_high_pct=100 * w.high,
                       verdict=verdict(paper, w.estimate, w.low, w.high, boot[0], boot[1]))
        else:
            row.update(ours_pct=math.nan, difference_pp=math.nan, wilson_low_pct=math.nan,
                       wilson_high_pct=math.nan, verdict="no executed trial")
        row.update(bootstrap_low_pct=100 * boot[0], bootstrap_high_pct=100 * boot[1],
                   n_clusters=boot[2])
        rows.append(row)
    cols = [*by, "paper_pct", "ours_pct", "difference_pp", "n", "successes", "n_error",
            "wilson_low_pct", "wilson_high_pct", "bootstrap_low_pct", "bootstrap_high_pct",
            "n_clusters", "verdict"]
    full = pd.DataFrame(rows, columns=cols)
    return TablePair(full, _rate_display(full, by, bootstrap))


def _sort_key(key: tuple, by: list[str], order: Mapping[str, Sequence] | None) -> tuple:
    out = []
    for col, value in zip(by, key, strict=True):
        levels = list((order or {}).get(col, []))
        out.append((levels.index(value) if value in levels else len(levels), str(value)))
    return tuple(out)


def _bootstrap(per_cluster: pd.DataFrame, index, n_by: int, spec: BootstrapSpec
               ) -> tuple[float, float, int]:
    sub = per_cluster.xs(index if n_by > 1 else (index,), level=list(range(n_by)))
    if len(sub) < 2:
        return math.nan, math.nan, len(sub)
    res = stats.cluster_bootstrap_interval(sub["sum"].to_numpy(), sub["size"].to_numpy(),
                                           n_resamples=spec.n_resamples,
                                           confidence_level=CONFIDENCE_LEVEL, rng=spec.seed)
    return res.low, res.high, res.n_clusters


def _rate_display(full: pd.DataFrame, by: list[str], bootstrap: BootstrapSpec | None
                  ) -> pd.DataFrame:
    display = full[by].copy()
    display["paper %"] = [format_number(v) for v in full["paper_pct"]]
    display["ours % (Wilson 95%)"] = [
        "\u2014" if not n else fmt.estimate(o, lo, hi, 1)
        for o, lo, hi, n in full[["ours_pct", "wilson_low_pct", "wilson_high_pct", "n"]]
        .itertuples(index=False)]
    display["difference"] = [format_signed(v) for v in full["difference_pp"]]
    display["n"] = full["n"]
    display["errors"] = full["n_error"]
    if bootstrap is not None:
        display[f"{bootstrap.cluster}-bootstrap 95%"] = [
            "\u2014" if math.isnan(lo) else fmt.interval(lo, hi, 1)
            for lo, hi in full[["bootstrap_low_pct", "bootstrap_high_pct"]].itertuples(index=False)]
    display["verdict"] = full["verdict"]
    return display


def differences_in_words(full: pd.DataFrame, label_cols: Sequence[str]) -> str:
    """Return a bullet list stating every row whose rate differs from the paper's."""
    lines = []
    for row in full.itertuples(index=False):
        row = row._asdict()
        if row["paper_pct"] is None or pd.isna(row["paper_pct"]) or not row["n"]:
            continue
        if row["verdict"].startswith("differs"):
            label = ", ".join(str(row[c]) for c in label_cols)
            lines.append(f"- **{label}:** ours {format_number(row['ours_pct'])}% "
                         f"(n = {row['n']}) against the paper's {format_number(row['paper_pct'])}%: "
                         f"{row['verdict']}.")
    if not lines:
        return "Every row with a paper value matches it to the printed precision."
    return "**Where we differ from the paper.**\n\n" + "\n".join(lines)


# --------------------------------------------------------------------------------------------
# Paired comparisons (McNemar on occurrence-matched pairs)
# --------------------------------------------------------------------------------------------


def paired_outcomes(records: pd.DataFrame, method: str = "planner", pair_on: str = "scene_id"
                    ) -> pd.DataFrame:
    """Return executed outcomes wide: one row per matched occurrence, one column per method.

    The k-th executed row of a method within a ``pair_on`` group pairs with the k-th row of every
    other method there (``k`` counts rows in trial order); errored trials leave their pair
    incomplete and it is dropped from that comparison.
    """
    ok = executed(records)
    if "trial_index" in ok:
        ok = ok.sort_values("trial_index", kind="stable")
    occurrence = ok.groupby([pair_on, method], sort=False).cumcount()
    wide = (ok.assign(_occurrence=occurrence)
            .pivot(index=[pair_on, "_occurrence"], columns=method, values="success"))
    return wide


def mcnemar_table(records: pd.DataFrame, reference: str, others: Sequence[str], *,
                  method: str = "planner", pair_on: str = "scene_id") -> TablePair:
    """Return McNemar's test of ``reference`` against each of ``others`` on matched pairs.

    Orientation as in :func:`graspcampaign.stats.mcnemar`: A = ``reference`` (the proposed
    planner), so ``n10`` counts pairs the reference won and an odds ratio above 1 favours it.
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
        n01, n10 = stats.discordant_pairs(a, b) if a.size else (0, 0)
        res = stats.mcnemar(n01, n10, CONFIDENCE_LEVEL)
        rows.append({
            "reference": reference, "compared": other, "pairs": int(a.size),
            "both_success": int(np.sum(a & b)), "reference_only": n10, "compared_only": n01,
            "both_fail": int(np.sum(~a & ~b)), "unpaired": int((~complete).sum()),
            "chi2_cc": res.statistic, "p_chi2": res.pvalue_chi2, "p_exact": res.pvalue_exact,
            "odds_ratio": res.odds_ratio, "odds_ratio_low": res.odds_ratio_low,
            "odds_ratio_high": res.odds_ratio_high, "paper": "not reported",
            "reading": _mcnemar_words(reference, other, n10, n01, res),
        })
    full = pd.DataFrame(rows, columns=[
        "reference", "compared", "pairs", "both_success", "reference_only", "compared_only",
        "both_fail", "unpaired", "chi2_cc", "p_chi2", "p_exact", "odds_ratio", "odds_ratio_low",
        "odds_ratio_high", "paper", "reading"])
    display = pd.DataFrame({
        "compared": full["compared"], "pairs": full["pairs"],
        f"{reference} only": full["reference_only"], "compared only": full["compared_only"],
        "both succeed": full["both_success"], "both fail": full["both_fail"],
        "χ² (cc)": [format_number(v, 1) for v in full["chi2_cc"]],
        "p (χ²)": [_format_p(v) for v in full["p_chi2"]],
        "p (exact)": [_format_p(v) for v in full["p_exact"]],
        "odds ratio (95%)": [_format_or(o, lo, hi) for o, lo, hi in
                             full[["odds_ratio", "odds_ratio_low", "odds_ratio_high"]]
                             .itertuples(index=False)],
        "paper": full["paper"], "reading": full["reading"],
    })
    return TablePair(full, display)


def _format_p(p: float) -> str:
    if math.isnan(p):
        return "\u2014"
    return "< 1e-300" if p < 1e-300 else (f"{p:.2g}" if p < 0.001 else format_number(p, 3))


def _format_or(o: float, lo: float, hi: float) -> str:
    if math.isnan(o):
        return "undefined"
    return f"{format_number(o, 2)} ({format_number(lo, 2)}–{format_number(hi, 2)})"


def _mcnemar_words(reference: str, other: str, n10: int, n01: int, res) -> str:
    if n10 + n01 == 0:
        return "no discordant pair: the test is undefined (p = 1)"
    better = reference if n10 > n01 else other if n01 > n10 else None
    head = (f"{reference} won {n10} pairs, {other} won {n01}")
    if better is None:
        return head + "; no difference"
    sig = "significant" if res.pvalue_exact < 0.05 else "not significant"
    return f"{head}; {better} better, {sig} at 5% (exact p = {_format_p(res.pvalue_exact)})"


# --------------------------------------------------------------------------------------------
# Design limit and failure checks
# --------------------------------------------------------------------------------------------


def design_limit_table(records: pd.DataFrame, by: Sequence[str],
                       order: Mapping[str, Sequence] | None = None) -> TablePair:
    """Return how often ``delta_max_mm`` exceeds the 1 mm design limit, per group.

    The paper keeps every contact within 1 mm (Sec. 4, Sec. 5.5); SPEC Sec. 2.7 requires the
    report to show how often our SI evaluation exceeds it, never to hide it.
    """
    by = list(by)
    ok = executed(records)
    ok = ok[ok["delta_max_mm"].notna()] if "delta_max_mm" in ok else ok.iloc[0:0]
    exceeds = (ok["exceeds_1mm"].astype("boolean").fillna(False).astype(bool)
               if "exceeds_1mm" in ok else ok["delta_max_mm"] > DESIGN_LIMIT_MM)
    ok = ok.assign(_exceeds=exceeds.to_numpy(), _succ_exceeds=(exceeds & ok["success"]).to_numpy())
    rows = []
    for key, grp in ok.groupby(by, sort=False):
        key = key if isinstance(key, tuple) else (key,)
        n, k = len(grp), int(grp["_exceeds"].sum())
        w = stats.wilson_interval(k, n, CONFIDENCE_LEVEL)
        d = grp["delta_max_mm"].to_numpy(dtype=float)
        rows.append({**dict(zip(by, key, strict=True)), "paper": "within 1 mm (Sec. 4, 5.5)",
                     "n": n, "exceeds_1mm": k, "exceeds_pct": 100 * w.estimate,
                     "wilson_low_pct": 100 * w.low, "wilson_high_pct": 100 * w.high,
                     "successes_exceeding": int(grp["_succ_exceeds"].sum()),
                     "delta_max_median_mm": float(np.median(d)),
                     "delta_max_p95_mm": float(np.quantile(d, 0.95)),
                     "delta_max_max_mm": float(d.max())})
    full = pd.DataFrame(rows, columns=[
        *by, "paper", "n", "exceeds_1mm", "exceeds_pct", "wilson_low_pct", "wilson_high_pct",
        "successes_exceeding", "delta_max_median_mm", "delta_max_p95_mm", "delta_max_max_mm"])
    full = _ordered(full, by, order)
    display = full[by].copy()
    display["paper"] = full["paper"]
    display["n"] = full["n"]
    display["> 1 mm"] = full["exceeds_1mm"]
    display["% > 1 mm (Wilson 95%)"] = [
        fmt.estimate(e, lo, hi, 1)
        for e, lo, hi in full[["exceeds_pct", "wilson_low_pct", "wilson_high_pct"]]
        .itertuples(index=False)]
    display["successes > 1 mm"] = full["successes_exceeding"]
    for col, label in (("delta_max_median_mm", "median δmax [mm]"),
                       ("delta_max_p95_mm", "95th pct δmax [mm]"),
                       ("delta_max_max_mm", "max δmax [mm]")):
        display[label] = [format_number(v, 3) for v in full[col]]
    return TablePair(full, display)


def failure_check_table(records: pd.DataFrame, by: Sequence[str],
                        order: Mapping[str, Sequence] | None = None,
                        paper: Callable[[tuple], str] | None = None) -> TablePair:
    """Return the first failing check of Algorithm 1 (none/residual/torque/slip) per group."""
    by = list(by)
    ok = executed(records)
    if "failure_check" not in ok:
        ok = ok.assign(failure_check="unknown")
    counts = (ok.groupby([*by, "failure_check"], sort=False).size()
              .unstack("failure_check", fill_value=0))
    checks = [*FAILURE_CHECKS, *sorted(str(c) for c in counts.columns if c not in FAILURE_CHECKS)]
    counts = counts.reindex(columns=checks, fill_value=0)
    full = counts.reset_index()
    full.columns = [str(c) for c in full.columns]
    full["n"] = counts.sum(axis=1).to_numpy()
    for c in counts.columns:
        full[f"{c}_pct"] = 100 * full[str(c)] / full["n"]
    full["paper"] = [paper(tuple(r)) if paper else "not reported"
                     for r in full[by].itertuples(index=False)]
    full = _ordered(full, by, order)
    display = full[by].copy()
    display["n"] = full["n"]
    for c in counts.columns:
        display[str(c)] = [f"{k} ({format_number(p)}%)" for k, p in
                           zip(full[str(c)], full[f"{c}_pct"], strict=True)]
    display["paper"] = full["paper"]
    return TablePair(full, display)


def _ordered(df: pd.DataFrame, by: list[str], order: Mapping[str, Sequence] | None
             ) -> pd.DataFrame:
    if df.empty:
        return df.reset_index(drop=True)
    keys = [_sort_key(tuple(r), by, order) for r in df[by].itertuples(index=False)]
    return df.iloc[sorted(range(len(df)), key=keys.__getitem__)].reset_index(drop=True)
