"""Report of ``dynamic_check``: every quasi-static label of a source study re-simulated by the dynamic
grasp, per material preset, beside the paper's Sec. 6.1 claim that the labels agree."""

from __future__ import annotations

import numpy as np
import pandas as pd

from graspcampaign.analysis import dynamic_check as dc
from graspcampaign.analysis.vocabulary import label
from graspcampaign.report import format as fmt
from graspcampaign.report import style
from graspcampaign.report.document import Col
from graspcampaign.report.render import Run
from graspcampaign.report.spec import Figure, Finding, ReportSpec, Table, verdicts
from graspcampaign.report.studies.dynamic import in_order

CLAIM_SHAPE, ALL = "sphere", "all shapes"  # Sec. 6.1's claim is the sphere's
DECISION = "`docs/decisions.md`, *Dynamic check report*"
PAIRS = {"source": "source study's label", "preset": "Algorithms 1–2 under the preset",
         "source_unbounded": "source label, no validity gate",
         "preset_unbounded": "Algorithms 1–2 under the preset, no validity gate"}
NOT_SETTLED = label("dynamic_status", dc.UNDETERMINED)
AGREE = [Col("n", "n determined"), Col("not_settled", f"{NOT_SETTLED} (left out)"),
         Col("both_success", "both succeed"), Col("qs_only", "quasi-static only"),
         Col("dynamic_only", "dynamic only"), Col("both_failure", "both fail"),
         Col("agreement_pct", "agreement % (Wilson 95%)", 1, low="agreement_low_pct",
             high="agreement_high_pct"),
         Col("kappa", "Cohen's κ (95%)", 2, low="kappa_low", high="kappa_high"), Col("kappa_why", "κ note")]


def _t_max(run: Run) -> str:
    """`` = t_max s`` of the run: the budget its records carry (a run stored before they did: its
    config's, if it sets one; the kind's default is not in the config)."""
    if "t_max_s" in run.records and run.records["t_max_s"].notna().any():
        return f" = {'/'.join(map(fmt.number, sorted(run.records['t_max_s'].dropna().unique())))} s"
    return f" = {fmt.number(run.params['t_max_s'])} s" if "t_max_s" in run.params else ""


def _left_out(run: Run) -> str:
    """The caption's words on the undetermined dynamic grasps."""
    return (f"dynamic grasps {NOT_SETTLED}{_t_max(run)} are counted in their own column, left out of the "
            "agreement")


def agreement(run: Run, by: list[str], pairs=("source",), records=None) -> pd.DataFrame:
    """Agreement of each label pair per group of ``by`` (presets and groups in design order) over
    ``records`` (default the run's)."""
    records = run.records if records is None else records
    t = pd.concat([dc.agreement_table(records, *dc.LABEL_PAIRS[p], by=by).assign(comparison=p)
                   for p in pairs], ignore_index=True)
    t = t.assign(**{f"{c}_pct": 100 * t[c] for c in ("agreement", "agreement_low", "agreement_high",
                                                     "qs_success_rate", "dynamic_success_rate")})
    return in_order(run, by, t, [t.comparison.map(list(PAIRS).index)])


def _kappa(run: Run) -> pd.DataFrame:
    """Per preset and label pair: the claim's scope (the sphere's trials) judged against full agreement,
    then every trial as context, without a verdict (the claim is the sphere's)."""
    sphere = run.records[run.records["shape"] == CLAIM_SHAPE]
    t = pd.concat([agreement(run, ["model_preset"], PAIRS, sphere).assign(scope=CLAIM_SHAPE, paper_pct=100.0),
                   agreement(run, ["model_preset"], PAIRS).assign(scope=ALL)], ignore_index=True)
    t["comparison_label"] = t.comparison.map(PAIRS)
    t["why"] = np.where(t.n == 0, "no verdict: nothing to compare", "")  # every grasp not settled
    context = np.where(t.scope == ALL, f"no verdict: context (the claim is on the {CLAIM_SHAPE})", "")
    return verdicts(t.assign(context=context), "agreement_pct", "paper_pct", "agreement_low_pct",
                    "agreement_high_pct", unit="%", because="context").drop(columns="context")


def _labels(run: Run, r) -> str:
    """One row's agreement, κ and the labels each evaluator gave over its determined trials, and the
    dynamic grasps left out as not settled, in words."""
    left_out = (f"{r.not_settled} of {r.n + r.not_settled} dynamic grasps {NOT_SETTLED}{_t_max(run)}: left "
                "out of the agreement")
    if not r.n:
        return left_out
    kappa = fmt.estimate(r.kappa, r.kappa_low, r.kappa_high, 2) + (f" ({r.kappa_why})" if r.kappa_why else "")
    return (f"the labels agree on {r.both_success + r.both_failure} of {r.n} ({r.agreement_pct:.1f}%, Wilson "
            f"95% {fmt.interval(r.agreement_low_pct, r.agreement_high_pct, 1)}), κ = {kappa}; quasi-static "
            f"passes {r.both_success + r.qs_only}, the dynamic grasp holds {r.both_success + r.dynamic_only}"
            + (f" ({left_out})" if r.not_settled else ""))


