"""Damaged runs, round 3: attacks on the account a run keeps of its other parts (campaign.parts).

Each case damages its own copy of the finished runs of tests/cli/test_lost_parts.py (``kept``: a
test2_grasp run with belief_none traces, a surrogate run with summary tables, a baseline_grid run of
two sessions with a preparation per body and candidates traces) and goes through the CLI: what
``status`` and ``report`` say of it, and what ``run`` makes of it.
"""

from __future__ import annotations

import shutil
from pathlib import Path

import pyarrow.compute as pc
import pyarrow.parquet as pq
import pytest
from cli_checks import BG, KEPT_OVERRIDES, invoke, kept_advice, refused, replaced, report_tables

from graspcampaign.campaign.records import RunStore, _write_atomic
from graspcampaign.campaign.verify import PARTS_KEY


def _run(kept_copy: Path, study: str, *extra: str):
    """``graspcampaign run`` of ``study`` as the fixture ran it (``extra`` replacing overrides)."""
    return invoke("run", study, *replaced(KEPT_OVERRIDES[study], *extra), "runner.progress=false",
                  "--root", kept_copy)


def _restamp(path: Path, metadata: dict[bytes, bytes]) -> None:
    """Rewrite ``path`` with ``metadata`` in place of its own as the store writes a file (the
    digest of its values stamped again): an older or foreign file, intact by every check of one
    file."""
    table = pq.read_table(path)
    _write_atomic(table.replace_schema_metadata(metadata), path)


def _first_session_records(run: Path) -> Path:
    """The records file of baseline_grid's first session (the sphere's and the pear's trials)."""
    (path,) = [p for p in (run / "records").glob("*.parquet")
               if "pear" in str(pq.read_table(p, columns=["shape"]).column("shape").to_pylist())]
    return path


@pytest.mark.parametrize(("account", "why"), [
    (b'{"pear_0.2', "it is not JSON"),
    (b'{"pear_0.2_0.3_ferrari_canny_s0-599544ae7e": {"tables": {"candidates": "50"}}}',
     'trial pear_0.2_0.3_ferrari_canny_s0-599544ae7e has {"tables": {"candidates": "50"}}, not its '
     "rows per trace table (whole numbers above 0) and the body id of its preparation"),
    (b'{"v":2,"tables":{"candidates":[50,50]}}', "table candidates has 2 values for the file's 4 rows"),
    (b'{"v":3,"tables":{}}', "it is of version 3, not 2"),
])
def test_an_account_the_tool_never_writes_is_a_damaged_file(kept_copy, account, why):
    """A records file whose account is not JSON or counts rows in text: status, report and run
    ended in a traceback (exit 1; json.loads, a sum of str). Now it is a damaged file: named
    (exit 2), moved aside by run, its trials run again. So is one of the row-by-row form whose
    list has another length than the file's rows, or of a version this release does not write."""
    run = kept_copy / "baseline_grid" / "default"
    path = _first_session_records(run)
    meta = pq.read_schema(path).metadata
    _restamp(path, {**meta, PARTS_KEY: account})
    rel = path.relative_to(run).as_posix()
    said = (f"run baseline_grid/default at {run} has a damaged file {rel} (its account of the "
            "run's other parts, metadata graspcampaign.parts, is not one the tool writes: "
            f"{why}); "
            f"{kept_advice(kept_copy, 'baseline_grid', 'quarantine the file and run its trials again')}")
    for command in ("status", "report"):
        refused(kept_copy, [command, "baseline_grid", "--root", kept_copy], said)
    mended = _run(kept_copy, "baseline_grid")
    assert mended.exit_code == 0, mended.output
    assert "4 ran (4 ok, 0 errors)" in mended.stdout
    assert invoke("report", "baseline_grid", "--root", kept_copy).exit_code == 0


def test_a_drifted_run_computes_the_preparations_of_its_recorded_trials_outside_its_design(kept_copy):
    """prepared/ of baseline_grid gone, the run resumed drifted to the sphere alone: it computed
    the sphere's preparation only and then refused itself in its final check (exit 2, the pear's
    and the ellipsoid's gone), which its advice (resume the run) could not mend. Now the bodies
    every recorded trial used are computed again, each read back from its record's factors, and
    the report is the undamaged run's again."""
    run = kept_copy / "baseline_grid" / "default"
    before = report_tables(kept_copy, "baseline_grid")
    ids = set(RunStore(run).read("prepared", ["body_id"]).column("body_id").to_pylist())
    shutil.rmtree(run / "prepared")
    mended = invoke("run", "baseline_grid", *BG, "runner.progress=false", "--allow-drift",
                    "--root", kept_copy)
    assert mended.exit_code == 0, mended.output
    assert mended.stderr == (f"warning: run baseline_grid/default at {run} has no prepared "
                             "directory, which holds the preparations of the 3 bodies its "
                             "recorded trials used; it is computed again\n")
    assert set(RunStore(run).read("prepared", ["body_id"]).column("body_id").to_pylist()) == ids
    for command in ("status", "report"):
        assert invoke(command, "baseline_grid", "--root", kept_copy).exit_code == 0
    assert _run(kept_copy, "baseline_grid").exit_code == 0  # back to the three shapes
    assert invoke("report", "baseline_grid", "--root", kept_copy).exit_code == 0
    assert report_tables(kept_copy, "baseline_grid") == before


