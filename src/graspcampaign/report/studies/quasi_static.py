"""Reports of the quasi-static studies: ``shapes`` (Sec. 6.2, Fig. 15), ``ablation`` (Sec. 6.3,
Fig. 16), ``baseline_grid`` (Sec. 6.5, Fig. 18), and any other study of the kind (``PLANNERS``).

Every rate is over executed trials with its Wilson interval and a shape-clustered bootstrap;
paired tests match trials by ``scene_id``. A planner whose overall paper rate is exactly 0 % or
100 % carries that rate to every subgroup (Sec. 6.5: the centroid's 0 % is "μ-independent").
"""

from __future__ import annotations

import numpy as np
import pandas as pd
from matplotlib.lines import Line2D
from matplotlib.patches import Patch

from graspcampaign.analysis.records import DESIGN_LIMIT_MM, Estimate
from graspcampaign.analysis.vocabulary import PROPOSED, colour, label, ordered
from graspcampaign.campaign.paper import study_paper
from graspcampaign.report import style
from graspcampaign.report.document import Col
from graspcampaign.report.render import Run
from graspcampaign.report.spec import (
    Claims,
    DesignLimit,
    FailureChecks,
    Figure,
    Finding,
    Paired,
    Rates,
    ReportSpec,
    Table,
    Value,
    verdicts,
)
from graspcampaign.report.studies.pso import table3

WHY = ("Our rates sit far below the paper's because Algorithm 2, implemented as published, "
       "releases the upper contacts at line 7's sign step, so most grasps end resting on one "
       "near-vertical fingertip with a horizontal residual the loop never acts on, and because "
       "in SI the paper's contact constants cannot carry 0.2–0.6 kg at a sane indentation "
       "(SPEC §8; `docs/decisions.md`, *Contact law, evaluator, planners, PSO (issue 4)* and "
       "*Simulation studies (issue 4, campaign side)*: the ‖R‖ residual check).")


def carried(table: dict, overall: dict, planner: str):
    """The paper's rate of ``planner`` in a subgroup: printed, or carried from 0 %/100 %."""
    if planner in table:
        return table[planner]
    value = overall.get(planner)
    return value if value in (0, 0.0, 100, 100.0) else None


def identifications(run: Run) -> pd.DataFrame:
    return run.part("prepared")


IDENTIFICATIONS = table3(
    "identifications", "PSO identifications of this run's soft bodies (prepared/) beside "
    "Table 3 (values from campaigns/pso_repeatability.yaml); b, k and c are in the paper's "
    "internal units", identifications, lambda run: study_paper("pso_repeatability").table3,
    empty=None)


def planner_finding(run: Run) -> str:
    """Success of every planner beside the paper, the paired test and the design limit."""
    rates = run.tables["success_by_planner"].set_index("planner")
    parts = [f"{label('planner', p)} {r['rate_pct']:.1f}%" + (
        f" (paper {r['paper_pct']:g}%)" if pd.notna(r["paper_pct"]) else "")
        for p, r in rates.iterrows() if r["n"]]
    n = int(rates["n"].max()) if len(rates) else 0
    text = (f"Success over executed trials (up to {n} per planner): " + "; ".join(parts) + ". "
            f"{int((rates['differs'] == True).sum())} of {int(rates['differs'].notna().sum())} "  # noqa: E712
            "rates with a paper value differ from it (the paper's value outside our 95% "
            "interval). ")
    paired = run.tables.get("mcnemar")
    if paired is not None and len(paired):
        won = paired.set_index("compared")
        text += "Paired on the same scenes, the proposed planner's pairs won–lost are " + \
            ", ".join(f"{r['reference_only']}–{r['compared_only']} against "
                      f"{label('planner', p)}" for p, r in won.iterrows()) + ". "
    limit = run.tables.get("design_limit")
    if limit is not None and len(limit):
        text += (f"{int(limit['exceeds'].sum())} of {int(limit['n'].sum())} executed trials "
                 f"exceed the paper's {DESIGN_LIMIT_MM:g} mm design limit. ")
    return text + WHY


