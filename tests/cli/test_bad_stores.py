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

import errno
import json
import os
import shutil
import sys
import tempfile
from pathlib import Path

import pyarrow as pa
import pyarrow.parquet as pq
import pytest
from cli_checks import invoke, refused, snapshot

from graspcampaign.campaign.records import CONTENT_KEY, RunStore, content_digest

#: the tiny baseline_grid run: one scene, the proposed planner and Ferrari-Canny, a cheap PSO
BG = ["seeds=1", "shape=[sphere]", "mass_kg=[0.2]", "mu=[0.3]", "planner=[heuristic,ferrari_canny]",
      "pso.n_particles=2", "pso.n_iterations=1", "runner.backend=sequential", "runner.batch_size=1"]
SMOKE = ["shape=[sphere]", "nodes=[144]", "runner.backend=sequential"]
RUN_NAME = ("is not allowed; use letters, digits, '.', '_' and '-' (starting with a letter or "
            "digit, at most 100), so the run stays inside the results directory.")
EMPTY_ROOT = ("is empty; give the results directory (for example results): an empty root would "
              "mean the current directory.")


@pytest.fixture(scope="module")
def finished(tmp_path_factory):
    """A results root with a finished tiny baseline_grid run and a smoke run, both reported."""
    root = tmp_path_factory.mktemp("bad_stores") / "results"
    for args in (["run", "baseline_grid", *BG], ["run", "smoke", *SMOKE], ["report"]):
        done = invoke(*args, "--root", root)
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
            refused(finished, [*args, "--root", root], message)
    assert sorted(p.name for p in tmp_path.iterdir()) == ["afile", "m.csv"]


def test_an_empty_root_or_run_name_isrefused(finished, tmp_path, monkeypatch):
    monkeypatch.chdir(tmp_path)  # an empty root would have meant here
    records = tmp_path / "m.csv"
    records.write_text("trial_id\n")
    for args in (["run", "smoke", *SMOKE], ["show", "smoke"], ["status", "smoke"], ["report"],
                 ["reproduce"], ["ingest", "test2_grasp", records], ["schedule", "test2_grasp"]):
        refused(finished, [*args, "--root", ""], f"--root {EMPTY_ROOT}")
    refused(finished, ["run", "smoke", *SMOKE, "output.root="], f"output.root {EMPTY_ROOT}")
    for args in (["run", "smoke", *SMOKE], ["show", "smoke"], ["status", "smoke"],
                 ["report", "smoke"], ["ingest", "test2_grasp", records]):
        refused(finished, [*args, "--run", "", "--root", finished], f"--run = '' {RUN_NAME}")
    assert sorted(p.name for p in tmp_path.iterdir()) == ["m.csv"]


@pytest.fixture
def read_only(tmp_path, monkeypatch):
    """A directory on a read-only file system (as root, chmod would not stop a write)."""
    folder = tmp_path / "ro"
    folder.mkdir()
    mkstemp = tempfile.mkstemp

    def probe(*args, dir=None, **kwargs):
        if dir is not None and (Path(dir) == folder or folder in Path(dir).parents):
            raise OSError(errno.EROFS, os.strerror(errno.EROFS))
        return mkstemp(*args, dir=dir, **kwargs)

    monkeypatch.setattr(tempfile, "mkstemp", probe)
    return folder


def test_a_read_only_root_or_output_is_refused_before_any_work(finished, read_only, tmp_path):
    ro = "cannot write there (Read-only file system)."
    records = tmp_path / "m.csv"
    records.write_text("trial_id\n")
    for root in (read_only, read_only / "results"):
        for args in (["run", "smoke", *SMOKE], ["reproduce"], ["ingest", "test2_grasp", records],
                     ["schedule", "test2_grasp"]):
            refused(finished, [*args, "--root", root], f"--root {root}: {ro}")
    # the --times file is checked before the first study runs, not after it
    fresh = tmp_path / "fresh"
    refused(finished, ["reproduce", "--root", fresh, "--times", read_only / "t.txt"],
            f"--times {read_only / 't.txt'}: {ro}")
    refused(finished, ["schedule", "test2_grasp", "--out", read_only / "sheet", "--root", fresh],
            f"--out {read_only / 'sheet'}: {ro}")
    assert not fresh.exists() and not any(read_only.iterdir())
    # reading a run needs no write: a read-only root is answered
    shutil.copytree(finished / "smoke", read_only / "smoke")
    assert invoke("status", "smoke", "--root", read_only).exit_code == 0


