"""Bad input, round 18: symbolic links that lead nowhere where a run, its study or a part of it
belongs, files in a run's place given to `ingest`, and named pipes (FIFOs) where the tool reads a
file, whose read waited for ever. Each is one sentence naming the run and what is in its place,
exit 2, nothing stored changed (``cli_checks.refused``), within its deadline.

(The places this user may not open are tests/cli/test_unreadable_places.py.)
"""

from __future__ import annotations

import os
import shlex
import shutil

import pytest
from cli_checks import SMOKE, T2, filled_records, invoke, refused, snapshot

#: the commands that open a run of smoke under a root (its records, then what they say)
OPENING = (["status", "smoke"], ["show", "smoke"], ["run", "smoke", *SMOKE], ["report", "smoke"])


def test_a_run_directory_that_is_a_link_in_a_loop_is_refused_naming_it(results):
    """It was "no run at ...; run `graspcampaign run smoke` first", and that run ended in a
    traceback (FileExistsError making the directory); show described a run not yet started."""
    run = results / "smoke" / "loop"
    run.symlink_to("loop")
    for args in OPENING:
        refused(results, [*args, "--run", "loop", "--root", results],
                f"run smoke/loop at {run} cannot be stored: it is a symbolic link in a loop (it leads "
                "back to itself); remove the link or choose another run name (--run NAME).")


def test_a_study_directory_that_is_a_link_to_nothing_is_refused_naming_it(results):
    study = results / "ablation"
    study.symlink_to(results / "gone")
    for args in (["status", "ablation"], ["show", "ablation"], ["run", "ablation", "seeds=1"]):
        refused(results, [*args, "--root", results],
                f"run ablation/default at {study / 'default'} cannot be stored: {study} is a symbolic "
                f"link to {results / 'gone'}, which does not exist; remove the link.")


@pytest.mark.parametrize("target", ["records", "elsewhere"], ids=["loop", "to nothing"])
def test_a_records_folder_that_is_a_link_leading_nowhere_is_refused_not_resumed(results, target):
    """It was "missing records: ... resume the run to run the missing trials again"; the resumed
    run wrote a new session into the manifest, then failed at its first shard ("file exists"),
    advising to run the command again, which failed the same way."""
    records = results / "smoke" / "default" / "records"
    shutil.rmtree(records)
    records.symlink_to(target)
    what = ("a symbolic link in a loop (it leads back to itself)" if target == "records" else
            "a symbolic link to elsewhere, which does not exist")
    for args in OPENING:
        refused(results, [*args, "--root", results],
                f"run smoke/default at {records.parent} has records/, which is {what}; remove the "
                "link or make it lead to a directory, then resume the run.")


def test_ingest_into_a_place_a_file_or_a_loop_holds_is_refused_naming_it(tmp_path):
    """Each ended in a traceback (FileExistsError making the run's directory to hold it), where
    `run` refused the same places."""
    sheet = tmp_path / "measured.csv"
    filled_records(tmp_path).to_csv(sheet, index=False)
    cases = {"loop": "cannot be stored: it is a symbolic link in a loop (it leads back to itself); "
                     "remove the link or choose another run name (--run NAME).",
             "file": "is a file, not a run directory; move it aside or choose another run name "
                     "(--run NAME).",
             "study file": "cannot be stored: {root}/test2_grasp is a file, not the study's "
                           "directory; move it aside."}
    for case, message in cases.items():
        root = tmp_path / case.replace(" ", "_")
        run = root / "test2_grasp" / "measured"
        if case == "study file":
            root.mkdir()
            run.parent.write_text("not a folder\n")
        else:
            run.parent.mkdir(parents=True)
            run.symlink_to("measured") if case == "loop" else run.write_text("not a folder\n")
        refused(root, ["ingest", "test2_grasp", sheet, *T2, "--root", root],
                f"run test2_grasp/measured at {run} {message.format(root=root)}")


def test_a_study_name_on_the_search_path_that_is_no_file_says_what_it_is(user_dir, tmp_path):
    """Each was "the file … is not read: a study file's name ends in .yaml or .yml in lower case
    …; rename it mine.yaml", the name it already had."""
    (user_dir / "loop.yaml").symlink_to("loop.yaml")
    (user_dir / "gone.yaml").symlink_to(user_dir / "elsewhere.yaml")
    (user_dir / "folder.yaml").mkdir()
    os.mkfifo(user_dir / "pipe.yaml")
    cases = {"loop": "is a symbolic link in a loop (it leads back to itself)",
             "gone": f"is a symbolic link to {user_dir / 'elsewhere.yaml'}, which does not exist",
             "folder": "is a directory, not a file", "pipe": "is a named pipe (FIFO), not a regular file"}
    for name, what in cases.items():
        for command in ("show", "run"):
            refused(tmp_path, [command, name, "--root", tmp_path / "results"],
                    f"unknown study {name!r}: {user_dir / name}.yaml {what}; make it a study file "
                    "(YAML) or move it aside.")


