"""A stored file is read in full and hashed once per process while it is unchanged (path, inode,
size, mtime, ctime); a file changed since it was verified is verified again."""

from __future__ import annotations

import os
import shutil
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
def within_the_tick(monkeypatch):
    """A process whose file system clock ticks once a test: every read is within the tick."""
    monkeypatch.setattr(verify, "_VERIFIED", {})
    monkeypatch.setattr(verify, "TICK_NS", {True: 10**12, False: 10**12})


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



def test_checking_files_too_new_to_remember_asks_each_files_facts_once(study_factory, opened,
                                                                         monkeypatch):
    # as the run's last check finds its freshly compacted files: none is remembered past the
    # check, but within it every question asked of a file (superseding what? damaged? whose
    # records? which trials?) is answered from one read (was 9 records and 5 trace reads, then
    # 6 and 4)
    summary = run_study(_trace_study(study_factory))
    monkeypatch.setattr(verify, "_VERIFIED", {})
    monkeypatch.setattr(verify, "TICK_NS", {True: 10**12, False: 10**12})  # every read within it
    opened.clear()
    assert check_run(RunStore(summary.path)) is not None
    assert opened.keys() == _stored(summary.path).keys()
    assert {name.split("/")[2]: n for name, n in opened.items()} == {"records": 1, "tables": 1}

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


def test_a_file_damaged_in_place_after_it_was_verified_is_verified_again(tmp_path, past_the_tick):
    store, path = _verified_shard(tmp_path)
    before = path.stat()
    corrupt_value_column(path, "x")  # same size
    os.utime(path, ns=(before.st_atime_ns, before.st_mtime_ns + 10**9))  # a new mtime
    assert path.stat().st_size == before.st_size
    with pytest.raises(DamagedRunError, match="CRC checksum verification failed"):
        store.read()


def test_a_file_damaged_at_its_old_size_and_mtime_is_verified_again(tmp_path, past_the_tick):
    store, path = _verified_shard(tmp_path)
    before = path.stat()
    time.sleep(0.05)  # past the file system's clock tick: the damage gets a new ctime
    corrupt_value_column(path, "x")
    os.utime(path, ns=(before.st_atime_ns, before.st_mtime_ns))  # only the ctime tells
    assert (path.stat().st_size, path.stat().st_mtime_ns) == (before.st_size, before.st_mtime_ns)
    with pytest.raises(DamagedRunError, match="CRC checksum verification failed"):
        store.read()


def test_a_file_rewritten_after_it_was_verified_is_verified_again_at_its_old_mtime(tmp_path, past_the_tick):
    store, path = _verified_shard(tmp_path)
    before = path.stat()
    table = pq.read_table(path)  # one more row under the digest stored for the 20 written
    pq.write_table(pa.concat_tables([table, table.slice(0, 1)]), path)
    os.utime(path, ns=(before.st_atime_ns, before.st_mtime_ns))  # the size tells
    assert path.stat().st_size != before.st_size
    with pytest.raises(DamagedRunError, match="its values differ from those written"):
        store.read()


def _keeping_its_key(path: Path, change) -> None:
    """Make ``change`` to ``path`` as if it left the file's key (inode, size, mtime, ctime) as
    this process knows it: a same-size rewrite within one tick of a coarse clock, simulated (here
    the change gets a new ctime, so the key this process holds, if any, is moved to it)."""
    change()
    name = os.path.abspath(path)
    if name in verify._VERIFIED:
        verify._VERIFIED[name] = (verify._key(os.stat(path)), verify._VERIFIED[name][1])


def _same_size_new_values(path: Path) -> None:
    """Rewrite ``path`` with other values in column x, under the digest of the old ones."""
    table = pq.read_table(path)
    changed = table.set_column(table.schema.get_field_index("x"), "x",
                               pa.array([99.0] * len(table))).replace_schema_metadata(
        table.schema.metadata)
    pq.write_table(changed, path, compression="zstd", write_page_checksum=True)


@pytest.mark.parametrize("rewrite", ["compact", "drop rows"])
def test_values_changed_under_an_unchanged_key_never_get_a_digest_of_their_own(
        tmp_path, past_the_tick, rewrite):
    """Compaction and row removal write what they read under a new digest: they verify the file
    again, whatever the key says (a column read trusts the key; a rewrite would launder)."""
    store = RunStore(tmp_path / "results" / "unit" / "r1")
    a = store.write_shard("records", "a", [{"trial_id": f"a{i}", "x": 0.5 * i} for i in range(5)])
    store.write_shard("records", "b", [{"trial_id": f"b{i}", "x": 0.5 * i} for i in range(5)])
    assert len(store.read()) == 10  # verified and remembered
    _keeping_its_key(a, lambda: _same_size_new_values(a))
    before = {p.name: p.read_bytes() for p in a.parent.iterdir()}
    with pytest.raises(DamagedRunError, match="its values differ from those written"):
        store.compact() if rewrite == "compact" else store.drop_rows("records", {"a0"})
    assert {p.name: p.read_bytes() for p in a.parent.iterdir()} == before  # nothing written
    with pytest.raises(DamagedRunError, match="its values differ from those written"):
        store.read()  # nor is the file trusted any longer
    verify._VERIFIED.clear()  # a new process
    assert verify.verify_file(a).startswith("its values differ from those written")


