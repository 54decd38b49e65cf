"""Shared fixtures."""

from __future__ import annotations

import os
import tempfile

import matplotlib
import pytest

matplotlib.use("Agg")
os.environ.setdefault("MPLBACKEND", "Agg")
# the catalog cache (campaign/catalog.py) of this test process: never the user's ~/.cache
os.environ["GRASPCAMPAIGN_CACHE"] = tempfile.mkdtemp(prefix="graspcampaign-test-cache-")
os.environ.pop("GRASPCAMPAIGN_PATH", None)


@pytest.fixture
def study_factory(tmp_path):
    """Build a StudyCfg for a test kind with results under tmp_path."""
    from graspcampaign.campaign.schema import OutputCfg, RunnerCfg, StudyCfg

    def make(kind="test_pi", factors=None, seeds=2, backend="sequential", n_jobs=1, **kw):
        return StudyCfg(
            name=kw.pop("name", "unit"), kind=kind, seed=kw.pop("seed", 7), seeds=seeds,
            factors=factors if factors is not None else {"mass_kg": [0.2, 0.4], "mu": [0.1, 0.3],
                                                         "planner": ["heuristic", "random"]},
            runner=RunnerCfg(backend=backend, n_jobs=n_jobs, progress=False, **kw.pop("runner", {})),
            output=OutputCfg(root=str(tmp_path / "results"), run="r1"),
            **kw,
        )

    return make
