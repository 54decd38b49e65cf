"""A study's report, declared: what to show, never how to format it."""

from __future__ import annotations

import itertools
import math
from collections.abc import Callable, Iterable, Sequence
from dataclasses import dataclass
from typing import Any

import numpy as np
import pandas as pd

from graspcampaign.analysis import records as rec
from graspcampaign.analysis.rates import BOOTSTRAP_RESAMPLES, wilson_interval
from graspcampaign.analysis.records import Estimate
from graspcampaign.analysis.vocabulary import PROPOSED, label, ordered
from graspcampaign.campaign.paper import Approximate
from graspcampaign.report import format as fmt
from graspcampaign.report.document import Col, Figure, Section, Table, Text  # noqa: F401 - API
from graspcampaign.report.render import Run, reason

PaperKey = Callable[[Any, dict], Any]
"""``(paper, group) -> the paper's value`` for one row of a grouped table (None: not reported)."""


def paper_of(run: Run, fn: Callable | None, *key) -> Any:
    """The paper's value ``fn(run.paper, *key)``; None where the paper reports none (no paper
    object, no ``fn``, or a missing key)."""
    try:
        return None if fn is None or run.paper is None else fn(run.paper, *key)
    except (KeyError, IndexError):
        return None


def share(frame: Any, event: Any) -> Estimate:
    """The share [%] of the rows of ``frame`` where ``event`` holds, with its Wilson 95 % interval."""
    if not len(frame):
        raise ValueError("no executed trial")
    w = wilson_interval(int(np.sum(event)), len(frame))
    return Estimate(100 * w.estimate, 100 * w.low, 100 * w.high, len(frame))


def rate_cols(g: pd.DataFrame, outcome: str, prefix: str) -> dict:
    """``<prefix>_pct`` and its Wilson 95 % ``<prefix>_low_pct``/``_high_pct`` of ``outcome`` over the
    executed trials of ``g`` with it recorded (the columns :func:`~graspcampaign.report.document.pct_col`
    shows), and their count ``n_<prefix>``."""
    e = rec.rate(g, outcome=outcome)
    return {f"{prefix}_pct": e.value, f"{prefix}_low_pct": e.low, f"{prefix}_high_pct": e.high,
            f"n_{prefix}": e.n}


def _paper_by(fn: PaperKey | None, run: Run, frame: pd.DataFrame, by: Sequence[str]) -> list:
    return [paper_of(run, fn, dict(zip(by, key, strict=True)))
            for key in frame[list(by)].itertuples(index=False)]


def verdicts(frame: pd.DataFrame, ours: str, paper: str, low: str | None = None,
             high: str | None = None, digits: int | str = 1, unit: str = "",
             why: str = "why", **forms: str) -> pd.DataFrame:
    """Add ``difference``, ``differs`` and ``verdict`` columns by the one verdict rule; ``unit`` and
    ``forms`` (:func:`~graspcampaign.report.format.verdict`'s ``ratio``, ``commanded``, ``because``,
    ``pinned``, ``bound``) are each a column of ``frame`` or the value itself; a row whose ours is missing
    is not compared because of its ``why`` text, if any. A row not compared has no difference."""
    out = []
    for r in frame.to_dict("records"):
        u = str(r[unit] or "") if unit in r else unit
        o, p = r[ours], r[paper]
        number = isinstance(p, int | float) and not isinstance(p, bool) and not fmt.is_missing(p)
        d = r[digits] if isinstance(digits, str) else digits
        words = {k: (r[v] or "") if v in r else v for k, v in forms.items()}
        if fmt.is_missing(o) and r.get(why):
            words["because"] = words.get("because") or str(r[why])
        verdict = fmt.verdict(o, p, low=r.get(low) if low else None, high=r.get(high) if high else None,
                              digits=3 if d == fmt.P else int(d), unit=u, **words)
        compared = number and not fmt.is_missing(o) and verdict.differs is not None
        out.append((float(o) - float(p) if compared else math.nan, verdict.differs, verdict.words))
    difference, differs, words = zip(*out, strict=True) if out else ((), (), ())
    return frame.assign(difference=list(difference), differs=list(differs), verdict=list(words))


