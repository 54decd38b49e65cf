"""Campaign engine: typed configs, composition, trial expansion, runner, records, provenance."""
