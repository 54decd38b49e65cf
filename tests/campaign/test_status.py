"""Tests of campaign/status.py beyond the command line's: the time a run's own records give."""

from __future__ import annotations

import numpy as np
import pyarrow as pa
import pytest

from graspcampaign.campaign import status


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
