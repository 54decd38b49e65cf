"""Report section for ``pso_repeatability`` (paper Sec. 6.8, Fig. 21) and Table 3.

The coefficient of variation of each identified parameter over the restarts (sample SD / mean,
:func:`graspcampaign.stats.coefficient_of_variation`) with a percentile bootstrap interval over
runs, beside the paper's CVs; the identified values beside Table 3; Fig. 21 from the records and
the ``pso_trace`` table (best cost per iteration of each run).
"""

from __future__ import annotations

import math

import numpy as np
import pandas as pd
from scipy.stats import bootstrap

from graspcampaign.campaign.records import RunStore
from graspcampaign import stats
from graspcampaign.report import figure
from graspcampaign.report import table as tbl
from graspcampaign.report.document import Report

#: Identified parameters in Table 3's order (record columns of docs/records.md).
PARAMETERS = ("lambda1", "lambda2", "n_exp", "b", "k", "c")
#: Table 3's symbol for each record column (the paper calls the exponent ``n``).
TABLE3_KEY = {"lambda1": "lambda1", "lambda2": "lambda2", "n_exp": "n", "b": "b", "k": "k",
              "c": "c"}


def paper_table3(manifest: dict) -> tuple[dict[str, float], str]:
    """Return Table 3's values keyed by record column, and where they were read from.

    Taken from the run's own ``config.paper.table3``; studies whose paper block does not carry
    Table 3 read it from the ``pso_repeatability`` study file, and the table says so.
    """
    block = ((manifest.get("config") or {}).get("paper") or {}).get("table3")
    where = "this run's config.paper.table3"
    if not block:
        from graspcampaign.report.headline import campaign_paper

        block = campaign_paper("pso_repeatability").get("table3") or {}
        where = "campaigns/pso_repeatability.yaml (paper.table3)"
    return {col: float(block[key]) for col, key in TABLE3_KEY.items() if key in block}, where


