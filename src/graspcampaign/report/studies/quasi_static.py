"""Reports of the quasi-static studies: ``shapes`` (Sec. 6.2, Fig. 15), ``ablation`` (Sec. 6.3,
Fig. 16), ``baseline_grid`` (Sec. 6.5, Fig. 18), ``grip_laws`` (that grid under the grip laws of
Sec. 6.5/12) and any other study of the kind (``PLANNERS``). Paired tests match ``scene_id`` (and
``grip_law`` where it is a factor); an overall paper rate of 0 % or 100 % is carried to subgroups.
"""

from __future__ import annotations

from dataclasses import replace

import numpy as np
import pandas as pd
from matplotlib.lines import Line2D
from matplotlib.patches import Patch
from matplotlib.ticker import MaxNLocator

from graspcampaign.analysis import quasi_static as qs
from graspcampaign.analysis import records as rec
from graspcampaign.analysis.rates import BOOTSTRAP_RESAMPLES
from graspcampaign.analysis.records import DESIGN_LIMIT_MM, FAILURE_CHECKS, Estimate
from graspcampaign.analysis.vocabulary import PROPOSED, colour, label, ordered
from graspcampaign.campaign.paper import study_paper
from graspcampaign.core.words import counted
from graspcampaign.report import format as fmt
from graspcampaign.report import spec as S
from graspcampaign.report import style
from graspcampaign.report.document import Col, cols, pct_col
from graspcampaign.report.render import Run
from graspcampaign.report.studies.pso import PARAMETERS, table3

DECISION = f"`docs/decisions.md`, *{S.VALIDITY}*"
LAWS, BY_LAW = ["planner", "grip_law"], ["grip_law", "planner"]
PAPER_MARKS = "black marks are the paper's (Algorithm 2) values"


def _carried(by_group: dict, p, k: dict):
    """The paper's rate of a planner in a subgroup: printed, or carried from an overall 0 % / 100 %."""
    value = by_group.get(k["planner"], p.success_pct.get(k["planner"]))
    return value if k["planner"] in by_group or value in (0, 100) else None


def _bounds(run: Run) -> str:
    """Which identified parameters ended on a PSO search bound, at what value; where J is flat."""
    prep, parts = run.part("prepared"), []
    for column, p in ((c, p) for c, p in PARAMETERS.items() if f"at_bound_{p}" in prep):
        if (on := rec.flag(prep, f"at_bound_{p}")).any():
            at = "/".join(fmt.number(v) for v in sorted(set(prep.loc[on, column])))
            parts.append(f"{label('parameter', p)} = {at} in {int(on.sum())} of {len(prep)}")
    flat = prep["flat_parameters"].value_counts() if "flat_parameters" in prep else pd.Series()
    flat_in = ", ".join(label("parameter", p) for p in str(flat.index[0]).split(",")) if len(flat) else ""
    return ("; on a PSO search bound: " + ", ".join(parts) if parts else "; none on a PSO bound") + (
        f" (J is flat in {flat_in} in {flat.iloc[0]} of {len(prep)} bodies)." if len(flat) else ".")


IDENTIFICATIONS = table3("identifications", lambda run: (
    "PSO identifications of this run's soft bodies (prepared/) beside Table 3; b, k, c in the paper's "
    "internal units" + _bounds(run)), lambda run: run.part("prepared"),
    lambda run: study_paper("pso_repeatability").table3, empty=None)