@pytest.mark.skipif(not sys.platform.startswith("linux"), reason="/proc takes no new files on Linux")
def test_a_root_where_no_file_can_be_created_is_refused_before_any_work(finished):
    # permission bits let root write into /proc, yet no file can be created there: the root is
    # judged by the rule the picture path of plan obeys (a probe), not by os.access
    no_files = "cannot write there (No such file or directory)."
    for args in (["run", "smoke", *SMOKE], ["schedule", "test2_grasp"]):
        refused(finished, [*args, "--root", "/proc/results"], f"--root /proc/results: {no_files}")
    refused(finished, ["schedule", "test2_grasp", "--out", "/proc/sheet", "--root", finished],
            f"--out /proc/sheet: {no_files}")


def test_an_output_file_that_is_a_directory_gets_the_options_own_hint(finished, tmp_path):
    refused(finished, ["reproduce", "--root", tmp_path / "fresh", "--times", tmp_path],
            f"--times {tmp_path} is a directory; give a file such as "
            f"{tmp_path / 'reproduce_times.txt'}.")
    assert not (tmp_path / "fresh").exists()


@pytest.mark.parametrize("option", ["--out", "--times"])
def test_a_named_pipe_given_for_an_output_file_is_refused_at_once(finished, tmp_path, option):
    pipe = tmp_path / "pipe"
    os.mkfifo(pipe)  # opening it to write would wait for a reader
    args = {"--out": ["schedule", "test2_grasp", "--out", pipe, "--root", finished],
            "--times": ["reproduce", "--root", tmp_path / "fresh", "--times", pipe]}[option]
    refused(finished, args, f"{option} {pipe}: is a named pipe (FIFO), not a regular file.",
            seconds=5)
    assert sorted(p.name for p in tmp_path.iterdir()) == ["pipe"]


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
    # status once reported such a run's source as null, then as "simulation" (the report's
    # fallback): neither, the run is refused as every command refuses it (docs/decisions.md)
    "no_source": (lambda m: json.dumps({k: v for k, v in m.items() if k != "source"}),
                  "it has no source field"),
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
        refused(results, [*args, "--root", results], message)


# -- 3 (and 2, 4). stored files not what the manifest says, or none; a run refused before it starts
def test_records_without_a_manifest_are_refused_alike_by_every_command(results):
    (_grid(results) / "manifest.json").unlink()
    message = (f"run baseline_grid/default at {_grid(results)} has stored files but no "
               "manifest.json, so what they hold cannot be checked; restore the file from a "
               "backup, or move the run directory aside and run the study again.")
    for args in (["status", "baseline_grid"], ["show", "baseline_grid", *BG[:5]],
                 ["report", "baseline_grid"], ["run", "baseline_grid", *BG]):
        refused(results, [*args, "--root", results], message)


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
    refused(results, ["run", "smoke", *SMOKE, "--run", "fresh", "--root", results], message)
    refused(results, ["run", "baseline_grid", *BG, "--root", results], message)
    assert not (results / "smoke" / "fresh").exists()


