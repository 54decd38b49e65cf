"""Report of ``pso_repeatability`` (Sec. 6.8, Fig. 21) and Table 3."""

from __future__ import annotations

import math
from collections.abc import Callable

import numpy as np
import pandas as pd

from graspcampaign.analysis import agreement
from graspcampaign.analysis.rates import BOOTSTRAP_RESAMPLES
from graspcampaign.analysis.records import at_bound
from graspcampaign.analysis.vocabulary import PROPOSED, colour, label
from graspcampaign.core.identify import PARAMETER_COLUMNS, PARAMETER_NAMES
from graspcampaign.report import format as fmt
from graspcampaign.report import style
from graspcampaign.report.document import Col
from graspcampaign.report.render import Run
from graspcampaign.report.spec import Figure, Finding, ReportSpec, Table, verdicts

#: Identified parameters in Table 3's order: record column -> Table 3's name (the identification's, §4).
PARAMETERS = dict(zip(PARAMETER_COLUMNS, PARAMETER_NAMES, strict=True))
BOUND = Col("at_bound", "on a search bound", share="at_bound_pct")
NOT_IDENTIFIABLE = "no verdict: J does not depend on it, so its spread measures no identifiability"


def _digits(table3, parameter: str) -> int | None:
    """A parameter row's decimals: 3 significant digits of Table 3's value (b ~ 0.6 and c ~ 0.002 share
    a column; one rounding per column hid c)."""
    return fmt.decimals([getattr(table3, PARAMETERS[parameter])])


def _budgets(run: Run) -> tuple[pd.DataFrame, pd.DataFrame]:
    """The restarts at the paper's 8 x 15 budget, and those compared with Table 3: the converged-budget
    ones if the run has them, else the same restarts."""
    ok = run.ok
    if "budget" in ok and (ok["budget"] == "repeatability").any() and ok["budget"].nunique() > 1:
        return ok[ok["budget"] == "repeatability"], ok[ok["budget"] != "repeatability"]
    return ok, ok


def _paper_cv(run: Run, parameter: str) -> float | tuple:
    """The paper's CV [%] of ``parameter`` (Sec. 6.8): n's, the λs' approximate one, the others' range."""
    cv = run.paper.cv_pct
    return cv.n if parameter == "n_exp" else cv.lambda_approx if parameter.startswith("lambda") \
        else cv.others_range


def _flat(run: Run) -> list[str]:
    """The parameters the cost J does not depend on (the identification's ``flat_parameters``)."""
    flat = run.ok["flat_parameters"].dropna() if "flat_parameters" in run.ok else pd.Series()
    return flat.iloc[0].split(",") if len(flat) else []


def _bound(rows: pd.DataFrame, parameter: str) -> dict:
    """How many ``rows`` ended with ``parameter`` on a search bound (nan: not recorded)."""
    try:
        k = int(at_bound(rows, parameter).sum())
    except KeyError:
        k = math.nan
    return {"at_bound": k, "at_bound_pct": 100 * k / len(rows)}


def _cv(run: Run) -> pd.DataFrame:
    ok, rows, flat = _budgets(run)[0], [], _flat(run)
    for p in [p for p in PARAMETERS if p in ok and ok[p].notna().sum() >= 2]:
        v, (low, high), why = ok[p].dropna().to_numpy(float), (math.nan, math.nan), ""
        try:
            low, high = agreement.cv_interval(v, seed=run.seed)
        except ValueError as exc:
            why = str(exc)
        digits, bound = _digits(run.paper.table3, p), _bound(ok[ok[p].notna()], p)
        pinned = ", ".join(fmt.number(x, digits) for x in ok[p].dropna().unique())  # on a bound in every run
        rows.append({"parameter": p, "parameter_label": label("parameter", p),
                     "paper_cv_pct": _paper_cv(run, p), "low_pct": 100 * low, "high_pct": 100 * high,
                     "why": why, "n": v.size,
                     "cv_pct": 100 * agreement.coefficient_of_variation(v), "mean": v.mean(),
                     "sd": v.std(ddof=1), "digits": digits, **bound,
                     "pinned": pinned if bound["at_bound"] == v.size else "",
                     "flat": NOT_IDENTIFIABLE if p in flat else ""})
    frame = verdicts(pd.DataFrame(rows), "cv_pct", "paper_cv_pct", "low_pct", "high_pct", unit="%",
                     pinned="pinned", because="flat").drop(columns=["pinned", "flat"])
    paper = frame["paper_cv_pct"]  # as the paper prints it: ≈ 19 (approximate), 47.0–77.0 (range)
    return frame.assign(paper_text=[fmt.paper_text(v, 1) + (" (range)" if isinstance(v, tuple) else "")
                                    for v in paper],
                        paper_cv_pct=[np.nan if isinstance(v, tuple) else v for v in paper])