def test_a_file_changed_within_the_clock_tick_of_its_verification_is_verified_again(
        tmp_path, within_the_tick):
    store, path = _verified_shard(tmp_path)  # not remembered: verified within the tick
    _keeping_its_key(path, lambda: _same_size_new_values(path))
    with pytest.raises(DamagedRunError, match="its values differ from those written"):
        store.read()


def test_a_file_replaced_while_it_is_read_is_read_as_the_version_it_was_known_by(
        tmp_path, past_the_tick, monkeypatch):
    store, path = _verified_shard(tmp_path)
    replacement = path.with_name("other.parquet")
    shutil.copy(path, replacement)
    _same_size_new_values(replacement)
    real = pq.ParquetFile

    def replaced_then_read(source, *args, **kwargs):  # an os.replace just before the read
        if replacement.exists():
            os.replace(replacement, path)
        return real(source, *args, **kwargs)

    monkeypatch.setattr(pq, "ParquetFile", replaced_then_read)
    assert store.read().column("x").to_pylist() == [0.5 * i for i in range(20)]  # not 99.0
    with pytest.raises(DamagedRunError, match="its values differ from those written"):
        store.read()  # the file now at its path: another inode, verified


def test_each_path_keeps_only_the_version_last_verified(tmp_path, past_the_tick):
    store = RunStore(tmp_path / "results" / "unit" / "r1")
    for k in range(3):  # the same shard rewritten (replaced) three times, each read back
        store.write_shard("records", "a", [{"trial_id": f"a{i}", "x": k} for i in range(4)])
        assert store.read().column("x").to_pylist() == [k] * 4
    assert list(verify._VERIFIED) == [os.path.abspath(store.path / "records" / "part-a.parquet")]


def test_status_reads_only_the_status_column_of_a_checked_run(study_factory, past_the_tick,
                                                               monkeypatch):
    # the records' source comes from the facts the run's check kept of each file (was read
    # again as a column)
    from graspcampaign.campaign import records
    from graspcampaign.campaign.status import run_status

    summary = run_study(study_factory())
    asked = []
    monkeypatch.setattr(records, "read_file", lambda path, columns=None, **kw: (
        asked.append(columns), verify.read_file(path, columns, **kw))[1])
    status = run_status(summary.path.parent.parent, "unit", "r1")
    assert (status["source"], status["n_recorded"]) == ("simulation", 16)
    assert asked == [["status"]]


def test_status_lists_the_records_once_after_the_runs_check(study_factory, monkeypatch):
    # was twice: reading the statuses and asking the records' source each listed the files
    from graspcampaign.campaign import status

    summary = run_study(study_factory())
    listed, listing, opening = [], RunStore.listing, status.open_run
    monkeypatch.setattr(RunStore, "listing", lambda self, part: (
        listed.append(part), listing(self, part))[1])
    monkeypatch.setattr(status, "open_run", lambda *args: (opening(*args), listed.clear())[0])
    got = status.run_status(summary.path.parent.parent, "unit", "r1")
    assert (got["source"], got["n_recorded"], got["n_ok"]) == ("simulation", 16, 16)
    assert listed == ["records"]


def test_removing_rows_reads_a_file_not_yet_verified_once(tmp_path, opened):
    # its verifying read is the table rewritten (was read once to verify it, again to rewrite it)
    store = RunStore(tmp_path / "results" / "unit" / "r1")
    store.write_shard("records", "a", [{"trial_id": f"a{i}"} for i in range(3)])
    store.write_shard("records", "b", [{"trial_id": "b1"}])
    store.drop_rows("records", {"a1"})
    assert opened == {"unit/r1/records/part-a.parquet": 1, "unit/r1/records/part-b.parquet": 1}
    assert store.recorded_ids() == {"a0", "a2", "b1"}


def test_a_session_asks_a_compacted_file_too_new_to_remember_once(study_factory, opened,
                                                                 monkeypatch):
    # each task's write_shard asks what the compacted files supersede; the session writes within
    # one check (was once a task: verified in full each time, being too new to be remembered)
    one = {"batch_size": 1}
    run_study(study_factory(factors={"mass_kg": [0.2], "mu": [0.1, 0.3],
                                     "planner": ["heuristic", "random"]}, runner=one), run="r")
    monkeypatch.setattr(verify, "_VERIFIED", {})  # a new process
    monkeypatch.setattr(verify, "TICK_NS", {True: 10**12, False: 10**12})  # every read within it
    asked, write = [], RunStore.write_shard

    def counting(self, *args, **kwargs):
        before = sum(n for name, n in opened.items() if "/compact-" in name)
        path = write(self, *args, **kwargs)
        asked.append(sum(n for name, n in opened.items() if "/compact-" in name) - before)
        return path

    monkeypatch.setattr(RunStore, "write_shard", counting)
    resumed = run_study(study_factory(runner=one), run="r", allow_drift=True)
    assert resumed.n_ran == len(asked) == 8
    assert asked[0] >= 1 and sum(asked[1:]) == 0, asked