@dataclass(frozen=True)
class ReportSpec:
    """A study's report: the study it serves and its items in order (each run of bare Rate/Value
    items is gathered into one Claims table, ``paper_comparison``, ``paper_comparison2`` ...)."""

    study: str
    items: Sequence[Any]

    def __post_init__(self):
        for number, item in enumerate(self.items, 1):
            _check_item(self.study, number, item)
        items = []
        for values, group in itertools.groupby(self.items, lambda item: isinstance(item, Value)):
            if not values:
                items += group
                continue
            n = sum(i.name.startswith("paper_comparison") for i in items if isinstance(i, Table))
            name = f"paper_comparison{n + 1 if n else ''}"
            items.append(Claims(name, "Ours beside the paper", list(group)))
        for kind, names in (("tables", [i.name for i in items if isinstance(i, Table)]),
                            ("figures", [i.name for i in items if isinstance(i, Figure)])):
            if twice := sorted({n for n in names if names.count(n) > 1}):
                raise ValueError(f"report spec {self.study!r}: two {kind} are named {twice[0]!r} (one "
                                 f"would overwrite the other's file); name them apart.")
        object.__setattr__(self, "items", tuple(items))


def _check_item(study: str, number: int, item: Any) -> None:
    """Raise one sentence naming the spec and item when ``item`` is no report item (a function
    such as ``Rates`` not called, a column list, a string) or a Finding without its function."""
    where = f"report spec {study!r}, item {number}"
    if not (isinstance(item, Value) or callable(getattr(item, "render", None))):  # duck-typed items too
        what = f"the function {item.__name__}" if callable(item) and hasattr(item, "__name__") \
            else f"a {type(item).__name__} ({str(item)[:40]})"
        raise TypeError(f"{where}: {what} is not a report item (Finding, Section, Text, Table, Figure, "
                        f"Value){'; call it' if callable(item) else ''}.")
    if isinstance(item, Finding) and not callable(item.text):
        raise TypeError(f"{where}: Finding takes a function of the run returning its paragraph, "
                        f"not a {type(item.text).__name__}.")


@dataclass(frozen=True)
class Finding:
    """The opening paragraph: the main finding from the records and where and why it differs from
    the paper (naming the decision in ``docs/decisions.md``); computed last, shown first, it ends
    with what the validity gate removed when the report has a :func:`GateRemoved` table. ``text``:
    the function of the run returning the paragraph; ``title`` names the item in a note and the
    list of failed items only (its heading is always "What this shows")."""

    text: Callable[[Run], str]
    title: str = "The main finding"

    def render(self, run: Run) -> list:
        return [Section("What this shows"), Text(self.text(run) + gate_text(run), "finding")]


# ------------------------------------------------------------------ tables of the records
def Rates(name: str, caption: str, by: Sequence[str], paper: PaperKey | None = None, bootstrap: bool = True,
          where: Callable[[pd.DataFrame], pd.Series] | None = None,
          because: Callable[[pd.DataFrame], Any] | None = None) -> Table:
    """The success rate per group of ``by`` beside the paper (Wilson 95 % per row; an
    object-clustered bootstrap when ``bootstrap``) over the trials ``where(records)`` selects;
    ``because(table)``: per row, why the paper's value is shown but not judged ("": judged)."""
    def compute(run: Run) -> pd.DataFrame:
        if missing := [c for c in by if c not in run.records]:
            raise KeyError(missing[0])  # "the records have no `<column>` column", not "empty"
        records = run.records[where(run.records)] if where else run.records
        frame = rec.rate_table(records, by, cluster=run.cluster if bootstrap else None, seed=run.seed,
                               order=run.order)
        frame.insert(len(by), "paper_pct", _paper_by(paper, run, frame, by))
        frame = frame.assign(_because=because(frame) if because else "")
        return verdicts(frame, "rate_pct", "paper_pct", "wilson_low_pct", "wilson_high_pct", unit="%",
                        because="_because").drop(columns="_because")

    def cols(run: Run, frame: pd.DataFrame) -> list[Col]:
        return [Col("paper_pct", "paper %", 1),
                Col("rate_pct", "ours % (Wilson 95%)", 1, low="wilson_low_pct", high="wilson_high_pct",
                    why="rate_why"),
                Col("difference", "difference [pp]", 1, signed=True), Col("n", "n"), Col("n_error", "errors"),
                *([Col("bootstrap_low_pct", f"{run.cluster}-bootstrap 95% [%]", 1, low="bootstrap_low_pct",
                       high="bootstrap_high_pct", why="bootstrap_why")] if bootstrap else []),
                *([Col("n_aborted", "aborted")] if frame["n_aborted"].any() else []),
                Col("verdict", "verdict")]

    return Table(name, lambda run: caption + "." + (
        f" Intervals: Wilson 95% per row; {run.cluster}-clustered percentile bootstrap ({run.cluster}s "
        f"resampled, not trials; {BOOTSTRAP_RESAMPLES} resamples, seed {run.seed})." if bootstrap else ""),
        compute, cols, by)


