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
    3 mu levels (24 trials) and stopped at the first error (mu = 13, fail-fast): it stores more
    than the first design's 8 trials, but the design it now runs (24) is not all recorded, so the
    run is neither complete nor finished (the first session's finish no longer stands)."""
    factors = {"mass_kg": [0.2, 0.4], "mu": [0.1], "planner": ["heuristic", "random"]}
    run_study(study_factory(factors=factors))
    grown = study_factory(factors={**factors, "mu": [0.1, 0.3, 13.0]}, runner={"batch_size": 2})
    assert run_study(grown, allow_drift=True, fail_fast=True).stopped_early
    root = grown.output.root
    stored = _stored(root)
    assert 8 < stored < 2 * 3 * 2 * 2
    info = status.run_status(root, "unit", "r1")
    assert (info["n_trials"], info["n_recorded"]) == (2 * 3 * 2 * 2, stored)
    assert not info["complete"] and info["finished_at"] is None


def test_a_drifted_design_that_left_the_first_designs_trials_out_is_complete_once_its_own_are(
        study_factory):
    """8 trials at mu = 0.1 (2 seeds), then under --allow-drift 8 trials at mu = 13 and 0.3 with
    one seed (no trial of the first design): stopped at its first error the run stores more
    records than its design counts and is not complete; run to its end (mu = 13 recorded as
    errors) it stores 16 records of an 8-trial design and is complete, as its last session
    recorded every trial of its design."""
    factors = {"mass_kg": [0.2, 0.4], "mu": [0.1], "planner": ["heuristic", "random"]}
    run_study(study_factory(factors=factors))
    moved = study_factory(factors={**factors, "mu": [13.0, 0.3]}, seeds=1, runner={"batch_size": 2})
    assert run_study(moved, allow_drift=True, fail_fast=True).stopped_early
    root = moved.output.root
    info = status.run_status(root, "unit", "r1")
    assert info["n_trials"] == 8 < info["n_recorded"] == _stored(root) < 16
    assert not info["complete"] and info["finished_at"] is None
    assert not run_study(moved, allow_drift=True).stopped_early
    info = status.run_status(root, "unit", "r1")
    assert (info["n_trials"], info["n_recorded"], info["n_error"]) == (8, 16, 4)
    assert info["complete"] and info["finished_at"] is not None


def _stored(root) -> int:
    """The records stored under the run unit/r1 of ``root``, counted from the Parquet files."""
    return sum(pq.read_metadata(p).num_rows for p in (Path(root) / "unit" / "r1" / "records").glob(
        "*.parquet"))


def test_status_reads_the_store_through_its_public_methods_only():
    """``run_status`` read ``store._read`` and ``store._source``, private to RunStore: a change
    there broke status unseen. Every attribute status reads of a store is public."""
    import ast

    tree = ast.parse(Path(status.__file__).read_text())
    private = sorted({f"{node.value.id}.{node.attr}" for node in ast.walk(tree)
                      if isinstance(node, ast.Attribute) and isinstance(node.value, ast.Name)
                      and node.value.id == "store" and node.attr.startswith("_")})
    assert private == []
