"""What a run keeps account of, where it keeps none, and a preparation moved aside by the repair.

A run stored before its records kept account of the trials' other parts (trace tables,
preparations) cannot name one of those parts lost: ``status`` says so. ``ingest`` writes the same
account as ``run`` (its trials store nothing else). A preparation the repair would move aside for
a conflict is refused under drifted preparation settings, as a lost one is.

Each case damages its own copy of the finished tiny baseline_grid run (``results``, conftest.py).
"""

from __future__ import annotations

import json
from pathlib import Path

import pyarrow.compute as pc
import pyarrow.parquet as pq
from cli_checks import (
    BG,
    BG_QUOTED,
    T1,
    bench_press,
    grid_run,
    invoke,
    refused,
    replaced,
    resume_grid,
)

from graspcampaign.campaign.grid import content_hash
from graspcampaign.campaign.records import _write_atomic
from graspcampaign.campaign.verify import CONFIG_KEY, PARTS_KEY

#: what status says it checked of a run (every run)
CHECKED = ("checked: records/ in full; tables/, prepared/ and summary/ by their directories and "
           "their files' footers (report and run verify every file)")


def _checked(root: Path, study: str, *args: str) -> str:
    """The ``checked`` line of ``status`` of ``study``'s run under ``root`` (it exits 0)."""
    done = invoke("status", study, *args, "--root", root)
    assert done.exit_code == 0, done.output
    (line,) = [line for line in done.stdout.splitlines() if line.startswith("checked: ")]
    return line


def _without_account(path: Path) -> None:
    """Rewrite records file ``path`` as the release before the account stored it: its values and
    their digest as they are, no ``graspcampaign.parts`` in its metadata."""
    meta = {k: v for k, v in (pq.read_metadata(path).metadata or {}).items() if k != PARTS_KEY}
    _write_atomic(pq.read_table(path).replace_schema_metadata(meta), path)
    assert PARTS_KEY not in (pq.read_metadata(path).metadata or {})


def test_status_says_a_run_stored_before_the_account_cannot_name_a_lost_trace(results):
    # a run whose records keep no account: its trace file deleted, status said what it says of
    # a whole run (exit 0) and report wrote a page whose epsilon items said "the records have
    # no `trial_id` column"; nothing can name the loss, and status now says so
    run = grid_run(results)
    (records,) = (run / "records").glob("*.parquet")
    _without_account(records)
    rel = records.relative_to(run).as_posix()
    said = (f"{CHECKED}; the traces and preparations of 2 recorded trials are not accounted ({rel} "
            "stored before runs kept that account), so one of theirs lost cannot be named")
    assert _checked(results, "baseline_grid") == said
    for trace in (run / "tables").rglob("*.parquet"):
        trace.unlink()
    assert _checked(results, "baseline_grid") == said


def test_a_resumed_run_keeps_its_trials_stored_before_the_account_unaccounted(results):
    # the old code's compaction merged a shard without an account with the resumed session's,
    # accounting its trials as having stored nothing else: made up after the fact, so a lost
    # trace file of theirs was never named and nothing said so
    run = grid_run(results)
    (records,) = (run / "records").glob("*.parquet")
    table = pq.read_table(records)
    meta = {CONFIG_KEY: pq.read_metadata(records).metadata[CONFIG_KEY]}
    ids = sorted(table.column("trial_id").to_pylist())
    shards = [run / "records" / f"part-{content_hash([trial])}.parquet" for trial in ids]
    _write_atomic(table.filter(pc.equal(table.column("trial_id"), ids[1]))
                  .replace_schema_metadata(meta), shards[1])  # as a release before kept none
    records.unlink()  # and the other trial's record lost: resumed, it runs again
    resume_grid(results)
    assert _checked(results, "baseline_grid") == (
        f"{CHECKED}; the traces and preparations of 1 recorded trial are not accounted "
        f"(records/{shards[1].name} stored before runs kept that account), so one of theirs lost "
        "cannot be named")


def test_ingest_keeps_the_account_a_run_keeps(results, tmp_path):
    # ingest stores no trace (Test 1's waveforms are fitted, not kept) and wrote no account; it now
    # writes the one a run writes, through the same encoding: its trials stored nothing else. An
    # ingested run is never called unaccounted, one stored before ingest kept it neither.
    bench_press().to_csv(tmp_path / "waves.csv", index=False)
    done = invoke("ingest", "test1_bench", tmp_path / "waves.csv", *T1, "--root", results)
    assert done.exit_code == 0, done.output
    run = results / "test1_bench" / "measured"
    assert sorted(p.relative_to(run).as_posix() for p in run.rglob("*.parquet")) == [
        f"records/{p.name}" for p in (run / "records").glob("*.parquet")]
    (records,) = (run / "records").glob("*.parquet")
    assert json.loads(pq.read_metadata(records).metadata[PARTS_KEY]) == {"v": 2, "tables": {}}
    assert _checked(results, "test1_bench", "--run", "measured") == CHECKED
    _without_account(records)
    assert _checked(results, "test1_bench", "--run", "measured") == CHECKED


def test_a_preparation_moved_aside_for_a_conflict_is_not_computed_again_under_other_settings(results):
    # a second file of prepared/ holding the run's body with other values: the repair moves both
    # aside and the old code computed the body again with the drifted pso.n_particles=3 (exit 0,
    # the recorded trials' identification replaced by another)
    run = grid_run(results)
    (own,) = (run / "prepared").glob("*.parquet")
    table = pq.read_table(own)
    (body,) = table.column("body_id").to_pylist()
    where = table.column_names.index("lambda1")
    other = table.set_column(where, "lambda1", pc.multiply(table.column(where), 2.0))
    _write_atomic(other.replace_schema_metadata(None), run / "prepared" / "compact-0000000000.parquet")
    drifted = ["run", "baseline_grid", *replaced(BG, "pso.n_particles=3"), "--allow-drift",
               "--root", results]
    refused(results, drifted,
            f"run baseline_grid/default at {run} has lost 1 preparation its recorded trials used "
            f"(first body {body}), which this session cannot compute again as they were: they "
            "were computed with the settings the run was started with (pso.n_particles 2 -> 3); "
            f"resume it as started (graspcampaign run baseline_grid {BG_QUOTED} --run default "
            f"--root {results}) to compute them again as they were, or start a new run for this "
            "config (output.run=NAME or --run NAME).")
    # the advice works: resumed as started, both files go aside and the body is computed as the
    # recorded trials used it (seeded by the body alone), the value stored before the damage
    assert resume_grid(results).stderr.count("moved to") == 2
    (again,) = (run / "prepared").glob("*.parquet")
    assert pq.read_table(again).column("lambda1").to_pylist() == table.column("lambda1").to_pylist()
    assert invoke(*drifted).exit_code == 0


def test_a_copy_of_a_preparation_moved_aside_leaves_it_to_a_drifted_run(results):
    # a byte-for-byte copy is a duplicate: moved aside, its body stays in the file it copies, so
    # nothing is computed again and the drifted session runs (as on the old code)
    run = grid_run(results)
    (own,) = (run / "prepared").glob("*.parquet")
    (run / "prepared" / "compact-0000000000.parquet").write_bytes(own.read_bytes())
    kept = own.read_bytes()
    drifted = invoke("run", "baseline_grid", *replaced(BG, "pso.n_particles=3"), "--allow-drift",
                     "--root", results)
    assert drifted.exit_code == 0, drifted.output
    assert drifted.stderr.count("moved to") == 1 and "duplicate" in drifted.stderr
    assert [p.read_bytes() for p in (run / "prepared").glob("*.parquet")] == [kept]