def _compact(results: Path) -> Path:
    (path,) = (_grid(results) / "records").glob("compact-*.parquet")
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
    _as_written(pa.concat_tables([table, table]), compact)
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
    _as_written(table.slice(0, 1), first)
    _as_written(table, both)
    compact.unlink()
    why = "1 of its 2 trials also in records/part-a.parquet"
    return (f"a duplicate file records/part-b.parquet ({why})", _advice(results), both,
            "file {path} moved to {target} (" + why + "); its trials will run again")


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
        return (text, _advice(results), compact, ("damaged file" if damaged else "file") +
                " {path} moved to {target} (" + reason + "); its trials will run again")
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
    message = f"run baseline_grid/default at {_grid(results)} has {text}; {advice}"
    for args in (["status", "baseline_grid"], ["show", "baseline_grid", *BG[:5]],
                 ["report", "baseline_grid"]):
        refused(results, [*args, "--root", results], message)
    # the advice works: resuming the run moves the file aside (never deletes it), then every
    # command reads the run again
    repaired = invoke("run", "baseline_grid", *BG, "runner.progress=false", "--root", results)
    assert repaired.exit_code == 0, repaired.output
    quarantined = None
    if offending is not None:
        quarantined = _grid(results) / "quarantine" / offending.relative_to(_grid(results)) \
            .as_posix().replace("/", "__")
        assert quarantined.read_bytes() == kept
    assert repaired.stderr == "warning: " + warning.format(path=offending, target=quarantined) + "\n"
    ran = RERUN.get(case, 2)
    assert f"2 trials, {2 - ran} already recorded, {ran} ran" in repaired.stdout
    status = invoke("status", "baseline_grid", "--root", results, "--json")
    assert status.exit_code == 0, status.output
    assert json.loads(status.stdout)["n_recorded"] == 2
    assert RunStore(_grid(results)).check() is not None


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
            f"run baseline_grid/default at {_grid(results)} has missing records: {missing}; "
            f"{_advice(results, 'run the missing trials again')}")
    for already, ran in ((1, 1), (2, 0)):  # the advice works once, then nothing is left to run
        again = invoke("run", "baseline_grid", *BG, "runner.progress=false", "--root", results)
        assert again.exit_code == 0, again.output
        assert f"2 trials, {already} already recorded, {ran} ran" in again.stdout
    status = invoke("status", "baseline_grid", "--root", results, "--json")
    assert status.exit_code == 0 and json.loads(status.stdout)["n_recorded"] == 2
    assert gone in RunStore(_grid(results)).recorded_ids()


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
        f"warning: run baseline_grid/default at {_grid(results)}: {missing}; the missing ones run "
        f"again\nerror: run baseline_grid/default at {_grid(results)} has missing records: "
        f"{missing} (records/ is empty); {_advice(results, 'run the missing trials again')}\n")


def test_run_quarantines_records_of_a_trial_outside_its_design(results):
    """A well-formed trial id no trial of the design has (the file rewritten as the tool writes
    files): `status` cannot tell without composing the design, `run` does and repairs."""
    foreign = "sphere_0.2_0.3_heuristic_s0-0123456789"
    compact = _edited(results, lambda t: _set(t, "trial_id", [foreign, *t["trial_id"].to_pylist()[1:]]),
                      True)
    kept = compact.read_bytes()
    repaired = invoke("run", "baseline_grid", *BG, "runner.progress=false", "--root", results)
    assert repaired.exit_code == 0, repaired.output
    target = _grid(results) / "quarantine" / f"records__{compact.name}"
    assert repaired.stderr == (f"warning: file {compact} moved to {target} (records of 1 trial not "
                               f"in the study's design ({foreign})); its trials will run again\n")
    assert "2 trials, 0 already recorded, 2 ran" in repaired.stdout
    assert target.read_bytes() == kept
    store = RunStore(_grid(results))
    assert store.check() is not None and foreign not in store.recorded_ids()
    assert len(store.recorded_ids()) == 2


def _config_edited(m: dict) -> dict:
    config = json.loads(json.dumps(m["config"]))
    config["factors"]["mu"] = [0.4]
    return {**m, "config": config}


_RESTORE = "restore the file from a backup"
#: manifest edits that make it describe another run than the one stored, and why that is seen
MISMATCHES = {
    "source_measured": (lambda m: {**m, "source": "measured"},
                        "source is 'measured', but trial kind quasi_static makes simulation records",
                        _RESTORE),
    "study_renamed": (lambda m: {**m, "study": "shapes"},
                      "study is 'shapes', but the run is stored as baseline_grid/default",
                      f"{_RESTORE}, or put a moved run directory back as shapes/default"),
    "run_renamed": (lambda m: {**m, "run": "other"},
                    "run is 'other', but the run is stored as baseline_grid/default",
                    f"{_RESTORE}, or put a moved run directory back as baseline_grid/other"),
    "kind_changed": (lambda m: {**m, "kind": "mesh_features"},
                     "kind is 'mesh_features', but its config says 'quasi_static'", _RESTORE),
    "fewer_trials": (lambda m: {**m, "n_trials": 1},
                     "n_trials is 1, but it stores 2 trials of its one config", _RESTORE),
    "more_trials": (lambda m: {**m, "n_trials": 5},
                    "n_trials is 5, but the finished run stores 2 trials of its one config",
                    _RESTORE),
    "config_edited": (_config_edited, None, _RESTORE),
}