def readings(by: list[str]) -> S.Table:
    """Success under every reading per group, and the passes the gate and τ_T alone removed; the
    trials left out for a reading missing in a column shown only where there are some."""
    heads = {"success": "success", "success_unbounded": "without the validity gate",
             "success_vertical": "|R_z| reading", "success_no_torque": "torque check off"}

    def compute(run: Run) -> pd.DataFrame:
        return run.memo(f"readings{by}", lambda: qs.readings(run.records, by, run.order))

    def torque(run: Run) -> str:
        """Sec. 3.7's claim that τ_T never binds, beside what the records show."""
        t, first = compute(run), int((run.ok["failure_check"] == "torque").sum())
        binds = t["torque_binds"] > 0
        return ("; τ_T off (Sec. 3.7: τ_T never binds" + (
            f"; here it does: τ_T alone removed {int(t['torque_binds'].sum())} passes, in "
            f"{int(binds.sum())} of {len(t)} groups, and torque is the first failing check of {first} "
            f"of {len(run.ok)} trials, table failure_checks)" if binds.any() else
            f"; here τ_T alone removed no pass; torque is the first failing check of {first} of "
            f"{len(run.ok)} trials)"))

    return S.Table("readings", lambda run: (
        "Success per reading (Wilson 95%): as configured (‖R‖ < τ_F, ‖τ‖ < τ_T = "
        f"{fmt.number(run.config['evaluator']['tau_t_nm'])} N·m, slip margin > 0, no active contact deeper "
        "than the fingertip radius); without that validity gate; |R_z| < τ_F (the paper's prose)"
        + torque(run) + "; the passes the gate alone and τ_T alone removed"),
        compute, lambda run, t: [
            Col("n", "n"), *[Col("n_unread", "a reading missing (left out)")] * bool(t["n_unread"].any()),
            *(pct_col(r, h) for r, h in heads.items()), Col("gate_removed", "removed by the gate"),
            Col("torque_binds", "failed only τ_T")], by=by)


#: The mechanism table's columns after n and their headings.
MECHANISM_HEADS = {"released": "released δ = 0", "upper_released": "released = upper",
                   "rho_median": "median ρ", "rho_passable": "ρ·W < τ_F", "successes": "passes",
                   "single_fingertip": "passes on one fingertip", "single_loaded": "passes, one loaded"}


def mechanism_cols(run: Run, t: pd.DataFrame) -> list[Col]:
    """The mechanism table's columns; after a count, the trials it left out for a reading not recorded
    (``<count>_unread``: its n is n less them, or the passes less them), where some row has any."""
    out = [Col("n", "n")]
    for key, head in MECHANISM_HEADS.items():
        out.append(Col(key, head, 3 if key == "rho_median" else None))
        if f"{key}_unread" in t and t[f"{key}_unread"].any():
            out.append(Col(f"{key}_unread", f"{head}: no reading (left out)"))
    return out


MECHANISM = S.Table("mechanism", lambda run: (
    "How Algorithm 2 ends each planner's triples (paper law): a contact released to δ = 0 by line 7; as many "
    "released as upper (n_out,z > 0) contacts; median ρ = |R_xy|/W; ρ·W < τ_F = "
    f"{fmt.number(run.config['evaluator']['tau_f_n'])} N (only these can pass ‖R‖ < τ_F); passes; passes "
    f"with one contact giving ≥ {fmt.number(100 * qs.SINGLE_FINGERTIP_SHARE)}% of the vertical support; with "
    "one loaded contact"),
    lambda run: qs.mechanism(run.records, run.config["evaluator"]["tau_f_n"], run.order), mechanism_cols,
    by=["planner"])