class Unmeasured(ValueError):
    """Raised by a :class:`Value`'s function when what the data show leaves nothing to measure ("every
    trial failed: no difference to test"): the row says it as a finding, not as "not computed: …"."""


@dataclass(frozen=True)
class Value:
    """One value beside the paper's (a row of :func:`Claims`): ``value(run)`` returns a number or an
    :class:`~graspcampaign.analysis.records.Estimate`; raising ValueError gives the reason; ``because``:
    why the paper's value is shown but not compared (a different quantity)."""

    label: str
    section: str
    value: Callable[[Run], float | Estimate]
    paper: Callable[[Any], Any] | None = None
    unit: str = ""
    digits: int = 2
    because: str = ""  # why ours is not compared (a context row), as the verdict rule's ``because``
    bound: str = "the paper's target"  # what a one-sided paper value is, as the verdict rule's ``bound``

    def estimate(self, run: Run) -> Estimate:
        return v if isinstance(v := self.value(run), Estimate) else Estimate(v)


def Rate(label: str, section: str, where: Callable[[Run], pd.Series], outcome: str = "success") -> Value:
    """One rate (a :class:`Value` row in %, one decimal, Wilson 95 %) over the executed trials that
    ``where(run)`` selects (a boolean mask over ``run.ok``; :func:`Rates`' ``where`` takes the records
    instead); the paper prints words, not a rate, for every such row (sensitivity's, judged in those
    words), so it has no paper value: a rate beside a paper number is a :class:`Value` of
    :func:`share` with its ``paper``."""
    return Value(label, section, lambda run: rec.rate(run.records, lambda ok: where(run).to_numpy(), outcome),
                 None, "%", 1)


def Claims(name: str, caption: str | Callable[[Run], str],
           rows: Sequence[Value] | Callable[[Run], Iterable[tuple]] = (),
           empty: str | None = "no executed trial has its data") -> Table:
    """A table of single quantities beside the paper's: :func:`Rate` and :class:`Value` rows, or
    ``rows(run)`` yielding ``(quantity, section, value, paper, unit, digits[, because[, bound]])`` with the
    paper's value itself and ours a number, an Estimate or a function of nothing giving one (its ValueError:
    the row's reason); ``digits`` the decimals, or ``fmt.P`` for a p-value; ``because`` why a context row is
    not compared; ``bound`` what a one-sided paper value is; ``empty`` as for :class:`Table`."""
    def compute(run: Run) -> pd.DataFrame:
        out = []
        for r in rows(run) if callable(rows) else rows:
            if not isinstance(r, Value):
                q, s, v, x, unit, digits, *because = r
                r = Value(q, s, lambda run, v=v: v() if callable(v) else v, lambda p, x=x: x, unit, digits,
                          *because)
            try:
                e, why = r.estimate(run), ""
            except (ValueError, KeyError, ZeroDivisionError) as exc:
                e, why = Estimate(math.nan), reason(exc) if isinstance(exc, Unmeasured) else \
                    f"not computed: {reason(exc)}"
            p = paper_of(run, r.paper)
            shown = isinstance(p, tuple | list | Approximate)  # as the paper prints it: 78.0–83.4, ≈ 86
            out.append([r.label, r.section, fmt.paper_text(p, r.digits) if shown else p,
                        e.value, e.low, e.high, e.n, r.unit, r.digits, why, p, r.because, r.bound])
        columns = ["quantity", "section", "paper", "value", "low", "high", "n", "unit", "digits", "why",
                   "_paper", "_because", "_bound"]
        frame = pd.DataFrame(out, columns=columns).astype({"n": "Int64"})
        return verdicts(frame, "value", "_paper", "low", "high", "digits", "unit", because="_because",
                        bound="_bound").drop(columns=["_paper", "_because", "_bound"])

    def shown(run: Run, frame: pd.DataFrame) -> list[Col]:
        ours = "ours (95%)" if (frame["low"].notna() & frame["high"].notna()).any() else "ours"
        # a unit or n column no row fills (counts tables) is left out: it printed blanks or dashes only
        filled = [c for c in ("unit", "n") if (frame[c].notna() & (frame[c] != "")).any()]
        return [Col("quantity", "quantity"), Col("section", "paper §"), Col("paper", "paper", "digits"),
                Col("value", ours, "digits", low="low", high="high", why="why"),
                *[Col(c, c, 0 if c == "n" else None) for c in filled],
                Col("difference", "difference", "digits", signed=True), Col("verdict", "verdict")]

    return Table(name, caption, compute, shown, empty=empty)