def test_a_trace_file_of_the_same_trials_with_other_values_is_trusted_for_none_of_them(kept_copy):
    """A copy of tables/belief_none's file with other values (another run's traces of the same
    trials) put in under a name sorting first: report called the run's own file the duplicate,
    and run moved it aside, keeping the copy's values as the run's traces. Now the values are
    compared, as for records: neither file is trusted, its trials run again."""
    run = kept_copy / "test2_grasp" / "default"
    before = report_tables(kept_copy, "test2_grasp")
    (own,) = (run / "tables" / "belief_none").glob("*.parquet")
    table = pq.read_table(own)
    n = len(set(table.column("trial_id").to_pylist()))
    where = table.column_names.index("contact_1_x_mm")
    other = table.set_column(where, "contact_1_x_mm", pc.multiply(table.column(where), 2.0))
    _write_atomic(other.replace_schema_metadata(None), own.with_name("compact-0000000000.parquet"))
    rel = own.relative_to(run).as_posix()
    why = (f"{n} trials also in tables/belief_none/compact-0000000000.parquet with other values "
           "(column contact_1_x_mm)")
    refused(kept_copy, ["report", "test2_grasp", "--root", kept_copy],
            f"run test2_grasp/default at {run} has a file {rel} holding the traces of {why}; "
            f"{kept_advice(kept_copy, 'test2_grasp', 'quarantine the file and run its trials again')}")
    mended = _run(kept_copy, "test2_grasp")
    assert mended.exit_code == 0, mended.output
    assert f"{n} ran ({n} ok, 0 errors)" in mended.stdout
    assert mended.stderr.startswith(f"warning: file {own} moved to ") and why in mended.stderr
    assert invoke("report", "test2_grasp", "--root", kept_copy).exit_code == 0
    assert report_tables(kept_copy, "test2_grasp") == before


@pytest.mark.parametrize("lost", [["complete.json"], ["complete.json", "surrogate_parity"], []])
def test_a_finished_run_without_its_summary_record_is_named_and_finalized_again(kept_copy, lost):
    """summary/complete.json of the finished surrogate run deleted, alone, with a summary table,
    or with the whole summary/ directory (``[]``): report exited 0, lacking the tables gone without
    a word (complete.json, which says which were stored, went with them). Now a finished run of a
    kind with a finalize stage names the file gone; run finalizes again, storing only the tables
    not stored (surrogate_timing, a measured time, stays byte for byte where it was kept)."""
    run = kept_copy / "surrogate" / "default"
    before, summary = report_tables(kept_copy, "surrogate"), run / "summary"
    timing = (summary / "surrogate_timing" / "part-final.parquet").read_bytes()
    for name in lost:
        (summary / name).unlink() if name.endswith(".json") else shutil.rmtree(summary / name)
    if not lost:
        shutil.rmtree(summary)
    said = (f"run surrogate/default at {run} has no summary/complete.json, which a finished run "
            "of surrogate stores when it computes its summary tables")
    for command in ("status", "report"):
        refused(kept_copy, [command, "surrogate", "--root", kept_copy],
                f"{said}; {kept_advice(kept_copy, 'surrogate', 'compute it again')}")
    mended = _run(kept_copy, "surrogate")
    assert mended.exit_code == 0, mended.output
    assert mended.stderr == f"warning: {said}; it is computed again\n"
    assert invoke("report", "surrogate", "--root", kept_copy).exit_code == 0
    if lost:
        assert (summary / "surrogate_timing" / "part-final.parquet").read_bytes() == timing
        assert report_tables(kept_copy, "surrogate") == before
    else:  # every table computed again: the same but for the measured times
        assert set(report_tables(kept_copy, "surrogate")) == set(before)


