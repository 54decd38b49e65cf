"""Bad input, round 8: a quoted comma in a long override, an old or encrypted Excel workbook given
to ingest, a negative ``runner.n_jobs`` beyond the machine's cores, an unfinished source run of
dynamic_check, two new runs of one run started at once, and the odd roots, options and files of
round 8's table (the final report of branch bad8).
Each refusal: exit 2, one sentence naming what is wrong and where, nothing stored changed
(``refused``)."""

from __future__ import annotations

import builtins
import errno
import fcntl
import io
import os
import shutil
import zipfile
from pathlib import Path

import pandas as pd
import pytest
import trimesh
from cli_checks import BG, SMOKE, invoke, refused, replaced, snapshot, unfinished_source

from graspcampaign.campaign import studyfile


def test_a_comma_inside_a_quoted_string_separates_no_values(results):
    """A quoted level holding 2,500 commas was refused as "2,500 comma-separated values, more than
    an override can hold"; Hydra reads it as one string, in linear time, so its own check speaks."""
    text = ",".join(["a"] * 2500)
    refused(results, ["show", "smoke", f"shape=['{text}']", "--root", results],
            f"factors.shape[0] has unknown value '{text[:60]}... ({len(text)} characters)'; "
            "allowed values: sphere, ellipsoid, rounded_cube, pear, handle.", seconds=10)


#: how a Microsoft compound document begins ([MS-CFB] 2.2), and a stream name in one (UTF-16)
COMPOUND = bytes.fromhex("d0cf11e0a1b11ae1") + bytes(504)
OLD_EXCEL = ("the file is an old-format Excel workbook (.xls), which ingest does not read; open it "
             "in a spreadsheet program and save it as .xlsx or as CSV UTF-8.")
ENCRYPTED = ("the file is an Excel workbook saved with a password (encrypted), which cannot be "
             "read; open it in a spreadsheet program, remove the password and save it again.")


@pytest.mark.parametrize(("name", "stream", "message"), [
    ("day1.xls", "Workbook", OLD_EXCEL),  # it said "unsupported file type '.xls'"
    # these said "... does not begin as one does; if it is CSV text, rename it to day1.csv."
    ("day1.xlsx", "Workbook", OLD_EXCEL),
    ("day1.xlsx", "EncryptedPackage", ENCRYPTED),
    ("day1.csv", "EncryptedPackage", ENCRYPTED),  # it said "the file is not UTF-8 text (byte 0xd0)"
])
def test_an_old_or_encrypted_excel_workbook_is_named_as_one(results, tmp_path, name, stream, message):
    path = tmp_path / name
    path.write_bytes(COMPOUND + stream.encode("utf-16-le") + bytes(64))
    refused(results, ["ingest", "test2_grasp", path, "--root", results], f"{name}: {message}")


