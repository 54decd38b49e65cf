"""Fixtures of the rig tests: one reduced Test 1 virtual-bench run, shared by the modules of
graspcampaign.rig.test1's tests."""

from __future__ import annotations

import pytest
from test1_seed import SEED

from graspcampaign.rig import test1 as T


@pytest.fixture(scope="session")
def reduced():
    """A reduced schedule (specimen 1 of each family, all three environments, all five blocks:
    1,624 events, about 5 s) and its virtual-bench run."""
    schedule = T.test1_schedule(SEED, specimens=[1])
    return schedule, T.run_virtual_bench(schedule, SEED)