def grid_finding(run: Run, more: str = "") -> str:
    """The proposed planner beside the paper, how many planners differ, and why the paper's rates
    cannot come from its own Algorithm 2 (said where the records cap a planner below its paper rate;
    per planner: table mechanism; the Why only where a planner differs or is capped); ``more``:
    sentences before the decision."""
    m, rates = run.tables["mechanism"], qs.algorithm_2(run.tables["success_by_planner"])
    t, paper = m.sum(numeric_only=True).astype(int), rates.set_index("planner")["paper_pct"]
    read = m["n"] - m["rho_passable_unread"]  # a count's n: the triples with its reading
    judged = m[read.gt(0) & m["planner"].isin(paper.dropna().index)]
    capped = int((100 * judged["rho_passable"] / read[judged.index] < judged["planner"].map(paper)).sum())
    released_n = t.n - t.released_unread
    released = f"released in {t.released} of {released_n} triples" + (
        " with an `n_released` reading" if released_n < t.n else "") + (
        f", {fmt.number(100 * t.released / released_n, 1)}%" if released_n else "")
    differ, compared = fmt.differing(rates)
    proposed = "".join(
        f"The proposed planner passes {fmt.number(h.rate_pct, 1)}% of {h.n} triples (Wilson 95% "
        f"{fmt.interval(h.wilson_low_pct, h.wilson_high_pct, 1)}; paper {fmt.number(h.paper_pct, 1)}%); "
        for h in rates[(rates["planner"] == PROPOSED) & (rates["n"] > 0)].itertuples())
    cannot = "**The paper's rates cannot come from its own Algorithm 2.** " if capped else ""  # none capped
    caps = f", which caps {capped} of {counted(len(judged), 'planner')} below the paper's rate" * bool(capped)
    why = (  # a gap to explain: a planner differing from the paper or capped below its rate
        f" Why: line 7 drives every upper contact (n_out,z > 0) to δ = 0 ({released}) and the lower ones "
        "leave a horizontal residual W·ρ the loop never reduces: only triples with ρ·W < τ_F can pass"
        f"{caps} (table mechanism)."
        if differ or capped else "")
    return (
        f"{cannot}{proposed}"
        f"{differ} of {counted(compared, 'planner')} with a paper value "
        f"{'differs' if differ == 1 else 'differ'} from it (table success_by_planner).{why}{more} "
        f"SPEC §8; {DECISION}.")


def LawPaired() -> S.Table:
    """McNemar of the proposed planner against each other, within each grip law."""
    base = S.Paired(caption="Paired comparison within each grip law, McNemar on pairs matched by "
                    "(scene_id, grip_law)")

    def compute(run: Run) -> pd.DataFrame:
        return pd.concat([base.compute(Run(run.records[run.records["grip_law"] == law], run.manifest,
                                           run.paper)).assign(grip_law=law,
                                                              grip_law_label=label("grip_law", law))
                          for law in run.order.get("grip_law", ["paper"])])

    return replace(base, compute=compute, cols=[Col("grip_law_label", "grip law"), *base.cols])


def no_candidates(run: Run) -> str:
    """Why the run holds no (H, ε) candidates of its ferrari_canny trials (``tables/candidates``), in
    the run's terms; "" if it holds them. Never a path: a report is the same bytes wherever it is made."""
    if len(run.aux("candidates")):
        return ""
    if run.params.get("candidate_sample") == 0:
        return "this run stored no candidate table (params.candidate_sample=0 keeps none)"
    # a run keeping account of its parts is refused by the report's check when one is gone
    return ("this run's candidate table (tables/candidates), which its ferrari_canny trials store, is "
            "missing; its records were stored before runs kept account of their tables, so `graspcampaign "
            "run` cannot redo it: restore it from a backup, or record a new run")


def h_epsilon_figure(run: Run, fig) -> None:
    trials = qs.ferrari_canny_trials(run.records)
    if why := no_candidates(run):
        raise ValueError(why)
    c = run.aux("candidates").query("trial_id in @trials.trial_id")
    a, b = fig.subplots(1, 2)
    bar = fig.colorbar(a.hexbin(c["h_total"], c["epsilon_fc"], gridsize=40, bins="log", mincnt=1), ax=a,
                       label="candidates [count]")
    style.plain_log(bar.ax.yaxis)  # counts: 1, 2, 5, not 2×10⁰
    a.set(xlabel="H(G) [–], lower is better", ylabel="Ferrari–Canny ε [–], higher is better",
          title="(a) every sampled candidate")
    b.hist(trials["spearman_h_epsilon"].dropna(), bins=30, color=colour("planner", "ferrari_canny"))
    b.axvline(0.0, color=style.CRITERION, linestyle="--", linewidth=1.0)
    b.set(xlabel="Spearman ρ of H and ε over one trial's candidates [–]", ylabel="trials [count]",
          title="(b) per trial (ρ < 0: H agrees with ε)")
    b.yaxis.set_major_locator(MaxNLocator(integer=True))  # trials are counted