@pytest.mark.parametrize("case", sorted(MISMATCHES))
def test_a_manifest_that_does_not_describe_its_run_is_refused_by_every_command(results, case):
    edit, why, advice = MISMATCHES[case]
    path = _grid(results) / "manifest.json"
    manifest = json.loads(path.read_text())
    path.write_text(json.dumps(edit(manifest), indent=2))
    if why is None:  # the hash of the edited config, as composing that config gives it
        from graspcampaign.campaign.compose import compose_study
        from graspcampaign.campaign.provenance import config_hash

        edited = config_hash(compose_study("baseline_grid", [*BG, "mu=[0.4]"]))
        why = f"config_hash is {manifest['config_hash']}, but its config hashes to {edited}"
    message = (f"run baseline_grid/default at {_grid(results)} has a manifest.json that does not "
               f"match the run ({why}); {advice}.")
    for args in (["status", "baseline_grid"], ["show", "baseline_grid", *BG[:5]],
                 ["report", "baseline_grid"], ["run", "baseline_grid", *BG]):
        refused(results, [*args, "--root", results], message)


def test_a_session_that_names_no_config_is_not_held_to_the_runs_one_config(results):
    """A session of an earlier ``ingest`` named no config: it may have run another design, so the
    manifest's n_trials is not the count of a run under one config (integrity, as status counts)."""
    path = _grid(results) / "manifest.json"
    manifest = json.loads(path.read_text())
    earlier = {k: v for k, v in manifest["sessions"][0].items() if k != "config_hash"}
    path.write_text(json.dumps({**manifest, "n_trials": 5,
                                "sessions": [*manifest["sessions"], earlier]}, indent=2))
    status = invoke("status", "baseline_grid", "--json", "--root", results)
    assert status.exit_code == 0, status.output
    assert json.loads(status.stdout)["n_recorded"] == len(pq.read_table(
        _grid(results) / "records", columns=["trial_id"]))


# -- a full disk: one sentence, no temporary file left, nothing stored lost --------------------------
def _disk_full(path) -> OSError:
    return OSError(errno.ENOSPC, os.strerror(errno.ENOSPC), str(path))


def test_a_full_disk_while_writing_the_manifest_changes_nothing(results, monkeypatch):
    write_text = Path.write_text

    def full(self, *args, **kwargs):
        if self.name.endswith(".tmp"):
            write_text(self, "")  # what a full disk leaves: an empty file
            raise _disk_full(self)
        return write_text(self, *args, **kwargs)

    monkeypatch.setattr(Path, "write_text", full)
    smoke = results / "smoke" / "default"
    refused(results, ["run", "smoke", *SMOKE, "--root", results],
            f"cannot write {smoke / 'manifest.json'}: no space left on device; what was stored "
            "before is kept, so free some space there and run the command again.")


def test_a_full_disk_while_writing_records_loses_nothing_and_the_run_resumes(results, monkeypatch):
    import re

    write_table = pq.write_table

    def full(table, where, *args, **kwargs):
        Path(where).write_bytes(b"PAR1")  # a partly written file
        raise _disk_full(where)

    before = snapshot(results)
    monkeypatch.setattr(pq, "write_table", full)
    fresh = results / "smoke" / "fresh"
    result = invoke("run", "smoke", *SMOKE, "runner.progress=false", "--run", "fresh",
                    "--root", results)
    assert result.exit_code == 2 and result.stdout == ""
    assert re.fullmatch(rf"error: cannot write {re.escape(str(fresh / 'records'))}/part-[0-9a-f]{{10}}"
                        r"\.parquet: no space left on device; what was stored before is kept, so "
                        r"free some space there and run the command again\.\n", result.stderr)
    after = snapshot(results)
    assert not [p for p in after if p.endswith(".tmp")]
    assert {p: h for p, h in after.items() if not p.startswith("smoke/fresh")} == before
    assert sorted(p for p in after if p.startswith("smoke/fresh/")) == [
        "smoke/fresh/manifest.json", "smoke/fresh/records"]  # the started run, no record file
    monkeypatch.setattr(pq, "write_table", write_table)
    resumed = invoke("run", "smoke", *SMOKE, "runner.progress=false", "--run", "fresh",
                     "--root", results)
    assert resumed.exit_code == 0 and "1 trial, 0 already recorded, 1 ran" in resumed.stdout


