"""Statistics, tables and figures. Reads records; never runs a trial."""
