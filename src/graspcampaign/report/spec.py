"""A study's report, declared: what to show, never how to format it.

A :class:`ReportSpec` is a list of items rendered in order by
:func:`graspcampaign.report.render.render`:

* :class:`Finding` -- the opening paragraph, computed from the records (and the tables above);
* :class:`Section` -- a heading (the page's navigation lists them);
* :class:`Text` -- a paragraph computed from the run;
* :class:`Rates` -- a rate per group with its Wilson and object-bootstrap intervals, the
  paper's value, the difference and the verdict;
* :class:`Claims` of :class:`Rate` and :class:`Value` rows -- single quantities beside the paper
  (bare Rate/Value items in a spec are gathered into one Claims table);
* :class:`Paired` -- McNemar on occurrence-matched pairs;
* :class:`DesignLimit` and :class:`FailureChecks` -- how often δmax exceeds 1 mm; the first
  failing check of Algorithm 1;
* :class:`Table` -- any DataFrame computed from the run, with its shown columns;
* :class:`Figure` -- a drawing function over the run, in the one figure style.

Paper values are read from the run's typed paper object (``lambda p: p.success_pct[...]``); the
one verdict rule (:func:`graspcampaign.report.format.verdict`), the one rounding and the one
missing mark apply everywhere. A Rate, Table or Figure for a new record column is a few lines.
"""

from __future__ import annotations

import math
from collections.abc import Callable, Sequence
from dataclasses import dataclass, field
from typing import Any

import pandas as pd

from graspcampaign.analysis import records as rec
from graspcampaign.analysis.records import Estimate
from graspcampaign.analysis.vocabulary import FACTOR_LABELS, PROPOSED, VOCABULARIES, label
from graspcampaign.report import format as fmt
from graspcampaign.report import style
from graspcampaign.report.document import Col, Heading
from graspcampaign.report.document import Figure as FigureBlock
from graspcampaign.report.document import Table as TableBlock
from graspcampaign.report.document import Text as TextBlock
from graspcampaign.report.render import Run

PaperKey = Callable[[Any, dict], Any]
"""``(paper, group) -> the paper's value`` for one row of a grouped table (None: not reported)."""


def _paper(fn: Callable | None, paper: Any, *args) -> Any:
    """Return ``fn(paper, *args)``; a missing paper object or key means "not reported"."""
    if fn is None or paper is None:
        return None
    try:
        return fn(paper, *args)
    except (KeyError, IndexError):
        return None


def labelled(frame: pd.DataFrame, by: Sequence[str]) -> tuple[pd.DataFrame, list[Col]]:
    """Add ``<column>_label`` (the shared vocabulary's words) for grouping columns; shown cols."""
    cols = []
    for c in by:
        if c in VOCABULARIES:
            frame[f"{c}_label"] = [label(c, v) for v in frame[c]]
            cols.append(Col(f"{c}_label", c.replace("_", " ")))
        else:
            cols.append(Col(c, FACTOR_LABELS.get(c, c.replace("_", " "))))
    return frame, cols


def verdicts(frame: pd.DataFrame, ours: str, paper: str, low: str | None = None,
             high: str | None = None, digits: int | str = 1, unit: str = "",
             why: str = "why") -> pd.DataFrame:
    """Add ``difference``, ``differs`` and ``verdict`` columns by the one verdict rule.

    ``digits`` (and ``unit``) may name a column holding each row's decimals (unit); a unit of
    ``%`` states its difference in percentage points. Where ours is missing the verdict is the
    row's ``why`` text (the reason it could not be computed).
    """
    out = []
    for r in frame.to_dict("records"):
        d = int(r[digits]) if isinstance(digits, str) else digits
        u = str(r[unit] or "") if unit in r else unit
        u = " pp" if u in ("%", " pp") else (f" {u}" if u else "")
        p = r[paper]
        number = isinstance(p, int | float) and not isinstance(p, bool)
        diff = (float(r[ours]) - float(p) if number and not fmt.is_missing(r[ours])
                and not fmt.is_missing(p) else math.nan)
        verdict = fmt.verdict(r[ours], p, low=r.get(low) if low else None,
                              high=r.get(high) if high else None, digits=d, unit=u)
        if fmt.is_missing(r[ours]) and r.get(why):
            verdict = (None, str(r[why]))
        out.append((diff, *verdict))
    frame["difference"] = [o[0] for o in out]
    frame["differs"] = [o[1] for o in out]
    frame["verdict"] = [o[2] for o in out]
    return frame


