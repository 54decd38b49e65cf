"""Report of ``dynamic_check``: every quasi-static label of a source study re-simulated by the dynamic
grasp, per material preset, beside the paper's Sec. 6.1 claim that the labels agree."""

from __future__ import annotations

import numpy as np
import pandas as pd

from graspcampaign.analysis import dynamic_check as dc
from graspcampaign.analysis.vocabulary import label
from graspcampaign.campaign.provenance import run_size
from graspcampaign.core.words import counted, plural
from graspcampaign.report import format as fmt
from graspcampaign.report import style
from graspcampaign.report.document import Col, pct_col
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
         Col("unlabelled", "a label missing (left out)"), Col("both_success", "both succeed"),
         Col("qs_only", "quasi-static only"), Col("dynamic_only", "dynamic only"),
         Col("both_failure", "both fail"), pct_col("agreement", "agreement"),
         Col("kappa", "Cohen's κ (95%)", 2, low="kappa_low", high="kappa_high"), Col("kappa_why", "κ note")]


def _agree(t: pd.DataFrame) -> list[Col]:
    """:data:`AGREE`, the trials missing a label (``unlabelled``) shown only where there are some."""
    return [c for c in AGREE if c.key != "unlabelled" or t.unlabelled.any()]


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


def _why(r) -> str:
    """Which way one preset's labels disagree, from its sphere row of table kappa ("" if they agree)."""
    holds, passes = r.both_success + r.dynamic_only, r.both_success + r.qs_only
    mutual = f" (κ {fmt.number(r.kappa, 2)}: agreement by mutual failure)" if not holds else ""
    return (f"under {label('model_preset', r.model_preset)} the dynamic grasp holds {holds} where the "
            f"quasi-static label passes {passes}{mutual}") if r.qs_only + r.dynamic_only else ""


def finding(run: Run) -> str:
    k, ok = run.tables["kappa"], run.ok
    judged = k[k.scope == CLAIM_SHAPE]
    claim = judged[(judged.comparison == "source") & (judged.n > 0)]
    differ, n_judged = fmt.differing(judged)
    source = ", ".join(sorted(set(ok.source_study)))
    if n_judged:
        agree = fmt.listed([f"{fmt.number(r.agreement_pct, 1)}%{' of the determined trials' * (i == 0)} "
                            f"under {label('model_preset', r.model_preset)}"
                            for i, r in enumerate(claim.itertuples())])
        text = (f"On the {CLAIM_SHAPE} (the claim's scope) the {source} label and the dynamic label agree on "
                f"{agree}, against the paper's full agreement (Sec. 6.1): "
                f"{differ} of {n_judged} {CLAIM_SHAPE} comparisons differ "
                "(table kappa). ")
        why = [w for w in map(_why, claim.itertuples()) if w]
        text += f"Why: {'; '.join(why)}. " if why else ""
    else:
        text = (f"No {CLAIM_SHAPE} comparison can be judged against the paper's full agreement (Sec. 6.1): "
                f"none of the {source} trials re-simulated has a settled dynamic grasp (table kappa). ")
    planned, out = run_size(run.manifest), int(judged.query("comparison == 'source'").not_settled.sum())
    if planned and len(run.records) < planned:
        text += f"Partial run: {len(run.records)} of {planned} dynamic grasps recorded. "
    if out:  # one source grasp is simulated once per preset
        g = ok[(ok["shape"] == CLAIM_SHAPE) & (ok.dynamic_status == dc.UNDETERMINED)]
        grasps = counted(g.source_trial_id.nunique(), f"{CLAIM_SHAPE} grasp")
        presets = counted(g.model_preset.nunique(), "preset")
        text += (f"{counted(out, 'simulation')} of {grasps} under {presets}, {NOT_SETTLED}{_t_max(run)}, "
                 f"{plural('is', out, 'are')} left out. ")
    return text + f"{DECISION}."


def confusion_figure(run: Run, fig) -> None:
    k = run.tables["kappa"].query(f"comparison in ['source', 'preset'] and scope == '{CLAIM_SHAPE}'")
    axes = fig.subplots(2, k.model_preset.nunique(), squeeze=False)
    for ax, r in zip(axes.ravel(), k.itertuples(), strict=True):  # rows: pair, columns: preset
        table = np.array([[r.both_success, r.qs_only], [r.dynamic_only, r.both_failure]])
        style.confusion(ax, table, ["success", "failure"], ["success", "failure"], "dynamic label",
                        "quasi-static label")
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
                 lambda run: agreement(run, ["model_preset", by]), lambda run, t: [
                     Col("qs_success_rate_pct", "quasi-static success %", 1),
                     Col("dynamic_success_rate_pct", "dynamic success %", 1), *_agree(t)],
                 by=["model_preset", by])


SPEC = ReportSpec("dynamic_check", [
    Finding(finding),
    Table("kappa", lambda run: f"Confusion matrix (rows quasi-static, columns dynamic), agreement and "
          f"Cohen's κ (asymptotic 95% interval, statsmodels) per preset and label pair, beside the paper's "
          f"claim \"{run.paper.claim}\" read as full agreement (100%): judged on the {CLAIM_SHAPE}'s trials "
          f"(the claim's scope); the rows over {ALL} are context, with no verdict; {_left_out(run)}",
          _kappa, lambda run, t: [
              Col("scope", "trials"), Col("comparison_label", "quasi-static label"), *_agree(t),
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