def planner_bars(ax, rates: pd.DataFrame) -> None:
    """Bars of success per planner with Wilson whiskers and the paper's marks."""
    x = np.arange(len(rates))
    marked = style.bars(ax, x, rates["rate_pct"], rates["wilson_low_pct"],
                        rates["wilson_high_pct"],
                        [colour("planner", p, i) for i, p in enumerate(rates["planner"])],
                        paper=rates["paper_pct"].tolist())
    ax.set_xticks(x, [f"{label('planner', p)}\nn={n}" for p, n in
                      zip(rates["planner"], rates["n"], strict=True)])
    style.rate_axes(ax)
    ax.legend(handles=[style.interval_handle("ours, Wilson 95%"),
                       *([style.paper_handle()] if marked else [])], loc="upper right")


def fig16(run: Run, fig) -> None:
    planner_bars(fig.subplots(), run.tables["success_by_planner"])


# ------------------------------------------------------------------------------------- shapes
def _shapes(run: Run) -> pd.DataFrame:
    p, rows = run.paper, []
    for shape in ordered("shape", run.records["shape"], run.order.get("shape", ())):
        g = run.ok[run.ok["shape"] == shape]
        checks = g["failure_check"].value_counts() if "failure_check" in g else pd.Series()
        row = {"shape": shape, "paper_success": p.success.get(shape),
               "paper_failure_check": p.failure_check.get(shape, "none" if p.success.get(shape)
                                                          else None),
               "n": len(g), "successes": int(g["success"].sum()) if len(g) else 0,
               "n_error": int(((run.records["shape"] == shape)
                               & (run.records["status"] == "error")).sum()),
               "ours_success": bool(g["success"].mean() >= 0.5) if len(g) else None,
               "failure_check": ", ".join(f"{c} {v}" for c, v in checks.items()),
               "exceeds_1mm": int((g["delta_max_mm"] > DESIGN_LIMIT_MM).sum())}
        for col in ("h_total", "residual_norm_n", "torque_norm_nm", "slip_margin_n",
                    "delta_max_mm"):
            row[col] = float(g[col].median()) if len(g) else float("nan")
        rows.append(row)
    return verdicts(pd.DataFrame(rows), "ours_success", "paper_success")


def _h(which: str):
    def value(run: Run) -> Estimate:
        h = run.ok["h_total"]
        return Estimate(float(h.min() if which == "min" else h.max()), n=len(h))
    return value


def shapes_finding(run: Run) -> str:
    t = run.tables["shapes"]
    agree = t[t["differs"] == False]  # noqa: E712
    differ = t[t["differs"] == True]  # noqa: E712
    text = (f"{len(agree)} of {len(t)} shapes reach the paper's outcome (Fig. 15)"
            + (f": {', '.join(label('shape', s) for s in agree['shape'])}" if len(agree) else "")
            + ". ")
    if len(differ):
        text += "Ours differs on " + "; ".join(
            f"{label('shape', r['shape'])} (paper {'success' if r['paper_success'] else 'fails'}"
            f", ours {r['successes']}/{r['n']}, first failing check {r['failure_check'] or '—'})"
            for _, r in differ.iterrows()) + ". "
    return text + WHY


