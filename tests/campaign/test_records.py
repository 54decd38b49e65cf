"""Record store: atomic shards, quarantine, compaction leftovers, schema union, outside readers."""

from __future__ import annotations

import shlex

import kinds_for_tests  # noqa: F401
import pandas as pd
import pyarrow.dataset as ds
import pytest
from damage import corrupt_value_column

from graspcampaign.campaign.records import RunStore, table_from_rows
from graspcampaign.campaign.runner import run_study
from graspcampaign.errors import DamagedRunError


def test_schema_union_keeps_columns_added_later(tmp_path):
    store = RunStore(tmp_path / "run")
    store.write_shard("records", "aaaaaaaaaa", [{"trial_id": "a", "x": 1.0}])
    store.write_shard("records", "bbbbbbbbbb", [{"trial_id": "b", "x": None, "y": "new"}])
    df = store.read().to_pandas().sort_values("trial_id")
    assert df["y"].isna().tolist() == [True, False] and df["y"].iloc[1] == "new"
    assert df["x"].iloc[0] == 1.0


def test_truncated_shard_is_quarantined_with_warning(tmp_path):
    store = RunStore(tmp_path / "run")
    store.write_shard("records", "aaaaaaaaaa", [{"trial_id": "a", "x": 1.0}])
    path = store.write_shard("records", "bbbbbbbbbb", [{"trial_id": "b", "x": 2.0}])
    data = path.read_bytes()
    path.write_bytes(data[: len(data) // 2])
    with pytest.warns(UserWarning, match="damaged file .*part-bbbbbbbbbb.parquet moved to"):
        moved = store.repair()
    assert [(m[0].name, m[1].name) for m in moved] == [("part-bbbbbbbbbb.parquet",
                                                         "records__part-bbbbbbbbbb.parquet")]
    assert store.recorded_ids() == {"a"}
    assert (tmp_path / "run" / "quarantine" / "records__part-bbbbbbbbbb.parquet").exists()


def _two_shards(tmp_path):
    store = RunStore(tmp_path / "results" / "unit" / "r1")
    store.write_shard("records", "aaaaaaaaaa", [{"trial_id": "a", "residual_norm_n": 0.25}])
    rows = [{"trial_id": f"b{i}", "residual_norm_n": 0.1 * i, "status": "ok"} for i in range(20)]
    path = store.write_shard("records", "bbbbbbbbbb", rows)
    return store, path


def test_advice_for_a_damaged_run_is_a_command_a_shell_runs_as_given(tmp_path):
    """The resume command names a results root with a space as one argument (was split in two)."""
    store = RunStore(tmp_path / "my results" / "unit" / "r1")
    path = store.write_shard("records", "bbbbbbbbbb", [{"trial_id": "b", "residual_norm_n": 0.5}])
    corrupt_value_column(path, "residual_norm_n")
    with pytest.raises(DamagedRunError) as info:
        store.read()
    advised = str(info.value).split("resume the run (", 1)[1].split(") to ", 1)[0]
    assert shlex.split(advised) == ["graspcampaign", "run", "unit", "--run", "r1", "--root",
                                    str(tmp_path / "my results")]


def test_damaged_value_column_is_refused_on_read_and_nothing_moves(tmp_path):
    store, path = _two_shards(tmp_path)
    corrupt_value_column(path, "residual_norm_n")
    message = (f"run unit/r1 at {store.path} has a damaged file records/part-bbbbbbbbbb.parquet "
               "(could not verify page integrity, CRC checksum verification failed for page_ordinal "
               "0); resume the run (graspcampaign run unit --run r1 --root "
               f"{tmp_path / 'results'}) to quarantine the file and run its trials again.")
    for read in (store.recorded_ids, store.read, store.verify,
                 lambda: store.read(columns=["trial_id"])):
        with pytest.raises(DamagedRunError) as info:
            read()
        assert str(info.value) == message
    assert path.exists() and not (store.path / "quarantine").exists()


def test_compaction_never_reads_an_unverified_shard(tmp_path):
    store, path = _two_shards(tmp_path)
    corrupt_value_column(path, "residual_norm_n")
    with pytest.raises(DamagedRunError, match="has a damaged file records/part-bbbbbbbbbb.parquet"):
        store.compact()
    assert sorted(p.name for p in (store.path / "records").iterdir()) == [
        "part-aaaaaaaaaa.parquet", "part-bbbbbbbbbb.parquet"]


def test_repair_moves_exactly_the_damaged_shard_and_never_overwrites_quarantine(tmp_path):
    store, path = _two_shards(tmp_path)
    kept = path.read_bytes()
    for _ in range(3):
        path.write_bytes(kept)
        corrupt_value_column(path, "residual_norm_n")
        with pytest.warns(UserWarning, match="damaged file"):
            store.repair()
        assert store.recorded_ids() == {"a"}
    names = sorted(p.name for p in (store.path / "quarantine").iterdir())
    assert names == ["records__part-bbbbbbbbbb.parquet", "records__part-bbbbbbbbbb~1.parquet",
                     "records__part-bbbbbbbbbb~2.parquet"]


def test_temporary_files_are_invisible_and_cleaned(tmp_path):
    store = RunStore(tmp_path / "run")
    store.write_shard("records", "aaaaaaaaaa", [{"trial_id": "a"}])
    tmp = tmp_path / "run" / "records" / ".part-bbbbbbbbbb.parquet.tmp"
    tmp.write_bytes(b"half a file")
    assert store.recorded_ids() == {"a"}
    store.clean()
    assert not tmp.exists()


def test_compaction_leftover_sources_are_not_read_twice(tmp_path):
    store = RunStore(tmp_path / "run")
    for name in "abc":
        store.write_shard("records", name, [{"trial_id": name}])
    saved = {p.name: p.read_bytes() for p in (tmp_path / "run" / "records").glob("part-*")}
    store.compact()
    # simulate a crash between writing the compacted file and deleting its sources
    for name, data in saved.items():
        (tmp_path / "run" / "records" / name).write_bytes(data)
    table = store.read()
    assert sorted(table.column("trial_id").to_pylist()) == ["a", "b", "c"]
    store.clean()
    assert not list((tmp_path / "run" / "records").glob("part-*"))


def test_pandas_pyarrow_and_duckdb_read_the_same_records(study_factory):
    duckdb = pytest.importorskip("duckdb")
    summary = run_study(study_factory(runner={"batch_size": 3}))
    ours = RunStore(summary.path).read().to_pandas()
    records_dir = summary.path / "records"
    via_pandas = pd.read_parquet(records_dir)
    via_dataset = ds.dataset(records_dir, format="parquet").to_table().to_pandas()
    via_duckdb = duckdb.sql(
        f"SELECT * FROM read_parquet('{records_dir}/*.parquet', union_by_name=true)"
    ).df()

    def norm(df):
        df = df[sorted(ours.columns)].sort_values("trial_id").reset_index(drop=True)
        # a missing string is NaN in one reader and None in another
        return df.astype(object).map(lambda v: None if v is None or v != v else v)

    for other in (via_pandas, via_dataset, via_duckdb):
        pd.testing.assert_frame_equal(norm(ours), norm(other), check_dtype=False)


def test_a_damaged_measured_run_is_refused_with_the_ingest_advice(tmp_path):
    from graspcampaign.campaign.provenance import write_manifest

    store, path = _two_shards(tmp_path)
    write_manifest(store.manifest_path, {"source": "measured"})
    corrupt_value_column(path, "residual_norm_n")
    with pytest.raises(DamagedRunError) as info:
        store.verify()
    assert str(info.value) == (
        f"run unit/r1 at {store.path} has a damaged file records/part-bbbbbbbbbb.parquet (could not verify "
        "page integrity, CRC checksum verification failed for page_ordinal 0); move it out of the "
        "run directory and ingest the file that held its records again.")



def test_a_damaged_ingested_virtual_run_is_refused_with_the_ingest_advice(tmp_path):
    # a virtual rig's exports are ingested as source = virtual; `run` refuses to add to the run,
    # so its advice is ingest's, never "resume the run"
    from graspcampaign.campaign.provenance import write_manifest

    store, path = _two_shards(tmp_path)
    write_manifest(store.manifest_path, {"source": "virtual",
                                         "sessions": [{"ingested": ["day1.csv"]}]})
    corrupt_value_column(path, "residual_norm_n")
    with pytest.raises(DamagedRunError, match=r"; move it out of the run directory and ingest the "
                       r"file that held its records again\.$"):
        store.verify()

def test_trace_rows_without_a_record_are_dropped_on_repair(tmp_path):
    store = RunStore(tmp_path / "run")
    store.write_shard("records", "aaaaaaaaaa", [{"trial_id": "a"}])
    store.write_shard("tables/trace", "aaaaaaaaaa", [{"trial_id": "a", "step": 0}])
    # a kill between a task's traces and its records leaves traces of an unrecorded trial
    store.write_shard("tables/trace", "bbbbbbbbbb", [{"trial_id": "b", "step": 0},
                                            {"trial_id": "b", "step": 1}])
    assert store.repair() == []
    assert store.read("tables/trace").column("trial_id").to_pylist() == ["a"]


def test_a_rewrite_interrupted_before_the_old_file_goes_counts_no_row_twice(tmp_path):
    store = RunStore(tmp_path / "run")
    for name in "ab":
        store.write_shard("records", name, [{"trial_id": f"{name}1"}, {"trial_id": f"{name}2"}])
    store.compact()
    (compact,) = (tmp_path / "run" / "records").glob("compact-*.parquet")
    saved = compact.read_bytes()
    store.drop_rows("records", {"a2"})  # what repair does for a trial whose traces were lost
    compact.write_bytes(saved)  # a crash before the old file was removed
    assert sorted(store.recorded_ids()) == ["a1", "b1", "b2"]
    store.clean()
    assert not compact.exists() and sorted(store.recorded_ids()) == ["a1", "b1", "b2"]


@pytest.mark.parametrize("first", [float("nan"), True])
def test_a_flag_missing_on_some_rows_is_a_nullable_bool_whatever_comes_first(first):
    """Test 1's ``slipped_measured`` is measured on oblique events only; pandas hands the other
    rows a NaN. Stored, it is a bool column with nulls there (pyarrow refused NaN after a bool,
    and typed the column double when the NaN came first)."""
    other = True if first is not True else float("nan")
    table = table_from_rows([{"trial_id": "a", "slipped_measured": first},
                             {"trial_id": "b", "slipped_measured": False},
                             {"trial_id": "c", "slipped_measured": other, "x_mm": float("nan")}])
    assert str(table.schema.field("slipped_measured").type) == "bool"
    assert table.column("slipped_measured").null_count == 1
    assert str(table.schema.field("x_mm").type) == "double"  # a NaN measurement stays a number


def test_read_with_facts_gives_the_rows_and_the_files_read_with_their_sources(tmp_path):
    """The public read ``status`` answers from (it read the store's private ``_read`` and
    ``_source``): the table ``read`` gives, the live records files with their verified facts, and
    the run's source from those facts (``virtual`` as soon as one record says so, SPEC §4)."""
    import pyarrow.parquet as pq

    store = RunStore(tmp_path / "results" / "unit" / "r1")
    store.write_shard("records", "aaaaaaaaaa", [{"trial_id": "a", "status": "ok", "source": "measured"}])
    store.write_shard("records", "bbbbbbbbbb", [{"trial_id": f"b{i}", "status": "error", "source": "virtual"}
                                                for i in range(3)])
    table, files = store.read_with_facts("records", ["status"])
    on_disk = sorted((store.path / "records").glob("*.parquet"))
    assert sorted(files) == on_disk
    assert sorted(table.column("status").to_pylist()) == sorted(
        s for path in on_disk for s in pq.read_table(path, columns=["status"]).column("status").to_pylist())
    assert [own.ids for own in map(files.get, on_disk)] == [{"a"}, {"b0", "b1", "b2"}]
    manifest = {"source": "measured"}
    assert store.source(manifest, files.values()) == store.source(manifest) == "virtual"
    assert store.source(manifest, [files[on_disk[0]]]) == "measured"  # the facts given, not re-listed
