"""A run whose stored files are not what its manifest says: exit 2, the whole one-sentence
message, nothing stored changed; what ``run`` can repair it repairs without deleting a stored file.

Layout, files that are not shards, duplicate, foreign, edited and missing records; reports that
must not overwrite good pages; the advice for a damaged trace table; a report that reads another
run. Every case damages its own copy of the finished runs (``results`` in conftest.py).
"""

from __future__ import annotations

import json
import shutil
from pathlib import Path

import pyarrow as pa
import pyarrow.parquet as pq
import pytest
from cli_checks import BG, grid_run, invoke, quarantined, refused, resume_advice, resume_grid, resumed

from graspcampaign.campaign.records import CONTENT_KEY, RunStore, content_digest


def _compact(results: Path) -> Path:
    (path,) = (grid_run(results) / "records").glob("compact-*.parquet")
    return path


def _as_written(table: pa.Table, target: Path) -> None:
    """Write ``table`` as ``target`` as the tool writes a file: with the digest of its values."""
    digest = {CONTENT_KEY: content_digest(table).encode()}
    pq.write_table(table.replace_schema_metadata({**(table.schema.metadata or {}), **digest}),
                   target, write_page_checksum=True)


def _rewritten(source: Path, target: Path, edit) -> None:
    """Write ``edit(table)`` of a verified shard as ``target`` (with ``source``'s metadata and
    the digest of its own values: a file the tool wrote)."""
    _as_written(edit(pq.read_table(source)), target)


def _with_run(table: pa.Table, run: str) -> pa.Table:
    i = table.schema.get_field_index("run")
    return table.set_column(i, "run", pa.array([run] * table.num_rows))


def _damage_records_file(results):
    records = grid_run(results) / "records"
    shutil.rmtree(records)
    records.write_text("not a directory")
    return ("a file records where its records directory belongs", resume_advice(results),
            records, "file {path} moved to {target} (a file where a directory belongs); its "
                     "trials no longer recorded will run again")


def _renamed_to_csv(results):
    compact = _compact(results)
    renamed = compact.with_suffix(".csv")
    compact.rename(renamed)
    return (f"a file records/{renamed.name} that is not a Parquet shard of the run",
            resume_advice(results), renamed, "file {path} moved to {target} (not a Parquet shard of "
                                       "the run); its trials no longer recorded will run again")


def _duplicate(results):
    compact = _compact(results)
    copy = compact.with_name("part-dddddddddd.parquet")
    shutil.copyfile(compact, copy)
    why = f"every trial also in records/{compact.name}"
    return (f"a duplicate file records/part-dddddddddd.parquet ({why})",
            resume_advice(results, "quarantine the duplicate"), copy,
            "duplicate file {path} moved to {target} (" + why + "); its trials stay recorded in "
            f"records/{compact.name}")


def _foreign_study(results):
    (shard,) = (results / "smoke" / "default" / "records").glob("*.parquet")
    copy = grid_run(results) / "records" / "part-ffffffffff.parquet"
    shutil.copyfile(shard, copy)
    return ("a file records/part-ffffffffff.parquet holding records of another study (smoke)",
            resume_advice(results), copy, "file {path} moved to {target} (records of another study "
                                    "(smoke)); its trials no longer recorded will run again")


def _another_run(results):
    copy = grid_run(results) / "records" / "part-0000000000.parquet"
    _rewritten(_compact(results), copy, lambda t: _with_run(t, "other"))
    return ("a file records/part-0000000000.parquet holding records of another run (other)",
            resume_advice(results), copy, "file {path} moved to {target} (records of another run "
                                    "(other)); its trials no longer recorded will run again")


def _another_config(results):
    copy = grid_run(results) / "records" / "part-cccccccccc.parquet"
    _rewritten(_compact(results), copy, lambda t: t.replace_schema_metadata(
        {b"graspcampaign.config_hashes": b'["0123456789abcdef"]'}))
    why = "records run with another config (hash 0123456789abcdef, not one this run ran with)"
    return (f"a file records/part-cccccccccc.parquet holding {why}", resume_advice(results), copy,
            "file {path} moved to {target} (" + why + "); its trials no longer recorded will run again")