def test_a_full_disk_anywhere_else_is_one_sentence(results, monkeypatch):
    write_text = Path.write_text

    def full(self, *args, **kwargs):
        if self.name == "index.md":  # the root pages, written after the runs' reports
            raise _disk_full(self)
        return write_text(self, *args, **kwargs)

    monkeypatch.setattr(Path, "write_text", full)
    result = invoke("report", "smoke", "--root", results)
    assert result.exit_code == 2 and result.stdout == ""
    assert result.stderr == (f"error: cannot write {results / 'index.md'}: no space left on device; "
                             "free some space there and run the command again.\n")


# -- a directory given as the results root that holds no runs -------------------------------------
def test_report_on_a_root_without_runs_says_so(finished, tmp_path):
    empty = tmp_path / "empty"
    empty.mkdir()
    refused(finished, ["report", "--root", empty],
            f"no runs under {empty}; run a study first (graspcampaign run STUDY --root {empty}).")
    for args in (["report"], ["report", "smoke"]):
        refused(finished, [*args, "--root", _grid(finished)],
                f"no runs under {_grid(finished)}: it is the directory of run "
                f"baseline_grid/default; give the results root that holds it (--root {finished}).")
        refused(finished, [*args, "--root", finished / "smoke"],
                f"no runs under {finished / 'smoke'}: it holds the runs of study smoke; give the "
                f"results root that holds it (--root {finished}).")
    assert not any(empty.iterdir())


def test_report_skips_what_cannot_be_read_and_folders_that_are_no_runs(finished, tmp_path,
                                                                        monkeypatch):
    """As under /proc (an entry that cannot even be looked at) and /sys (folders of folders, none
    a run: /sys/firmware/acpi/tables): no traceback, no "broken run", the root holds no runs."""
    junk = tmp_path / "junk"
    (junk / "firmware" / "acpi" / "tables").mkdir(parents=True)
    (junk / "firmware" / "acpi" / "tables" / "DSDT").write_bytes(b"\0")
    (junk / "firmware" / "acpi" / "pm_profile").write_text("0\n")
    (junk / "1" / "cwd").mkdir(parents=True)
    stat = os.stat

    def locked(path, *args, **kwargs):
        if os.fspath(path).endswith("cwd"):
            raise PermissionError(13, "Permission denied", os.fspath(path))
        return stat(path, *args, **kwargs)

    def unlisted(path):
        raise PermissionError(13, "Permission denied", os.fspath(path))

    before = snapshot(junk)
    none = f"no runs under {junk}; run a study first (graspcampaign run STUDY --root {junk})."
    for patch, message in (((), none), (("stat", locked), none),
                           (("listdir", unlisted), f"cannot list the runs under {junk} "
                                                   "(Permission denied).")):
        if patch:
            monkeypatch.setattr(os, *patch)
        result = invoke("report", "--root", junk)
        monkeypatch.undo()
        assert (result.exit_code, result.stdout, result.stderr) == (2, "", f"error: {message}\n")
    assert snapshot(junk) == before


def test_a_file_in_place_of_the_run_directory_is_refused_by_every_command(results):
    shutil.rmtree(_grid(results))
    _grid(results).write_text("not a run")
    message = (f"run baseline_grid/default at {_grid(results)} is a file, not a run directory; "
               "move it aside or choose another run name (--run NAME).")
    for args in (["status", "baseline_grid"], ["show", "baseline_grid", *BG[:5]],
                 ["report", "baseline_grid"], ["run", "baseline_grid", *BG]):
        refused(results, [*args, "--root", results], message)


