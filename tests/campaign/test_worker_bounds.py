"""``schema.check_workers``: the bounds of ``runner.n_jobs`` on a machine of a known core count.

joblib reads a negative ``n_jobs`` as ``cores + 1 + n_jobs`` workers (its documentation: -1 every
core, -2 all but one), so on 8 cores -8 is one worker and -9 would be none (joblib then silently
runs one); the upper bound is 4 workers per core (docs/decisions.md), 32 on 8 cores. The numbers
below are worked out by hand for 8 cores, not read from the code.
"""

from __future__ import annotations

import os

import pytest

from graspcampaign.campaign.schema import RunnerCfg, check_workers
from graspcampaign.errors import ConfigError


@pytest.fixture
def eight_cores(monkeypatch):
    monkeypatch.setattr(os, "cpu_count", lambda: 8)


@pytest.mark.parametrize("n_jobs", [-8, -1, 1, 32])
def test_every_n_jobs_from_one_worker_to_four_per_core_is_accepted(eight_cores, n_jobs):
    check_workers(RunnerCfg(backend="loky", n_jobs=n_jobs))


def test_one_core_more_than_the_machine_has_left_unused_is_refused(eight_cores):
    with pytest.raises(ConfigError, match=r"^runner\.n_jobs = -9 would leave 8 cores unused, and "
                                          r"this machine has 8; give a number of worker processes "
                                          r"\(1 to 32\), or -1 for one per core down to -8 for one "
                                          r"worker\.$"):
        check_workers(RunnerCfg(backend="loky", n_jobs=-9))


def test_one_worker_more_than_four_per_core_is_refused(eight_cores):
    with pytest.raises(ConfigError, match=r"^runner\.n_jobs = 33 would start 33 worker processes, "
                                          r"more than 4 per core of this machine \(8 cores\)"):
        check_workers(RunnerCfg(backend="dask", n_jobs=33))


@pytest.mark.parametrize("runner", [RunnerCfg(backend="sequential", n_jobs=-1_000_000),
                                    RunnerCfg(backend="dask", n_jobs=-1_000_000, address="tcp://h:8786"),
                                    RunnerCfg(backend="dask", n_jobs=1_000, address="tcp://h:8786")],
                         ids=["sequential", "remote-negative", "remote-many"])
def test_n_jobs_is_not_bounded_where_it_starts_no_local_worker(eight_cores, runner):
    """A sequential run reads no n_jobs; a remote Dask cluster has the workers it has."""
    check_workers(runner)


def test_a_machine_whose_cores_are_unknown_is_named_as_the_one_core_the_bound_counts(monkeypatch):
    """os.cpu_count() is None where the count cannot be found; the bound then counts one core
    (4 workers), and the sentence names that one core, not 'None cores'."""
    monkeypatch.setattr(os, "cpu_count", lambda: None)
    with pytest.raises(ConfigError, match=r"^runner\.n_jobs = 5 would start 5 worker processes, "
                                          r"more than 4 per core of this machine \(1 core\); .* "
                                          r"give at most 4, or -1 for one per core\.$"):
        check_workers(RunnerCfg(backend="loky", n_jobs=5))
