"""A part of a finished run gone (a trace table, one file of it, prepared/, a summary table): every
other file is intact, so no check of one file sees it, and the report silently lacked its rows.
The records say what each trial stored besides its record (``campaign.parts``): ``report`` and
``status`` refuse the run naming what is gone, ``run`` computes exactly that again, and the report
is then the undamaged run's, table for table, byte for byte.

Every case damages its own copy of the finished runs (``kept_copy`` of ``kept``, conftest.py).
"""

from __future__ import annotations

import shutil
from pathlib import Path

import pyarrow.parquet as pq
from cli_checks import KEPT_OVERRIDES, invoke, kept_advice, refused, report_tables

from graspcampaign.campaign.records import RunStore


def _mended(kept_copy: Path, study: str, lost: str, counted: str | None = None) -> None:
    """``report`` refuses the run with "<run> has <lost>; <advice>" and ``status`` with the same
    or, where only the files' footers tell (it reads no more than the records), with "<run> has
    <counted>; <advice>" (exit 2, nothing changed); ``run`` warns as ``report`` and computes it
    again; the report's tables are then the undamaged run's, byte for byte."""
    before, run = report_tables(kept_copy, study), kept_copy / study / "default"
    label = f"run {study}/default at {run} has"
    again = "run those trials again" if lost.startswith(("tables/", "no tables/")) else \
        "compute it again"
    advice = kept_advice(kept_copy, study, again)
    refused(kept_copy, ["report", study, "--root", kept_copy], f"{label} {lost}; {advice}")
    refused(kept_copy, ["status", study, "--root", kept_copy], f"{label} {counted or lost}; {advice}")
    mended = invoke("run", study, *KEPT_OVERRIDES[study], "runner.progress=false", "--root", kept_copy)
    assert mended.exit_code == 0, mended.output
    then = "those trials run again" if again.startswith("run") else "it is computed again"
    assert mended.stderr == f"warning: {label} {lost}; {then}\n"
    assert invoke("report", study, "--root", kept_copy).exit_code == 0
    assert report_tables(kept_copy, study) == before


def _first(run: Path, part: str) -> str:
    """The first trial id (by sort order) with rows in ``part`` of the run."""
    return min(RunStore(run).read(part, ["trial_id"]).column("trial_id").to_pylist())


def test_a_deleted_trace_table_is_named_and_its_trials_run_again(kept_copy):
    """tables/belief_none of test2_grasp deleted: its rows vanished from Tables 6-7 without a
    word; now report and status refuse it and run runs the trials that stored them again."""
    run = kept_copy / "test2_grasp" / "default"
    n = len(set(RunStore(run).read("tables/belief_none").column("trial_id").to_pylist()))
    shutil.rmtree(run / "tables" / "belief_none")
    _mended(kept_copy, "test2_grasp", f"no tables/belief_none directory, where {n} recorded trials "
                                    "stored traces")


def test_a_deleted_compacted_trace_file_is_named_and_its_trials_run_again(kept_copy):
    """The compacted file of tables/belief_none deleted, its directory left empty."""
    run = kept_copy / "test2_grasp" / "default"
    first = _first(run, "tables/belief_none")
    n = len(set(RunStore(run).read("tables/belief_none").column("trial_id").to_pylist()))
    (compacted,) = (run / "tables" / "belief_none").glob("*.parquet")
    rows = _rows(compacted)
    compacted.unlink()
    _mended(kept_copy, "test2_grasp", f"tables/belief_none without the traces of {n} recorded "
                                    f"trials (first {first})",
            f"tables/belief_none with 0 trace rows where {n} recorded trials stored {rows}")