def Paired(name: str = "mcnemar", caption: str = (
        "Paired comparison, McNemar on occurrence-matched pairs (rows paired by scene_id: same "
        "object, mass, friction and seed)"), pair_on: str = "scene_id",
        paper: Callable[[Any, str], Any] | None = None,
        trials: Callable[[Run], pd.DataFrame] | None = None) -> Table:
    """McNemar (1947) of the proposed planner against every other planner on occurrence-matched pairs of
    ``trials(run)`` (default the run's records), in the vocabulary's planner order; ``caption`` says
    which pairs, the statistics' description follows it."""
    def compute(run: Run) -> pd.DataFrame:
        frame = run.records if trials is None else trials(run)
        planners = [p for p in ordered("planner", frame["planner"], run.order.get("planner", []))
                    if p != PROPOSED]
        frame = rec.mcnemar_table(frame, PROPOSED, planners, pair_on=pair_on)
        return frame.assign(paper=[paper_of(run, paper, p) or "not reported" for p in frame["compared"]],
                            compared_label=[label("planner", p) for p in frame["compared"]])

    return Table(name, f"{caption}; χ² with continuity correction (none when the two discordant counts "
                 "b and c are equal: χ² = 0, p = 1, as R's mcnemar.test; statsmodels' corrected χ² gives "
                 "1/(b + c) there), exact binomial p, discordant-pair odds "
                 "ratio (> 1 favours the proposed planner) with its exact 95% interval", compute, [
        Col("compared_label", "compared"), Col("pairs", "pairs"),
        Col("reference_only", f"{label('planner', PROPOSED)} only"), Col("compared_only", "compared only"),
        Col("both_success", "both succeed"), Col("both_fail", "both fail"),
        Col("chi2_cc", "χ² (cc)", 1, why="test_why"), Col("p_chi2", "p (χ²)"), Col("p_exact", "p (exact)"),
        Col("odds_ratio", "odds ratio (95%)", 2, low="odds_ratio_low", high="odds_ratio_high",
            why="test_why"), Col("paper", "paper")])


def DesignLimit(by: Sequence[str]) -> Table:
    """How often the deepest contact exceeds the paper's 1 mm design limit (Sec. 4), per group; the
    trials deeper than the fingertip radius r are counted apart (non-physical), the δmax statistics
    are over the others (table ``design_limit``, which :func:`FailureChecks`' caption names)."""
    return Table("design_limit", lambda run: (
        "Penetration against the paper's 1 mm design limit (Sec. 4, 5.5): executed trials whose deepest "
        "contact δmax exceeds 1 mm (Wilson 95%); our SI evaluation keeps the published algorithm, so this is "
        "reported, never rescaled (SPEC §2.7); δmax > r: trials with a contact deeper than the fingertip "
        f"radius r = {fmt.number(run.radius_mm)} mm, whose fingertip centre lies inside the object "
        "(non-physical; the validity gate makes them failures); the δmax statistics are over the physical "
        "trials, δmax ≤ r (— where none)"),
        lambda run: rec.design_limit_table(run.records, by, radius_mm=run.radius_mm, order=run.order)
        .assign(paper=f"within {fmt.number(rec.DESIGN_LIMIT_MM)} mm"), [
        Col("paper", "paper"), Col("n", "n"), Col("exceeds", "> 1 mm"),
        Col("exceeds_pct", "% > 1 mm (Wilson 95%)", 1, low="wilson_low_pct", high="wilson_high_pct"),
        Col("successes_exceeding", "successes > 1 mm"), Col("beyond_radius", "δmax > r (non-physical)"),
        Col("delta_max_median_mm", "median δmax, δmax ≤ r [mm]", sig=3),
        Col("delta_max_p95_mm", "95th pct δmax, δmax ≤ r [mm]", sig=3),
        Col("delta_max_max_mm", "max δmax, δmax ≤ r [mm]", sig=3)], by)


