"""LEGACY PATH (issue 14): section modules of the studies not yet ported to a report spec, called
through :class:`graspcampaign.report.build.LegacyReport`. Porting a study means writing its spec in
:mod:`graspcampaign.report.studies`, adding it to ``build.SPECS``, removing its ``build.LEGACY``
entry and its module here; these helpers serve these modules only."""

from __future__ import annotations

from graspcampaign.analysis.rates import wilson_interval
from graspcampaign.analysis.records import executed
from graspcampaign.report import format as fmt

__all__ = ["executed", "paper_value", "rate_cell"]


def rate_cell(successes: int, n: int) -> str:
    """Return ``"k/n = e % (low–high)"`` with its Wilson 95 % interval; the missing mark if n = 0."""
    if not n:
        return fmt.MISSING
    ci = wilson_interval(int(successes), int(n))
    return (f"{successes}/{n} = {fmt.number(100 * ci.estimate, 1)} % "
            f"({fmt.interval(100 * ci.low, 100 * ci.high, 1)})")


def paper_value(paper, *path):
    """Walk ``path`` through the typed paper values: a dataclass step reads its attribute (a typo
    raises), a dict step (values keyed by planner, shape ...) or any step below None gives None."""
    for key in path:
        paper = None if paper is None else paper.get(key) if isinstance(paper, dict) else getattr(paper, key)
    return paper