@pytest.mark.parametrize("name", ["part-0123456789.parquet", "compact-0123456789.parquet"])
def test_a_named_pipe_named_as_a_shard_is_named_and_moved_aside(results, name):
    """status, show and report waited for ever, reading it; run waited too."""
    records = results / "smoke" / "default" / "records"
    os.mkfifo(records / name)
    for args in OPENING[:2] + OPENING[3:]:
        refused(results, [*args, "--root", results],
                f"run smoke/default at {records.parent} has records/{name}, named as a shard, which "
                "is a named pipe (FIFO), not a regular file; resume the run (graspcampaign run "
                f"smoke {shlex.join(SMOKE)} --run default --root {results}) to quarantine the file "
                "and run its trials again.")
    kept = {k: v for k, v in snapshot(records).items() if k != name}
    done = invoke(*OPENING[2], "--root", results, seconds=20)  # the records stay as they were
    assert done.exit_code == 0, done.output
    assert done.stderr.startswith(f"warning: file {records / name} moved to {records.parent}/"
                                  f"quarantine/records__{name} (it is a named pipe (FIFO), not a ")
    assert snapshot(records) == kept


def test_a_manifest_that_is_a_named_pipe_is_refused_and_a_lock_that_is_one_is_no_run(results):
    """status and run waited for ever reading the manifest; status, probing the lock, too."""
    run = results / "smoke" / "default"
    os.mkfifo(run / ".lock")
    done = invoke("status", "smoke", "--root", results, seconds=20)
    assert done.exit_code == 0 and "\ncomplete: True\n" in done.stdout, done.output
    (run / "manifest.json").unlink()
    os.mkfifo(run / "manifest.json")
    for args in (["status", "smoke"], ["run", "smoke", *SMOKE]):
        refused(results, [*args, "--root", results],
                f"run smoke/default at {run} has a damaged manifest.json (it is a named pipe (FIFO), "
                "not a regular file); its records cannot be checked without it, so restore the file "
                "from a backup or move the run directory aside and run the study again.")


def test_a_config_group_file_or_the_cache_that_is_a_named_pipe_is_not_read(home, tmp_path,
                                                                            monkeypatch):
    """show and list waited for ever reading them."""
    monkeypatch.setenv("GRASPCAMPAIGN_CACHE", str(tmp_path / "cache"))
    (tmp_path / "cache").mkdir()
    os.mkfifo(tmp_path / "cache" / "catalog.json")
    done = invoke("list", "--names", seconds=20)
    assert (done.exit_code, done.stderr) == (0, "") and "baseline_grid" in done.stdout.split()
    firm = home / "conf" / "model" / "firm.yaml"
    firm.unlink()
    os.mkfifo(firm)
    refused(tmp_path, ["show", "smoke", "--root", tmp_path / "results"],
            f"{firm} is a named pipe (FIFO), not a regular file; a config-group file is a YAML file.")


def test_a_config_place_that_is_a_link_in_a_loop_is_said_so(tmp_path, monkeypatch):
    """Each was said not to exist (GRASPCAMPAIGN_PATH, GRASPCAMPAIGN_HOME), or not writable
    because the file exists (GRASPCAMPAIGN_CACHE)."""
    from graspcampaign.campaign import studyfile

    loop = tmp_path / "loop"
    loop.symlink_to("loop")
    said = f"{loop} is a symbolic link in a loop (it leads back to itself)"
    monkeypatch.setenv("GRASPCAMPAIGN_PATH", str(loop))
    done = invoke("list", "--names", seconds=20)
    assert done.exit_code == 0 and "baseline_grid" in done.stdout.split()
    assert done.stderr == f"warning: GRASPCAMPAIGN_PATH entry {said}; it is skipped.\n"
    monkeypatch.delenv("GRASPCAMPAIGN_PATH")
    monkeypatch.setenv("GRASPCAMPAIGN_CACHE", str(loop))
    done = invoke("show", "smoke", "--root", tmp_path / "results", seconds=20)
    assert done.exit_code == 0 and "study: smoke" in done.stdout
    assert done.stderr == (f"warning: GRASPCAMPAIGN_CACHE={said}, so the catalog cache is not kept; "
                           "list and show work without it, recomputing what they need (slower).\n")
    monkeypatch.setenv("GRASPCAMPAIGN_HOME", str(loop))
    studyfile.project_dirs.cache_clear()
    try:
        refused(tmp_path, ["list"], f"GRASPCAMPAIGN_HOME={said}; point it at a directory holding conf/ "
                "(with conf/config.yaml and the config groups) and campaigns/ (the study files), e.g. "
                "a copy of the shipped ones, or unset it to use those.")
    finally:
        studyfile.project_dirs.cache_clear()