def _twice_in_one_file(results):
    compact = _compact(results)
    table = pq.read_table(compact)
    _as_written(pa.concat_tables([table, table]), compact)
    return (f"a file records/{compact.name} that records 2 trials twice", resume_advice(results),
            compact, "file {path} moved to {target} (it records 2 trials twice); its trials no "
                     "longer recorded will run again")


def _records_removed(results):
    shutil.rmtree(grid_run(results) / "records")
    return ("missing records: its manifest counts 2 recorded trials but 0 are stored (records/ is "
            "missing)", resume_advice(results, "run the missing trials again"), None,
            f"run baseline_grid/default at {grid_run(results)}: its manifest counts 2 recorded trials "
            "but 0 are stored; the missing ones run again")


def _records_emptied(results):
    _compact(results).unlink()
    return ("missing records: its manifest counts 2 recorded trials but 0 are stored (records/ is "
            "empty)", resume_advice(results, "run the missing trials again"), None,
            f"run baseline_grid/default at {grid_run(results)}: its manifest counts 2 recorded trials "
            "but 0 are stored; the missing ones run again")


def _partly_duplicated(results):
    compact = _compact(results)
    table = pq.read_table(compact)
    first, both = compact.with_name("part-aaaaaaaaaa.parquet"), compact.with_name("part-bbbbbbbbbb.parquet")
    _as_written(table.slice(0, 1), first)
    _as_written(table, both)
    compact.unlink()
    why = "1 of its 2 trials also in records/part-aaaaaaaaaa.parquet"
    return (f"a duplicate file records/part-bbbbbbbbbb.parquet ({why})", resume_advice(results), both,
            "file {path} moved to {target} (" + why + "); its trials no longer recorded will run again")


def _edited(results, edit, digest: bool | None):
    """The run's records file rewritten as ``edit(table)`` with valid page checksums and its
    metadata (``digest``: True the digest of the new values, as the tool writes a file; None the
    file's own stale digest; False none), the way a script or another tool rewrites it."""
    compact = _compact(results)
    table = edit(pq.read_table(compact))
    if digest:
        _as_written(table, compact)
    else:
        meta = {k: v for k, v in table.schema.metadata.items() if digest is None or k != CONTENT_KEY}
        pq.write_table(table.replace_schema_metadata(meta), compact, write_page_checksum=True)
    return compact


def _set(table: pa.Table, column: str, values) -> pa.Table:
    i = table.schema.get_field_index(column)
    return table.set_column(i, column, pa.array(values, table.schema.field(i).type)
                            if isinstance(values, list) else values)


_STALE = "its values differ from those written: their SHA-256 is not the one stored with them"


def _edit_case(edit, digest: bool | None, why: str, damaged: bool = False):
    def case(results):
        compact = _edited(results, edit, digest)
        text = f"a damaged file records/{compact.name} ({why})" if damaged else \
            f"a file records/{compact.name} {why}"
        reason = why if damaged else why.split(" ", 1)[1]
        return (text, resume_advice(results), compact, ("damaged file" if damaged else "file") +
                " {path} moved to {target} (" + reason + "); its trials no longer recorded will run again")
    return case