def _rho_text(run: Run) -> str:
    t = run.tables["h_epsilon"].set_index("reading")
    return "; ".join(f"{k} ρ = {fmt.estimate(*t.loc[k, ['rho', 'low', 'high']], 2)}"
                     for k in ("pooled", "median per trial") if k in t.index)


EPSILON = [
    S.Table("epsilon", "Ferrari–Canny ε of each planner's chosen triples (paper law; ε is geometric) "
            "and their share in force closure (ε > 0); the Ferrari–Canny ε planner takes the largest ε "
            "of the candidates the heuristic scores",
            lambda run: qs.epsilon_table(run.records, run.order), [
                Col("n", "n"), pct_col("force_closure", "force closure"),
                *(Col(f"epsilon_{s}", f"{s} ε", sig=3) for s in ("median", "mean", "max"))],
            by=["planner"]),
    S.Table("h_epsilon", lambda run: "Does H(G) rank grasps as the classical metric does? Spearman ρ "
            "of H(G) and ε (ρ < 0: agreement) over the Ferrari–Canny ε planner's trials' candidates, per "
            "trial and pooled; percentile bootstrap over trials (a trial's candidates share a body): "
            f"{BOOTSTRAP_RESAMPLES} resamples of each per-trial median, then {qs.POOLED_RESAMPLES} of the "
            f"pooled ρ, from one generator of seed {run.seed}"
            + (f"; no pooled row: {why}" if (why := no_candidates(run)) else ""),
            lambda run: qs.h_epsilon_correlation(run.records, run.aux("candidates"), seed=run.seed),
            [Col("reading", "reading"), Col("rho", "ρ (95%)", 3, low="low", high="high"),
             Col("n_trials", "trials"), Col("n_pairs", "candidates")]),
    S.Figure("h_epsilon", lambda run: "H(G) against Ferrari–Canny ε: (a) the Ferrari–Canny ε "
             "planner's trials' sampled candidates (log colour scale), (b) each trial's rank correlation; "
             + _rho_text(run), h_epsilon_figure, (10.0, 3.8)),
]


# ------------------------------------------------------------------------------------- shapes
def _shapes(run: Run) -> pd.DataFrame:
    p, rows = run.paper, []
    for shape in ordered("shape", run.records["shape"], run.order.get("shape", ())):
        g = run.ok[run.ok["shape"] == shape]
        deep = rec.beyond_radius(g, run.radius_mm)
        rows.append({
            "shape": shape, "paper_success": p.success.get(shape), "paper_failure_check":
            p.failure_check.get(shape, "none" if p.success.get(shape) else None), "n": len(g),
            "successes": int(g["success"].sum()),
            "n_error": len(run.records.query("shape == @shape and status == 'error'")),
            "ours_success": bool(g["success"].mean() >= 0.5) if len(g) else None,
            "failure_check": ", ".join(f"{c} ×{v}" for c, v in g["failure_check"].value_counts().items()),
            "exceeds_1mm": int((g["delta_max_mm"] > DESIGN_LIMIT_MM).sum()),
            "beyond_radius": int(deep.sum()),
            **g[["h_total", "residual_norm_n", "torque_norm_nm", "slip_margin_n"]].median(),
            "delta_max_mm": g.loc[~deep, "delta_max_mm"].median()})
    return S.verdicts(pd.DataFrame(rows), "ours_success", "paper_success")


