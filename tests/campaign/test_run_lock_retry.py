"""The run lock's retry (``runner.run_lock``): a lock file its holder removed after this process
opened it is no lock, so the run opens the file there now; a lock directory removed meanwhile is
made again; anything else the file system says is not retried.

Another process is imitated by wrapping ``fcntl.flock`` (it removes the lock file just before this
process locks the one it opened, as a holder ending then does) or ``os.open``; whether the run then
holds the lock of the file at ``<run>/.lock`` is asked of the operating system, by a second
descriptor of that path trying to lock it (flock(2): locks of two open file descriptions conflict).
"""

from __future__ import annotations

import errno
import fcntl
import os

import pytest

from graspcampaign.campaign import runner
from graspcampaign.campaign.records import RunStore
from graspcampaign.campaign.runner import run_lock
from graspcampaign.errors import UserInputError


def _removing_first(times: int):
    """An ``fcntl.flock`` before which the lock file's holder removes it, the first ``times`` times."""
    flock, removed = fcntl.flock, []

    def flock_after_removal(fd, operation):
        if len(removed) < times and operation & fcntl.LOCK_EX:
            removed.append(fd)
            os.unlink(os.readlink(f"/proc/self/fd/{fd}"))
        return flock(fd, operation)

    return flock_after_removal, removed


def _locked_by_another(path) -> bool:
    """Whether a new open file description of ``path`` is refused its exclusive lock."""
    fd = os.open(path, os.O_RDWR)
    try:
        fcntl.flock(fd, fcntl.LOCK_EX | fcntl.LOCK_NB)
    except BlockingIOError:
        return True
    finally:
        os.close(fd)
    return False


def _open_descriptors() -> set[str]:
    return set(os.listdir("/proc/self/fd"))


@pytest.mark.skipif(not os.path.isdir("/proc/self/fd"), reason="reads /proc/self/fd")
def test_a_lock_file_removed_after_it_was_opened_is_opened_again_and_held(tmp_path, monkeypatch):
    flock, removed = _removing_first(2)
    monkeypatch.setattr(fcntl, "flock", flock)
    store, before = RunStore(tmp_path / "study" / "run"), _open_descriptors()
    with run_lock(store, "study/run"):
        assert len(removed) == 2  # two files removed under it, the third one held
        assert _locked_by_another(store.path / ".lock")
    monkeypatch.undo()
    assert not (store.path / ".lock").exists()
    assert _open_descriptors() == before  # the two descriptors of removed files were closed too


@pytest.mark.skipif(not os.path.isdir("/proc/self/fd"), reason="reads /proc/self/fd")
def test_a_lock_file_removed_every_time_is_refused_after_the_attempts(tmp_path, monkeypatch):
    flock, removed = _removing_first(10**6)
    monkeypatch.setattr(fcntl, "flock", flock)
    store, before = RunStore(tmp_path / "study" / "run"), _open_descriptors()
    with pytest.raises(UserInputError) as refused, run_lock(store, "study/run"):
        pytest.fail("the run went on without its lock")
    assert str(refused.value) == (f"run study/run at {store.path}: its lock file was removed "
                                  f"{len(removed)} times while this run opened it; run it from one "
                                  "process at a time.")
    assert len(removed) > 1 and _open_descriptors() == before
    assert not (tmp_path / "study").exists()  # the directories it made, removed again


def test_a_lock_directory_removed_meanwhile_is_made_again(tmp_path, monkeypatch):
    opened, real_open = [], os.open

    def open_after_removal(path, *args):  # the other run, refused, removed the run's directories
        if str(path).endswith(".lock") and not opened:
            opened.append(path)
            os.rmdir(os.path.dirname(path))
        return real_open(path, *args)

    monkeypatch.setattr(runner.os, "open", open_after_removal)
    store = RunStore(tmp_path / "run")
    with run_lock(store, "study/run"):
        assert opened and _locked_by_another(store.path / ".lock")


def test_a_lock_file_that_cannot_be_opened_is_not_retried(tmp_path, monkeypatch):
    """Only a file or directory removed meanwhile is tried again: a lock file this process may not
    open (root passes permission bits, so the refusal is imitated) says so at once."""
    calls = []

    def denied(path, *args):
        calls.append(path)
        raise PermissionError(errno.EACCES, os.strerror(errno.EACCES), str(path))

    (tmp_path / "run").mkdir()  # a new run's folder is probed for a write before: the lock's open
    monkeypatch.setattr(runner.os, "open", denied)
    with pytest.raises(PermissionError, match="Permission denied"), \
            run_lock(RunStore(tmp_path / "run"), "study/run"):
        pytest.fail("the run went on without its lock")
    assert len(calls) == 1