@dataclass(frozen=True)
class ReportSpec:
    """A study's report: the study (or studies) it serves and its items in order."""

    study: str
    items: Sequence[Any]

    def __post_init__(self):
        items, rows = [], []
        for item in [*self.items, None]:
            if isinstance(item, Rate | Value):
                rows.append(item)
                continue
            if rows:
                n = sum(isinstance(i, Claims) for i in items)
                items.append(Claims(f"paper_comparison{n + 1 if n else ''}",
                                    "Ours beside the paper", rows))
                rows = []
            if item is not None:
                items.append(item)
        object.__setattr__(self, "items", tuple(items))


# ------------------------------------------------------------------------------ text items
@dataclass(frozen=True)
class Section:
    """A heading; the HTML page's navigation lists every section."""

    title: str

    def render(self, run: Run) -> list:
        return [Heading(self.title)]


@dataclass(frozen=True)
class Text:
    """A paragraph: a string, or a function of the run returning Markdown."""

    text: str | Callable[[Run], str]
    title: str = "a paragraph"

    def render(self, run: Run) -> list:
        text = self.text(run) if callable(self.text) else self.text
        return [TextBlock(text)] if text else []


@dataclass(frozen=True)
class Finding:
    """The opening paragraph: the main finding from the records, and where and why it differs
    from the paper (naming the decision in ``docs/decisions.md``)."""

    text: Callable[[Run], str]
    title: str = "The main finding"

    def render(self, run: Run) -> list:
        return [Heading("What this shows"), TextBlock(self.text(run), "finding")]


# ------------------------------------------------------------------------------ rate tables
@dataclass(frozen=True)
class Rates:
    """The rate of ``outcome`` per group of ``by`` beside the paper (Wilson 95 % per row; an
    object-clustered bootstrap when ``bootstrap``), over the executed trials ``where`` selects.
    """

    name: str
    caption: str
    by: Sequence[str]
    paper: PaperKey | None = None
    outcome: str = "success"
    bootstrap: bool = True
    where: Callable[[pd.DataFrame], pd.Series] | None = None

    @property
    def title(self) -> str:
        return f"Table {self.name}"

    def render(self, run: Run) -> list:
        records = run.records[self.where(run.records)] if self.where else run.records
        cluster = run.cluster if self.bootstrap else None
        frame = rec.rate_table(records, self.by, outcome=self.outcome, cluster=cluster,
                               seed=run.seed, order=run.order)
        frame.insert(len(self.by), "paper_pct", [
            _paper(self.paper, run.paper, dict(zip(self.by, key, strict=True)))
            for key in frame[list(self.by)].itertuples(index=False)])
        frame = verdicts(frame, "rate_pct", "paper_pct", "wilson_low_pct", "wilson_high_pct",
                         unit="%")
        frame, cols = labelled(frame, self.by)
        cols += [Col("paper_pct", "paper %", 1),
                 Col("rate_pct", "ours % (Wilson 95%)", 1, low="wilson_low_pct",
                     high="wilson_high_pct", why="rate_why"),
                 Col("difference", "difference [pp]", 1, signed=True), Col("n", "n"),
                 Col("n_error", "errors")]
        note = ""
        if cluster:
            cols.append(Col("bootstrap_low_pct", f"{cluster}-bootstrap 95% [%]", 1,
                            low="bootstrap_low_pct", high="bootstrap_high_pct",
                            why="bootstrap_why"))
            note = (f" Intervals: Wilson 95% per row; {cluster}-clustered percentile bootstrap "
                    f"({cluster}s resampled, not trials; {rec.rates.BOOTSTRAP_RESAMPLES} "
                    f"resamples, seed {run.seed}).")
        if frame["n_aborted"].any():
            cols.append(Col("n_aborted", "aborted"))
        cols.append(Col("verdict", "verdict"))
        return [TableBlock(self.name, self.caption + "." + note, frame, cols)]


@dataclass(frozen=True)
class Rate:
    """One rate beside the paper's (a row of :class:`Claims`) over the executed trials that
    ``where(run)`` selects (a boolean mask over ``run.ok``; None: all)."""

    label: str
    section: str
    where: Callable[[Run], pd.Series] | None = None
    paper: Callable[[Any], Any] | None = None
    outcome: str = "success"
    digits: int = 1

    def row(self, run: Run) -> dict:
        e = rec.rate(run.records, (lambda ok: self.where(run).to_numpy()) if self.where else None,
                     self.outcome)
        return {"value": e.value, "low": e.low, "high": e.high, "n": e.n, "unit": "%"}


