"""The pre-execution flags scored against the rig's outcome, shared by Tests 2 and 3: the classifier
table per flag, belief reading and scope beside the paper's scores, and the confusion-matrix panel."""

from __future__ import annotations

from decimal import Decimal

import numpy as np
import pandas as pd

from graspcampaign.analysis import hardware as hw
from graspcampaign.report import format as fmt
from graspcampaign.report import style
from graspcampaign.report.document import Col, Table
from graspcampaign.report.render import Run
from graspcampaign.report.spec import paper_of, verdicts
from graspcampaign.report.studies.opening import FLAGS, ex, frames

RESIDUAL = "predicted_stable_residual"
"""The flag §8.4 scores: §8.1, "the pre-execution flag itself is the planner's residual criterion"."""


def scores(c) -> tuple:
    """A printed classifier's (accuracy, precision, recall), as :func:`classifier` takes them."""
    return c.accuracy, c.precision, c.recall


def classifier(name: str, caption: str, scopes, paper) -> Table:
    """The flags against the rig's success per belief reading and scope, beside the paper's scores
    (``paper(p)``: (scope, flag) -> (accuracy, precision, recall[, note]), None where not printed; a note,
    why the paper's value is in doubt, ends the verdict). A paper value names the one flag it was computed
    for and stands beside it alone: the other flag's rows show ours ("no paper value")."""
    def compute(run: Run) -> pd.DataFrame:
        d, ref = frames(run), paper_of(run, paper) or {}
        out = hw.classifier_table(hw.scoped(d, scopes(d)), FLAGS, ["belief_error", "scope"])
        refs = [(ref.get((s, f)) if b == "paper" else None) or (None,) * 3
                for f, s, b in zip(out["flag"], out["scope"], out["belief_error"], strict=True)]
        for i, k in enumerate(("accuracy", "precision", "recall")):
            out[f"paper_{k}"] = [r[i] for r in refs]
        out["paper_why"] = [r[3] if len(r) > 3 else "" for r in refs]
        out["why"] = np.where(out["flagged"] > 0, "", "no trial flagged")
        # the paper's accuracy with the decimals it prints (§8.4 "80.6 %" = 0.806 and "0.93"; §9.5 0.888):
        # two decimals printed 0.806 as 0.81
        out["paper_accuracy_digits"] = pd.array([None if fmt.is_missing(v) else typed_decimals(v)
                                                 for v in out["paper_accuracy"]], dtype="Int64")
        out = verdicts(out, "precision", "paper_precision", "precision_low", "precision_high", digits=2)
        out["verdict"] = [f"{v}; {w}" if w else v
                          for v, w in zip(out["verdict"], out["paper_why"], strict=True)]
        return out if out["paper_why"].any() else out.drop(columns="paper_why")  # a column only with a note
    fracs = [c for k, h in (("base", "base success rate"), ("precision", "precision"), ("recall", "recall"))
             for c in (Col(k, f"{h} (Wilson 95%)", 3, low=f"{k}_low", high=f"{k}_high",
                           why="why" if k == "precision" else None),
                       *[Col(f"paper_{k}", "paper", 2)] * (k != "base"))]
    return Table(name, caption, compute, [
        *(Col(c, c) for c in ("n", "flagged", "fp")), *fracs, Col("above_base", "precision above base"),
        Col("accuracy", "accuracy", 3), Col("paper_accuracy", "paper", "paper_accuracy_digits"),
        Col("verdict", "verdict (precision)")], by=["flag", "belief_error", "scope"])


def group_c(g) -> dict:
    """The paper's precisions of the flag inside group C and outside it (``classifier`` keys), each beside
    the residual flag, the one §8.1 gives them, for the population its section states: §8.1 the proposed
    planner's trials, §8.4 the pooled ones; both group C rows say the two values cannot both hold."""
    p, q, flag = g.proposed, g.pooled, RESIDUAL
    clash = (f"{p.section} prints {fmt.number(p.precision, 2)} ({p.certified - p.certified_failed} of "
             f"{p.certified}) and {q.section} {fmt.number(q.precision, 2)} for group C, whose {p.trials} "
             f"trials {p.section} lists under the proposed planner alone: both cannot hold")
    return {("group C, proposed", flag): (None, p.precision, None, clash),
            ("group C, all planners", flag): (None, q.precision, None, clash),
            ("outside C, all planners", flag): (None, q.precision_elsewhere, None)}


def typed_decimals(value: float) -> int:
    """The decimals of a paper value as its study file types it (0.806: 3, 0.93: 2, 1.0: 1)."""
    return max(0, -Decimal(repr(float(value))).as_tuple().exponent)


def confusion(paper, flag: str):
    """Panel: ``predicted_stable`` against the rig's outcome, with ours and the paper's scores (``paper``
    None: ours alone, where the paper scores another flag); ``flag`` says in words what the flag predicts
    (the y label; the caption names the column)."""
    def draw(run: Run, ax) -> None:
        m = hw.classifier_table(ex(run).assign(all=1), ["predicted_stable"], ["all"]).iloc[0]
        cells, ref = np.array([[m["tn"], m["fn"]], [m["fp"], m["tp"]]]), paper_of(run, paper)
        style.confusion(ax, cells, ["no", "yes"], ["failed", "succeeded"], f"{run.rig} outcome [trials]",
                        flag)
        ax.set_title("(c) flag vs outcome")
        ax.plot([], [], " ", label="\n".join([f"n = {m['n']}", *(
            f"{k}: ours {fmt.number(m[k], 2)}" + (f", paper {fmt.number(getattr(ref, k), 2)}" if ref else "")
            for k in ("accuracy", "precision", "recall"))]))
        ax.legend(loc="upper left", bbox_to_anchor=(1.02, 1.0), handlelength=0)
    return draw
