"""Damaged and tampered stored runs, round 2: what a disk, a sync tool or a colleague leaves in a
finished run, and what ``run`` (resume), ``status`` and ``report`` then do. A report never counts
data it cannot trust, and what a repair says it does, it does.

Every case damages its own copy of the finished runs (``results`` in conftest.py).
"""

from __future__ import annotations

import shutil

import pyarrow as pa
import pyarrow.compute as pc
import pyarrow.parquet as pq
import pytest
from cli_checks import BG, grid_run, immutable, invoke, refused, resume_advice, resumed

from graspcampaign.campaign.records import CONTENT_KEY, RunStore, content_digest


def _prepared(results) -> list[dict]:
    """The stored preparations (PSO identifications) of the tiny baseline_grid run, by body,
    without the time each took (a measurement, not a result)."""
    rows = pq.read_table(grid_run(results) / "prepared").to_pylist()
    return sorted(({k: v for k, v in r.items() if k != "wall_time_s"} for r in rows),
                  key=lambda r: r["body_id"])


def test_a_quarantined_preparation_is_computed_again_as_the_warning_says(results):
    """A damaged prepared/ file is moved aside with "it is computed again": it is, for the
    recorded trials' bodies too (it was not: only pending trials' bodies were prepared, so a
    finished run's resume left prepared/ empty, exit 0, and the report dropped the
    identifications table without a word)."""
    before = _prepared(results)
    assert before
    (shard,) = (grid_run(results) / "prepared").glob("*.parquet")
    size = shard.stat().st_size
    with shard.open("r+b") as handle:  # cut short in its middle, as an interrupted copy leaves it
        handle.truncate(size // 2)
    repaired, _ = resumed(results, shard, "it does not end with a Parquet footer: cut short, or not a "
                          "Parquet file", damaged=True, then="it is computed again")
    assert "2 trials, 2 already recorded, 0 ran" in repaired.stdout
    assert _prepared(results) == before  # seeded by the body: the ones the trials used
    assert invoke("report", "baseline_grid", "--root", results).exit_code == 0
    assert (grid_run(results) / "report" / "tables" / "identifications.csv").is_file()


def test_a_file_that_cannot_be_moved_aside_is_refused_in_one_sentence_nothing_copied(results):
    """A file a sync tool left (``desktop.ini``) in a records/ directory, the file immutable: `run`
    says what it could not move and why, exit 2, and leaves no copy in quarantine/ (it copied the
    file there, failed to remove it, and ended in a traceback: the file then stood in both
    places). A records/ directory nothing can be written in is refused before that, as one this
    user may not write (``runner.run_lock``)."""
    records = grid_run(results) / "records"
    stray = records / "desktop.ini"
    stray.write_text("[.ShellClassInfo]\n")
    target = grid_run(results) / "quarantine" / "records__desktop.ini"
    run = ["run", "baseline_grid", *BG, "runner.progress=false", "--root", results]
    with immutable(stray):
        refused(results, run, f"cannot move {stray} to {target} (not a Parquet shard of the run): "
                f"operation not permitted; it stays where it is, so make {records} and "
                f"{target.parent} writable and run the command again.")
    with immutable(records):
        refused(results, run, f"run baseline_grid/default at {grid_run(results)}: {records}: cannot "
                "write there (Operation not permitted); make it writable for this user, or run the "
                "command as the user who owns the run.")


def _as_written(table: pa.Table, target) -> None:
    """Write ``table`` as ``target`` as the tool writes a file: with the digest of its values."""
    digest = {CONTENT_KEY: content_digest(table).encode()}
    pq.write_table(table.replace_schema_metadata({**(table.schema.metadata or {}), **digest}),
                   target, write_page_checksum=True)


def test_a_trial_recorded_twice_with_other_values_is_run_again_not_kept_from_either(results):
    """A colleague's file of the same run, written by the tool, recording one of its trials with
    another verdict: not "a duplicate" whose trials "stay recorded" in the run's file (which kept
    the run's verdict, unchecked, and said the two agreed); neither record is trusted, the trial
    runs again and its record is the one the design's seed gives."""
    records = grid_run(results) / "records"
    (compact,) = records.glob("compact-*.parquet")
    table = pq.read_table(compact)
    first, truth = table["trial_id"][0].as_py(), table["success"][0].as_py()
    flipped = table.slice(0, 1).set_column(table.schema.get_field_index("success"), "success",
                                           pc.invert(table.slice(0, 1)["success"]))
    colleague = records / "part-c0c0c0c0c0.parquet"
    _as_written(flipped, colleague)
    why = f"1 trial also in records/{compact.name} with other values (column success)"
    for args in (["status", "baseline_grid"], ["report", "baseline_grid"]):
        refused(results, [*args, "--root", results],
                f"run baseline_grid/default at {grid_run(results)} has a file "
                f"records/part-c0c0c0c0c0.parquet recording {why}; {resume_advice(results)}")
    kept = colleague.read_bytes()
    repaired, target = resumed(results, colleague, why)
    assert "2 trials, 1 already recorded, 1 ran" in repaired.stdout
    assert target.read_bytes() == kept
    again = RunStore(grid_run(results)).read().to_pandas().set_index("trial_id")
    assert len(again) == 2 and bool(again.loc[first, "success"]) == truth


@pytest.mark.parametrize(("part", "copy"), [
    ("records", "{stem} (conflicted copy 2026-11-30).parquet"),  # Dropbox
    ("tables/candidates", "{stem} (1).parquet"),  # a browser's or Google Drive's second download
    ("records", "{stem}-DESKTOP-7QK3M2L.parquet"),  # OneDrive: "-<computer name>", no space
])
def test_a_sync_tools_copy_of_a_shard_is_moved_aside_not_the_shard(results, part, copy):
    """A byte-identical copy of a shard under a sync tool's name: the copy is moved aside and
    nothing runs again (the run's own file was called the duplicate, its name sorting after the
    copy's, and moved aside, so the run went on from the copy; and a trace table's copy, now moved
    aside, would have run all its trials again although the run's own file holds their traces).
    The warning says only the trials no longer recorded run again (it said "its trials will run
    again" over "0 ran")."""
    (own,) = (grid_run(results) / part).glob("*.parquet")
    kept = own.read_bytes()
    duplicate = own.with_name(copy.format(stem=own.stem))
    duplicate.write_bytes(kept)
    rel = duplicate.relative_to(grid_run(results)).as_posix()
    why = "named as a copy of a shard: not a name the tool writes"
    refused(results, ["report", "baseline_grid", "--root", results],
            f"run baseline_grid/default at {grid_run(results)} has a file {rel} {why}; "
            f"{resume_advice(results)}")
    repaired, target = resumed(results, duplicate, why)
    assert "2 trials, 2 already recorded, 0 ran" in repaired.stdout
    assert own.read_bytes() == kept and target.read_bytes() == kept


def test_run_moves_nothing_aside_in_an_ingested_run(results):
    """The quarantine warning's "will run again" is never said of an ingested run: `run` refuses
    such a run before its repair moves anything (ingested runs are added to by `ingest` only)."""
    import json

    manifest_path = grid_run(results) / "manifest.json"
    manifest = json.loads(manifest_path.read_text())
    manifest["sessions"][0]["ingested"] = ["day1.csv"]
    manifest_path.write_text(json.dumps(manifest, indent=2))
    (own,) = (grid_run(results) / "records").glob("*.parquet")
    shutil.copyfile(own, own.with_name(f"{own.stem} (1).parquet"))
    refused(results, ["run", "baseline_grid", *BG, "--root", results],
            f"run baseline_grid/default at {grid_run(results)} holds simulation records (ingested); "
            "`run` never adds simulated or virtual trials to them, so choose another run name "
            "(--run NAME).")
