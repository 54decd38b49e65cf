"""The record store's edges that decide what is stored and read (mutation testing, round 7).

Each test checks a consequence read back by pyarrow or through the store's own reading: a shard
is read once, a compacted file keeps what it supersedes and the configs of its shards, a rewrite
keeps its last row, a removed trial is gone, a written file reached the disk before its name.
"""

from __future__ import annotations

import json
import os
import shutil

import kinds_for_tests  # noqa: F401  (registers the test kinds)
import pyarrow as pa
import pyarrow.parquet as pq
import pytest
from damage import as_written, corrupt_value_column

from graspcampaign.campaign import records, verify
from graspcampaign.campaign.paths import run_path
from graspcampaign.campaign.records import RunStore, config_metadata
from graspcampaign.campaign.runner import run_study
from graspcampaign.campaign.verify import CONFIG_KEY, SOURCES_KEY
from graspcampaign.errors import DamagedRunError


def _ids(store: RunStore, part: str = "records") -> list:
    """Every stored trial id of ``part``, one per row (a trial read twice appears twice)."""
    return sorted(store.read(part).column("trial_id").to_pylist(), key=str)


def _compacted(store: RunStore, part: str = "records"):
    files = sorted((store.path / part).glob("compact-*.parquet"))
    assert len(files) == 1, files
    return files[0]


def test_a_shard_named_after_two_superseded_shards_is_read(tmp_path):
    """``write_shard`` skips every name a compacted file lists (part-aaaaaaaaaa and
    part-aaaaaaaaaa-1 here), not only the first: a shard under a superseded name is ignored as a
    compaction's leftover."""
    store = RunStore(tmp_path / "run")
    store.write_shard("records", "aaaaaaaaaa", [{"trial_id": "a"}])
    store.write_shard("records", "bbbbbbbbbb", [{"trial_id": "b"}])
    store.compact()  # supersedes part-aaaaaaaaaa, part-bbbbbbbbbb
    assert store.write_shard("records", "aaaaaaaaaa", [{"trial_id": "c"}]).name == "part-aaaaaaaaaa-1.parquet"
    store.write_shard("records", "dddddddddd", [{"trial_id": "d"}])
    store.compact()  # a second compacted file supersedes part-aaaaaaaaaa-1, part-dddddddddd
    path = store.write_shard("records", "aaaaaaaaaa", [{"trial_id": "e"}])
    assert path.name == "part-aaaaaaaaaa-2.parquet"
    assert _ids(store) == ["a", "b", "c", "d", "e"]


def test_a_shard_duplicating_part_of_a_compacted_file_is_the_one_moved_aside(tmp_path):
    """Of two files recording one trial the compacted file is the earlier one and stays: the shard
    is moved aside and every trial of the compacted file stays recorded, none runs again."""
    store = RunStore(tmp_path / "run")
    store.write_shard("records", "0000000000", [{"trial_id": "a"}, {"trial_id": "b"}])
    store.write_shard("records", "1111111111", [{"trial_id": "c"}])
    store.compact()
    store.write_shard("records", "2222222222", [{"trial_id": "a"}])
    with pytest.warns(UserWarning, match=r"duplicate file .*part-2222222222\.parquet moved to"):
        moved = store.repair()
    assert [path.name for path, _, _ in moved] == ["part-2222222222.parquet"]
    assert _ids(store) == ["a", "b", "c"]


def test_a_rewritten_compacted_file_still_supersedes_its_shards(tmp_path):
    """Removing rows from a compacted file writes a file that supersedes it and the shards it
    superseded: a shard a crash left behind stays unread (each trial read once)."""
    store = RunStore(tmp_path / "run")
    left = store.write_shard("records", "0000000000", [{"trial_id": "a"}, {"trial_id": "b"}])
    kept = left.read_bytes()
    store.write_shard("records", "1111111111", [{"trial_id": "c"}])
    store.compact()
    left.write_bytes(kept)  # a crash between writing the compacted file and removing its sources
    assert _ids(store) == ["a", "b", "c"]
    store.drop_rows("records", {"c"})
    written = json.loads(pq.read_schema(_compacted(store)).metadata[SOURCES_KEY])
    assert "part-0000000000.parquet" in written
    assert _ids(store) == ["a", "b"]


