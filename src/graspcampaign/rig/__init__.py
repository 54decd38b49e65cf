"""Hardware protocols (Tests 1-3): schedules, ingest and validation, the virtual rig."""

DEFAULT_PLAN_MATERIAL = "silicone_ref"
"""Contact law used by ``plan`` when no ``--material`` is given (the stiffest, Table 4 reference).
Kept here, free of numpy, so the command line's help shows it without the numerical layers."""