def test_run_never_writes_into_measured_records_nor_ingest_into_simulated_ones(results, tmp_path):
    from graspcampaign.campaign.compose import compose_study
    from graspcampaign.campaign.provenance import new_manifest, write_manifest

    # a protocol's runs as `ingest` (measured) and `run` (the virtual rig) start them
    study = compose_study("test2_grasp", [f"output.root={results}"])
    for run, source in (("measured", "measured"), ("default", "virtual")):
        write_manifest(results / "test2_grasp" / run / "manifest.json",
                       new_manifest(study, run, 10, source))
    refused(results, ["run", "test2_grasp", "--run", "measured", "--root", results],
            f"run test2_grasp/measured at {results / 'test2_grasp' / 'measured'} holds measured "
            "records (ingested); `run` never adds simulated or virtual trials to them, so choose "
            "another run name (--run NAME).")
    sheet = tmp_path / "m.csv"
    sheet.write_text("trial_id\n")
    refused(results, ["ingest", "test2_grasp", sheet, "--run", "default", "--root", results],
            f"run test2_grasp/default at {results / 'test2_grasp' / 'default'} holds virtual "
            "records (from `graspcampaign run`); measured records are stored in a run of their "
            "own, so choose another run name (--run NAME; default measured).")


# -- 4. reports check first and never overwrite good pages ------------------------------------------
def test_report_checks_every_named_study_before_writing_any(results):
    shutil.rmtree(_grid(results) / "report")  # so that a report written before failing shows
    from graspcampaign.campaign.studyfile import list_studies

    refused(results, ["report", "baseline_grid", "nosuch_study", "--root", results],
            f"unknown study 'nosuch_study': not on the config search path and no records under "
            f"{results}; available studies: {', '.join(list_studies())}.")
    refused(results, ["report", "ablation", "--root", results],  # known, never run here
            f"no records for study 'ablation' under {results}; run it first.")
    refused(results, ["report", "smoke", "baseline_grid", "--run", "nosuch", "--root", results],
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
    (trace,) = (_grid(results) / "tables" / "candidates").glob("*.parquet")
    trace.write_bytes(b"x" * 100)  # neither its footer nor its trial ids can be read
    why = ("Parquet magic bytes not found in footer. Either the file is corrupted or this is not a "
           "parquet file.")
    refused(results, ["report", "baseline_grid", "--root", results],
            f"run baseline_grid/default at {_grid(results)} has a damaged file "
            f"tables/candidates/{trace.name} ({why}); {_advice(results)}")
    repaired = invoke("run", "baseline_grid", *BG, "runner.progress=false", "--root", results)
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
        refused(results, [command, folder, "--root", results],
                f"study file {folder} is a directory, not a file.")
    refused(results, ["ingest", "test2_grasp", tmp_path, "--root", results],
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

    again = invoke("run", "baseline_grid", *BG, "runner.progress=false", "--run", "again",
                   "--root", results)
    assert again.exit_code == 0, again.output
    base = RunStore(_grid(results)).read().to_pandas()
    key = ["shape", "mass_kg", "mu", "planner", "seed"]
    records = base[key + ["success", "residual_norm_n"]].assign(
        trial_id=[f"t{i}" for i in range(len(base))], status="ok", panel="n_max")
    run = Run(records, {}, store=RunStore(results / "mesh_resolution" / "default"))
    assert _cross_check(run) == (f"Cross-check against the `baseline_grid` records beside this run: "
                                 f"{len(base)} of {len(base)} re-derived trials have the baseline's "
                                 f"verdict and {len(base)} its residual (relative 1e-9).")


def test_a_named_pipe_in_place_of_a_schedule_file_is_refused_at_once(finished, tmp_path):
    # --out is a stem: schedule writes <stem>.csv and <stem>.parquet, each checked before any work
    os.mkfifo(tmp_path / "sheet.csv")
    refused(finished, ["schedule", "test2_grasp", "--out", tmp_path / "sheet", "--root", finished],
            f"--out {tmp_path / 'sheet'}: sheet.csv is a named pipe (FIFO), not a regular file.",
            seconds=5)
    assert sorted(p.name for p in tmp_path.iterdir()) == ["sheet.csv"]