def shapes_finding(run: Run) -> str:
    """How many shapes reach the paper's outcome, which differ, and the SI reason, from the records
    (each shape's checks and metrics: table shapes)."""
    t, ok = run.tables["shapes"], run.ok
    differ = [label("shape", s) for s in t.loc[t["differs"].eq(True), "shape"]]
    deep, released = int(t["beyond_radius"].sum()), int((ok.get("n_released", pd.Series()) > 0).sum())
    ours, paper = int(t["ours_success"].eq(True).sum()), int(t["paper_success"].eq(True).sum())
    return (f"Ours succeeds on {ours} of {len(t)} shapes (on at least half of a shape's trials; {len(ok)} "
            f"trials), the paper on {paper} (Fig. 15); {int(t['differs'].eq(False).sum())} of {len(t)} "
            "reach the paper's outcome"
            + (f"; ours differs on {fmt.listed(differ)}" if differ else "")
            + " (each shape's first failing checks: table shapes). " +
        (f"{deep} of {len(ok)} trials have a contact deeper than r = {fmt.number(run.radius_mm)} mm: in SI "
         "the paper's contact constants cannot carry the object at a sane indentation" if deep else "") + (
        f"{'; ' if deep else ''}Algorithm 2's sign step released a contact in {released} of {len(ok)} trials"
        if released else "") + (f" (SPEC §8; {DECISION})." if deep or released else ""))


def fig15(run: Run, fig) -> None:
    t, ev, r = run.tables["shapes"], run.config["evaluator"], run.radius_mm
    tau, tau_t = float(ev["tau_f_n"]), float(ev["tau_t_nm"])
    axes, x, good, bad = fig.subplots(2, 2, sharex=True).ravel(), np.arange(len(t)), "#2e7d32", "#c62828"
    hatch = ["//" if b else None for b in t["beyond_radius"] > 0]  # a non-physical state (δ > r)
    for ax, col, title, line in zip(axes, ("h_total", "residual_norm_n", "torque_norm_nm", "slip_margin_n"), (
            "(a) heuristic H(G) [–]", "(b) force residual ‖R‖ [N]", "(c) torque residual ‖τ‖ [N·m]",
            "(d) slip margin [N]"), (None, tau, tau_t, 0.0), strict=True):
        ax.bar(x, np.nan_to_num(t[col].to_numpy(float)), 0.7, hatch=hatch, edgecolor="white",
               color=[good if s else bad for s in t["ours_success"]])
        ax.set_title(title)
        if line is not None:
            ax.axhline(line, color=style.CRITERION, linestyle="--", linewidth=1.0)
    lo, hi = run.paper.h_range
    axes[0].axhspan(lo, hi, color=style.PAPER, alpha=0.12, zorder=0)
    axes[0].set_ylim(0, 1.35 * max(float(np.nanmax(t["h_total"].to_numpy(float))), hi))
    mark = {True: "✓", False: "✗", None: "—"}
    for xi, (ours, paper) in enumerate(zip(t["ours_success"], t["paper_success"], strict=True)):
        axes[0].annotate(f"ours {mark[bool(ours)]}\npaper {mark[paper]}", (xi, 1),
                         xycoords=("data", "axes fraction"), ha="center", va="top", fontsize=7)
    for ax in axes[2:]:
        ax.set_xticks(x, [style.tick(label("shape", s)) for s in t["shape"]])
    fig.legend(handles=[
        Patch(color=good, label="ours: success"), Patch(color=bad, label="ours: failure"),
        Patch(facecolor="0.6", hatch="//", edgecolor="white",
              label=f"contact deeper than r = {fmt.number(r)} mm (non-physical; the validity gate fails it)"),
        Patch(color=style.PAPER, alpha=0.12, label=f"paper's H range {lo}–{hi}"),
        Line2D([], [], color=style.CRITERION, linestyle="--",
               label=f"criteria: ‖R‖ < τ_F = {fmt.number(tau)} N; ‖τ‖ < τ_T = {fmt.number(tau_t)} N·m; "
               "slip margin > 0")], loc="outside lower center", ncol=2)