def fig15(run: Run, fig) -> None:
    t = run.tables["shapes"]
    axes = fig.subplots(2, 2, sharex=True).ravel()
    x = np.arange(len(t))
    tau = float(run.config["evaluator"]["tau_f_n"])
    colours = ["#2e7d32" if s else "#c62828" for s in t["ours_success"].fillna(False)]
    for ax, (col, title, line) in zip(axes, (
            ("h_total", "(a) heuristic H(G) [–]", None),
            ("residual_norm_n", "(b) force residual ‖R‖ [N]", tau),
            ("torque_norm_nm", "(c) torque residual ‖τ‖ [N·m]", None),
            ("slip_margin_n", "(d) slip margin [N]", 0.0)), strict=True):
        ax.bar(x, np.nan_to_num(t[col].to_numpy(float)), 0.7, color=colours)
        ax.set_title(title)
        if line is not None:
            ax.axhline(line, color=style.CRITERION, linestyle="--", linewidth=1.0)
    lo, hi = run.paper.h_range
    axes[0].axhspan(lo, hi, color=style.PAPER, alpha=0.12, zorder=0)
    axes[0].set_ylim(0, 1.35 * max(float(np.nanmax(t["h_total"].to_numpy(float))), hi))
    for xi, (ours, paper) in enumerate(zip(t["ours_success"], t["paper_success"], strict=True)):
        axes[0].annotate(f"ours {'✓' if ours else '✗'}\npaper "
                         f"{'—' if paper is None else '✓' if paper else '✗'}", (xi, 1),
                         xycoords=("data", "axes fraction"), ha="center", va="top", fontsize=7)
    for ax in axes[2:]:
        ax.set_xticks(x, [label("shape", s).replace(" ", "\n") for s in t["shape"]])
    fig.legend(handles=[Patch(color="#2e7d32", label="ours: success"),
                        Patch(color="#c62828", label="ours: failure"),
                        Patch(color=style.PAPER, alpha=0.12, label=f"paper's H range {lo}–{hi}"),
                        Line2D([], [], color=style.CRITERION, linestyle="--",
                                     label=f"criterion: ‖R‖ < {tau:g} N; slip margin > 0")],
               loc="outside lower center", ncol=4)


SHAPES = ReportSpec("shapes", [
    Finding(shapes_finding),
    Table("shapes", "Outcome and grasp metrics per shape beside Fig. 15 (medians over the "
          "shape's executed trials)", _shapes, [
              Col("paper_success", "paper: success"), Col("paper_failure_check", "paper: check"),
              Col("ours_success", "ours: success"), Col("successes", "successes"),
              Col("n", "n"), Col("n_error", "errors"), Col("failure_check", "ours: checks"),
              Col("h_total", "H(G)", 3), Col("residual_norm_n", "‖R‖ [N]", 3),
              Col("torque_norm_nm", "‖τ‖ [N·m]", 4), Col("slip_margin_n", "slip margin [N]", 3),
              Col("delta_max_mm", "δmax [mm]", 2), Col("exceeds_1mm", "> 1 mm"),
              Col("verdict", "verdict")], by=["shape"]),
    Claims("h_range", "Heuristic value range across shapes beside the Fig. 15 caption", [
        Value("H(G) of the chosen grasps, lowest over shapes", "Fig. 15", _h("min"),
              lambda p: p.h_range, digits=2),
        Value("H(G) of the chosen grasps, highest over shapes", "Fig. 15", _h("max"),
              lambda p: p.h_range, digits=2)]),
    Figure("fig15_shape_metrics", "Fig. 15 (ours): chosen grasp's metrics per shape (medians); "
           "green = success, red = failure; our and the paper's outcome above panel (a)",
           fig15, (9.0, 6.4)),
    DesignLimit(["shape"]),
    FailureChecks(["shape"], lambda p, k: p.failure_check.get(
        k["shape"], "none" if p.success.get(k["shape"]) else "not reported")),
    IDENTIFICATIONS,
])

# ----------------------------------------------------------------------------------- ablation
def ablation_finding(run: Run) -> str:
    full = run.tables["success_by_planner"].set_index("planner").loc[PROPOSED]
    half = (full["wilson_high_pct"] - full["wilson_low_pct"]) / 2
    return planner_finding(run) + (
        f" Power: at the paper's {run.paper.trials_per_variant} trials per variant its interval "
        f"is roughly ±{run.paper.interval_half_width_pp:g} pp (Sec. 6.3); ours on the full "
        f"heuristic is ±{half:.1f} pp at n = {full['n']}.")


