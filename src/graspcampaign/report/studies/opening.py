"""The Tests 2-3 reports' shared reading of the trials: both belief readings' frames and the opening
paragraph (the main finding, why it differs from the paper, what exact beliefs change), from the records."""

from __future__ import annotations

import pandas as pd

from graspcampaign.analysis import hardware as hw
from graspcampaign.analysis.vocabulary import PROPOSED, label
from graspcampaign.report import format as fmt
from graspcampaign.report.render import Run
from graspcampaign.report.spec import paper_of

FLAGS = ("predicted_stable", "predicted_stable_residual")
WHY_NOT = {"predicted_stable_residual": "it is the paper's §8.1 flag (Algorithm 2's residual ≤ τ_F = "
           "0.0886 N), friction-blind: it carries no information about a friction hold",
           "predicted_stable": "the believed margins are optimistic where the beliefs are wrong"}
#: The study's table of the flags against success (its ``all`` scope is the opening's)
CLASSIFIER = {"test2_grasp": "test2_classifier", "test3_disturbance": "test3_retention_classifier"}


def frames(run: Run) -> pd.DataFrame:
    """Executed trials of both belief readings with the derived columns (computed once per run)."""
    return run.memo("hardware", lambda: hw.derive(hw.beliefs(run.records, run.aux("belief_none"))))


def ex(run: Run, planner: str | None = None) -> pd.DataFrame:
    """The executed trials as recorded (the planners' own beliefs), of ``planner`` if given."""
    d = frames(run)
    return d[(d["belief_error"] == "paper") & (d["planner"] == planner if planner else True)]


def first(rates: pd.Series) -> str:
    """Who ranks first by ``rates`` (per planner, %): one planner, or the planners tying first (equal
    rates share a rank, as in the belief-pairs table)."""
    top = [label("planner", q) for q, v in rates.items() if v == rates.max()]
    return f"the {top[0]} planner ranks first" if len(top) == 1 else \
        f"{fmt.listed(top)} tie first at {fmt.number(rates.max(), 1)} %"


def belief_gap(paper: pd.Series, none: pd.Series) -> str:
    """What the counterfactual measured: how far the proposed planner trails the first with the planners'
    own beliefs (``paper``) and with exact ones (``none``), and how much exact beliefs change it (point
    estimates: which cause makes most of the gap is not tested, docs/decisions.md)."""
    # rounded as printed, so the printed gaps and their difference add up
    gap, gap0 = round(paper.max() - paper[PROPOSED], 1), round(none.max() - none[PROPOSED], 1)
    ranks = [r.rank(ascending=False, method="min") for r in (paper, none.reindex(paper.index))]
    widened = round(gap0 - gap, 1)
    if widened > 0:
        closed = f"exact beliefs widen it by {fmt.number(widened, 1)} pp"
    elif widened == 0:
        closed = "exact beliefs leave it as it is"
    else:
        closed = (f"exact beliefs close {fmt.number(-widened, 1)} pp of it; the other {fmt.number(gap0, 1)} "
                  "pp remain when every planner knows the trial's actual μ_s, G_geo and contact law")
    return (f"{first(none)} and the ranks {'do not ' * ranks[0].equals(ranks[1])}change. The proposed "
            f"planner trails the first by {fmt.number(gap, 1)} pp with the planners' own beliefs and by "
            f"{fmt.number(gap0, 1)} pp with exact ones: {closed} (point estimates, no interval). ")


