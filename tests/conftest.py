"""Shared fixtures."""

from __future__ import annotations

import os

import matplotlib
import pytest

matplotlib.use("Agg")
os.environ.setdefault("MPLBACKEND", "Agg")


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


@pytest.fixture(scope="session")
def surrogate_scenarios():
    """A factory of ``surrogate`` records whose outcomes are known functions of the inputs."""
    import numpy as np
    import pandas as pd

    def make(n: int = 400, seed: int = 3) -> pd.DataFrame:
        rng = np.random.default_rng(seed)
        df = pd.DataFrame({
            "status": "ok", "shape": rng.choice(["sphere", "pear"], n),
            "mass_kg": rng.uniform(0.1, 0.8, n), "mu": rng.uniform(0.05, 0.6, n),
            "lambda1": rng.uniform(0.05, 1.5, n), "lambda2": rng.uniform(0.05, 1.5, n),
            "msd_b": rng.uniform(0.1, 2.0, n), "n_exp": 0.487, "pso_n_evaluations": 25,
            "pso_time_s": rng.uniform(0.04, 0.06, n)})
        df["success"] = df["success_unbounded"] = df["mass_kg"] < 0.3
        df["success_vertical"] = df["mu"] > 0.3
        df["residual_norm_n"] = 10 ** (3 * df["mass_kg"])
        df["abs_residual_z_n"] = df["mass_kg"] * 9.81
        df["delta_max_mm"] = 10 ** (1.5 - df["lambda1"])
        return df

    return make


@pytest.fixture(scope="session")
def surrogate_finalize():
    """Run the surrogate kind's finalize stage on records; its tables as DataFrames."""
    from types import SimpleNamespace

    import pandas as pd

    from graspcampaign.campaign.kinds.surrogate import SurrogateParams, finalize

    def run(df):
        tables = finalize(SimpleNamespace(seed=5), SurrogateParams(shapes=["sphere", "pear"]), df)
        return {k: pd.DataFrame(v) for k, v in tables.items()}

    return run
