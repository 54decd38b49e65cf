"""Tests of campaign/status.py beyond the command line's: the time a run's own records give and
when a run is complete."""

from __future__ import annotations

from pathlib import Path

import kinds_for_tests  # noqa: F401  (registers the test kinds)
import numpy as np
import pyarrow as pa
import pyarrow.parquet as pq
import pytest

from graspcampaign.campaign import status
from graspcampaign.campaign.runner import run_study


class _Store:
    """A run store holding only the trial times (one untimed)."""

    def __init__(self, times):
        self.times = times

    def read(self, columns):
        assert columns == ["wall_time_s"]
        return pa.table({"wall_time_s": pa.array(self.times, pa.float64())})


def test_the_time_per_trial_of_a_run_is_the_mean_of_its_recorded_trials():
    """The remaining time is count x mean: with nine 1 ms events and one of 100 ms the median
    (1 ms) said a tenth of it (test1_bench: median 0.5 ms, mean 2.3 ms)."""
    times = [0.001] * 9 + [0.1]
    assert status._mean_trial_s(_Store([*times, None])) == pytest.approx(np.mean(times), rel=1e-12)
    assert status._mean_trial_s(_Store([None])) is None


def test_a_run_holding_more_records_than_its_first_design_is_not_complete_before_its_last_one_is(
        study_factory):
    """A run of 8 trials (2 masses x 1 mu x 2 planners x 2 seeds), resumed under --allow-drift with
    3 mu levels (24 trials) and stopped at the first error (mu = 13, fail-fast): its manifest still
    counts the first design's 8 trials and it stores more than that, but the design it now runs is
    not all recorded, so the run is not complete."""
    factors = {"mass_kg": [0.2, 0.4], "mu": [0.1], "planner": ["heuristic", "random"]}
    run_study(study_factory(factors=factors))
    grown = study_factory(factors={**factors, "mu": [0.1, 0.3, 13.0]}, runner={"batch_size": 2})
    assert run_study(grown, allow_drift=True, fail_fast=True).stopped_early
    root = grown.output.root
    stored = sum(pq.read_metadata(p).num_rows for p in (Path(root) / "unit" / "r1" / "records").glob(
        "*.parquet"))
    assert 8 < stored < 2 * 3 * 2 * 2
    info = status.run_status(root, "unit", "r1")
    assert (info["n_trials"], info["n_recorded"]) == (8, stored)
    assert not info["complete"]