def test_one_deleted_file_of_a_trace_table_is_named_and_its_trials_run_again(kept_copy):
    """The compacted file of tables/candidates deleted (the first session's: the sphere's and the
    pear's traces), its other file kept: the ellipsoid's trial keeps its traces and its record,
    the sphere's and the pear's run again."""
    run = kept_copy / "baseline_grid" / "default"
    (compacted,) = (run / "tables" / "candidates").glob("compact-*.parquet")
    (shard,) = (run / "tables" / "candidates").glob("part-*.parquet")
    assert _holds(shard, "ellipsoid") and not _holds(compacted, "ellipsoid")
    first = min(_holds(compacted, "pear"), _holds(compacted, "sphere"))
    kept, rows = _rows(shard), _rows(shard) + _rows(compacted)
    compacted.unlink()
    _mended(kept_copy, "baseline_grid", f"tables/candidates without the traces of 2 recorded "
                                      f"trials (first {first})",
            f"tables/candidates with {kept} trace rows where 3 recorded trials stored {rows}")


def _rows(path: Path) -> int:
    return pq.read_metadata(path).num_rows


def _holds(path: Path, prefix: str) -> str | None:
    """The trial id starting with ``prefix`` that ``path`` holds traces of, or None."""
    ids = set(pq.read_table(path, columns=["trial_id"]).column("trial_id").to_pylist())
    return next((i for i in sorted(ids) if i.startswith(prefix)), None)


def test_a_deleted_prepared_directory_is_named_and_computed_again(kept_copy):
    """prepared/ of baseline_grid deleted: report lost its identifications table without a word
    (run recomputed it, report did not notice)."""
    run = kept_copy / "baseline_grid" / "default"
    n = len(RunStore(run).read("prepared", ["body_id"]))
    assert n == 3  # the sphere's body, the pear's and the ellipsoid's
    shutil.rmtree(run / "prepared")
    _mended(kept_copy, "baseline_grid", "no prepared directory, which holds the preparations of "
                                      f"the {n} bodies its recorded trials used")


def test_a_deleted_preparation_is_named_and_computed_again(kept_copy):
    """The ellipsoid's preparation deleted (the second session's shard; the first session's two
    are compacted into one file, which stays)."""
    run = kept_copy / "baseline_grid" / "default"
    (shard,) = (run / "prepared").glob("part-*.parquet")
    body = RunStore(run).read("prepared", ["body_id", "shape"]).to_pydict()
    assert dict(zip(body["shape"], body["body_id"], strict=True))["ellipsoid"] in shard.name
    shard.unlink()
    _mended(kept_copy, "baseline_grid", "prepared without 1 preparation its recorded trials used "
                                      f"(first body {shard.name[5:-8]})",
            "prepared with 2 preparations where its recorded trials used 3 bodies")


def test_a_deleted_summary_table_is_named_and_computed_again(kept_copy):
    """summary/surrogate_parity deleted: complete.json says finalize stored it; finalize runs
    again and stores it alone (the other tables stay as they are)."""
    run = kept_copy / "surrogate" / "default"
    timing = (run / "summary" / "surrogate_timing" / "part-final.parquet").read_bytes()
    shutil.rmtree(run / "summary" / "surrogate_parity")
    _mended(kept_copy, "surrogate", "no summary/surrogate_parity table, which "
                                  "summary/complete.json says was stored")
    assert (run / "summary" / "surrogate_timing" / "part-final.parquet").read_bytes() == timing


def test_an_undamaged_run_and_a_trial_without_traces_are_never_called_damaged(kept):
    """Every finished run reports (the fixture) and shows its status; in baseline_grid the
    heuristic trials store no candidates and in test2_grasp not every trial stores belief_none
    rows, and neither is missing anything."""
    for study in ("test2_grasp", "surrogate", "baseline_grid"):
        assert invoke("status", study, "--root", kept).exit_code == 0
    run = kept / "baseline_grid" / "default"
    traced = set(RunStore(run).read("tables/candidates", ["trial_id"]).column("trial_id").to_pylist())
    recorded = RunStore(run).recorded_ids()
    assert traced and traced < recorded