@pytest.mark.parametrize("other", [False, True])
def test_a_second_preparation_of_a_body_is_named_not_reported_twice(kept_copy, other):
    """baseline_grid's first-session preparations copied in under another shard name, byte for
    byte or with other values (another run's identification of the same bodies): status and
    report exited 0, and Table 3 counted each body twice or mixed the copy's values in (a
    preparation is keyed by its body_id, not by a trial id, so no check saw two). Now a copy is a
    duplicate, moved aside by run; other values are trusted in neither file: both moved aside,
    every body computed again. The report is then the undamaged run's."""
    run = kept_copy / "baseline_grid" / "default"
    before = report_tables(kept_copy, "baseline_grid")
    (own,) = (run / "prepared").glob("compact-*.parquet")
    table = pq.read_table(own)
    if other:
        where = table.column_names.index("lambda1")
        table = table.set_column(where, "lambda1", pc.multiply(table.column(where), 2.0))
    copy = run / "prepared" / "compact-0000000000.parquet"
    _write_atomic(table.replace_schema_metadata(None), copy)
    rel, advice = own.relative_to(run).as_posix(), kept_advice(kept_copy, "baseline_grid", "X")[:-2]
    said = (f"a file {rel} holding 2 preparations of bodies also in prepared/{copy.name} with "
            f"other values (column lambda1) (and 1 more problem); {advice}compute it again."
            if other else f"a duplicate file {rel} (every preparation also in prepared/{copy.name})"
                          f"; {advice}quarantine the duplicate.")
    refused(kept_copy, ["report", "baseline_grid", "--root", kept_copy],
            f"run baseline_grid/default at {run} has {said}")
    mended = _run(kept_copy, "baseline_grid")
    assert mended.exit_code == 0, mended.output
    assert mended.stderr.count("moved to") == (2 if other else 1), mended.stderr
    assert invoke("report", "baseline_grid", "--root", kept_copy).exit_code == 0
    assert report_tables(kept_copy, "baseline_grid") == before


def test_a_trace_file_cut_short_is_named_by_report_as_by_status(kept_copy):
    """The second session's candidates file rewritten without 10 of its trial's 50 rows (its
    digest stamped again): status refused it (its footers count 140 rows where 150 were stored),
    but report exited 0 on the cut traces and run found nothing to do, so status refused the run
    for ever. Now report and run count each trial's rows too; run runs that trial again."""
    run = kept_copy / "baseline_grid" / "default"
    before = report_tables(kept_copy, "baseline_grid")
    (shard,) = (run / "tables" / "candidates").glob("part-*.parquet")
    table = pq.read_table(shard)
    (trial,) = set(table.column("trial_id").to_pylist())
    _write_atomic(table.slice(10), shard)
    lost = (f"tables/candidates with other trace rows than 1 recorded trial stored (first {trial}: "
            "40 where it stored 50)")
    advice = kept_advice(kept_copy, "baseline_grid", "run those trials again")
    label = f"run baseline_grid/default at {run} has"
    refused(kept_copy, ["report", "baseline_grid", "--root", kept_copy], f"{label} {lost}; {advice}")
    refused(kept_copy, ["status", "baseline_grid", "--root", kept_copy],
            f"{label} tables/candidates with 140 trace rows where 3 recorded trials stored 150; "
            f"{advice}")
    mended = _run(kept_copy, "baseline_grid")
    assert mended.exit_code == 0, mended.output
    assert mended.stderr == f"warning: {label} {lost}; those trials run again\n"
    assert "1 ran (1 ok, 0 errors)" in mended.stdout
    for command in ("status", "report"):
        assert invoke(command, "baseline_grid", "--root", kept_copy).exit_code == 0
    assert report_tables(kept_copy, "baseline_grid") == before


def test_status_says_what_it_checked_where_report_names_a_loss_it_cannot_see(kept_copy):
    """A byte of the second session's candidates file flipped: report names the damaged file;
    status, which reads the records and only the other parts' footers (it answers in well under a
    second), exits 0, and now says so in its output, where it said nothing of what it left out."""
    run = kept_copy / "baseline_grid" / "default"
    (shard,) = (run / "tables" / "candidates").glob("part-*.parquet")
    data = bytearray(shard.read_bytes())
    data[len(data) // 3] ^= 0xFF
    shard.write_bytes(bytes(data))
    assert invoke("report", "baseline_grid", "--root", kept_copy).exit_code == 2
    shown = invoke("status", "baseline_grid", "--root", kept_copy)
    assert shown.exit_code == 0, shown.output
    assert shown.stdout.endswith(
        "checked: records/ in full; tables/, prepared/ and summary/ by their directories and their "
        "files' footers (report and run verify every file)\n")
