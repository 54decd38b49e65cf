"""Shared fixtures."""

from __future__ import annotations

import hashlib
import os
import tempfile

# One BLAS thread per test process, set before numpy loads OpenBLAS: `make test` runs one pytest
# worker per core, and OpenBLAS's own thread per core on top made the workers' threads spin
# against each other (a 486 x 486 eigvalsh 24x slower on a busy 2-core machine). The studies
# keep their own rule (joblib's loky workers limit their BLAS threads) (docs/decisions.md, "One
# BLAS thread per test process").
for _var in ("OPENBLAS_NUM_THREADS", "OMP_NUM_THREADS", "MKL_NUM_THREADS"):
    os.environ.setdefault(_var, "1")

import matplotlib  # noqa: E402
import pytest  # noqa: E402
from hypothesis import settings  # noqa: E402

# CI (.ci/run sets HYPOTHESIS_PROFILE=ci) draws the same examples on every landing, so a change
# lands or not on its own merits; local runs keep drawing new ones, which is how a case the
# properties miss is found (then pinned with @example) (docs/decisions.md, "Property tests in CI").
settings.register_profile("ci", derandomize=True)
if os.environ.get("HYPOTHESIS_PROFILE"):
    settings.load_profile(os.environ["HYPOTHESIS_PROFILE"])

matplotlib.use("Agg")
os.environ.setdefault("MPLBACKEND", "Agg")
# The catalog cache (campaign/catalog.py) of the test runs of this checkout, never the user's
# ~/.cache: shared by the xdist workers and kept between runs, which is safe because its facts
# are keyed by the hash of the package's source (tests of the cache itself use their own dirs).
_CHECKOUT = hashlib.sha256(os.path.abspath(__file__).encode()).hexdigest()[:10]
os.environ["GRASPCAMPAIGN_CACHE"] = os.path.join(tempfile.gettempdir(),
                                                 f"graspcampaign-test-catalog-{_CHECKOUT}")
os.environ.pop("GRASPCAMPAIGN_PATH", None)

#: xdist scope of every test module that uses the session fixture ``sim_root``
SIM_ROOT_SCOPE = "sim_root"


@pytest.hookimpl(tryfirst=True)  # before `-m "not slow"` deselects
def pytest_collection_modifyitems(config, items):
    """Mark ``slow`` every test on ``sim_root`` (tests/report/conftest.py: every study run
    reduced and reported, ~50 s of one worker before its first test): these end-to-end checks
    run in `make test-slow` (CI, after `make test`) and `make test-full`; `make test` keeps the
    unit and per-study report checks (docs/decisions.md, "The fast suite under 90 s")."""
    for item in items:
        if "sim_root" in getattr(item, "fixturenames", ()):
            item.add_marker(pytest.mark.slow)


def pytest_xdist_make_scheduler(config, log):
    """Schedule ``pytest -n auto --dist loadscope`` (Makefile ``test-slow``, ``test-full``) with one
    scope more.

    As with plain ``loadscope``, a module's tests run on one worker, so its module fixtures are
    built once; in addition every module that names ``sim_root`` (the reduced results tree of
    tests/report/conftest.py, the most expensive fixture) joins one scope, so that tree is built
    once per test session instead of once on each worker that runs such a module; that scope is
    handed out first (the other scopes follow xdist's order, most tests first), so the longest
    chain of work starts at once. (``--dist loadgroup`` with ``xdist_group`` marks would say the
    same, but pytest-xdist 3.8 cannot tag the node ids of pytest 9 and then schedules test by
    test.) Other ``--dist`` modes are left to xdist.
    """
    if config.getvalue("dist") != "loadscope":
        return None
    from xdist.scheduler import LoadScopeScheduling

    tests = config.rootpath / "tests"
    shared = {path.relative_to(config.rootpath).as_posix() for path in tests.rglob("test_*.py")
              if "sim_root" in path.read_text()}

    class SharedTreeScheduling(LoadScopeScheduling):
        def _split_scope(self, nodeid: str) -> str:
            module = nodeid.split("::")[0]
            return SIM_ROOT_SCOPE if module in shared else super()._split_scope(nodeid)

        def _assign_work_unit(self, node) -> None:
            if SIM_ROOT_SCOPE in self.workqueue:  # first: the longest scope, ~1/3 of the suite
                self.workqueue.move_to_end(SIM_ROOT_SCOPE, last=False)
            super()._assign_work_unit(node)

    return SharedTreeScheduling(config, log)


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
def study_run(tmp_path_factory):
    """Run a study once per test session (per xdist worker) and share the finished run.

    ``study_run(name, *overrides)`` composes ``name`` with ``overrides`` under a results root of
    its own (sequential backend, no progress output) and returns ``(root, RunSummary)``; the same
    arguments give the same run. A test must not change the run it gets; writing other runs beside
    it (another ``output.run``, an ingested ``measured`` run) is fine.
    """
    from graspcampaign.campaign.compose import compose_study
    from graspcampaign.campaign.runner import run_study

    done: dict[tuple, tuple] = {}

    def get(name: str, *overrides: str):
        key = (name, overrides)
        if key not in done:
            root = tmp_path_factory.mktemp(f"shared-{name}")
            study = compose_study(name, ["runner.backend=sequential", "runner.progress=false",
                                         f"output.root={root}", *overrides])
            done[key] = root, run_study(study)
        return done[key]

    return get


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
    from graspcampaign.campaign.schema import RunnerCfg

    def run(df, n_jobs: int = 1, **params):
        study = SimpleNamespace(seed=5, runner=RunnerCfg(backend="loky", n_jobs=n_jobs))
        tables = finalize(study, SurrogateParams(shapes=["sphere", "pear"], **params), df)
        return {k: pd.DataFrame(v) for k, v in tables.items()}

    return run


@pytest.fixture
def past_the_tick(monkeypatch):
    """A process that has verified no file yet (an empty cache), every read of which comes long
    past the clock tick of the file's last change (a file read within it is read again)."""
    from graspcampaign.campaign import verify

    monkeypatch.setattr(verify, "_VERIFIED", {})
    monkeypatch.setattr(verify, "TICK_NS", {True: -10**12, False: -10**12})


@pytest.fixture
def opened(monkeypatch, past_the_tick):
    """Count every opening of a Parquet file (by path relative to the results root) from here on
    (:func:`past_the_tick`: a file read within the tick of its last change is read again)."""
    import collections
    from pathlib import Path

    import pyarrow.parquet as pq

    counts: collections.Counter = collections.Counter()

    def counting(real):
        def opening(source, *args, **kwargs):
            name = getattr(source, "name", source)  # a path, or the file opened to read it
            counts[Path(name).as_posix().split("/results/")[-1]] += 1
            return real(source, *args, **kwargs)
        return opening

    for name in ("ParquetFile", "read_schema", "read_table"):
        monkeypatch.setattr(pq, name, counting(getattr(pq, name)))
    return counts
