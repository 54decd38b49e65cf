"""Hardware protocols (Tests 1-3): schedules, ingest and validation, the virtual rig."""

from graspcampaign.core.plausible import FINGERTIP_RADIUS

DEFAULT_PLAN_MATERIAL = "silicone_ref"
"""Contact law used by ``plan`` when no ``--material`` is given (the stiffest, Table 4 reference).
Kept here, free of numpy, so the command line's help shows it without the numerical layers."""

DEFAULT_FINGERTIP_RADIUS_MM = 1e3 * FINGERTIP_RADIUS
"""Fingertip radius ``plan`` assumes when no ``--fingertip-radius-mm`` is given [mm] (the paper's
R, :data:`graspcampaign.core.plausible.FINGERTIP_RADIUS`)."""
