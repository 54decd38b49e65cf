"""Hardware protocols (Tests 1-3): schedules, ingest and validation, the virtual rig."""