@dataclass(frozen=True)
class Value:
    """One value beside the paper's (a row of :class:`Claims`): ``value(run)`` returns a number
    or an :class:`~graspcampaign.analysis.records.Estimate`; raising ValueError gives the reason.
    """

    label: str
    section: str
    value: Callable[[Run], float | Estimate]
    paper: Callable[[Any], Any] | None = None
    unit: str = ""
    digits: int = 2

    def row(self, run: Run) -> dict:
        v = self.value(run)
        e = v if isinstance(v, Estimate) else Estimate(v)
        return {"value": e.value, "low": e.low, "high": e.high, "n": e.n, "unit": self.unit}


@dataclass(frozen=True)
class Claims:
    """A table of single quantities (Rate and Value rows) beside the paper's values."""

    name: str
    caption: str
    rows: Sequence[Rate | Value] = field(default_factory=tuple)

    @property
    def title(self) -> str:
        return f"Table {self.name}"

    def render(self, run: Run) -> list:
        out = []
        for r in self.rows:
            base = {"quantity": r.label, "section": r.section, "digits": r.digits, "why": ""}
            try:
                base.update(r.row(run))
            except (ValueError, KeyError, ZeroDivisionError) as exc:
                from graspcampaign.report.render import reason

                base.update(value=math.nan, low=math.nan, high=math.nan, n=None,
                            unit=getattr(r, "unit", ""), why=f"not computed: {reason(exc)}")
            p = _paper(r.paper, run.paper)
            base["paper"] = fmt.paper_text(p, r.digits) if isinstance(p, tuple | list) else p
            base["_paper"] = p
            out.append(base)
        frame = pd.DataFrame(out, columns=["quantity", "section", "paper", "value", "low",
                                           "high", "n", "unit", "digits", "why", "_paper"])
        frame = verdicts(frame, "value", "_paper", "low", "high", "digits", "unit")
        frame = frame.drop(columns="_paper")
        cols = [Col("quantity", "quantity"), Col("section", "paper §"),
                Col("paper", "paper", "digits"),
                Col("value", "ours (95%)", "digits", low="low", high="high", why="why"),
                Col("unit", "unit"), Col("n", "n", 0),
                Col("difference", "difference", "digits", signed=True),
                Col("verdict", "verdict")]
        return [TableBlock(self.name, self.caption, frame, cols)]


@dataclass(frozen=True)
class Paired:
    """McNemar (1947) of the proposed planner against every other on occurrence-matched pairs."""

    name: str = "mcnemar"
    caption: str = ("Paired comparison, McNemar on occurrence-matched pairs (rows paired by "
                    "scene_id: same object, mass, friction and seed); χ² with continuity "
                    "correction, exact binomial p, discordant-pair odds ratio (> 1 favours the "
                    "proposed planner) with its exact 95% interval")
    reference: str = PROPOSED
    pair_on: str = "scene_id"
    paper: Callable[[Any, str], Any] | None = None
    title: str = "Paired comparison"

    def render(self, run: Run) -> list:
        planners = [p for p in run.order.get("planner", []) if p != self.reference]
        frame = rec.mcnemar_table(run.records, self.reference, planners, pair_on=self.pair_on)
        frame["paper"] = [_paper(self.paper, run.paper, p) or "not reported"
                          for p in frame["compared"]]
        frame, cols = labelled(frame, ["compared"])
        frame["compared_label"] = [label("planner", p) for p in frame["compared"]]
        cols += [Col("pairs", "pairs"), Col("reference_only", f"{label('planner', self.reference)}"
                                                              " only"),
                 Col("compared_only", "compared only"), Col("both_success", "both succeed"),
                 Col("both_fail", "both fail"), Col("chi2_cc", "χ² (cc)", 1, why="test_why"),
                 Col("p_exact", "p (exact)", sig=2),
                 Col("odds_ratio", "odds ratio (95%)", 2, low="odds_ratio_low",
                     high="odds_ratio_high", why="test_why"), Col("paper", "paper")]
        return [TableBlock(self.name, self.caption, frame, cols)]