def section(report: Report, records: pd.DataFrame, manifest: dict, store: RunStore | None) -> None:
    """CV per parameter beside the paper, Table 3, Fig. 21."""
    report.text(tbl.status_note(records))
    ok = records[records["status"] == "ok"]
    if "flat_parameters" in ok and ok["flat_parameters"].notna().any():
        flat = ok["flat_parameters"].dropna().iloc[0]
        report.text(
            f"**Read the CVs with care:** in the quasi-static evaluator the cost J does not depend "
            f"on {flat.replace(',', ', ')} (the damping term vanishes in the static loop and the "
            "MSD constants do not enter Algorithms 1-2), so their spread is where the swarm "
            "stopped inside the bounds, not a measure of identifiability. Parameters pinned at "
            "a bound show a CV of 0.")
    converged = ok.iloc[0:0]
    if "budget" in ok and (ok["budget"] == "repeatability").any() and ok["budget"].nunique() > 1:
        converged = ok[ok["budget"] != "repeatability"]
        ok = ok[ok["budget"] == "repeatability"]
        report.text(f"The CV table and Fig. 21 use the {len(ok)} restarts at the paper's 8 x 15 "
                    f"budget (Sec. 6.8); Table 3 uses the {len(converged)} converged-budget "
                    "restarts (the paper's Table 3 comes from a converged run, Sec. 5.3).")
    params = [p for p in PARAMETERS if p in ok and ok[p].notna().sum() >= 2]
    paper = ((manifest.get("config") or {}).get("paper") or {}).get("cv_pct") or {}
    seed = int((manifest.get("config") or {}).get("seed", 0))
    rows = []
    for p in params:
        values = ok[p].dropna().to_numpy(dtype=float)
        cv = float(stats.coefficient_of_variation(values))
        low, high = _cv_interval(values, seed)
        paper_value, paper_text, verdict = _paper_cv(p, 100 * cv, paper, low, high)
        rows.append({"parameter": p, "paper_cv_pct": paper_value, "paper_text": paper_text,
                     "cv_pct": 100 * cv, "difference_pp": 100 * cv - paper_value
                     if paper_value is not None else math.nan,
                     "low_pct": 100 * low, "high_pct": 100 * high, "n": int(values.size),
                     "mean": float(values.mean()), "sd": float(values.std(ddof=1)),
                     "verdict": verdict})
    full = pd.DataFrame(rows, columns=["parameter", "paper_cv_pct", "paper_text", "cv_pct",
                                       "difference_pp", "low_pct", "high_pct", "n", "mean", "sd",
                                       "verdict"])
    if len(full):
        display = pd.DataFrame({
            "parameter": full["parameter"], "paper CV %": full["paper_text"],
            "ours CV % (95%)": [f"{tbl.format_number(c)} ({tbl.format_number(lo)}–"
                                f"{tbl.format_number(hi)})" if not math.isnan(lo) else
                                f"{tbl.format_number(c)} (every run at one value)" for c, lo, hi
                                in full[["cv_pct", "low_pct", "high_pct"]].itertuples(index=False)],
            "difference": [tbl.format_signed(v) for v in full["difference_pp"]],
            "n": full["n"], "mean": [f"{v:.4g}" for v in full["mean"]],
            "SD": [f"{v:.4g}" for v in full["sd"]], "verdict": full["verdict"]})
        report.table("cv", full,
                     "Coefficient of variation of each identified parameter over the PSO "
                     "restarts beside Sec. 6.8 (sample SD / mean; 95% percentile bootstrap over "
                     f"runs, {tbl.BOOTSTRAP_RESAMPLES} resamples, seed {seed})", display)
        report.text(_ranking_words(full))
    table3_rows = converged if len(converged) else ok
    if len(table3_rows):
        add_table3(report, table3_rows, manifest, name="table3",
                   label=f"identified values of the {len(table3_rows)} "
                         f"{'converged-budget ' if len(converged) else ''}restarts")
    bands = None
    if store is not None:
        trace = store.read("tables/pso_trace").to_pandas()
        if len(trace):
            bands = convergence_bands(trace[trace["trial_id"].isin(ok["trial_id"])])
    if params:
        normalised = pd.DataFrame({p: ok[p].to_numpy(dtype=float) / ok[p].mean() for p in params})
        cv = dict(zip(full["parameter"], full["cv_pct"], strict=True))
        paper_txt = dict(zip(full["parameter"], full["paper_text"], strict=True))
        report.figure("fig21_pso", figure.fig21_pso(normalised, cv, paper_txt, bands),
                      f"Fig. 21 (ours): (a) identified values over {len(ok)} restarts normalised "
                      "by their mean, with our CV and the paper's; (b) mean and 25–75% / 10–90% "
                      "bands of the best cost")
    if bands is not None and len(bands):
        report.table("convergence", bands, "Best-cost convergence bands across restarts "
                     "(Fig. 21b)")


def _ranking_words(full: pd.DataFrame) -> str:
    """Say whether n is the most identifiable parameter, as the paper finds (Sec. 6.8)."""
    head = "The paper finds the exponent n the most identifiable (smallest CV). "
    pinned = full[full["sd"] == 0]
    spread = full[full["sd"] > 0]
    text = ""
    if len(pinned):
        text = ("Ours: " + ", ".join(f"{p} ends at {m:.4g}" for p, m in
                                     zip(pinned["parameter"], pinned["mean"], strict=True))
                + " in every run (CV 0: pinned, typically at a bound of the search box), so a "
                "CV ranking says nothing about them. ")
    if not len(spread):
        return head + text
    tightest = spread.loc[spread["cv_pct"].idxmin()]
    if tightest["parameter"] == "n_exp":
        return head + text + f"Ours agrees: n has the smallest CV " \
            f"({tbl.format_number(tightest['cv_pct'])}%)."
    among = "Among the parameters that vary, " if len(pinned) else "Ours differs: "
    return (head + text + f"{among}{tightest['parameter']} has the smallest CV "
            f"({tbl.format_number(tightest['cv_pct'])}%)"
            + (", not n." if "n_exp" in set(spread["parameter"]) else "."))


def _cv_interval(values: np.ndarray, seed: int) -> tuple[float, float]:
    if values.size < 3 or np.ptp(values) == 0:
        return math.nan, math.nan
    res = bootstrap((values,), lambda x, axis=-1: np.std(x, axis=axis, ddof=1) /
                    np.mean(x, axis=axis), n_resamples=tbl.BOOTSTRAP_RESAMPLES,
                    method="percentile", rng=np.random.default_rng(seed), vectorized=True)
    return float(res.confidence_interval.low), float(res.confidence_interval.high)