_EDITS = {
    # the tester's edit: a row removed, the file rewritten with its metadata (a stale digest)
    "row_removed": _edit_case(lambda t: t.slice(1), None, _STALE, damaged=True),
    "value_edited": _edit_case(lambda t: _set(t, "residual_norm_n", [999.0] * len(t)), None,
                               _STALE, damaged=True),
    "column_added": _edit_case(lambda t: t.append_column("extra", pa.array([1] * len(t))), None,
                               _STALE, damaged=True),
    # rewritten without the digest: what every record has is still checked
    "status_unknown": _edit_case(lambda t: _set(t, "status", ["weird"] * len(t)), False,
                                 "with status 'weird', not ok or error"),
    "column_dropped": _edit_case(lambda t: t.drop(["trial_index"]), False,
                                 "with no column trial_index, which every record has"),
    "column_retyped": _edit_case(
        lambda t: _set(t, "trial_index", t.column("trial_index").cast(pa.string())), False,
        "with column trial_index of type string, not whole numbers"),
    "trial_id_null": _edit_case(lambda t: _set(t, "trial_id", [None, *t["trial_id"].to_pylist()[1:]]),
                                False, "with 1 record without a trial_id"),
    "trial_id_renamed": _edit_case(
        lambda t: _set(t, "trial_id", ["bogus-123", *t["trial_id"].to_pylist()[1:]]), False,
        "with trial_id 'bogus-123', which the tool never makes: its ids end in '-' and the "
        "10-digit hash of the trial's factors"),
    "output_retyped": _edit_case(
        lambda t: _set(t, "residual_norm_n", t.column("residual_norm_n").cast(pa.string())), False,
        "with no digest of its values, which every file of this run gets when it is written"),
    # a file as the tool writes it, with a column of lists where the run's records have text
    "study_listed": _edit_case(lambda t: _set(t, "study", pa.array([["baseline_grid"]] * len(t))),
                               True, "its study column holds values of type list<element: string>, "
                                     "not text", damaged=True),
    # a file as the tool writes it, of another source
    "source_measured": _edit_case(lambda t: _set(t, "source", ["measured"] * len(t)), True,
                                  "holding records of another source (measured)"),
}
DAMAGES = {**{f.__name__.lstrip("_"): f for f in (
    _damage_records_file, _renamed_to_csv, _duplicate, _partly_duplicated, _foreign_study,
    _another_run, _another_config, _twice_in_one_file, _records_removed, _records_emptied)},
    **_EDITS}
#: trials that run again after the repair: none where the file was added beside the run's own
#: records, the other trial of a partly duplicated file, every trial where the run's file went
RERUN = {"duplicate": 0, "foreign_study": 0, "another_run": 0, "another_config": 0,
         "partly_duplicated": 1}


@pytest.mark.parametrize("case", sorted(DAMAGES))
def test_a_run_not_what_its_manifest_says_is_refused_then_repaired_by_run(results, case):
    text, advice, offending, warning = DAMAGES[case](results)
    kept = offending.read_bytes() if offending is not None else None
    message = f"run baseline_grid/default at {grid_run(results)} has {text}; {advice}"
    for args in (["status", "baseline_grid"], ["show", "baseline_grid", *BG[:5]],
                 ["report", "baseline_grid"]):
        refused(results, [*args, "--root", results], message)
    # the advice works: resuming the run moves the file aside (never deletes it), then every
    # command reads the run again
    repaired = resume_grid(results)
    target = None
    if offending is not None:
        target = quarantined(results, offending)
        assert target.read_bytes() == kept
    assert repaired.stderr == "warning: " + warning.format(path=offending, target=target) + "\n"
    ran = RERUN.get(case, 2)
    assert f"2 trials, {2 - ran} already recorded, {ran} ran" in repaired.stdout
    status = invoke("status", "baseline_grid", "--root", results, "--json")
    assert status.exit_code == 0, status.output
    assert json.loads(status.stdout)["n_recorded"] == 2
    assert RunStore(grid_run(results)).check() is not None


def test_a_trial_run_again_counts_though_a_compaction_listed_its_shard_name(results):
    """A row removed from a compacted file (rewritten as the tool writes files) whose sources
    list the name the trial's shard once had: the trial runs again and counts (its new shard was
    ignored as superseded, and every `run` said "1 ran" while `status` refused the run)."""
    from graspcampaign.campaign.grid import content_hash

    compact = _compact(results)
    table = pq.read_table(compact)
    gone = table["trial_id"][0].as_py()
    meta = dict(table.schema.metadata)
    sources = json.loads(meta[b"graspcampaign.sources"]) + [f"part-{content_hash([gone])}.parquet"]
    meta[b"graspcampaign.sources"] = json.dumps(sources).encode()
    _as_written(table.slice(1).replace_schema_metadata(meta), compact)
    missing = "its manifest counts 2 recorded trials but 1 are stored"
    refused(results, ["status", "baseline_grid", "--root", results],
            f"run baseline_grid/default at {grid_run(results)} has missing records: {missing}; "
            f"{resume_advice(results, 'run the missing trials again')}")
    for already, ran in ((1, 1), (2, 0)):  # the advice works once, then nothing is left to run
        again = resume_grid(results)
        assert f"2 trials, {already} already recorded, {ran} ran" in again.stdout
    status = invoke("status", "baseline_grid", "--root", results, "--json")
    assert status.exit_code == 0 and json.loads(status.stdout)["n_recorded"] == 2
    assert gone in RunStore(grid_run(results)).recorded_ids()


