"""Hardware protocols (Tests 1-3): schedules, ingest and validation, the virtual rig."""

DEFAULT_PLAN_MATERIAL = "silicone_ref"
"""Contact law used by ``plan`` when no ``--material`` is given (the stiffest, Table 4 reference).
Kept here, free of numpy, so the command line's help shows it without the numerical layers."""

DEFAULT_FINGERTIP_RADIUS_MM = 5.0
"""Fingertip radius ``plan`` assumes when no ``--fingertip-radius-mm`` is given [mm] (Table 2,
R = 5 mm; the simulated fingertip of ``conf/model``'s ``fingertip_radius_m``)."""
