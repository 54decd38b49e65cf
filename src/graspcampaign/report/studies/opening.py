"""The Tests 2-3 reports' shared reading of the trials: both belief readings' frames and the opening
paragraph (the main finding, why it differs from the paper, what exact beliefs change), from the records."""

from __future__ import annotations

import pandas as pd

from graspcampaign.analysis import hardware as hw
from graspcampaign.analysis.vocabulary import PROPOSED, label
from graspcampaign.report import format as fmt
from graspcampaign.report.render import Run

FLAGS = ("predicted_stable", "predicted_stable_residual")


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
        f"{fmt.listed(top)} tie first at {fmt.number(rates.max(), 1)}%"


def belief_gap(paper: pd.Series, none: pd.Series, table: str) -> str:
    """What exact beliefs change, in one clause: the ranks, and the proposed planner's gap to the first
    with the planners' own beliefs (``paper``) and with exact ones (``none``), both per planner in
    ``table`` (point estimates: which cause makes most of the gap is not tested, docs/decisions.md). Each
    gap is the difference of the two rates as the tables print them (one decimal): from the unrounded
    rates it read 30.9 pp beside the table's 74.1 % and 43.1 %."""
    shown = [r.map(lambda v: round(float(v), 1)) for r in (paper, none)]  # as fmt.number(v, 1) prints it
    gap, gap0 = (fmt.number(r.max() - r[PROPOSED], 1) for r in shown)
    ranks = [r.rank(ascending=False, method="min") for r in (paper, none.reindex(paper.index))]
    return (f"Exact beliefs {'do not ' * ranks[0].equals(ranks[1])}change the ranks and take the proposed "
            f"planner's gap to the first from {gap} pp to {gap0} pp (table {table}). ")


def why(beliefs: pd.DataFrame, top: str, table: str, digits: int | str | None) -> str:
    """Why the proposed planner trails ``top``, as far as ``beliefs`` (``table``'s rows of the planners' own
    beliefs, by planner) show it: a lower median G_geo (less vertical friction) and a grip more often at the
    damage cap, each said only where the records hold it; where neither holds, that they do not show why.
    G_geo at ``digits``, the decimals of the table's column (it said 0.70 beside the table's 0.699)."""
    g, cap = beliefs["g_geo_actual"], beliefs["grip_capped_pct"]  # as the table prints them
    who, n1, n2 = label("planner", top), (lambda v: fmt.number(v, 1)), (lambda v: fmt.number(v, digits))
    less, more = bool(g[PROPOSED] < g[top]), bool(cap[PROPOSED] > cap[top])
    capped = f"{n1(cap[PROPOSED])}% of trials ({who} {n1(cap[top])}%; {table})"
    if not (less or more):
        return (f"The records do not show why: the proposed planner's median G_geo is {n2(g[PROPOSED])} "
                f"({who} {n2(g[top])}), its grip at the damage cap on {capped}. ")
    friction = (f"the proposed score H~ has no gravity term, so its contacts reach less vertical friction "
                f"(median G_geo {n2(g[PROPOSED])}, {who} {n2(g[top])}{'' if more else '; ' + table})")
    whose = "its" if less else "the proposed planner's"
    grip = f"{whose} grip hits the damage cap on {capped}"
    return f"Why: {' and '.join([friction] * less + [grip] * more)}. "


def finding(run: Run, extra=lambda run: "") -> str:
    """The opening paragraph, from the records: who ranks first and how the proposed planner stands
    against the paper, for how many planners Table 7 (or 9) differs, why (the belief table holds the
    detail), what exact beliefs change, the decisions."""
    n1, prefix = (lambda v: fmt.number(v, 1)), run.study.split("_")[0]
    table_number = 7 + 2 * (prefix == "test3")  # the paper's Table 7 (test 2) or 9 (test 3)
    t = run.tables[f"table{table_number}"].set_index(["belief_error", "planner"])  # success per reading
    s, n = t["success_pct"], t["n"]
    paper, rows = s["paper"].sort_values(ascending=False), t.loc["paper"]
    theirs = rows["paper_success_pct"]  # as the table prints them
    tops, top, ranked = list(paper.index[paper == paper.max()]), paper.index[0], first(paper)

    def wilson(q: str) -> str:  # as the table prints it
        return f"Wilson 95% {fmt.interval(rows.success_low_pct[q], rows.success_high_pct[q], 1)}"

    text = (f"{ranked[0].upper()}{ranked[1:]} ({n1(paper.max()) + '% ' if len(tops) == 1 else ''}of "
            f"{fmt.listed([str(n['paper'][q]) for q in tops])} trials"
            f"{', ' + wilson(top) if len(tops) == 1 else ''}; "
            f"paper {fmt.listed([n1(theirs[q]) for q in tops])}%)")
    if PROPOSED not in tops:
        text += (f"; the proposed planner, {'first ' * (theirs.idxmax() == PROPOSED)}in the paper at "
                 f"{n1(theirs[PROPOSED])}%, succeeds on {n1(paper[PROPOSED])}% of {n['paper'][PROPOSED]} "
                 f"({wilson(PROPOSED)}")
        overlap = len(tops) == 1 and rows.success_low_pct[top] <= rows.success_high_pct[PROPOSED]
        text += "; the intervals overlap)" if overlap else ")"
    differ, judged = fmt.differing(rows)
    text += (f"; success differs from the paper's for {differ} of {judged} planners (Table "
             f"{table_number}). ")
    if PROPOSED not in tops:  # a gap to explain
        table = run.tables[f"{prefix}_belief"]
        beliefs = table.query("belief_error == 'paper'").set_index("planner")
        text += why(beliefs, top, f"table {prefix}_belief", fmt.decimals(table["g_geo_actual"]))
    text += extra(run)
    if "none" in s and paper[PROPOSED] < paper.max():
        text += belief_gap(paper, s["none"].reindex(paper.index), f"{prefix}_belief_pairs")
    text += ("Simulated virtual-rig data, not hardware. " if run.source == "virtual" else
             "Measured on hardware. ") + ("Filled by `graspcampaign ingest` from virtual-rig exports (their "
                                          "`source` column says virtual), not rig measurements. "
                                          if run.ingested_exports else "")
    return text + ("`docs/decisions.md`, *Planner beliefs on the virtual rig* and "
                   "*Tests 2-3 protocols and virtual rig*.")
