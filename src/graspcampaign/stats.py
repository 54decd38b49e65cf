"""Public statistics API for notebooks: ``from graspcampaign import stats``.

A re-export of :mod:`graspcampaign.report.stats` (its ``__all__``); see there for the functions,
their result dataclasses and their references.
"""

from graspcampaign.report.stats import *  # noqa: F403
from graspcampaign.report.stats import __all__  # noqa: F401