SHAPES = S.ReportSpec("shapes", [
    S.Finding(shapes_finding),
    S.Table("shapes", lambda run: "Outcome and grasp metrics per shape beside Fig. 15 (medians over executed "
            "trials); δ > r: trials with a contact deeper than the fingertip radius r = "
            f"{fmt.number(run.radius_mm)} mm (non-physical: the validity gate fails them, whatever their "
            "first failing check; their metrics are of no physical contact), δmax the median over the others "
            "(— where none)",
            _shapes, [
                Col("paper_success", "paper: success"), Col("paper_failure_check", "paper: check"),
                Col("ours_success", "ours: success"), Col("successes", "successes"), Col("n", "n"),
                Col("n_error", "errors"), Col("failure_check", "ours: checks"),
                Col("h_total", "H(G)", 3), *cols("residual_norm_n", "torque_norm_nm", "slip_margin_n"),
                Col("delta_max_mm", "δmax, δ ≤ r [mm]", 1),
                Col("exceeds_1mm", "> 1 mm"), Col("beyond_radius", "δ > r (non-physical)"),
                Col("verdict", "verdict")], by=["shape"]),
    S.Claims("h_range", "Heuristic value range across shapes beside the Fig. 15 caption", [S.Value(
        f"H(G) of the chosen grasps, {w} over shapes", "Fig. 15", lambda run, f=f: Estimate(
            float(getattr(run.ok["h_total"], f)()), n=len(run.ok)), lambda p: p.h_range, digits=2)
        for w, f in (("lowest", "min"), ("highest", "max"))]),
    S.Figure("fig15_shape_metrics", "Fig. 15 (ours): chosen grasp's metrics per shape (medians); "
             "green = success, red = failure, hatched = a contact deeper than the fingertip radius "
             "(non-physical); dashed: each check's threshold; our and the paper's outcome above panel (a)",
             fig15, (9.0, 7.0)),
    S.DesignLimit(["shape"]), S.FailureChecks(["shape"], lambda p, k: p.failure_check.get(
        k["shape"], "none" if p.success.get(k["shape"]) else "not reported")),
    readings(["shape"]), IDENTIFICATIONS,
])


# --------------------------------------------------------------------- ablation, grid, grip laws
GRIP_NEED = S.Table(
    "grip_need", lambda run: "What an equal grip needs under slip and oracle: triples whose needed grip "
    f"(with the design margin {fmt.number(run.config['evaluator']['grip_safety_factor'])}) fits within the "
    "grip cap, triples no equal grip holds, passes at the capped grip (a capped grip presses every finger to "
    f"the cap depth, the material's damage depth, at most r = {fmt.number(run.radius_mm)} mm, so δmax is the "
    "cap whatever the planner), median steepest contact |n_out,z| (0: horizontal normals)",
    lambda run: qs.grip_need(run.records, run.order), [
        Col("n", "n"), Col("holdable", "within the cap"), Col("no_equal_grip", "no equal grip holds"),
        Col("capped_passes", "passes at the cap"),
        Col("steepest_normal_z_median", "median steepest |n_z|", 2)], by=BY_LAW)


def ablation_finding(run: Run) -> str:
    """The grid's finding and what the grip laws the paper names but did not run did: passes and
    the most frequent first failing check per law (per planner: tables grip_need, failure_checks)."""
    laws = qs.law_outcomes(run.records, run.order)
    top = laws[[c for c in FAILURE_CHECKS if c != "none"]].idxmax(axis=1)  # most frequent, first in order
    outcomes = [f"{r.successes} of {r.n} ({label('grip_law', r.grip_law)}"
                + (f"; {r[check]} fail first on {check}" if r[check] else "") + ")"
                for (_, r), check in zip(laws.iterrows(), top, strict=True)]
    return grid_finding(run, f" The grip laws the paper did not run (Sec. 6.5, 12) pass "
                             f"{fmt.listed(outcomes)}; per planner: tables grip_need and failure_checks."
                        if outcomes else "")


def power(run: Run) -> str:
    """The paper's interval at its ablation's trials per variant (Sec. 6.3), beside ours in the table."""
    return (f"At the paper's {run.paper.trials_per_variant} trials per variant its interval is roughly "
            f"±{fmt.number(run.paper.interval_half_width_pp)} pp (Sec. 6.3).")


