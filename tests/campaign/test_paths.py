"""campaign/paths.py: ``write_file`` writes a file whole or not at all, as a write in place would
have left it otherwise (its permissions, a symbolic link to it), whoever else writes it meanwhile.

The rest of the module (results roots, output places, run names) is exercised through the commands
in tests/cli (test_bad_places.py, test_bad_input_round8.py).
"""

from __future__ import annotations

import errno
import os
import stat

import pytest

from graspcampaign.campaign import paths
from graspcampaign.campaign.paths import write_file
from graspcampaign.errors import UserInputError


@pytest.fixture
def umask_022():
    """A known umask, so that a mode kept is told from the one a new file gets (0o644)."""
    old = os.umask(0o022)
    yield
    os.umask(old)


@pytest.mark.parametrize("mode", [0o600, 0o664], ids=oct)
def test_a_file_written_over_keeps_its_permissions(tmp_path, umask_022, mode):
    path = tmp_path / "report.md"
    path.write_text("before")
    path.chmod(mode)
    write_file(path, "after")
    assert path.read_text() == "after"
    assert stat.S_IMODE(path.stat().st_mode) == mode


def test_a_new_file_gets_the_umasks_permissions(tmp_path, umask_022):
    write_file(tmp_path / "report.md", b"new")
    assert stat.S_IMODE((tmp_path / "report.md").stat().st_mode) == 0o644


def test_a_symbolic_link_written_through_stays_a_link(tmp_path):
    (tmp_path / "kept").mkdir()
    target, link = tmp_path / "kept" / "headline.md", tmp_path / "headline.md"
    target.write_text("before")
    link.symlink_to(target)
    write_file(link, "after")
    assert link.is_symlink() and os.readlink(link) == str(target)
    assert target.read_text() == "after"
    assert sorted(p.name for p in tmp_path.rglob("*")) == ["headline.md", "headline.md", "kept"]


def test_two_writers_of_one_file_never_take_each_others_temporary_file(tmp_path, monkeypatch):
    """Another process writes the file while this one is between writing its temporary file and
    moving it in place: each moves its own, the last one's stays, and nothing is left beside it."""
    path, replace, others = tmp_path / "index.md", os.replace, []

    def meanwhile(src, dst):
        if not others:  # the other writer, a process of another id, runs its whole write here
            others.append(1)
            monkeypatch.setattr(paths.os, "getpid", lambda: 1)
            write_file(path, "theirs")
            monkeypatch.undo()
            monkeypatch.setattr(paths.os, "replace", meanwhile)
        replace(src, dst)

    monkeypatch.setattr(paths.os, "replace", meanwhile)
    write_file(path, "ours")
    assert path.read_text() == "ours"
    assert [p.name for p in tmp_path.iterdir()] == ["index.md"]


def test_a_write_stopped_midway_leaves_the_file_as_it_was_and_nothing_beside_it(tmp_path, monkeypatch):
    """A full disk when the file is moved in place: the file keeps its old content, no temporary
    file stays behind, and the error names the file the write was for (not the temporary one)."""
    path = tmp_path / "report.md"
    path.write_text("before")

    def disk_full(src, dst):
        raise OSError(errno.ENOSPC, os.strerror(errno.ENOSPC), str(src))

    monkeypatch.setattr(paths.os, "replace", disk_full)
    with pytest.raises(OSError) as stopped:
        write_file(path, "after")
    assert (stopped.value.errno, stopped.value.filename) == (errno.ENOSPC, str(path))
    assert path.read_text() == "before"
    assert [p.name for p in tmp_path.iterdir()] == ["report.md"]


def test_a_directory_where_the_file_belongs_is_named_and_left_alone(tmp_path):
    (tmp_path / "report.md" / "inside").mkdir(parents=True)
    with pytest.raises(UserInputError) as refused:
        write_file(tmp_path / "report.md", "text")
    assert str(refused.value) == (f"{tmp_path / 'report.md'} is a directory where this command writes "
                                  "a file; move it aside and run the command again.")
    assert [p.name for p in tmp_path.rglob("*")] == ["report.md", "inside"]


def test_a_regular_file_or_a_link_to_one_is_a_file_to_read(tmp_path):
    """``input_file_problem`` finds nothing wrong with a file to read, given as itself or through a
    symbolic link (it asks :func:`path_problem`, whose checks a link to a file must pass)."""
    (tmp_path / "day1.csv").write_text("trial_id\n")
    (tmp_path / "link.csv").symlink_to(tmp_path / "day1.csv")
    assert [paths.input_file_problem(tmp_path / name) for name in ("day1.csv", "link.csv")] == [None, None]
    assert paths.input_file_problem(tmp_path) == "is a directory, not a file"
    assert paths.input_file_problem(tmp_path / "none.csv") == "does not exist"