def finding(run: Run, extra=lambda run: "") -> str:
    """The opening paragraph, from the records: who ranks first and how the proposed planner stands
    against the paper, why, what exact beliefs change; the per-planner numbers are Table 7's (or 9's)."""
    d, e, n1, n2 = frames(run), ex(run), (lambda v: fmt.number(v, 1)), (lambda v: fmt.number(v, 2))
    by = d.groupby(["belief_error", "planner"])["success"]
    s, n, lab = by.mean() * 100, by.size(), (lambda q: label("planner", q))
    paper, table = s["paper"].sort_values(ascending=False), f"table{7 + 2 * (run.study != 'test2_grasp')}"
    theirs = {q: paper_of(run, lambda p, q: getattr(p, table)[q].success_pct, q) for q in paper.index}
    tops, top, where = list(paper.index[paper == paper.max()]), paper.index[0], f"Table {table[5:]}"
    ranked, ci = first(paper), run.tables[table].query("belief_error == 'paper'").set_index("planner")
    wilson = {q: f"Wilson 95 % {fmt.interval(ci.success_low_pct[q], ci.success_high_pct[q], 1)}"
              for q in (top, PROPOSED)}  # as the table prints them
    text = (f"{ranked[0].upper()}{ranked[1:]} ({n1(paper.max()) + ' % ' if len(tops) == 1 else ''}of "
            f"{fmt.listed([str(n['paper'][q]) for q in tops])} executed trials"
            f"{', ' + wilson[top] if len(tops) == 1 else ''}; "
            f"paper {fmt.listed([n1(theirs[q]) for q in tops])} %)")
    if PROPOSED not in tops:
        best = max(theirs, key=lambda q: -1 if theirs[q] is None else theirs[q])
        text += (f", while the proposed planner, {'first ' * (best == PROPOSED)}in the paper at "
                 f"{n1(theirs[PROPOSED])} %, succeeds on {n1(paper[PROPOSED])} % of "
                 f"{n['paper'][PROPOSED]} ({wilson[PROPOSED]})")
        if len(tops) == 1 and ci.success_low_pct[top] <= ci.success_high_pct[PROPOSED]:
            text += "; the two intervals overlap, so these trials do not separate the two planners"
    text += f" (every planner with its Wilson interval and the paper's value: {where}). "
    g, gap = (e.groupby("planner")[c].median() for c in ("g_geo_actual", "g_geo_gap"))
    cap = e.groupby("planner")["grip_capped"].mean() * 100
    text += (f"The proposed score H~ has no gravity term, so its triples give friction less vertical reach "
             f"than a horizontal triangle (median G_geo of the realised contacts, true μ_s: {lab(PROPOSED)} "
             f"{n2(g[PROPOSED])}, {lab(top)} {n2(g[top])}), and its calibrated grip hits the damage cap on "
             f"{n1(cap[PROPOSED])} % of its trials ({lab(top)} {n1(cap[top])} %). ") + extra(run)
    text += ("**VIRTUAL RIG data**: every number here is the output of the virtual rig's stochastic model "
             "of the gripper executing the commanded sheet (`rig/virtual.py`), not a hardware measurement; "
             "no constant of the rig was tuned towards the paper. " if run.source == "virtual" else
             "Measured on hardware. ") + ("This run was filled by `graspcampaign ingest`, but its files "
                                          "carried `source = virtual`: they are virtual-rig exports, not rig "
                                          "measurements. " if run.ingested_exports else "")
    if "none" in s and paper[PROPOSED] < paper.max():
        text += ("Removing the belief errors (`belief_error = none`: every planner sizes its grip from the "
                 f"trial's actual μ_s, G_geo and contact law, same execution noise; {where}'s `none` rows): "
                 + belief_gap(paper, s["none"].reindex(paper.index)))
    elif "none" not in s:
        text += "This run has no `belief_error = none` counterfactual (a real rig has no oracle). "
    widest = gap.abs().idxmax()
    text += (f"The beliefs differ as documented: median believed − actual G_geo up to {n2(gap[widest])} "
             f"({lab(widest)}; every planner: table `{run.study.split('_')[0]}_belief`). ")
    flags = run.tables[CLASSIFIER[run.study]].query("scope == 'all' and belief_error == 'paper'")
    flags = flags.set_index("flag")
    text += "; ".join(  # the intervals, the trials flagged and the recall are the classifier table's
        f"`{f}` {'has precision ' * (i == 0)}{n2(r['precision'])}"
        f"{f' against a base success rate of {n2(r.base)}' * (i == 0)}: "
        + ("above it" if r["above_base"] else f"not above it, because {WHY_NOT[f]}")
        for i, (f, r) in enumerate(flags.iterrows()))
    text += (" (point estimates; their Wilson intervals, the trials flagged and the recall: the classifier "
             "table). ")
    return text + ("See `docs/decisions.md`, *Planner beliefs on the virtual rig* and "
                   "*Tests 2-3 protocols and virtual rig*.")