def test_removing_rows_keeps_a_single_remaining_row(tmp_path):
    store = RunStore(tmp_path / "run")
    store.write_shard("records", "0000000000", [{"trial_id": "a"}, {"trial_id": "b"}])
    store.drop_rows("records", {"b"})
    assert _ids(store) == ["a"]


def test_removing_every_row_of_a_file_removes_its_trials(tmp_path):
    store = RunStore(tmp_path / "run")
    store.write_shard("records", "0000000000", [{"trial_id": "a"}, {"trial_id": "b"}])
    store.write_shard("records", "1111111111", [{"trial_id": "c"}])
    store.drop_rows("records", {"a", "b"})
    assert _ids(store) == ["c"]
    assert not (store.path / "records" / "part-0000000000.parquet").exists()


def test_keeping_the_rows_of_recorded_trials_drops_rows_without_a_trial_id(tmp_path):
    """A trace table's rows without a trial id belong to no recorded trial: keeping the rows of
    the recorded trials drops them, even from a file whose ids are all recorded."""
    store = RunStore(tmp_path / "run")
    store.write_shard("tables/trace", "0000000000", [{"trial_id": "a", "v": 1.0},
                                                     {"trial_id": None, "v": 2.0}])
    store.keep_rows("tables/trace", {"a"})
    table = pq.read_table(_compacted(store, "tables/trace"))
    assert table.column("trial_id").to_pylist() == ["a"]
    assert table.column("v").to_pylist() == [1.0]


def test_a_compacted_file_names_the_configs_of_its_shards(tmp_path):
    """What pyarrow reads in the compacted file's metadata: both sessions' configs, so that a
    shard of another config stays recognisable after compaction."""
    store = RunStore(tmp_path / "run")
    store.write_shard("records", "0000000000", [{"trial_id": "a"}], metadata=config_metadata("h2"))
    store.write_shard("records", "1111111111", [{"trial_id": "b"}], metadata=config_metadata("h1"))
    store.compact()
    meta = pq.read_schema(_compacted(store)).metadata
    assert json.loads(meta[CONFIG_KEY]) == ["h1", "h2"]


def test_a_file_rewritten_without_some_rows_keeps_its_config(tmp_path):
    store = RunStore(tmp_path / "run")
    store.write_shard("records", "0000000000", [{"trial_id": "a"}, {"trial_id": "b"}],
                      metadata=config_metadata("h1"))
    store.drop_rows("records", {"b"})
    assert json.loads(pq.read_schema(_compacted(store)).metadata[CONFIG_KEY]) == ["h1"]


def test_cleaning_keeps_a_compacted_file_whose_footer_cannot_be_read(tmp_path):
    """``clean`` removes temporary and superseded files only: a compacted file it cannot read
    supersedes nothing it knows, and is evidence for the repair, never deleted."""
    store = RunStore(tmp_path / "run")
    store.write_shard("records", "0000000000", [{"trial_id": "a"}])
    bad = store.path / "records" / "compact-0123456789.parquet"
    bad.write_bytes(b"not a parquet file")
    (store.path / "records" / ".part-1111111111.parquet.tmp").write_bytes(b"half")
    store.clean()
    assert sorted(p.name for p in (store.path / "records").iterdir()) == [
        "compact-0123456789.parquet", "part-0000000000.parquet"]


def test_a_damaged_compacted_file_still_supersedes_its_shards(tmp_path):
    """A compacted file whose values are damaged but whose footer reads still names its sources:
    a leftover source shard is not live beside it (the damage is the one problem counted)."""
    store = RunStore(tmp_path / "run")
    left = store.write_shard("records", "0000000000", [{"trial_id": f"a{i}", "v": 0.5 * i}
                                                       for i in range(20)])
    kept = left.read_bytes()
    store.write_shard("records", "1111111111", [{"trial_id": "b", "v": 1.0}])
    store.compact()
    compacted = _compacted(store)
    corrupt_value_column(compacted, "v")
    left.write_bytes(kept)
    assert [p.name for p, _ in store.damaged("records")] == [compacted.name]
    assert store.listing("records")[0] == [compacted]


