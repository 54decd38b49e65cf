"""The run lock (``runner.run_lock``) where file systems differ: NFS, which emulates ``flock`` with
byte-range locks that need a descriptor open for writing, and a file system without locks.

The file systems are imitated by wrapping ``fcntl.flock`` with what flock(2) documents for them.
"""

from __future__ import annotations

import errno
import fcntl
import os

import kinds_for_tests  # noqa: F401  (registers the test kinds)
import pyarrow.parquet as pq
import pytest

from graspcampaign.campaign.paths import held_by_a_run, run_path
from graspcampaign.campaign.records import RunStore
from graspcampaign.campaign.runner import run_lock, run_study
from graspcampaign.errors import UserInputError


def test_the_lock_is_held_on_a_descriptor_open_for_writing_as_nfs_needs(tmp_path, monkeypatch):
    flock = fcntl.flock

    def nfs_flock(fd, operation):  # flock(2): an exclusive lock over NFS needs O_WRONLY or O_RDWR
        if operation & fcntl.LOCK_EX and fcntl.fcntl(fd, fcntl.F_GETFL) & os.O_ACCMODE == os.O_RDONLY:
            raise OSError(errno.EBADF, os.strerror(errno.EBADF))
        return flock(fd, operation)

    monkeypatch.setattr(fcntl, "flock", nfs_flock)
    store = RunStore(tmp_path / "study" / "run")
    with run_lock(store, "study/run"):
        (store.path / "manifest.json").write_text("{}")
    assert (store.path / "manifest.json").is_file()


def test_a_file_system_without_locks_is_warned_of_and_the_run_goes_on(study_factory, monkeypatch):
    def no_locks(fd, operation):
        raise OSError(errno.ENOLCK, os.strerror(errno.ENOLCK))

    monkeypatch.setattr(fcntl, "flock", no_locks)
    study = study_factory()
    lock = run_path(study) / ".lock"
    with pytest.warns(UserWarning, match=rf"^run unit/r1: {lock} cannot be locked on its file "
                                         r"system \(No locks available\); run it from one process"):
        summary = run_study(study)
    stored = pq.read_table(run_path(study) / "records", columns=["trial_id"]).num_rows
    assert summary.n_ran == stored == 16


def test_a_run_refused_under_the_lock_leaves_no_directory_behind(tmp_path):
    store = RunStore(tmp_path / "new" / "study" / "run")
    with pytest.raises(RuntimeError), run_lock(store, "study/run"):
        raise RuntimeError("refused")
    assert not (tmp_path / "new").exists()


def test_a_held_run_is_refused_before_its_dask_scheduler_is_awaited(study_factory):
    """A second run of a held run was refused only after its backend came up (a LocalCluster
    started, or a scheduler awaited up to connect_timeout_s); the lock is now taken first."""
    study = study_factory(backend="dask", runner={"address": "tcp://127.0.0.1:9",  # nothing listens
                                                  "connect_timeout_s": 0.5})
    store = RunStore(run_path(study))
    with run_lock(store, "held"), pytest.raises(UserInputError, match=r"^run unit/r1 at .* is "
                                                                      r"being run by another process"):
        run_study(study)
    assert not (store.path / "manifest.json").exists()


def test_a_held_run_is_seen_held_and_the_probe_takes_nothing(tmp_path):
    """``paths.held_by_a_run`` (what ``report`` asks): no run directory or lock file is not held;
    a run whose lock another holder has is, and the probe neither keeps a lock nor makes a file."""
    store = RunStore(tmp_path / "study" / "run")
    assert not held_by_a_run(store.path)
    with run_lock(store, "study/run"):
        assert held_by_a_run(store.path) and held_by_a_run(store.path)
    assert not (tmp_path / "study").exists()  # the lock's holder removed what it made
    store.path.mkdir(parents=True)
    (store.path / ".lock").touch()  # left by a holder that died: the system let its lock go
    assert not held_by_a_run(store.path)
    with run_lock(store, "study/run"):  # the probe kept no lock: the run is taken at once
        pass


def test_a_run_starting_while_a_status_probes_it_is_not_refused(tmp_path):
    """``held_by_a_run`` (``status``, ``report``) holds the lock file shared for an instant; a run
    taking the run then was refused as "being run by another process". The probe's hold is
    stretched here to 50 ms, by a shared lock taken as it takes one and let go by a timer."""
    import threading

    store = RunStore(tmp_path / "study" / "run")
    store.path.mkdir(parents=True)
    probe = os.open(store.path / ".lock", os.O_RDONLY | os.O_CREAT, 0o644)
    fcntl.flock(probe, fcntl.LOCK_SH | fcntl.LOCK_NB)  # as held_by_a_run does
    threading.Timer(0.05, os.close, (probe,)).start()  # the probe lets go
    with run_lock(store, "study/run"):
        assert held_by_a_run(store.path)


def test_a_run_held_by_another_run_is_still_refused_within_the_probe_grace(tmp_path):
    store = RunStore(tmp_path / "study" / "run")
    with run_lock(store, "study/run"), pytest.raises(UserInputError, match=r"^run again at .* is "
                                                                           r"being run by another"):
        with run_lock(store, "again"):
            pass
