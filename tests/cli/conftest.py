"""Fixtures of the command-line tests: a user's own study directory and a breakable config home."""

from __future__ import annotations

import shutil
from pathlib import Path

import pytest

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
