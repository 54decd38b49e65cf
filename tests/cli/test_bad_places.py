"""Bad places, class by class: exit 2, the whole one-sentence message, nothing stored changed.

A bad ``--root`` (a file, a path under a file, a device, an empty name, a read-only file system)
and an empty ``--run``; output paths checked before work; a full disk; a results root that holds
no runs; a directory given where a file belongs. The finished runs they are checked against are
made once (``finished`` in conftest.py).
"""

from __future__ import annotations

import errno
import os
import shutil
import sys
import tempfile
from pathlib import Path

import pyarrow.parquet as pq
import pytest
from cli_checks import SMOKE, grid_run, invoke, refused, snapshot

RUN_NAME = ("is not allowed; use ASCII letters (a-z, A-Z), digits, '.', '_' and '-' (starting "
            "with a letter or digit, at most 100), so the run stays inside the results directory.")
EMPTY_ROOT = ("is empty; give the results directory (for example results): an empty root would "
              "mean the current directory.")


# -- 1 and 5. the results root, the run name and output paths ------------------------------------
def test_a_root_that_is_not_a_directory_is_refused_before_any_work(finished, tmp_path):
    blocker = tmp_path / "afile"
    blocker.write_text("a file, not a folder")
    records = tmp_path / "m.csv"
    records.write_text("trial_id\n")
    cases = {blocker: f"--root {blocker}: is a file, not a directory.",
             blocker / "sub": f"--root {blocker / 'sub'}: {blocker} is a file, not a directory.",
             Path("/dev/null"): "--root /dev/null: is a character device, not a directory."}
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
                     ["schedule", "test2_grasp"], ["report"]):  # report writes the root's index
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

    write_table = pq.ParquetWriter.write_table

    def full(self, table, *args, **kwargs):  # the file's start written, then no room for its pages
        raise _disk_full(self.where)

    before = snapshot(results)
    monkeypatch.setattr(pq.ParquetWriter, "write_table", full)
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
    monkeypatch.setattr(pq.ParquetWriter, "write_table", write_table)
    resumed = invoke("run", "smoke", *SMOKE, "runner.progress=false", "--run", "fresh",
                     "--root", results)
    assert resumed.exit_code == 0 and "1 trial, 0 already recorded, 1 ran" in resumed.stdout


def test_a_full_disk_anywhere_else_is_one_sentence(results, monkeypatch):
    def full(write):
        def writing(self, *args, **kwargs):
            if "index.md" in self.name:  # the root pages (or their temporary files), written last
                raise _disk_full(self)
            return write(self, *args, **kwargs)
        return writing

    monkeypatch.setattr(Path, "write_text", full(Path.write_text))
    monkeypatch.setattr(Path, "write_bytes", full(Path.write_bytes))
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
    assert not any(empty.iterdir())


def test_a_root_at_or_inside_a_run_or_a_study_is_refused_by_every_command(finished):
    """A run's or a study's directory (or a place inside a run) given as the root: ``run`` wrote a
    run into the records of the run there, which every command then refused (exit 0 first)."""
    run = grid_run(finished)
    cases = {run: f"it is the directory of run baseline_grid/default; give the results root that "
                  f"holds it ({finished}).",
             run / "records": f"it is inside run baseline_grid/default ({run}); give the results "
                              f"root that holds it ({finished}).",
             run / "records" / "new": f"it is inside run baseline_grid/default ({run}); give the "
                                      f"results root that holds it ({finished}).",
             finished / "smoke": f"it holds the runs of study smoke; give the results root that "
                                 f"holds it ({finished})."}
    for root, why in cases.items():
        for args in (["run", "smoke", *SMOKE], ["show", "smoke"], ["status", "smoke"], ["report"],
                     ["report", "smoke"], ["schedule", "test2_grasp"]):
            refused(finished, [*args, "--root", root], f"--root {root}: {why}")


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


# -- 7. a directory where a file belongs -------------------------------------------------------------
def test_a_directory_given_for_a_file_is_named_as_one(results, tmp_path):
    folder = tmp_path / "adir.yaml"
    folder.mkdir()
    for command in ("show", "run"):
        refused(results, [command, folder, "--root", results],
                f"study file {folder} is a directory, not a file; give a YAML file.")
    refused(results, ["ingest", "test2_grasp", tmp_path, "--root", results],
            f"{tmp_path} is a directory, not a file; give a file of measured records (CSV, XLSX "
            "or Parquet).")


def test_a_named_pipe_in_place_of_a_schedule_file_is_refused_at_once(finished, tmp_path):
    # --out is a stem: schedule writes <stem>.csv and <stem>.parquet, each checked before any work
    os.mkfifo(tmp_path / "sheet.csv")
    refused(finished, ["schedule", "test2_grasp", "--out", tmp_path / "sheet", "--root", finished],
            f"--out {tmp_path / 'sheet'}: sheet.csv is a named pipe (FIFO), not a regular file.",
            seconds=5)
    assert sorted(p.name for p in tmp_path.iterdir()) == ["sheet.csv"]