ABLATION = ReportSpec("ablation", [
    Finding(ablation_finding),
    Rates("success_by_planner", "Success per variant beside Fig. 16", ["planner"],
          lambda p, k: p.success_pct.get(k["planner"])),
    Figure("fig16_ablation", "Fig. 16 (ours): success per variant with Wilson 95% whiskers; "
           "black marks are the paper's values", fig16, (7.2, 3.6)),
    Paired(),
    DesignLimit(["planner"]),
    FailureChecks(["planner"]),
    IDENTIFICATIONS,
])


# ------------------------------------------------------------------------------ baseline grid
def fig18(run: Run, fig) -> None:
    ax_a, ax_b = fig.subplots(1, 2, width_ratios=[1, 2.2])
    planner_bars(ax_a, run.tables["success_by_planner"])
    ax_a.set_title("(a) overall")
    by = run.tables["success_by_shape"]
    planners = list(dict.fromkeys(by["planner"]))
    shapes = list(dict.fromkeys(by["shape"]))
    width = 0.8 / max(len(planners), 1)
    marked = False
    for i, p in enumerate(planners):
        sub = by[by["planner"] == p].set_index("shape").reindex(shapes)
        xs = np.arange(len(shapes)) + (i - (len(planners) - 1) / 2) * width
        marked |= style.bars(ax_b, xs, sub["rate_pct"], sub["wilson_low_pct"],
                             sub["wilson_high_pct"], colour("planner", p, i), width,
                             sub["paper_pct"].tolist(), label=label("planner", p))
    ax_b.set_xticks(np.arange(len(shapes)), [label("shape", s) for s in shapes])
    style.rate_axes(ax_b)
    ax_b.set_title("(b) by shape (Wilson 95% whiskers)")
    handles = ax_b.get_legend_handles_labels()[0] + ([style.paper_handle()] if marked else [])
    style.legend_below(ax_b, handles, ncol=min(len(handles), 5))


def _carried_overall(p, k: dict):
    return carried({}, p.success_pct, k["planner"])


BASELINE_GRID = ReportSpec("baseline_grid", [
    Finding(planner_finding),
    Rates("success_by_planner", "Success per planner beside Fig. 18a", ["planner"],
          lambda p, k: p.success_pct.get(k["planner"])),
    Rates("success_by_shape", "Success per shape and planner beside Fig. 18b (the paper prints "
          "only the rounded cube's values; a planner at 0% overall is 0% on every shape)",
          ["shape", "planner"], lambda p, k: carried(p.success_by_shape_pct.get(k["shape"], {}),
                                                     p.success_pct, k["planner"]),
          bootstrap=False),
    Paired(),
    DesignLimit(["planner"]),
    Figure("fig18_baselines", "Fig. 18 (ours): (a) overall success per planner, (b) per shape; "
           "Wilson 95% whiskers; black marks are the paper's values", fig18, (10.5, 4.0)),
    Rates("success_by_mu", "Success per planner and friction coefficient μ (not printed in the "
          "paper except where a planner's overall rate is 0% or 100%)", ["planner", "mu"],
          _carried_overall),
    Rates("success_by_mass_kg", "Success per planner and object mass (not printed in the paper "
          "except where a planner's overall rate is 0% or 100%)", ["planner", "mass_kg"],
          _carried_overall),
    FailureChecks(["planner"], lambda p, k: "residual (normal forces stay at seed level, "
                  "Sec. 6.5)" if k["planner"] == "centroid" else None),
    IDENTIFICATIONS,
])

# ----------------------------------------------------------------------- any other such study
PLANNERS = ReportSpec("quasi_static", [
    Rates("success_rates", "Success per planner", ["planner"],
          lambda p, k: getattr(p, "success_pct", {}).get(k["planner"])),
    Paired(),
    DesignLimit(["planner"]),
    FailureChecks(["planner"]),
    IDENTIFICATIONS,
])