def finding(run: Run) -> str:
    k, ok = run.tables["kappa"], run.ok
    claim, context = (k[(k.comparison == "source") & (k.scope == s)] for s in (CLAIM_SHAPE, ALL))
    judged = k[k.scope == CLAIM_SHAPE]
    n_judged = int(judged.differs.notna().sum())
    verdict = "; ".join(f"**{label('model_preset', r.model_preset)}**: {_labels(run, r)} — {r.verdict}"
                        for r in claim.itertuples())
    differ = (f"{int(judged.differs.eq(True).sum())} of {n_judged} {CLAIM_SHAPE} comparisons differ from "
              "full agreement (its 100% outside our Wilson interval). " if n_judged else
              f"No {CLAIM_SHAPE} comparison can be judged: none has a settled dynamic grasp. ")
    mutual = ("Agreement by mutual failure gives κ near 0, or none when every trial has one label in both "
              "columns: it is not evidence that the evaluators agree. " if n_judged else "")
    return (
        f"The paper: \"{run.paper.claim}\". Re-simulating {ok.source_trial_id.nunique()} "
        f"{', '.join(sorted(set(ok.source_study)))} trials, judged on the claim's scope, the "
        f"{CLAIM_SHAPE}'s trials "
        f"(source study's label against the dynamic label): {verdict}. Like for like on the {CLAIM_SHAPE} "
        "(Algorithms 1–2 under the same preset): agreement " + ", ".join(
            f"{label('model_preset', r.model_preset)} "
            + (f"{r.agreement_pct:.1f}%" if r.n else "nothing to compare")
            for r in judged[judged.comparison == "preset"].itertuples()) + ". "
        + differ + "For context only (beyond the claim's scope, no verdict), over every shape and planner: "
        + "; ".join(f"{label('model_preset', r.model_preset)}: {_labels(run, r)}"
                    for r in context.itertuples()) + f". {mutual}{DECISION}.")


def confusion_figure(run: Run, fig) -> None:
    k = run.tables["kappa"].query(f"comparison in ['source', 'preset'] and scope == '{CLAIM_SHAPE}'")
    axes = fig.subplots(2, k.model_preset.nunique(), squeeze=False)
    for ax, r in zip(axes.ravel(), k.itertuples(), strict=True):  # rows: pair, columns: preset
        table = np.array([[r.both_success, r.qs_only], [r.dynamic_only, r.both_failure]])
        ax.imshow(table, cmap="Blues", vmin=0, vmax=max(1, table.max()))
        for (i, j), v in np.ndenumerate(table):
            ax.text(j, i, str(v), ha="center", va="center", color="white" if v > table.max() / 2 else "black")
        ax.grid(False)
        ax.set(xticks=[0, 1], yticks=[0, 1], xticklabels=["success", "failure"],
               yticklabels=["success", "failure"], xlabel="dynamic label", ylabel="quasi-static label")
        left_out = f"\n({r.not_settled} {NOT_SETTLED}, left out)" if r.not_settled else ""
        ax.set_title(f"{label('model_preset', r.model_preset)}:\n{PAIRS[r.comparison]}{left_out}", fontsize=9)


def group_figure(run: Run, fig) -> None:
    axes = fig.subplots(1, 2)
    for ax, by in zip(axes, ("planner", "shape"), strict=True):
        t = run.tables[f"agreement_by_{by}"]
        style.grouped_bars(ax, t, by, "model_preset",
                           ("agreement_pct", "agreement_low_pct", "agreement_high_pct"))
        ax.set(ylabel="labels agree [%]", title=f"per {by} (Wilson 95%)")
        if not t.n.any():
            ax.text(0.5, 0.5, f"nothing to compare: every dynamic grasp {NOT_SETTLED}",
                    transform=ax.transAxes, ha="center")
    axes[0].get_legend().remove()  # both panels share the presets' legend


def _by(by: str) -> Table:
    return Table(f"agreement_by_{by}", lambda run: f"Agreement of the source study's quasi-static label and "
                 f"the dynamic label per preset and {by}; κ undefined where every trial has one label in "
                 f"both columns; {_left_out(run)}",
                 lambda run: agreement(run, ["model_preset", by]), [
                     Col("qs_success_rate_pct", "quasi-static success %", 1),
                     Col("dynamic_success_rate_pct", "dynamic success %", 1), *AGREE],
                 by=["model_preset", by])


SPEC = ReportSpec("dynamic_check", [
    Finding(finding),
    Table("kappa", lambda run: f"Confusion matrix (rows quasi-static, columns dynamic), agreement and "
          f"Cohen's κ (asymptotic 95% interval, statsmodels) per preset and label pair, beside the paper's "
          f"claim \"{run.paper.claim}\" read as full agreement (100%): judged on the {CLAIM_SHAPE}'s trials "
          f"(the claim's scope); the rows over {ALL} are context, with no verdict; {_left_out(run)}",
          _kappa, [
              Col("scope", "trials"), Col("comparison_label", "quasi-static label"), *AGREE,
              Col("paper_pct", "paper %", 1), Col("verdict", "verdict")], by=["model_preset"]),
    Figure("confusion", f"Confusion matrices per preset on the {CLAIM_SHAPE} (the claim's scope): the "
           "source study's label and Algorithms 1–2 under the preset (rows) against the dynamic label "
           f"(columns); every shape's counts are in table kappa; grasps {NOT_SETTLED} are left out "
           "(their count in the panel's title)", confusion_figure, (8.0, 7.0)),
    _by("planner"), _by("shape"),
    Figure("agreement_by_group", "Share of the determined trials whose labels agree per planner and per "
           f"shape, per preset (a group whose dynamic grasps are all {NOT_SETTLED} has no bar)",
           group_figure, (11.0, 4.0)),
    Table("dynamic_status", lambda run: "How the dynamic grasps ended, per preset and planner" + (
          f" (t_max{_t_max(run)} of simulated time)" if _t_max(run) else ""),
          lambda run: in_order(run, ["model_preset", "planner"], pd.crosstab(
              [run.ok.model_preset, run.ok.planner], run.ok.dynamic_status).reset_index()),
          lambda run, t: [Col(c, label("dynamic_status", c)) for c in t if c not in
                          ("model_preset", "planner") and not c.endswith("_label")],
          by=["model_preset", "planner"]),
])
