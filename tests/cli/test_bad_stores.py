"""Bad places and damaged runs, class by class: exit 2, the whole one-sentence message, nothing
stored changed; what ``run`` can repair it repairs without deleting a stored file.

One tiny finished ``baseline_grid`` run (two trials: the proposed planner and Ferrari-Canny, whose
candidates fill ``tables/candidates``) and one ``smoke`` run, both reported, are made once per
module; every damaged case works on its own copy (``shutil.copytree``). The classes: a bad
``--root`` (a file, a path under a file, a device, an empty name, a read-only file system) and
an empty ``--run``; a damaged or missing ``manifest.json``; a run whose stored files are not
what its manifest says (layout, files that are not shards, duplicate, foreign and missing
records); reports that must not overwrite good pages; output paths checked before work; the
advice for a damaged trace table; a directory given where a file belongs.
"""

from __future__ import annotations

import hashlib
import json
import os
import shutil
from pathlib import Path

import pyarrow as pa
import pyarrow.parquet as pq
import pytest
from typer.testing import CliRunner

from graspcampaign.campaign.records import RunStore
from graspcampaign.cli.main import app

runner = CliRunner()
#: the tiny baseline_grid run: one scene, the proposed planner and Ferrari-Canny, a cheap PSO
BG = ["seeds=1", "shape=[sphere]", "mass_kg=[0.2]", "mu=[0.3]", "planner=[heuristic,ferrari_canny]",
      "pso.n_particles=2", "pso.n_iterations=1", "runner.backend=sequential", "runner.batch_size=1"]
SMOKE = ["shape=[sphere]", "nodes=[144]", "runner.backend=sequential"]
RUN_NAME = ("is not allowed; use letters, digits, '.', '_' and '-' (starting with a letter or "
            "digit, at most 100), so the run stays inside the results directory.")
EMPTY_ROOT = ("is empty; give the results directory (for example results): an empty root would "
              "mean the current directory.")


def _invoke(*args):
    return runner.invoke(app, [str(a) for a in args], catch_exceptions=False)


def _snapshot(root: Path) -> dict[str, str]:
    return {p.relative_to(root).as_posix(): hashlib.sha256(p.read_bytes()).hexdigest()
            for p in sorted(root.rglob("*")) if p.is_file()}


def _refused(root: Path, args, message: str) -> None:
    before = _snapshot(root) if root.is_dir() else None
    result = _invoke(*args)
    assert result.exit_code == 2, result.output
    assert result.stderr == f"error: {message}\n" and result.stdout == ""
    assert (_snapshot(root) if root.is_dir() else None) == before


@pytest.fixture(scope="module")
def finished(tmp_path_factory):
    """A results root with a finished tiny baseline_grid run and a smoke run, both reported."""
    root = tmp_path_factory.mktemp("bad_stores") / "results"
    for args in (["run", "baseline_grid", *BG], ["run", "smoke", *SMOKE], ["report"]):
        done = _invoke(*args, "--root", root)
        assert done.exit_code == 0, done.output
    return root


@pytest.fixture
def results(finished, tmp_path):
    """A copy of the finished results root this test may damage."""
    return Path(shutil.copytree(finished, tmp_path / "results"))


def _grid(root: Path) -> Path:
    return root / "baseline_grid" / "default"


def _advice(root: Path, then: str = "quarantine the file and run its trials again") -> str:
    return f"resume the run (graspcampaign run baseline_grid --run default --root {root}) to {then}."


# -- 1 and 5. the results root, the run name and output paths ------------------------------------
def test_a_root_that_is_not_a_directory_is_refused_before_any_work(finished, tmp_path):
    blocker = tmp_path / "afile"
    blocker.write_text("a file, not a folder")
    records = tmp_path / "m.csv"
    records.write_text("trial_id\n")
    cases = {blocker: f"--root {blocker}: is a file, not a directory.",
             blocker / "sub": f"--root {blocker / 'sub'}: {blocker} is a file, not a directory.",
             Path("/dev/null"): "--root /dev/null: is not a directory."}
    for root, message in cases.items():
        for args in (["run", "smoke", *SMOKE], ["show", "smoke"], ["status", "smoke"], ["report"],
                     ["report", "smoke"], ["reproduce"], ["ingest", "test2_grasp", records],
                     ["schedule", "test2_grasp"]):
            _refused(finished, [*args, "--root", root], message)
    assert sorted(p.name for p in tmp_path.iterdir()) == ["afile", "m.csv"]