@pytest.mark.parametrize(("name", "make", "message"), [
    # these two said "the file cannot be read as xlsx (BadZipFile)." and "... parquet (ArrowInvalid)."
    ("day1.xlsx", lambda path: pd.DataFrame({"trial_id": ["a"]}).to_excel(path, index=False),
     "the file cannot be read as xlsx (BadZipFile); it is damaged or incomplete (a copy cut short?): "
     "copy or save it again."),
    ("day1.parquet", lambda path: pd.DataFrame({"trial_id": ["a"]}).to_parquet(path),
     "the file cannot be read as parquet (ArrowInvalid); it is damaged or incomplete (a copy cut "
     "short?): copy or save it again."),
    # it said "the file cannot be read as xlsx (KeyError)."
    ("day1.xlsx", lambda path: zipfile.ZipFile(path, "w").writestr("word/document.xml", "<w/>"),
     "the file is a zip archive but not an Excel workbook (it holds no xl/workbook.xml); save the "
     "sheet from the spreadsheet program as .xlsx or as CSV UTF-8."),
    # named .csv, it was told "the file is an Excel workbook (xlsx) ...; rename it to day1.xlsx"
    ("day1.csv", lambda path: zipfile.ZipFile(path, "w").writestr("word/document.xml", "<w/>"),
     "the file is a zip archive but not an Excel workbook (it holds no xl/workbook.xml); save the "
     "sheet from the spreadsheet program as .xlsx or as CSV UTF-8."),
])
def test_a_workbook_or_table_cut_short_or_a_zip_of_another_kind_is_named(results, tmp_path, name,
                                                                        make, message):
    path = tmp_path / name
    make(path)
    if "damaged" in message:  # the first half of the file, as a copy stopped midway
        path.write_bytes(path.read_bytes()[:path.stat().st_size // 2])
    refused(results, ["ingest", "test2_grasp", path, "--root", results], f"{name}: {message}")


@pytest.mark.parametrize("n_jobs", [-1_000_000, -(os.cpu_count() + 1)])
def test_a_negative_n_jobs_beyond_the_cores_is_refused_with_the_range(results, n_jobs):
    """joblib reads n_jobs < 0 as cores + 1 + n_jobs workers, at least one: -1000000 ran one
    worker, silently."""
    cores = os.cpu_count()
    refused(results, ["run", "smoke", *replaced(SMOKE, "runner.backend=loky"), f"runner.n_jobs={n_jobs}",
                      "--root", results],
            f"runner.n_jobs = {n_jobs} would leave {-n_jobs - 1:,} cores unused, and this machine "
            f"has {cores}; give a number of worker processes (1 to {4 * cores}), or -1 for one "
            f"per core down to -{cores} for one worker.")


def test_dynamic_check_of_an_unfinished_source_run_says_how_to_finish_it(tmp_path, monkeypatch):
    """The advice named `graspcampaign run baseline_grid` without the source run's overrides, which
    `run` refuses as a run started with another config."""
    root = tmp_path / "results"
    source = unfinished_source(root, monkeypatch)
    again = " ".join(f"'{o}'" if "[" in o else o for o in BG)
    refused(root, ["run", "dynamic_check", "runner.backend=sequential", "--root", root],
            f"dynamic_check needs every trial of baseline_grid/default, but 1 of 2 are not recorded "
            f"under {source}; run `graspcampaign run baseline_grid {again} --root {root}` again to "
            "finish it.")
    shown = invoke("show", "dynamic_check", "--root", root)  # describes it, the missing part a line
    assert shown.exit_code == 0, shown.output
    assert ("design: not known until its source run is recorded: dynamic_check needs every trial "
            "of baseline_grid/default, but 1 of 2") in shown.stdout
    assert invoke("run", "baseline_grid", *BG, "--root", root).exit_code == 0  # as it says


@pytest.mark.parametrize("when", ["before its lock is opened", "after its lock is opened"])
def test_a_run_whose_directory_another_run_removes_meanwhile_runs(tmp_path, monkeypatch, when):
    """Two new runs of one run at once, the first refused after it made the run's directory (its
    backend down): its cleanup removes the lock and the directory while the second is between
    making the directory and opening the lock (a traceback, FileNotFoundError) or between opening
    and locking it (refused as "being run by another process", which none was)."""
    root = tmp_path / "results"
    run = root / "smoke" / "default"
    os_open, flock, done = os.open, fcntl.flock, []

    def other_run_cleans_up():  # what the refused run's run_lock does on leaving, once
        if not done:
            done.append(True)
            (run / ".lock").unlink()
            for directory in (run, run.parent, root):
                directory.rmdir()

    def opening(path, *args, **kwargs):
        if str(path).endswith(".lock") and when.startswith("before"):
            other_run_cleans_up()
        return os_open(path, *args, **kwargs)

    def locking(handle, operation):
        if when.startswith("after"):
            other_run_cleans_up()
        return flock(handle, operation)

    run.mkdir(parents=True)  # the other run's directory and lock, made first
    (run / ".lock").touch()
    monkeypatch.setattr(os, "open", opening)
    monkeypatch.setattr(fcntl, "flock", locking)
    done_run = invoke("run", "smoke", *SMOKE, "--root", root)
    assert done_run.exit_code == 0, done_run.output
    assert (run / "manifest.json").is_file() and not (run / ".lock").exists()


# -- round 8's table: what `report`, `status`, `schedule` and the environment were given ----------
@pytest.mark.parametrize(("place", "make", "message"), [
    # it said "could not be written: FileExistsError: [Errno 17] File exists: '.../report'", exit 1
    ("smoke/default/report", Path.touch, "the report of smoke/default could not be written: "
     "{path} is a file where the report's directory belongs; move it aside and report again"),
    # a traceback (IsADirectoryError), exit 1
    ("index.md", Path.mkdir, "{path} is a directory where this command writes a file; move it "
                             "aside and run the command again."),
])
def test_a_file_where_a_report_directory_belongs_or_the_reverse_is_named(results, place, make,
                                                                         message):
    path = results / place
    shutil.rmtree(path) if path.is_dir() else path.unlink()
    make(path)
    refused(results, ["report", "smoke", "--root", results], message.format(path=path))


def _cut_short(monkeypatch, name: str, exc: BaseException) -> None:
    """Make every file opened for writing whose name holds ``name`` (or its temporary file's) stop
    with ``exc`` after its first 100 bytes or characters, as a Ctrl-C or a full disk midway (by
    ``open``, which pathlib, pandas and pyarrow's Python files all write through)."""
    real = io.open

    class Cut:
        def __init__(self, handle):
            self.handle = handle

        def write(self, data):
            self.handle.write(data[:100])
            self.handle.flush()
            raise exc

        def __getattr__(self, attribute):
            return getattr(self.handle, attribute)

        def __enter__(self):
            return self

        def __exit__(self, *exc_info):
            return self.handle.__exit__(*exc_info)

        def __iter__(self):
            return iter(self.handle)

    def opening(file, mode="r", *args, **kwargs):
        handle = real(file, mode, *args, **kwargs)
        writing = isinstance(file, (str, os.PathLike)) and set(mode) & set("wax")
        return Cut(handle) if writing and name in os.path.basename(file) else handle

    monkeypatch.setattr(io, "open", opening)
    monkeypatch.setattr(builtins, "open", opening)


def test_a_report_interrupted_while_writing_leaves_every_file_whole(results, monkeypatch):
    """report.md was written in place: a Ctrl-C midway left its first 100 characters, the report
    before it lost."""
    before = snapshot(results)
    _cut_short(monkeypatch, "report.md", KeyboardInterrupt())
    assert invoke("report", "smoke", "--root", results).exit_code == 130
    assert snapshot(results) == before  # report.md as it was, no temporary file left


def test_a_full_disk_while_writing_a_runs_report_is_one_sentence(results, monkeypatch):
    """It said "could not be written: OSError: [Errno 28] No space left on device: '...'", exit 1."""
    path = results / "smoke" / "default" / "report" / "report.md"
    _cut_short(monkeypatch, "report.md", OSError(errno.ENOSPC, os.strerror(errno.ENOSPC), str(path)))
    refused(results, ["report", "smoke", "--root", results],
            f"the report of smoke/default could not be written: cannot write {path}: no space left "
            "on device; free some space there and run the command again")


def test_a_schedule_interrupted_while_writing_its_sheet_can_be_written_again(results, tmp_path,
                                                                            monkeypatch):
    """The sheet was written in place: a Ctrl-C midway left its first part, and `schedule` again
    refused it as a sheet that "already exists and differs" (filled in?)."""
    command = ["schedule", "test3_disturbance", "params.fraction=0.05", "--out", tmp_path / "day1",
               "--root", results]
    with monkeypatch.context() as stopped:
        _cut_short(stopped, "day1.csv", KeyboardInterrupt())
        invoke(*command)
    assert not (tmp_path / "day1.csv").exists()
    again = invoke(*command)
    assert again.exit_code == 0, again.output


@pytest.mark.parametrize("name", ["day1.xlsx", "day1.XLS", "day1.json"])
def test_a_schedule_out_in_a_format_it_does_not_write_is_refused(results, tmp_path, name):
    """``schedule --out day1.xlsx`` wrote day1.xlsx.csv and day1.xlsx.parquet: a sheet asked for as
    a workbook came out as CSV under a name that says it is none."""
    (sheets := tmp_path / "sheets").mkdir()
    out, stem = sheets / name, sheets / "day1"
    refused(results, ["schedule", "test3_disturbance", "--out", out, "--root", results],
            f"--out {out}: schedule writes the sheet as CSV and Parquet (<stem>.csv and <stem>.parquet), "
            f"not as {out.suffix}; give --out {stem} or {stem}.csv.")
    assert list(sheets.iterdir()) == []


def test_report_over_a_root_of_files_only_is_one_sentence(tmp_path):
    """``report --root /etc`` printed one "is a file, not a run directory" error per file two levels
    down (550 lines); a root whose every entry where a run would be is a file is no results root."""
    for name in ("app/a.conf", "app/b.conf", "other/c.conf"):
        (tmp_path / name).parent.mkdir(exist_ok=True)
        (tmp_path / name).write_text("x")
    refused(tmp_path, ["report", "--root", tmp_path],
            f"no runs under {tmp_path}: its 3 entries where runs would be (app/a.conf, …) are files, "
            f"not run directories, so it is no results root; give the root your runs are in, or make "
            f"one with graspcampaign run STUDY --root {tmp_path}.")


def test_report_jobs_beyond_four_per_core_are_refused_before_any_starts(results):
    """``report --jobs 100000`` had loky start processes until the command was killed (two runs to
    report), each left running."""
    cores, jobs = os.cpu_count(), 4 * os.cpu_count() + 1
    refused(results, ["report", "--jobs", jobs, "--root", results],
            f"--jobs {jobs}: more than 4 processes per core of this machine ({cores} cores); give at "
            f"most {4 * cores}, or -1 for one per core.", seconds=60)


@pytest.mark.parametrize(("command", "missing"), [
    ("status", "no run at {root}/smoke/defualt"),
    ("report", "no run 'defualt' of study 'smoke' under {root}"),
])
def test_a_misspelt_run_is_named_beside_the_command_that_would_make_it(results, command, missing):
    """Only the command making a run 'defualt' was suggested."""
    refused(results, [command, "smoke", "--run", "defualt", "--root", results],
            missing.format(root=results) + "; did you mean --run default? run "
            f"`graspcampaign run smoke --run defualt --root {results}` first.")


def test_a_catalog_cache_this_code_did_not_write_is_recomputed(tmp_path, monkeypatch):
    """A cache file holding a JSON list was a traceback (AttributeError) of `list` and `show`."""
    (tmp_path / "catalog.json").write_text("[1, 2]")
    monkeypatch.setenv("GRASPCAMPAIGN_CACHE", str(tmp_path))
    listed = invoke("list", "--names")
    assert listed.exit_code == 0 and "baseline_grid" in listed.stdout.split()


NOBODY = "~graspcampaign-no-such-user"  # no system has this user, so no home directory to read


@pytest.mark.parametrize(("variable", "message"), [
    ("GRASPCAMPAIGN_HOME", "error: GRASPCAMPAIGN_HOME={value} starts with {nobody}, a home directory "
     "that cannot be found; point it at a directory holding conf/ (with conf/config.yaml and the "
     "config groups) and campaigns/ (the study files), e.g. a copy of the shipped ones, or unset it "
     "to use those.\n"),
    ("GRASPCAMPAIGN_PATH", "warning: GRASPCAMPAIGN_PATH entry {value} starts with {nobody}, a home "
     "directory that cannot be found; it is skipped.\n"),
    ("GRASPCAMPAIGN_CACHE", "warning: GRASPCAMPAIGN_CACHE={value} cannot be written (starts with "
     "{nobody}, a home directory that cannot be found), so the catalog cache is not kept; list and "
     "show work without it, recomputing what they need (slower).\n"),
])
def test_a_home_directory_that_cannot_be_found_is_named(tmp_path, monkeypatch, variable, message):
    """Each was a traceback (RuntimeError: Could not determine home directory.), and the cache
    would have been kept in a directory named '~...' under the current one."""
    value = f"{NOBODY}/x"
    monkeypatch.setenv(variable, value)
    monkeypatch.chdir(tmp_path)
    studyfile.project_dirs.cache_clear()
    try:
        listed = invoke("list", "--names")
    finally:
        studyfile.project_dirs.cache_clear()
    assert listed.stderr == message.format(value=value, nobody=NOBODY)
    assert listed.exit_code == (2 if variable == "GRASPCAMPAIGN_HOME" else 0)
    assert not any(tmp_path.iterdir())


def test_a_study_file_under_an_unknown_home_is_named(tmp_path):
    refused(tmp_path, ["show", f"{NOBODY}/mine.yaml"], f"study file {NOBODY}/mine.yaml starts with "
            f"{NOBODY}, a home directory that cannot be found; give its path in full.")


def test_the_catalog_cache_under_a_home_is_kept_there_not_in_the_current_directory(tmp_path,
                                                                                  monkeypatch):
    monkeypatch.setenv("HOME", str(tmp_path / "home"))
    monkeypatch.setenv("GRASPCAMPAIGN_CACHE", "~/cache")
    monkeypatch.chdir(tmp_path)
    assert invoke("list", "--names").exit_code == 0
    assert (tmp_path / "home" / "cache" / "catalog.json").is_file() and not (tmp_path / "~").exists()


@pytest.mark.parametrize(("args", "where"), [
    # it wrote records/sheet.csv and .parquet: every command then refused the run as damaged
    (["schedule", "test2_grasp", "--out", "{run}/records/sheet"], "--out {run}/records/sheet"),
    (["reproduce", "--times", "{run}/times.txt"], "--times {run}/times.txt"),
    (["plan", "{mesh}", "--mass-kg", "0.1", "--png", "{run}/records/plan.png"],
     "--png {run}/records/plan.png"),
])
def test_an_output_inside_a_run_directory_is_refused(results, args, where):
    run, mesh = results / "smoke" / "default", results.parent / "sphere.stl"
    trimesh.creation.icosphere(subdivisions=2, radius=40.0).export(mesh)
    given = [a.format(run=run, mesh=mesh) for a in args]
    refused(results, [*given, *(["--root", results] if args[0] != "plan" else [])],
            f"{where.format(run=run)} is inside the directory of run smoke/default ({run}), which "
            "holds that run's files only; give a path outside it.")


@pytest.mark.parametrize(("args", "what", "wanted"), [
    (["ingest", "test2_grasp", "{path}"], "{path}", "a file of measured records (CSV, XLSX or Parquet)"),
    (["show", "{path}"], "study file {path}", "a YAML file"),
    (["plan", "{path}", "--mass-kg", "0.1"], "{path}", "a mesh file (STL, OBJ or PLY)"),
])
@pytest.mark.parametrize("special", ["named pipe", "/dev/null"])
def test_a_named_pipe_or_a_device_given_for_a_file_is_named_as_one(results, tmp_path, args, what,
                                                                   wanted, special):
    """Each said "no such file" (or "does not exist") of a file that exists."""
    path = tmp_path / ("given.yaml" if args[0] == "show" else "given.csv")
    os.mkfifo(path) if special == "named pipe" else path.symlink_to(os.devnull)
    kind = "a named pipe (FIFO)" if special == "named pipe" else "a character device"
    rooted = [] if args[0] == "plan" else ["--root", results]
    refused(results, [*(a.format(path=path) for a in args), *rooted],
            f"{what.format(path=path)} is {kind}, not a regular file; give {wanted}.")