def test_a_run_never_ends_with_exit_0_on_a_run_its_own_checks_refuse(results, monkeypatch):
    """Records that do not reach the store (here: never written) make `run` fail naming what is
    missing, not report success over a run that every other command then refuses."""
    write = RunStore.write_shard

    def lost(self, part, name, rows, *args, **kwargs):
        if part == "records":
            return self.path / part / f"part-{name}.parquet"
        return write(self, part, name, rows, *args, **kwargs)

    _compact(results).unlink()
    monkeypatch.setattr(RunStore, "write_shard", lost)
    result = invoke("run", "baseline_grid", *BG, "runner.progress=false", "--root", results)
    assert result.exit_code == 2
    missing = "its manifest counts 2 recorded trials but 0 are stored"
    assert result.stderr == (
        f"warning: run baseline_grid/default at {grid_run(results)}: {missing}; the missing ones run "
        f"again\nerror: run baseline_grid/default at {grid_run(results)} has missing records: "
        f"{missing} (records/ is empty); {resume_advice(results, 'run the missing trials again')}\n")


def test_run_quarantines_records_of_a_trial_outside_its_design(results):
    """A well-formed trial id no trial of the design has (the file rewritten as the tool writes
    files): `status` cannot tell without composing the design, `run` does and repairs."""
    foreign = "sphere_0.2_0.3_heuristic_s0-0123456789"
    compact = _edited(results, lambda t: _set(t, "trial_id", [foreign, *t["trial_id"].to_pylist()[1:]]),
                      True)
    kept = compact.read_bytes()
    repaired, target = resumed(results, compact, f"records of 1 trial not in the study's design ({foreign})")
    assert "2 trials, 0 already recorded, 2 ran" in repaired.stdout
    assert target.read_bytes() == kept
    store = RunStore(grid_run(results))
    assert store.check() is not None and foreign not in store.recorded_ids()
    assert len(store.recorded_ids()) == 2


# -- 4. reports check first and never overwrite good pages ------------------------------------------
def test_report_checks_every_named_study_before_writing_any(results):
    shutil.rmtree(grid_run(results) / "report")  # so that a report written before failing shows
    from graspcampaign.campaign.studyfile import list_studies

    refused(results, ["report", "baseline_grid", "nosuch_study", "--root", results],
            f"unknown study 'nosuch_study': not on the config search path and no records under "
            f"{results}; available studies: {', '.join(list_studies())}.")
    refused(results, ["report", "ablation", "--root", results],  # known, never run here
            f"no records for study 'ablation' under {results}; run `graspcampaign run ablation --root "
            f"{results}` first.")  # the command that makes it (was "run it first")
    refused(results, ["report", "smoke", "baseline_grid", "--run", "nosuch", "--root", results],
            f"no run 'nosuch' of study 'smoke' under {results}; run `graspcampaign run smoke --run nosuch "
            f"--root {results}` first.")
    refused(results, ["report", "test2_grasp", "--run", "measured", "--root", results],  # a rig's run
            f"no records for study 'test2_grasp' under {results}; store the rig's measured records with "
            f"`graspcampaign ingest test2_grasp FILE… --root {results}` first.")


