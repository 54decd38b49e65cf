"""Fixtures of the command-line tests: a user's own study directory, a breakable config home, and
finished runs (made once) that a bad-store test damages a copy of, and a mesh to plan on."""

from __future__ import annotations

import shutil
from pathlib import Path

import pytest
import trimesh
from cli_checks import (
    BG,
    KEPT_FIRST,
    KEPT_SURROGATE,
    KEPT_T2,
    KEPT_THEN,
    SMOKE,
    T2,
    filled_records,
    invoke,
)

from graspcampaign.campaign import studyfile

PROJECT = Path(studyfile.project_dirs()[0]).parent


@pytest.fixture
def user_dir(tmp_path, monkeypatch):
    """A directory of the user's own study files on GRASPCAMPAIGN_PATH."""
    folder = tmp_path / "my_studies"
    folder.mkdir()
    monkeypatch.setenv("GRASPCAMPAIGN_PATH", str(folder))
    return folder


@pytest.fixture
def home(tmp_path, monkeypatch):
    """A GRASPCAMPAIGN_HOME copy of conf/ and campaigns/ whose files a test may break."""
    root = tmp_path / "home"
    shutil.copytree(PROJECT / "conf", root / "conf")
    shutil.copytree(PROJECT / "campaigns", root / "campaigns")
    monkeypatch.setenv("GRASPCAMPAIGN_HOME", str(root))
    studyfile.project_dirs.cache_clear()
    yield root
    studyfile.project_dirs.cache_clear()


@pytest.fixture(scope="session")
def finished(tmp_path_factory):
    """A results root with a finished tiny baseline_grid run and a smoke run, both reported."""
    root = tmp_path_factory.mktemp("bad_stores") / "results"
    for args in (["run", "baseline_grid", *BG], ["run", "smoke", *SMOKE], ["report"]):
        done = invoke(*args, "--root", root)
        assert done.exit_code == 0, done.output
    return root


@pytest.fixture
def results(finished, tmp_path):
    """A copy of the finished results root this test may damage."""
    return Path(shutil.copytree(finished, tmp_path / "results"))


@pytest.fixture
def sphere(tmp_path):
    """A valid mesh file to plan on (40 mm sphere)."""
    path = tmp_path / "sphere.stl"
    trimesh.creation.icosphere(subdivisions=2, radius=40.0).export(path)
    return path


@pytest.fixture
def stored(results, tmp_path):
    """``results`` with a measured Test 2 run holding two trials: a refused ingest must leave
    them as they are."""
    filled_records(tmp_path, rows=slice(0, 2)).to_csv(tmp_path / "day1.csv", index=False)
    done = invoke("ingest", "test2_grasp", tmp_path / "day1.csv", *T2, "--root", results)
    assert done.exit_code == 0, done.output
    return results


@pytest.fixture(scope="session")
def kept(tmp_path_factory):
    """A results root with finished test2_grasp (belief_none traces), surrogate (summary tables)
    and baseline_grid runs (a preparation per body; candidates traces in two files: the first
    session's two shards compacted, the second session's one shard), each reported."""
    root = tmp_path_factory.mktemp("lost_parts") / "results"
    for args in (["run", "test2_grasp", *KEPT_T2], ["run", "surrogate", *KEPT_SURROGATE],
                 ["run", "baseline_grid", *KEPT_FIRST],
                 ["run", "baseline_grid", *KEPT_THEN, "--allow-drift"],
                 ["report"]):
        done = invoke(*args, "runner.progress=false", "--root", root) if args[0] == "run" else \
            invoke(*args, "--root", root)
        assert done.exit_code == 0, done.output
    return root


@pytest.fixture
def kept_copy(kept, tmp_path):
    """A copy of :func:`kept`'s finished runs this test may damage (tests/cli/test_lost_parts.py,
    test_damaged_round3.py)."""
    return Path(shutil.copytree(kept, tmp_path / "results"))