def test_a_null_and_a_zero_have_different_digests():
    """Nulls are in the digest's mask, their slots read 0: [null, 1] and [0, 1] are other values."""
    assert verify.content_digest(pa.table({"n": pa.array([None, 1], pa.int64())})) != \
        verify.content_digest(pa.table({"n": pa.array([0, 1], pa.int64())}))


def test_the_facts_count_missing_ids_and_name_a_malformed_one(tmp_path):
    """A trial id is a key, "-", then 10 hex digits (grid.expand): one with 8 is malformed."""
    path = tmp_path / "r.parquet"
    pq.write_table(pa.table({"trial_id": ["a-0123456789", None, "b-01234567", None]}), path)
    facts = verify.facts(path)
    assert (facts.n_rows, facts.n_null_ids, facts.bad_id) == (4, 2, "b-01234567")


def test_a_reason_is_cut_only_past_120_characters():
    assert verify.reason(ValueError("x" * 120)) == "x" * 120
    assert verify.reason(ValueError("x" * 121)) == "x" * 117 + "..."


def _other_values_same_size(path: Path) -> bytes:
    """``path``'s table with other values in column x under the digest of the old ones, written as
    the store writes (zstd, page checksums: every page reads as sound): its first m values 99 and
    one more metadata entry, padded, for the first m and padding that give the old size."""
    import io
    from itertools import product

    import numpy as np

    table = pq.read_table(path)
    x = table.column("x").to_numpy()

    def written(m: int, pad: int) -> bytes:
        values = pa.array(np.where(np.arange(len(x)) < m, 99.0, x))
        changed = table.set_column(table.schema.get_field_index("x"), "x", values)
        out = io.BytesIO()
        pq.write_table(changed.replace_schema_metadata({**table.schema.metadata, b"pad": b"p" * pad}),
                       out, compression="zstd", write_page_checksum=True)
        return out.getvalue()

    same = next((data for data in (written(m, pad) for m, pad in product(range(1, len(x) + 1), range(40)))
                 if len(data) == path.stat().st_size), None)
    if same is None:  # the encoder of another pyarrow release may give no such rewrite
        pytest.skip(f"pyarrow {pa.__version__} writes no same-size rewrite in this search")
    return same


def test_a_file_rewritten_in_place_at_its_old_size_and_mtime_is_known_by_its_ctime(tmp_path,
                                                                                    past_the_tick):
    """Same inode, same size, mtime set back with os.utime, every page checksum sound: only the
    ctime, which no call sets back, says the file changed, and its values then differ from the
    digest stored with them."""
    store, path = _verified_shard(tmp_path)
    before = path.stat()
    data = _other_values_same_size(path)
    time.sleep(0.05)  # past the file system's clock tick: the rewrite gets a new ctime
    with open(path, "r+b") as handle:
        handle.write(data)
    os.utime(path, ns=(before.st_atime_ns, before.st_mtime_ns))
    after = path.stat()
    assert (after.st_ino, after.st_size, after.st_mtime_ns) == (before.st_ino, before.st_size,
                                                                before.st_mtime_ns)
    assert after.st_ctime_ns != before.st_ctime_ns
    assert pq.read_table(path).column("x").to_pylist() != [0.5 * i for i in range(20)]  # sound pages
    with pytest.raises(DamagedRunError, match="its values differ from those written"):
        store.read()


@pytest.mark.parametrize("read_after_s, remembered", [(1.5, False), (2.5, True)])
def test_a_file_with_whole_second_times_is_remembered_two_seconds_after_its_change(
        tmp_path, monkeypatch, read_after_s, remembered):
    """FAT keeps a file's mtime in 2 s steps (Microsoft's FAT specification: the write time's
    seconds field counts 2 s units): a change stamped at a whole second T may have happened up to
    T + 2 s, so a read 1.5 s after T may precede a change the same stamp hides, and is not
    remembered; 2.5 s after it is."""
    from types import SimpleNamespace

    monkeypatch.setattr(verify, "_VERIFIED", {})
    path = RunStore(tmp_path / "results" / "unit" / "r1").write_shard(
        "records", "a", [{"trial_id": f"a{i}", "x": 0.5 * i} for i in range(3)])
    stamp = 1_700_000_000 * 10**9  # a whole second
    monkeypatch.setattr(verify, "_key", lambda stat: (stat.st_ino, stat.st_size, stamp, stamp))
    monkeypatch.setattr(verify, "time", SimpleNamespace(
        time_ns=lambda: stamp + int(read_after_s * 10**9)))
    verify.read_file(path)
    assert (verify.cached(path) is not None) == remembered
