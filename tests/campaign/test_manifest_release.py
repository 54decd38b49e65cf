"""A run stored by another commit of this release (``provenance._check_not_newer``): read without a
warning. Only a later release warns (tests/cli/test_bad_input_round9.py), and a commit is no
release: the version after ``+`` is the commit, and PEP 440 orders versions by their release
numbers before it.
"""

from __future__ import annotations

import warnings

import pytest

import graspcampaign
from graspcampaign.campaign.provenance import _check_not_newer


@pytest.mark.parametrize("theirs", [f"{graspcampaign.__version__}+0123456789ab", graspcampaign.__version__],
                         ids=["another-commit", "no-commit"])
def test_a_run_of_this_release_is_read_without_a_word(tmp_path, theirs):
    with warnings.catch_warnings():
        warnings.simplefilter("error")
        _check_not_newer(tmp_path / "smoke" / "default", {"code_version": theirs, "format": 1})


def test_a_run_of_the_next_patch_release_is_warned_of(tmp_path):
    major, minor, patch = (int(p) for p in graspcampaign.__version__.split("+")[0].split(".")[:3])
    with pytest.warns(UserWarning, match=rf"^run smoke/default was stored by graspcampaign "
                                         rf"{major}\.{minor}\.{patch + 1}\+0123456789ab, a later release"):
        _check_not_newer(tmp_path / "smoke" / "default",
                         {"code_version": f"{major}.{minor}.{patch + 1}+0123456789ab"})


def test_reading_a_run_of_this_release_asks_git_nothing(tmp_path, monkeypatch):
    """Every manifest read passes the release check (a report reads about a hundred); the commit
    (two git processes) is needed only to name this code in a refusal or warning."""
    from graspcampaign.campaign import provenance

    def no_git():
        raise AssertionError("git_state called to read a manifest of this release")

    monkeypatch.setattr(provenance, "git_state", no_git)
    _check_not_newer(tmp_path / "smoke" / "default",
                     {"code_version": f"{graspcampaign.__version__}+0123456789ab", "format": 1})