def table3(name: str, caption: str | Callable[[Run], str], identified, paper_from,
           empty: str | None = None) -> Table:
    """A Table item: identified parameters (mean, median, best-cost run, runs on a search bound)
    beside Table 3; ``identified(run)`` returns the identifications, ``paper_from(run)`` Table 3."""
    def compute(run: Run) -> pd.DataFrame:
        ident, ref, rows = identified(run), paper_from(run), []
        cost = ident["best_cost"].astype(float) if "best_cost" in ident else pd.Series(np.nan, ident.index)
        best = ident[cost == cost.min()]  # every run reaching the best cost (none without a cost)
        tied = f"{len(best)} runs tie at the best J = {fmt.number(cost.min(), sig=4)}"
        for p in [p for p in PARAMETERS if p in ident and ident[p].notna().any()]:
            v, pv = ident[p].dropna().to_numpy(float), getattr(ref, PARAMETERS[p])
            at_best = best[p].dropna().unique()  # one value, or runs tied at the best cost disagreeing
            rows.append({"parameter": p, "parameter_label": label("parameter", p), "paper": pv,
                         "digits": _digits(ref, p), "ours_mean": v.mean(), "ours_median": np.median(v),
                         "ours_best_run": float(at_best[0]) if at_best.size == 1 else math.nan,
                         "best_run_why": tied if at_best.size > 1 else "",
                         "difference_mean": v.mean() - pv, "n": v.size,
                         "relative_difference_pct": 100 * (v.mean() - pv) / pv,
                         **_bound(ident[ident[p].notna()], p)})
        return pd.DataFrame(rows)

    return Table(name, caption, compute, [
        Col("parameter_label", "parameter"), Col("paper", "paper (Table 3)", "digits"),
        Col("ours_mean", "ours mean", "digits"), Col("ours_median", "ours median", "digits"),
        Col("ours_best_run", "ours best-cost run", "digits", why="best_run_why"),
        Col("difference_mean", "difference (mean − paper)", "digits", signed=True),
        Col("relative_difference_pct", "relative [%]", 0, signed=True), Col("n", "n"), BOUND], empty=empty)


def convergence_bands(run: Run) -> pd.DataFrame:
    """Mean and 10/25/75/90th percentiles of the best cost per iteration across restarts."""
    trace = run.aux("pso_trace")
    trace = trace[trace["trial_id"].isin(_budgets(run)[0]["trial_id"])] if len(trace) else trace
    if not len(trace):
        return pd.DataFrame()
    g = trace.groupby("iteration", sort=True)
    cost = g["best_cost"]
    return pd.DataFrame({"iteration": cost.mean().index, "n_runs": cost.size().to_numpy(),
                         "n_evaluations": g["n_evaluations"].mean().to_numpy(),
                         "mean": cost.mean().to_numpy(),
                         **{f"p{q}": cost.quantile(q / 100).to_numpy() for q in (10, 25, 75, 90)}})


def finding(run: Run) -> str:
    cv, flat = run.tables["cv"], _flat(run)
    judged = cv[~cv["parameter"].isin(flat)]  # a parameter J does not depend on has no verdict
    spread, pinned = judged[judged["sd"] > 0], cv[(cv["sd"] == 0) & (cv["at_bound"] == cv["n"])]
    differ = judged[judged["differs"].eq(True)]
    on_bound = int((differ["at_bound"] == differ["n"]).sum())  # CV 0 measures the bound (their verdicts)
    text = (f"Over {len(_budgets(run)[0])} restarts at the paper's budget, {len(differ)} of {len(judged)} "
            "judged parameters' CVs differ from the paper's (Sec. 6.8; table cv)" + (
                f", {on_bound} of them because they sit on a search bound in every run" if on_bound else "")
            + ". ")
    if len(spread):
        tight = spread.loc[spread["cv_pct"].idxmin()]
        text += ("The paper finds the exponent n the most identifiable; among ours that J depends on and "
                 f"vary, {label('parameter', tight['parameter'])} has the smallest CV "
                 f"({fmt.number(tight['cv_pct'], 1)}%). ")
    if len(pinned):
        text += "Pinned in every run (CV 0, a bound of the search box): " + ", ".join(
            f"{label('parameter', p)} at {fmt.number(m, d)}"  # as the cv table's mean column
            for p, m, d in pinned[["parameter", "mean", "digits"]].itertuples(index=False)) + ". "
    if flat:
        text += (f"Why: J does not depend on {fmt.listed([label('parameter', p) for p in flat])} in the "
                 "quasi-static evaluator (the damping term vanishes in the static loop; the MSD constants do "
                 "not enter Algorithms 1-2), so their spread is where the swarm stopped and gets no verdict "
                 "(`docs/decisions.md`, *Report*: PSO). ")
    return text + "Runs ending on a search bound: column 'on a search bound' of tables cv and table3."