def test_an_empty_root_or_run_name_is_refused(finished, tmp_path, monkeypatch):
    monkeypatch.chdir(tmp_path)  # an empty root would have meant here
    records = tmp_path / "m.csv"
    records.write_text("trial_id\n")
    for args in (["run", "smoke", *SMOKE], ["show", "smoke"], ["status", "smoke"], ["report"],
                 ["reproduce"], ["ingest", "test2_grasp", records], ["schedule", "test2_grasp"]):
        _refused(finished, [*args, "--root", ""], f"--root {EMPTY_ROOT}")
    _refused(finished, ["run", "smoke", *SMOKE, "output.root="], f"output.root {EMPTY_ROOT}")
    for args in (["run", "smoke", *SMOKE], ["show", "smoke"], ["status", "smoke"],
                 ["report", "smoke"], ["ingest", "test2_grasp", records]):
        _refused(finished, [*args, "--run", "", "--root", finished], f"--run = '' {RUN_NAME}")
    assert sorted(p.name for p in tmp_path.iterdir()) == ["m.csv"]


@pytest.fixture
def read_only(tmp_path, monkeypatch):
    """A directory on a read-only file system (as root, chmod would not stop a write)."""
    folder = tmp_path / "ro"
    folder.mkdir()
    access, statvfs = os.access, os.statvfs

    def inside(path) -> bool:
        return Path(path) == folder or folder in Path(path).parents

    class ReadOnly:
        f_flag = os.ST_RDONLY

    monkeypatch.setattr(os, "access", lambda p, mode, **kw: False if inside(p) and mode & os.W_OK
                        else access(p, mode, **kw))
    monkeypatch.setattr(os, "statvfs", lambda p: ReadOnly() if inside(p) else statvfs(p))
    return folder


def test_a_read_only_root_or_output_is_refused_before_any_work(finished, read_only, tmp_path):
    ro = "cannot write there (Read-only file system)."
    records = tmp_path / "m.csv"
    records.write_text("trial_id\n")
    for root in (read_only, read_only / "results"):
        for args in (["run", "smoke", *SMOKE], ["reproduce"], ["ingest", "test2_grasp", records],
                     ["schedule", "test2_grasp"]):
            _refused(finished, [*args, "--root", root], f"--root {root}: {ro}")
    # the --times file is checked before the first study runs, not after it
    fresh = tmp_path / "fresh"
    _refused(finished, ["reproduce", "--root", fresh, "--times", read_only / "t.txt"],
             f"--times {read_only / 't.txt'}: {ro}")
    _refused(finished, ["schedule", "test2_grasp", "--out", read_only / "sheet", "--root", fresh],
             f"--out {read_only / 'sheet'}: {ro}")
    assert not fresh.exists() and not any(read_only.iterdir())
    # reading a run needs no write: a read-only root is answered
    shutil.copytree(finished / "smoke", read_only / "smoke")
    assert _invoke("status", "smoke", "--root", read_only).exit_code == 0


def test_an_output_file_that_is_a_directory_gets_the_options_own_hint(finished, tmp_path):
    _refused(finished, ["reproduce", "--root", tmp_path / "fresh", "--times", tmp_path],
             f"--times {tmp_path} is a directory; give a file such as "
             f"{tmp_path / 'reproduce_times.txt'}.")
    assert not (tmp_path / "fresh").exists()


# -- 2. a damaged manifest ----------------------------------------------------------------------------
def _json_error(text: str) -> str:
    try:
        json.loads(text)
    except json.JSONDecodeError as exc:
        return f"not valid JSON: {exc.msg} (line {exc.lineno}, column {exc.colno})"
    raise AssertionError(text)


def _manifest(results: Path) -> dict:
    return json.loads((_grid(results) / "manifest.json").read_text())