@dataclass(frozen=True)
class DesignLimit:
    """How often the deepest contact exceeds the paper's 1 mm design limit (Sec. 4), per group."""

    by: Sequence[str]
    name: str = "design_limit"
    caption: str = ("Penetration against the paper's 1 mm design limit (Sec. 4, 5.5): executed "
                    "trials whose deepest contact δmax exceeds 1 mm (Wilson 95%); our SI "
                    "evaluation keeps the published algorithm, so this is reported, never "
                    "rescaled (SPEC §2.7)")
    title: str = "Design limit"

    def render(self, run: Run) -> list:
        frame = rec.design_limit_table(run.records, self.by, order=run.order)
        frame["paper"] = f"within {rec.DESIGN_LIMIT_MM:g} mm"
        frame, cols = labelled(frame, self.by)
        cols += [Col("paper", "paper"), Col("n", "n"), Col("exceeds", "> 1 mm"),
                 Col("exceeds_pct", "% > 1 mm (Wilson 95%)", 1, low="wilson_low_pct",
                     high="wilson_high_pct"),
                 Col("successes_exceeding", "successes > 1 mm"),
                 Col("delta_max_median_mm", "median δmax [mm]", sig=3),
                 Col("delta_max_p95_mm", "95th pct δmax [mm]", sig=3),
                 Col("delta_max_max_mm", "max δmax [mm]", sig=3)]
        return [TableBlock(self.name, self.caption, frame, cols)]


@dataclass(frozen=True)
class FailureChecks:
    """The first failing check of Algorithm 1 per group (none = success)."""

    by: Sequence[str]
    paper: PaperKey | None = None
    name: str = "failure_checks"
    caption: str = ("First failing check of Algorithm 1 (none = success; residual ‖R‖ ≥ τ_F, "
                    "torque, slip margin ≤ 0), executed trials")
    title: str = "Failing checks"

    def render(self, run: Run) -> list:
        frame = rec.failure_check_table(run.records, self.by, order=run.order)
        frame["paper"] = [_paper(self.paper, run.paper, dict(zip(self.by, k, strict=True)))
                          or "not reported" for k in frame[list(self.by)].itertuples(index=False)]
        frame, cols = labelled(frame, self.by)
        checks = [c for c in frame.columns if f"{c}_pct" in frame.columns]
        cols += [Col("n", "n"), *(Col(c, c, share=f"{c}_pct") for c in checks),
                 Col("paper", "paper")]
        return [TableBlock(self.name, self.caption, frame, cols)]


# ------------------------------------------------------------------------------ generic items
@dataclass(frozen=True)
class Table:
    """Any table computed from the run: ``compute(run)`` returns the full-precision frame;
    ``cols`` are the shown columns (default: every column, 4 significant digits)."""

    name: str
    caption: str | Callable[[Run], str]
    compute: Callable[[Run], pd.DataFrame]
    cols: Sequence[Col] | None = None
    by: Sequence[str] = ()
    empty: str | None = "no executed trial has its data"  # None: an empty table is left out

    @property
    def title(self) -> str:
        return f"Table {self.name}"

    def render(self, run: Run) -> list:
        frame = self.compute(run)
        if frame is None or not len(frame):
            return [TextBlock(f"Table {self.name} is empty: {self.empty}.", "note")] \
                if self.empty else []
        frame = frame.reset_index(drop=True)
        lead = labelled(frame, self.by)[1] if self.by else []
        cols = list(self.cols) if self.cols is not None else [
            Col(c, c.replace("_", " ")) for c in frame.columns if not c.endswith("_label")
            and c not in self.by]
        caption = self.caption(run) if callable(self.caption) else self.caption
        return [TableBlock(self.name, caption, frame, [*lead, *cols])]


@dataclass(frozen=True)
class Figure:
    """A figure: ``draw(run, fig)`` draws on a figure of ``size`` inches in the one style."""

    name: str
    caption: str | Callable[[Run], str]
    draw: Callable[[Run, Any], None]
    size: tuple[float, float] = (6.4, 3.6)

    @property
    def title(self) -> str:
        return f"Figure {self.name}"

    def render(self, run: Run) -> list:
        images = style.draw(lambda fig: self.draw(run, fig), self.size, run.source,
                            (run.figure_format,))
        caption = self.caption(run) if callable(self.caption) else self.caption
        return [FigureBlock(self.name, caption, images)]