def fig21(run: Run, fig) -> None:
    ax_a, ax_b = fig.subplots(1, 2, width_ratios=[1.3, 1])
    ok, cv, c = _budgets(run)[0], run.tables["cv"].set_index("parameter"), colour("planner", PROPOSED)
    data = [ok[p].dropna().to_numpy(float) / ok[p].mean() for p in cv.index]
    ax_a.boxplot(data, positions=range(len(cv)), widths=0.55, showfliers=False, medianprops={"color": c})
    jitter = np.random.default_rng(run.seed)  # the dots' jitter only; no statistic uses it
    for i, v in enumerate(data):
        ax_a.scatter(i + jitter.uniform(-0.15, 0.15, v.size), v, s=9, alpha=0.6, color=c, zorder=3)
    ax_a.axhline(1.0, color=style.CRITERION, linestyle="--", linewidth=1.0)
    ax_a.set_xticks(range(len(cv)), [
        f"{label('parameter', p)}\nCV {fmt.number(r['cv_pct'], 0)}%\npaper "
        f"{fmt.paper_text(_paper_cv(run, p), 0)}%"
        + (f"\non bound {fmt.number(int(r['at_bound']))}/{r['n']}" if r["at_bound"] > 0 else "")
        for p, r in cv.iterrows()], fontsize=7)
    ax_a.set(ylabel="identified value / mean over runs [–]", title=f"(a) identified values, {len(ok)} runs")
    if len(bands := convergence_bands(run)):
        x = bands["n_evaluations"].to_numpy(float)
        ax_b.fill_between(x, bands["p10"], bands["p90"], color=c, alpha=0.15, label="10–90%")
        ax_b.fill_between(x, bands["p25"], bands["p75"], color=c, alpha=0.3, label="25–75%")
        ax_b.plot(x, bands["mean"], color=c, label="mean")
        if (bands[["p10", "mean"]] > 0).all().all() and bands["mean"].max() / bands["p10"].min() > 50:
            ax_b.set_yscale("log")
        ax_b.legend(loc="upper right")
    ax_b.set(xlabel="function evaluations [count]", ylabel="best cost J [–]",
             title="(b) convergence bands of the best cost")


def _cv_caption(run: Run) -> str:
    """The CV table's caption: its restarts (those at the paper's budget when the run has two budgets)."""
    rep, conv = _budgets(run)
    restarts = f"{len(rep)} PSO restarts" + ("" if conv is rep else " at the paper's 8 × 15 budget")
    return (f"Coefficient of variation of each identified parameter over the {restarts} beside Sec. 6.8 "
            f"(sample SD / mean; 95% percentile bootstrap over runs, {BOOTSTRAP_RESAMPLES} resamples, seed "
            f"{run.seed}); runs ending on a search bound")


SPEC = ReportSpec("pso_repeatability", [
    Finding(finding),
    Table("cv", _cv_caption, _cv, [
              Col("parameter_label", "parameter"),
              Col("paper_text", "paper CV %"),
              Col("cv_pct", "ours CV % (95%)", 1, low="low_pct", high="high_pct", why="why"),
              Col("difference", "difference [pp]", 1, signed=True), Col("n", "n"),
              Col("mean", "mean", "digits"),
              Col("sd", "SD", "digits"), BOUND, Col("verdict", "verdict")]),
    table3("table3", "Table 3 beside our identified values (converged-budget restarts when the run has "
           "them: the paper's Table 3 comes from a converged run, Sec. 5.3); b, k and c are in the paper's "
           "internal unit system (Table 3 caption), so only their order of magnitude is comparable; a value "
           "on a search bound is the box's edge",
           lambda run: _budgets(run)[1], lambda run: run.paper.table3),
    Figure("fig21_pso", "Fig. 21 (ours): (a) identified values over the restarts normalised by their mean, "
           "with our CV, the paper's and the runs on a search bound; (b) mean and 25–75% / 10–90% bands of "
           "the best cost", fig21, (10.0, 3.8)),
    Table("convergence", "Best cost J [–] (the composite cost of Sec. 11) reached by each iteration: its "
          "mean and 10th, 25th, 75th and 90th percentiles across restarts (Fig. 21b)", convergence_bands,
          empty="the run has no pso_trace table"),
])