MANIFESTS = {
    "truncated": (lambda m: json.dumps(m, indent=2)[:300], None),
    "garbled": (lambda m: json.dumps(m).encode()[:40] + b"\xff\xfe" + json.dumps(m).encode()[42:],
                "not UTF-8 text: byte 40 is 0xff"),
    "zero_bytes": (lambda m: b"", "it is empty"),
    "a_list": (lambda m: "[1, 2]", "it holds a JSON list, not an object of the run's fields"),
    "n_trials_many": (lambda m: json.dumps({**m, "n_trials": "many"}),
                      'n_trials is "many", not a whole number of trials'),
    "config_hash_null": (lambda m: json.dumps({**m, "config_hash": None}),
                         "config_hash is null, not a hash"),
    "no_sessions": (lambda m: json.dumps({k: v for k, v in m.items() if k != "sessions"}),
                    "it has no sessions field"),
}


@pytest.mark.parametrize("case", sorted(MANIFESTS))
def test_a_damaged_manifest_is_refused_by_every_command(results, case):
    make, why = MANIFESTS[case]
    text = make(_manifest(results))
    path = _grid(results) / "manifest.json"
    if isinstance(text, bytes):
        path.write_bytes(text)
    else:
        path.write_text(text)
    why = why or _json_error(text)
    message = (f"run baseline_grid/default at {_grid(results)} has a damaged manifest.json ({why}); "
               "its records cannot be checked without it, so restore the file from a backup or "
               "move the run directory aside and run the study again.")
    for args in (["status", "baseline_grid"], ["show", "baseline_grid", *BG[:5]],
                 ["report", "baseline_grid"], ["run", "baseline_grid", *BG]):
        _refused(results, [*args, "--root", results], message)


# -- 3 (and 2, 4). stored files not what the manifest says, or none; a run refused before it starts
def test_records_without_a_manifest_are_refused_alike_by_every_command(results):
    (_grid(results) / "manifest.json").unlink()
    message = (f"run baseline_grid/default at {_grid(results)} has stored files but no "
               "manifest.json, so what they hold cannot be checked; restore the file from a "
               "backup, or move the run directory aside and run the study again.")
    for args in (["status", "baseline_grid"], ["show", "baseline_grid", *BG[:5]],
                 ["report", "baseline_grid"], ["run", "baseline_grid", *BG]):
        _refused(results, [*args, "--root", results], message)


def test_a_run_refused_before_it_starts_writes_nothing(results, monkeypatch):
    import contextlib

    from graspcampaign.campaign import runner as runner_module
    from graspcampaign.errors import UserInputError

    @contextlib.contextmanager
    def unreachable(study):  # what an unreachable Dask scheduler does, without the wait
        raise UserInputError("runner.address = 'tcp://127.0.0.1:9': no Dask scheduler answered.")
        yield

    monkeypatch.setattr(runner_module, "_executor", unreachable)
    message = "runner.address = 'tcp://127.0.0.1:9': no Dask scheduler answered."
    _refused(results, ["run", "smoke", *SMOKE, "--run", "fresh", "--root", results], message)
    _refused(results, ["run", "baseline_grid", *BG, "--root", results], message)
    assert not (results / "smoke" / "fresh").exists()


def _compact(results: Path) -> Path:
    (path,) = (_grid(results) / "records").glob("compact-*.parquet")
    return path


def _rewritten(source: Path, target: Path, edit) -> None:
    """Write ``edit(table)`` of a verified shard as ``target`` (with ``source``'s metadata)."""
    table = pq.read_table(source)
    pq.write_table(edit(table), target, write_page_checksum=True)


def _with_run(table: pa.Table, run: str) -> pa.Table:
    i = table.schema.get_field_index("run")
    return table.set_column(i, "run", pa.array([run] * table.num_rows))


def _damage_records_file(results):
    records = _grid(results) / "records"
    shutil.rmtree(records)
    records.write_text("not a directory")
    return ("a file records where its records directory belongs", _advice(results),
            records, "file {path} moved to {target} (a file where a directory belongs); its "
                     "trials will run again")