def test_a_run_that_cannot_be_read_never_replaces_what_the_root_pages_say(results):
    _duplicate(results)
    pages = {p.name: p.read_bytes() for p in results.glob("*.*")}
    assert sorted(pages) == ["headline.csv", "headline.md", "index.md"]
    why = (f"run baseline_grid/default at {grid_run(results)} has a duplicate file "
           f"records/part-dddddddddd.parquet (every trial also in records/{_compact(results).name}); "
           + resume_advice(results, "quarantine the duplicate")[:-1])
    left = f"warning: the headline and index pages were left as they were: run " \
           f"baseline_grid/default cannot be read ({why})\n"
    # every run: the others are reported, the damaged one is named, the pages stay as they were
    every = invoke("report", "--root", results)
    assert every.exit_code == 2
    assert every.stdout == f"report: {results / 'smoke' / 'default' / 'report' / 'report.md'}\n"
    assert every.stderr == left + f"error: the report of baseline_grid/default could not be " \
                                  f"written: {why}\n"
    assert {p.name: p.read_bytes() for p in results.glob("*.*")} == pages
    # another study's report is written; the pages still say what they said of the damaged run
    other = invoke("report", "smoke", "--root", results)
    assert other.exit_code == 0 and other.stderr == left
    assert {p.name: p.read_bytes() for p in results.glob("*.*")} == pages


# -- 6. a damaged trace table: the advice works -------------------------------------------------------
def test_the_advice_for_an_unidentifiable_trace_file_is_true(results):
    (trace,) = (grid_run(results) / "tables" / "candidates").glob("*.parquet")
    trace.write_bytes(b"x" * 100)  # neither its footer nor its trial ids can be read
    why = "it does not end with a Parquet footer: cut short, or not a Parquet file"
    refused(results, ["report", "baseline_grid", "--root", results],
            f"run baseline_grid/default at {grid_run(results)} has a damaged file "
            f"tables/candidates/{trace.name} ({why}); {resume_advice(results)}")
    repaired, target = resumed(results, trace, why, damaged=True)
    assert "2 ran" in repaired.stdout and target.read_bytes() == b"x" * 100
    store = RunStore(grid_run(results))
    assert store.check() is not None and len(store.read("tables/candidates")) > 0


def test_a_report_reading_another_run_skips_one_that_cannot_be_read(results):
    """mesh_resolution cross-checks its re-derived trials against the baseline_grid runs beside
    it: a duplicated baseline shard is not compared with (its trials would count twice)."""
    import pandas as pd

    from graspcampaign.report.render import Run
    from graspcampaign.report.studies.mesh_resolution import _cross_check

    _duplicate(results)
    records = pd.DataFrame({"trial_id": ["t"], "status": ["ok"], "panel": ["n_max"],
                            "success": [True]})
    run = Run(records, {}, store=RunStore(results / "mesh_resolution" / "default"))
    assert _cross_check(run) == ("No records of the baseline-grid study beside this run (run default "
                                 "skipped: it cannot be read): the re-derived trials were not "
                                 "cross-checked against them.")


def test_a_trial_in_two_baseline_runs_is_cross_checked_once(results):
    """Two readable baseline_grid runs holding the same trials (a copy kept under another name):
    each re-derived trial is compared once, not once per run."""

    from graspcampaign.report.render import Run
    from graspcampaign.report.studies.mesh_resolution import _cross_check

    again = invoke("run", "baseline_grid", *BG, "runner.progress=false", "--run", "again",
                   "--root", results)
    assert again.exit_code == 0, again.output
    base = RunStore(grid_run(results)).read().to_pandas()
    key = ["shape", "mass_kg", "mu", "planner", "seed"]
    records = base[key + ["success", "residual_norm_n"]].assign(
        trial_id=[f"t{i}" for i in range(len(base))], status="ok", panel="n_max")
    run = Run(records, {}, store=RunStore(results / "mesh_resolution" / "default"))
    assert _cross_check(run) == (f"Cross-check against the baseline-grid study's records beside this run: "
                                 f"{len(base)} of {len(base)} re-derived trials have the baseline's "
                                 f"verdict and {len(base)} its residual (relative 1e-9).")
