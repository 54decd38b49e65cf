"""A stored file is read in full and hashed once per process while it is unchanged (path, inode,
size, mtime, ctime); a file changed since it was verified is verified again."""

from __future__ import annotations

import collections
import os
import time
from pathlib import Path

import kinds_for_tests  # noqa: F401  (registers the test kinds)
import pyarrow as pa
import pyarrow.parquet as pq
import pytest
from damage import corrupt_value_column

from graspcampaign.campaign import verify
from graspcampaign.campaign.integrity import check_run
from graspcampaign.campaign.records import RunStore
from graspcampaign.campaign.runner import run_study
from graspcampaign.errors import DamagedRunError


@pytest.fixture
def opened(monkeypatch):
    """Count every opening of a Parquet file (by path relative to the results root) from here on,
    in a process that has verified no file yet (an empty cache)."""
    counts: collections.Counter = collections.Counter()
    monkeypatch.setattr(verify, "_VERIFIED", {})

    def counting(real):
        def opening(source, *args, **kwargs):
            counts[Path(source).as_posix().split("/results/")[-1]] += 1
            return real(source, *args, **kwargs)
        return opening

    for name in ("ParquetFile", "read_schema", "read_table"):
        monkeypatch.setattr(pq, name, counting(getattr(pq, name)))
    return counts


def _stored(run: Path) -> dict[str, int]:
    root = run.parent.parent
    return {p.relative_to(root).as_posix(): 1 for p in run.rglob("*.parquet")}


def _trace_study(study_factory):
    return study_factory(kind="test_pi_trace", runner={"batch_size": 4})  # 4 shards per part


def test_a_new_run_reads_each_file_it_wrote_once(study_factory, opened):
    summary = run_study(_trace_study(study_factory))
    assert sum("/part-" in name for name in opened) == 8  # 4 shards of each part, to compact them
    assert _stored(summary.path).keys() <= opened.keys()  # the compacted files, by the last check
    assert set(opened.values()) == {1}, opened


def test_checking_a_run_reads_each_file_once_and_its_ids_need_no_read(study_factory, opened):
    summary = run_study(_trace_study(study_factory))
    verify._VERIFIED.clear()  # a new process
    opened.clear()
    store = RunStore(summary.path)
    assert check_run(store) is not None
    assert opened == _stored(summary.path)
    opened.clear()
    assert len(store.recorded_ids()) == 16 and not opened


def test_resuming_a_finished_run_reads_each_file_once(study_factory, opened):
    study = _trace_study(study_factory)
    summary = run_study(study)
    verify._VERIFIED.clear()  # a new process
    opened.clear()
    assert run_study(study).n_ran == 0
    assert opened == _stored(summary.path)


def test_writing_a_shard_reads_no_footer_of_a_verified_compacted_file(tmp_path, opened):
    store = RunStore(tmp_path / "results" / "unit" / "r1")
    for name in "ab":
        store.write_shard("records", name, [{"trial_id": f"{name}1"}])
    store.compact()
    assert store.recorded_ids() == {"a1", "b1"}
    opened.clear()
    for name in "cde":
        store.write_shard("records", name, [{"trial_id": f"{name}1"}])
    assert not opened


def _verified_shard(tmp_path) -> tuple[RunStore, Path]:
    store = RunStore(tmp_path / "results" / "unit" / "r1")
    path = store.write_shard("records", "a", [{"trial_id": f"a{i}", "x": 0.5 * i} for i in range(20)])
    assert len(store.read()) == 20  # verified and cached
    return store, path


def test_a_file_damaged_in_place_after_it_was_verified_is_verified_again(tmp_path):
    store, path = _verified_shard(tmp_path)
    before = path.stat()
    corrupt_value_column(path, "x")  # same size
    os.utime(path, ns=(before.st_atime_ns, before.st_mtime_ns + 10**9))  # a new mtime
    assert path.stat().st_size == before.st_size
    with pytest.raises(DamagedRunError, match="CRC checksum verification failed"):
        store.read()


def test_a_file_damaged_at_its_old_size_and_mtime_is_verified_again(tmp_path):
    store, path = _verified_shard(tmp_path)
    before = path.stat()
    time.sleep(0.05)  # past the file system's clock tick: the damage gets a new ctime
    corrupt_value_column(path, "x")
    os.utime(path, ns=(before.st_atime_ns, before.st_mtime_ns))  # only the ctime tells
    assert (path.stat().st_size, path.stat().st_mtime_ns) == (before.st_size, before.st_mtime_ns)
    with pytest.raises(DamagedRunError, match="CRC checksum verification failed"):
        store.read()


def test_a_file_rewritten_after_it_was_verified_is_verified_again_at_its_old_mtime(tmp_path):
    store, path = _verified_shard(tmp_path)
    before = path.stat()
    table = pq.read_table(path)  # one more row under the digest stored for the 20 written
    pq.write_table(pa.concat_tables([table, table.slice(0, 1)]), path)
    os.utime(path, ns=(before.st_atime_ns, before.st_mtime_ns))  # the size tells
    assert path.stat().st_size != before.st_size
    with pytest.raises(DamagedRunError, match="its values differ from those written"):
        store.read()