def _renamed_to_csv(results):
    compact = _compact(results)
    renamed = compact.with_suffix(".csv")
    compact.rename(renamed)
    return (f"a file records/{renamed.name} that is not a Parquet shard of the run",
            _advice(results), renamed, "file {path} moved to {target} (not a Parquet shard of "
                                       "the run); its trials will run again")


def _duplicate(results):
    compact = _compact(results)
    copy = compact.with_name("part-dup.parquet")
    shutil.copyfile(compact, copy)
    why = f"every trial also in records/{compact.name}"
    return (f"a duplicate file records/part-dup.parquet ({why})",
            _advice(results, "quarantine the duplicate"), copy,
            "duplicate file {path} moved to {target} (" + why + "); its trials stay recorded in "
            f"records/{compact.name}")


def _foreign_study(results):
    (shard,) = (results / "smoke" / "default" / "records").glob("*.parquet")
    copy = _grid(results) / "records" / "part-foreign.parquet"
    shutil.copyfile(shard, copy)
    return ("a file records/part-foreign.parquet holding records of another study (smoke)",
            _advice(results), copy, "file {path} moved to {target} (records of another study "
                                    "(smoke)); its trials will run again")


def _another_run(results):
    copy = _grid(results) / "records" / "part-other.parquet"
    _rewritten(_compact(results), copy, lambda t: _with_run(t, "other"))
    return ("a file records/part-other.parquet holding records of another run (other)",
            _advice(results), copy, "file {path} moved to {target} (records of another run "
                                    "(other)); its trials will run again")


def _another_config(results):
    copy = _grid(results) / "records" / "part-config.parquet"
    _rewritten(_compact(results), copy, lambda t: t.replace_schema_metadata(
        {b"graspcampaign.config_hashes": b'["0123456789abcdef"]'}))
    why = "records run with another config (hash 0123456789abcdef, not one this run ran with)"
    return (f"a file records/part-config.parquet holding {why}", _advice(results), copy,
            "file {path} moved to {target} (" + why + "); its trials will run again")


def _twice_in_one_file(results):
    compact = _compact(results)
    table = pq.read_table(compact)
    pq.write_table(pa.concat_tables([table, table]), compact, write_page_checksum=True)
    return (f"a file records/{compact.name} that records 2 trials twice", _advice(results),
            compact, "file {path} moved to {target} (it records 2 trials twice); its trials will "
                     "run again")


def _records_removed(results):
    shutil.rmtree(_grid(results) / "records")
    return ("missing records: its manifest counts 2 recorded trials but 0 are stored (records/ is "
            "missing)", _advice(results, "run the missing trials again"), None,
            f"run baseline_grid/default at {_grid(results)}: its manifest counts 2 recorded trials "
            "but 0 are stored; the missing ones run again")


def _records_emptied(results):
    _compact(results).unlink()
    return ("missing records: its manifest counts 2 recorded trials but 0 are stored (records/ is "
            "empty)", _advice(results, "run the missing trials again"), None,
            f"run baseline_grid/default at {_grid(results)}: its manifest counts 2 recorded trials "
            "but 0 are stored; the missing ones run again")


def _partly_duplicated(results):
    compact = _compact(results)
    table = pq.read_table(compact)
    first, both = compact.with_name("part-a.parquet"), compact.with_name("part-b.parquet")
    pq.write_table(table.slice(0, 1), first, write_page_checksum=True)
    pq.write_table(table, both, write_page_checksum=True)
    compact.unlink()
    why = "1 of its 2 trials also in records/part-a.parquet"
    return (f"a duplicate file records/part-b.parquet ({why})", _advice(results), both,
            "file {path} moved to {target} (" + why + "); its trials will run again")


DAMAGES = {f.__name__.lstrip("_"): f for f in (
    _damage_records_file, _renamed_to_csv, _duplicate, _partly_duplicated, _foreign_study,
    _another_run, _another_config, _twice_in_one_file, _records_removed, _records_emptied)}
#: trials that run again after the repair: none where the file was added beside the run's own
#: records, the other trial of a partly duplicated file, every trial where the run's file went
RERUN = {"duplicate": 0, "foreign_study": 0, "another_run": 0, "another_config": 0,
         "partly_duplicated": 1}