def test_a_shard_reaches_the_disk_before_it_gets_its_name(tmp_path, monkeypatch):
    """The temporary file is synced before it is renamed into place: a power cut after the rename
    never leaves a named shard whose pages were not written (the rename itself is atomic)."""
    events = []
    fsync, replace = os.fsync, os.replace

    def synced(fd):
        events.append(("fsync", os.path.basename(os.readlink(f"/proc/self/fd/{fd}"))))
        return fsync(fd)

    def renamed(src, dst):
        events.append(("replace", os.path.basename(src)))
        return replace(src, dst)

    monkeypatch.setattr(records.os, "fsync", synced)
    monkeypatch.setattr(records.os, "replace", renamed)
    RunStore(tmp_path / "run").write_shard("records", "0000000000", [{"trial_id": "a"}])
    assert events == [("fsync", ".part-0000000000.parquet.tmp"), ("replace", ".part-0000000000.parquet.tmp")]


def test_the_first_malformed_trial_id_in_row_order_is_named(tmp_path):
    path = RunStore(tmp_path / "run").write_shard("records", "0000000000", [
        {"trial_id": "zz bad"}, {"trial_id": "a-0123456789"}, {"trial_id": "aa bad"}])
    assert verify.facts(path).bad_id == "zz bad"


@pytest.mark.parametrize("wrong", ["a-0123456789abcdef", "a-0123456789.parquet", "a-0123456789\n"])
def test_a_trial_id_with_anything_after_its_ten_hex_digits_is_malformed(tmp_path, wrong):
    """An id ends in '-' and exactly ten hex digits (``grid.expand``)."""
    path = RunStore(tmp_path / "run").write_shard("records", "0000000000", [
        {"trial_id": "a-0123456789"}, {"trial_id": wrong}])
    assert verify.facts(path).bad_id == wrong


def test_the_facts_of_a_file_replaced_after_it_was_verified_are_its_new_ones(tmp_path, past_the_tick):
    store = RunStore(tmp_path / "run")
    path = store.write_shard("records", "0000000000", [{"trial_id": "a"}])
    assert verify.facts(path).ids == {"a"}
    assert verify.cached(path) is not None  # remembered: past the tick
    store.write_shard("records", "0000000000", [{"trial_id": "b"}, {"trial_id": "c"}])  # same name
    assert verify.cached(path) is None
    assert verify.facts(path).ids == {"b", "c"}


def test_a_file_that_changed_while_it_was_read_is_not_remembered(tmp_path, monkeypatch):
    """Within one check a file is read once while its key holds; one whose key changed during the
    read (a writer still at it) is read again when next asked, not trusted as first read."""
    path = RunStore(tmp_path / "run").write_shard("records", "0000000000", [{"trial_id": "a"}])
    monkeypatch.setattr(verify, "_VERIFIED", {})
    calls, fstat = [], os.fstat

    def moving(fd):  # the second look at the open file sees it written to: later mtime and ctime
        calls.append(fd)
        st = fstat(fd)
        if len(calls) % 2:
            return st
        fields = list(st)
        fields[8] += 1  # st_mtime, st_ctime (whole seconds), which the key's ns fields follow
        fields[9] += 1
        return os.stat_result(fields, {"st_mtime_ns": st.st_mtime_ns + 10**9,
                                       "st_ctime_ns": st.st_ctime_ns + 10**9})

    monkeypatch.setattr(verify.os, "fstat", moving)
    with verify.one_check():
        verify.facts(path)
        assert verify.cached(path) is None


# -- a run checked against its manifest (campaign.integrity) -------------------------------------
def test_a_file_whose_name_only_begins_like_a_shard_is_no_shard(finished):
    _, store, compact = finished
    shutil.copy(compact, store.path / "records" / "part-0000000000.parquet.bak")
    with pytest.raises(DamagedRunError, match=r"has a file records/part-0000000000\.parquet\.bak that is "
                                              "not a Parquet shard of the run"):
        store.check()


def test_one_trial_recorded_twice_in_one_file_is_found(finished):
    _, store, compact = finished
    table = pq.read_table(compact)
    as_written(pa.concat_tables([table, table.slice(3, 1)]), compact)
    with pytest.raises(DamagedRunError, match=f"a file records/{compact.name} that records 1 "
                                              "trial twice"):
        store.check()