def over_limit(run: Run) -> str:
    """Per grip law, how many successes exceed the paper's 1 mm design limit and how many sit at the
    grip cap δmax ≤ r (from the records); they stay successes: SPEC §2.7 reports the limit, never
    rescales it. "" when the records have no outcome (every trial errored)."""
    if not {"success", "delta_max_mm"} <= set(run.ok):
        return ""
    ok, r = run.ok[run.ok["success"].astype(bool)], run.radius_mm
    laws = run.order.get("grip_law", ["paper"]) if "grip_law" in ok else [None]
    parts = []
    for law in laws:
        g = ok if law is None else ok[ok["grip_law"] == law]
        cap = rec.flag(g, "grip_capped") if "grip_capped" in g else np.isclose(
            g["delta_max_mm"], r, rtol=0, atol=1e-6)
        parts.append(("" if law is None else f"{label('grip_law', law)} ") + (
            f"{int((g['delta_max_mm'] > DESIGN_LIMIT_MM).sum())} of {len(g)}" if len(g) else "no success") + (
            f" ({int(cap.sum())} at the grip cap, δmax = {fmt.span(g.loc[cap, 'delta_max_mm'])} mm ≤ r = "
            f"{fmt.number(r)} mm)" if cap.any() else ""))
    return (f"Successes deeper than the paper's {fmt.number(DESIGN_LIMIT_MM)} mm design limit: "
            + "; ".join(parts)
            + "; counted as successes (the limit is reported, never rescaled, SPEC §2.7; δ ≤ r is valid "
            "contact; table design_limit).")


def law_items(figure: str, name: str, what: str, note=lambda run: "") -> list:
    """Success per planner and grip law beside the paper (``note``: a caption's last sentence), its
    figure, McNemar within each law."""
    rates = S.Rates("success_by_planner", f"Success per {what} and grip law beside {figure} (the "
                    "paper's values are Algorithm 2's, shown beside every law and judged under it only)",
                    LAWS, lambda p, k: p.success_pct.get(k["planner"]), because=lambda t: np.where(
                        t["grip_law"] == "paper", "", "no verdict: the paper ran Algorithm 2 only"))

    return [replace(rates, caption=lambda run: " ".join(
        part for part in (rates.caption(run), over_limit(run), note(run)) if part)),
            S.Figure(name, f"{figure} (ours): success per {what} under each grip law, Wilson 95% "
                     f"whiskers; {PAPER_MARKS}",
                     lambda run, fig: style.grouped_bars(
                         fig.subplots(), run.tables["success_by_planner"], "planner", "grip_law"),
                     (10.0, 3.8)), LawPaired()]


ABLATION = S.ReportSpec("ablation", [
    S.Finding(ablation_finding), *law_items("Fig. 16", "fig16_ablation", "variant", power), MECHANISM,
    readings(BY_LAW), GRIP_NEED, *EPSILON, S.DesignLimit(BY_LAW), S.FailureChecks(BY_LAW),
    IDENTIFICATIONS,
])


def fig18(run: Run, fig) -> None:
    # (a) wide enough for its five planners' names half an em apart ("proposed" ran into "antipodal")
    ax_a, ax_b = fig.subplots(1, 2, width_ratios=[1.3, 2.2])
    style.grouped_bars(ax_a, run.tables["success_by_planner"], "planner")
    style.grouped_bars(ax_b, run.tables["success_by_shape"], "shape", "planner")
    ax_a.set_title("(a) overall")
    ax_b.set_title("(b) by shape")