@pytest.mark.parametrize("case", sorted(DAMAGES))
def test_a_run_not_what_its_manifest_says_is_refused_then_repaired_by_run(results, case):
    text, advice, offending, warning = DAMAGES[case](results)
    kept = offending.read_bytes() if offending is not None else None
    message = f"run baseline_grid/default at {_grid(results)} has {text}; {advice}"
    for args in (["status", "baseline_grid"], ["show", "baseline_grid", *BG[:5]],
                 ["report", "baseline_grid"]):
        _refused(results, [*args, "--root", results], message)
    # the advice works: resuming the run moves the file aside (never deletes it), then every
    # command reads the run again
    repaired = _invoke("run", "baseline_grid", *BG, "runner.progress=false", "--root", results)
    assert repaired.exit_code == 0, repaired.output
    quarantined = None
    if offending is not None:
        quarantined = _grid(results) / "quarantine" / offending.relative_to(_grid(results)) \
            .as_posix().replace("/", "__")
        assert quarantined.read_bytes() == kept
    assert repaired.stderr == "warning: " + warning.format(path=offending, target=quarantined) + "\n"
    ran = RERUN.get(case, 2)
    assert f"2 trials, {2 - ran} already recorded, {ran} ran" in repaired.stdout
    status = _invoke("status", "baseline_grid", "--root", results, "--json")
    assert status.exit_code == 0, status.output
    assert json.loads(status.stdout)["n_recorded"] == 2
    assert RunStore(_grid(results)).check() is not None


def test_a_file_in_place_of_the_run_directory_is_refused_by_every_command(results):
    shutil.rmtree(_grid(results))
    _grid(results).write_text("not a run")
    message = (f"run baseline_grid/default at {_grid(results)} is a file, not a run directory; "
               "move it aside or choose another run name (--run NAME).")
    for args in (["status", "baseline_grid"], ["show", "baseline_grid", *BG[:5]],
                 ["report", "baseline_grid"], ["run", "baseline_grid", *BG]):
        _refused(results, [*args, "--root", results], message)


def test_run_never_writes_into_measured_records_nor_ingest_into_simulated_ones(results, tmp_path):
    measured = results / "baseline_grid" / "measured"
    shutil.copytree(_grid(results), measured)
    manifest = json.loads((measured / "manifest.json").read_text())
    (measured / "manifest.json").write_text(json.dumps({**manifest, "source": "measured"}))
    _refused(results, ["run", "baseline_grid", *BG, "--run", "measured", "--root", results],
             f"run baseline_grid/measured at {measured} holds measured records (ingested); `run` "
             "never adds simulated or virtual trials to them, so choose another run name "
             "(--run NAME).")
    simulated = results / "test2_grasp" / "default"
    shutil.copytree(_grid(results), simulated)
    sheet = tmp_path / "m.csv"
    sheet.write_text("trial_id\n")
    _refused(results, ["ingest", "test2_grasp", sheet, "--run", "default", "--root", results],
             f"run test2_grasp/default at {simulated} holds simulation records (from `graspcampaign "
             "run`); measured records are stored in a run of their own, so choose another run "
             "name (--run NAME; default measured).")


# -- 4. reports check first and never overwrite good pages ------------------------------------------
def test_report_checks_every_named_study_before_writing_any(results):
    shutil.rmtree(_grid(results) / "report")  # so that a report written before failing shows
    from graspcampaign.campaign.studyfile import list_studies

    _refused(results, ["report", "baseline_grid", "nosuch_study", "--root", results],
             f"unknown study 'nosuch_study': not on the config search path and no records under "
             f"{results}; available studies: {', '.join(list_studies())}.")
    _refused(results, ["report", "ablation", "--root", results],  # known, never run here
             f"no records for study 'ablation' under {results}; run it first.")
    _refused(results, ["report", "smoke", "baseline_grid", "--run", "nosuch", "--root", results],
             f"no run 'nosuch' of study 'smoke' under {results}.")