def test_an_unfinished_run_storing_one_trial_more_than_its_design_is_refused(finished):
    _, store, compact = finished
    manifest = json.loads(store.manifest_path.read_text())
    store.manifest_path.write_text(json.dumps({**manifest, "finished_at": None}))
    table = pq.read_table(compact)
    extra = table.slice(0, 1).set_column(0, "trial_id", pa.array(["extra-0123456789"]))
    assert table.column_names[0] == "trial_id"
    as_written(extra.replace_schema_metadata(table.schema.metadata),
                store.path / "records" / "part-eeeeeeeeee.parquet")
    with pytest.raises(DamagedRunError, match=r"n_trials is 16, but it stores 17 trials of its one "
                                              "config"):
        store.check()


def test_shards_live_again_after_a_compacted_file_moves_aside_are_checked_too(tmp_path):
    """A damaged compacted file is moved aside; the shards it superseded (a crash left them) are
    live again and checked in turn: a damaged one moves aside too, an intact one is read."""
    store = RunStore(tmp_path / "run")
    x = store.write_shard("records", "0000000000", [{"trial_id": f"a{i}", "v": 0.5 * i} for i in range(20)])
    y = store.write_shard("records", "1111111111", [{"trial_id": "b", "v": 1.0}])
    kept = {x: x.read_bytes(), y: y.read_bytes()}
    store.compact()
    corrupt_value_column(_compacted(store), "v")
    for path, data in kept.items():
        path.write_bytes(data)
    corrupt_value_column(x, "v")
    compacted = _compacted(store).name
    with pytest.warns(UserWarning, match="damaged file"):
        moved = store.repair()
    assert sorted(path.name for path, _, _ in moved) == sorted([compacted, "part-0000000000.parquet"])
    assert _ids(store) == ["b"]


def test_a_trace_file_of_no_task_runs_again_only_the_trials_without_other_traces(tmp_path):
    """An unreadable trace file with no records file of its name: its trials are the recorded ones
    without a row in the table's other files; only their records are dropped to run again."""
    store = RunStore(tmp_path / "run")
    store.write_shard("records", "0000000000", [{"trial_id": "a"}, {"trial_id": "b"}])
    store.write_shard("records", "1111111111", [{"trial_id": "c"}, {"trial_id": "d"}])
    store.write_shard("tables/trace", "1111111111", [{"trial_id": "c", "v": 1.0},
                                                     {"trial_id": "d", "v": 2.0}])
    (store.path / "tables" / "trace" / "part-3333333333.parquet").write_bytes(b"not a parquet file")
    with pytest.warns(UserWarning, match="part-3333333333.parquet moved to"):
        store.repair()
    assert _ids(store) == ["c", "d"]
    assert _ids(store, "tables/trace") == ["c", "d"]


def test_a_run_resumed_under_another_config_holds_its_sessions_records(study_factory):
    """The records a session of another config wrote (``--allow-drift``) are the run's own: a
    check of the run afterwards, as status and report make, names no foreign file."""
    run_study(study_factory())
    run_study(study_factory(seeds=3), allow_drift=True)
    store = RunStore(run_path(study_factory()))
    manifest = store.check()
    assert len({s["config_hash"] for s in manifest["sessions"]}) == 2
    assert len(store.recorded_ids()) == 24


def test_an_exact_duplicate_trace_file_drops_no_record(tmp_path):
    """A trace file duplicating another moves aside; its trials' traces stay in the other file,
    so their records stay and nothing runs again."""
    store = RunStore(tmp_path / "run")
    store.write_shard("records", "0000000000", [{"trial_id": "a"}, {"trial_id": "b"}])
    rows = [{"trial_id": "a", "v": 1.0}, {"trial_id": "b", "v": 2.0}]
    store.write_shard("tables/trace", "0000000000", rows)
    store.write_shard("tables/trace", "2222222222", rows)
    with pytest.warns(UserWarning, match=r"duplicate file .*part-2222222222\.parquet moved to"):
        store.repair()
    assert _ids(store) == ["a", "b"]
    assert _ids(store, "tables/trace") == ["a", "b"]