def _paper_cv(param: str, cv_pct: float, paper: dict, low: float, high: float
              ) -> tuple[float | None, str, str]:
    """Return the paper's CV for ``param`` (number or None), as text, and our verdict."""
    if param == "n_exp" and "n" in paper:
        value = float(paper["n"])
        return value, f"{value:g}", _cv_words(cv_pct, value, low, high)
    lam = paper.get("lambda_approx")
    if param in ("lambda1", "lambda2") and lam is not None:
        value = float(lam)
        return value, f"≈{value:g}", _cv_words(cv_pct, value, low, high)
    rng = paper.get("others_range")
    if rng and param != "n_exp":
        inside = rng[0] <= cv_pct <= rng[1]
        text = f"{rng[0]:g}–{rng[1]:g} (range)"
        return None, text, ("inside the paper's range" if inside else
                            f"differs from the paper: outside its {rng[0]:g}–{rng[1]:g}% range")
    return None, "not reported", "the paper reports no value for this parameter"


def _cv_words(cv_pct: float, paper: float, low: float, high: float) -> str:
    diff = cv_pct - paper
    where = "" if math.isnan(low) else (
        "; inside our 95% interval" if 100 * low <= paper <= 100 * high else
        "; outside our 95% interval")
    if tbl.format_number(diff) in ("0.0", f"{tbl.MINUS}0.0"):
        return f"matches the paper{where}"
    return f"differs from the paper by {tbl.format_signed(diff)}{where}"


def convergence_bands(trace: pd.DataFrame) -> pd.DataFrame:
    """Return mean and 10/25/75/90th percentiles of the best cost per iteration across runs."""
    if not len(trace):
        return pd.DataFrame()
    grouped = trace.groupby("iteration", sort=True)
    cost = grouped["best_cost"]
    return pd.DataFrame({
        "iteration": cost.mean().index.to_numpy(),
        "n_evaluations": grouped["n_evaluations"].mean().to_numpy(),
        "n_runs": cost.size().to_numpy(),
        "mean": cost.mean().to_numpy(), "p10": cost.quantile(0.10).to_numpy(),
        "p25": cost.quantile(0.25).to_numpy(), "p75": cost.quantile(0.75).to_numpy(),
        "p90": cost.quantile(0.90).to_numpy(),
    })


def add_table3(report: Report, identified: pd.DataFrame, manifest: dict, *, name: str,
               label: str) -> None:
    """Add the identified parameters (mean, median, best-cost run) beside Table 3's values."""
    paper, where = paper_table3(manifest)
    params = [p for p in PARAMETERS if p in identified and identified[p].notna().any()]
    if not params:
        return
    best = None
    if "best_cost" in identified and identified["best_cost"].notna().any():
        best = identified.loc[identified["best_cost"].astype(float).idxmin()]
    rows = []
    for p in params:
        values = identified[p].dropna().to_numpy(dtype=float)
        pv = paper.get(p)
        mean = float(values.mean())
        rows.append({"parameter": p, "paper": pv, "ours_mean": mean,
                     "ours_median": float(np.median(values)),
                     "ours_best_run": float(best[p]) if best is not None else math.nan,
                     "difference_mean": mean - pv if pv is not None else math.nan,
                     "relative_difference_pct": 100 * (mean - pv) / pv if pv else math.nan,
                     "n": int(values.size)})
    full = pd.DataFrame(rows)
    display = pd.DataFrame({
        "parameter": full["parameter"],
        "paper (Table 3)": [_num(v) for v in full["paper"]],
        "ours mean": [_num(v) for v in full["ours_mean"]],
        "ours median": [_num(v) for v in full["ours_median"]],
        "ours best-cost run": [_num(v) for v in full["ours_best_run"]],
        "difference (mean − paper)": [_num(v, signed=True) for v in full["difference_mean"]],
        "relative": [tbl.format_signed(v, 0, " %") for v in full["relative_difference_pct"]],
        "n": full["n"]})
    report.table(name, full, f"Table 3 beside our {label}; paper values from {where}. b, k and "
                 "c are in the paper's internal unit system (Table 3 caption), so only their "
                 "order of magnitude is comparable", display)


def _num(value: float | None, signed: bool = False) -> str:
    if value is None or (isinstance(value, float) and math.isnan(value)):
        return "—"
    text = f"{value:+.3g}" if signed else f"{value:.3g}"
    return text.replace("-", tbl.MINUS)