def test_a_run_that_cannot_be_read_never_replaces_what_the_root_pages_say(results):
    _duplicate(results)
    pages = {p.name: p.read_bytes() for p in results.glob("*.*")}
    assert sorted(pages) == ["headline.csv", "headline.md", "index.md"]
    why = (f"run baseline_grid/default at {_grid(results)} has a duplicate file "
           f"records/part-dup.parquet (every trial also in records/{_compact(results).name}); "
           + _advice(results, "quarantine the duplicate")[:-1])
    left = f"warning: the headline and index pages were left as they were: run " \
           f"baseline_grid/default cannot be read ({why})\n"
    # every run: the others are reported, the damaged one is named, the pages stay as they were
    every = _invoke("report", "--root", results)
    assert every.exit_code == 2
    assert every.stdout == f"report: {results / 'smoke' / 'default' / 'report' / 'report.md'}\n"
    assert every.stderr == left + f"error: the report of baseline_grid/default could not be " \
                                  f"written: {why}\n"
    assert {p.name: p.read_bytes() for p in results.glob("*.*")} == pages
    # another study's report is written; the pages still say what they said of the damaged run
    other = _invoke("report", "smoke", "--root", results)
    assert other.exit_code == 0 and other.stderr == left
    assert {p.name: p.read_bytes() for p in results.glob("*.*")} == pages


# -- 6. a damaged trace table: the advice works -------------------------------------------------------
def test_the_advice_for_an_unidentifiable_trace_file_is_true(results):
    (trace,) = (_grid(results) / "tables" / "candidates").glob("*.parquet")
    trace.write_bytes(b"x" * 100)  # neither its footer nor its trial ids can be read
    why = ("Parquet magic bytes not found in footer. Either the file is corrupted or this is not a "
           "parquet file.")
    _refused(results, ["report", "baseline_grid", "--root", results],
             f"run baseline_grid/default at {_grid(results)} has a damaged file "
             f"tables/candidates/{trace.name} ({why}); {_advice(results)}")
    repaired = _invoke("run", "baseline_grid", *BG, "runner.progress=false", "--root", results)
    assert repaired.exit_code == 0, repaired.output
    target = _grid(results) / "quarantine" / f"tables__candidates__{trace.name}"
    assert repaired.stderr == (f"warning: damaged file {trace} moved to {target} ({why}); its "
                               "trials will run again\n")
    assert "2 ran" in repaired.stdout and target.read_bytes() == b"x" * 100
    store = RunStore(_grid(results))
    assert store.check() is not None and len(store.read("tables/candidates")) > 0


# -- 7. a directory where a file belongs -------------------------------------------------------------
def test_a_directory_given_for_a_file_is_named_as_one(results, tmp_path):
    folder = tmp_path / "adir.yaml"
    folder.mkdir()
    for command in ("show", "run"):
        _refused(results, [command, folder, "--root", results],
                 f"study file {folder} is a directory, not a file.")
    _refused(results, ["ingest", "test2_grasp", tmp_path, "--root", results],
             f"{tmp_path} is a directory, not a file of measured records.")


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
    assert _cross_check(run) == ("No `baseline_grid` records beside this run (run default skipped: "
                                 "it cannot be read): the re-derived trials were not cross-checked "
                                 "against them.")


def test_a_trial_in_two_baseline_runs_is_cross_checked_once(results):
    """Two readable baseline_grid runs holding the same trials (a copy kept under another name):
    each re-derived trial is compared once, not once per run."""

    from graspcampaign.report.render import Run
    from graspcampaign.report.studies.mesh_resolution import _cross_check

    shutil.copytree(_grid(results), _grid(results).with_name("again"))
    base = RunStore(_grid(results)).read().to_pandas()
    key = ["shape", "mass_kg", "mu", "planner", "seed"]
    records = base[key + ["success", "residual_norm_n"]].assign(
        trial_id=[f"t{i}" for i in range(len(base))], status="ok", panel="n_max")
    run = Run(records, {}, store=RunStore(results / "mesh_resolution" / "default"))
    assert _cross_check(run) == (f"Cross-check against the `baseline_grid` records beside this run: "
                                 f"{len(base)} of {len(base)} re-derived trials have the baseline's "
                                 f"verdict and {len(base)} its residual (relative 1e-9).")
