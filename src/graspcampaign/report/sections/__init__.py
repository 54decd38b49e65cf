"""LEGACY PATH (issue 14): section modules of the studies not yet ported to a report spec.

Each module here is called by :func:`graspcampaign.report.build._legacy` through the old
``Report`` API (:class:`graspcampaign.report.build.LegacyReport`). Porting a study means writing
its spec in :mod:`graspcampaign.report.studies` (docs/ARCHITECTURE.md shows how), adding it to
``build.SPECS``, removing its ``build.LEGACY`` entry and deleting its module here. The helpers
below serve these modules only; new code uses :mod:`graspcampaign.report.spec`.
"""

from __future__ import annotations

from graspcampaign.analysis.rates import CONFIDENCE_LEVEL, wilson_interval
from graspcampaign.analysis.records import executed
from graspcampaign.report import format as fmt

__all__ = ["executed", "paper_value", "rate_cell"]


def rate_cell(successes: int, n: int) -> str:
    """Return ``"k/n = e % (low–high)"`` with its Wilson 95 % interval; the missing mark if n = 0."""
    if n == 0:
        return fmt.MISSING
    ci = wilson_interval(int(successes), int(n), CONFIDENCE_LEVEL)
    return (f"{successes}/{n} = {fmt.number(100 * ci.estimate, 1)} % "
            f"({fmt.interval(100 * ci.low, 100 * ci.high, 1)})")


def paper_value(paper, *path):
    """Walk ``path`` through the typed paper values (:mod:`graspcampaign.campaign.paper`).

    A step into a dataclass reads its attribute (a mistyped name raises AttributeError); a step
    into a dict (values keyed by planner, shape, material ...) gives None for a key the paper
    does not report; so does any step below a None.
    """
    value = paper
    for key in path:
        if value is None:
            return None
        value = value.get(key) if isinstance(value, dict) else getattr(value, key)
    return value
