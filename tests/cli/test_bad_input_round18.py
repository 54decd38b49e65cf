"""Bad input, round 18: symbolic links that lead nowhere where a run, its study or a part of it
belongs, and files in a run's place given to `ingest`. Each is one sentence naming the run and
what is in its place, exit 2, nothing stored changed (``cli_checks.refused``).

(The places this user may not open are tests/cli/test_unreadable_places.py.)
"""

from __future__ import annotations

import shutil

import pytest
from cli_checks import SMOKE, T2, filled_records, refused

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
    import os

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