def FailureChecks(by: Sequence[str], paper: PaperKey | None = None) -> Table:
    """The first failing check of Algorithm 1 per group (none = success); the caption says where
    the trials with a contact deeper than the fingertip radius are counted."""
    def compute(run: Run) -> pd.DataFrame:
        frame = rec.failure_check_table(run.records, by, order=run.order)
        return frame.assign(paper=[p or "not reported" for p in _paper_by(paper, run, frame, by)])

    return Table("failure_checks", lambda run: (
        "First failing check of Algorithm 1 (none = success; residual ‖R‖ ≥ τ_F, torque, slip margin ≤ 0; "
        "geometry = only the validity gate: a contact deeper than the fingertip radius), executed trials; "
        "the checks run in that order and the first failing one is counted, so geometry counts only trials "
        f"passing every published check: {int(rec.beyond_radius(run.ok, run.radius_mm).sum())} of "
        f"{len(run.ok)} trials have a contact deeper than r = {fmt.number(run.radius_mm)} mm (non-physical, "
        "failed by the gate too) and are counted under their first failing published check (table "
        "design_limit)"), compute, lambda run, frame: [
        Col("n", "n"), *(Col(c, c, share=f"{c}_pct") for c in frame if f"{c}_pct" in frame),
        Col("paper", "paper")], by)


#: The `docs/decisions.md` heading of the validity gate, as the reports cite it.
VALIDITY = "Physical validity, grip laws, Ferrari–Canny ε"
GATE = "gate_removed"
"""The name of the :func:`GateRemoved` table, which :func:`gate_text` reads."""


def gate_text(run: Run) -> str:
    """The Finding's sentence on the :func:`GateRemoved` table ("" without one): the trials deeper
    than r of those with a ``valid_geometry`` reading, and how many have none where some do."""
    if (g := run.tables.get(GATE)) is None or not len(g):
        return ""
    successes = int(g["success_unbounded"].sum())
    removed = f"removed {int(g['removed'].sum())} of {successes} successes" if successes \
        else "removed none (no trial succeeded without it)"
    read, n = int(g["n_valid_geometry"].sum()), int(g["n"].sum())  # a trial without the reading: n only
    unread = f"no reading in {n - read} of {n}; " if read < n else ""
    return (f" The validity gate {removed}: {int(g['invalid_geometry'].sum())} of {read} executed trials "
            f"{'with a validity reading (`valid_geometry`) ' * bool(unread)}have a contact deeper than the "
            f"fingertip radius, which is no contact ({unread}table {GATE}; `docs/decisions.md`, "
            f"*{VALIDITY}*).")


def GateRemoved(by: Sequence[str]) -> Table:
    """How many successes the validity gate removed per group (issue 13 item 1), from the records'
    ``success_unbounded`` and ``valid_geometry``: add ``GateRemoved(["planner"])`` to a spec."""
    return Table(GATE, f"Successes the validity gate removed (`docs/decisions.md`, *{VALIDITY}*): trials "
                 "passing every check (success without the gate) with a contact deeper than the fingertip "
                 "radius, which is no contact any more, count as failures; Wilson 95%",
                 lambda run: rec.gate_table(run.records, by, run.order), [
        "n", Col("success_unbounded", "successes without the gate"), "removed_pct", "removed", "success",
        Col("invalid_geometry", "contact deeper than r")], by)