BASELINE_GRID = S.ReportSpec("baseline_grid", [
    S.Finding(grid_finding),
    S.Rates("success_by_planner", "Success per planner beside Fig. 18a", ["planner"],
            lambda p, k: p.success_pct.get(k["planner"])),
    S.Rates("success_by_shape", "Success per shape and planner beside Fig. 18b (the paper prints "
            "only the rounded cube's values; a planner at 0% overall is 0% on every shape)",
            ["shape", "planner"], lambda p, k: _carried(p.success_by_shape_pct.get(k["shape"], {}),
                                                        p, k), bootstrap=False),
    S.Paired(), S.DesignLimit(["planner"]),
    S.Figure("fig18_baselines", "Fig. 18 (ours): (a) overall success per planner, (b) per shape; "
             f"Wilson 95% whiskers; {PAPER_MARKS}", fig18, (10.5, 4.2)),
    *(S.Rates(f"success_by_{f}", f"Success per planner and {w} (not printed in the paper except "
              "where a planner's overall rate is 0% or 100%)", ["planner", f],
              lambda p, k: _carried({}, p, k)) for f, w in (("mu", "friction coefficient μ"),
                                                           ("mass_kg", "object mass"))),
    S.FailureChecks(["planner"], lambda p, k: "residual (normal forces stay at seed level, Sec. "
                    "6.5)" if k["planner"] == "centroid" else None),
    MECHANISM, readings(["planner"]), *EPSILON, IDENTIFICATIONS,
])


def grip_finding(run: Run) -> str:
    """Under which grip law the paper's ordering appears, the proposed planner's rate under each,
    the paired tests counted, and the physical reason where it loses a pair (per planner: the tables)."""
    t, tests, paper = run.tables["success_by_planner"], run.tables["mcnemar"], run.paper.success_pct
    sig, need = tests.query("p_exact < 0.05"), run.tables["grip_need"].query("grip_law == 'oracle'")
    beats, loses = (sig.query(f"reference_only {than} compared_only") for than in (">", "<"))
    ours = t.pivot(index="planner", columns="grip_law", values="rate_pct")  # NaN: a planner not run
    laws = run.order["grip_law"]
    same = [law for law in laws  # strictly: planners tied at one rate (say all at 0%) show no order
            if ours[law].reindex(sorted(paper, key=lambda p: -paper[p])).diff().iloc[1:].lt(0).all()]
    deep = int(run.tables["design_limit"]["successes_exceeding"].sum())
    return (
        "The paper's ordering (Fig. 18: " + ", ".join(
            f"{label('planner', p)} {fmt.number(v, 1)}%" for p, v in paper.items())
        + f") appears under {fmt.listed([label('grip_law', law) for law in same], 'none of the laws')}: "
        "the proposed planner passes " + fmt.listed([
            f"{fmt.number(ours.loc[PROPOSED, law], 1)}% under {label('grip_law', law)}" for law in laws])
        + " (table success_by_planner). " + (
            f"{deep} of the {int(t['successes'].sum())} successes lie deeper than the paper's "
            f"{fmt.number(DESIGN_LIMIT_MM)} mm design limit (per law: table design_limit). " if deep else "")
        + f"Paired per law (McNemar, exact p < 0.05; table mcnemar), it beats {len(beats)} and loses to "
        f"{len(loses)} of {len(tests)} planner–law pairs. " + (  # a loss to explain
            "Why: H(G) is geometric and sees neither gravity nor the tilt of the contact plane; horizontal "
            "normals (the centroid planner's triple) let an equal grip balance by symmetry, while under "
            f"oracle no equal grip holds on {need['no_equal_grip'].sum()} of {need['n'].sum()} triples "
            "(normals per planner: table grip_need). " if len(loses) else "") + f"{DECISION}.")


GRIP_LAWS = S.ReportSpec("grip_laws", [
    S.Finding(grip_finding), *law_items("Fig. 18", "fig18_grip_laws", "planner"), readings(BY_LAW),
    S.FailureChecks(BY_LAW),
    GRIP_NEED,
    MECHANISM, *EPSILON, S.DesignLimit(BY_LAW), IDENTIFICATIONS,
])

PLANNERS = S.ReportSpec("quasi_static", [
    S.Rates("success_rates", "Success per planner", ["planner"],
            lambda p, k: getattr(p, "success_pct", {}).get(k["planner"])),
    S.Paired(), S.DesignLimit(["planner"]), S.FailureChecks(["planner"]), readings(["planner"]),
    IDENTIFICATIONS,
])
