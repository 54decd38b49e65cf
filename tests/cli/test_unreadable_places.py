"""Places this user may not open (chmod 000, another user's run or folder): one sentence naming
the place and what to do, exit 2, nothing stored changed; never a traceback, an intact file called
damaged and quarantined, or a file said not to exist.

Permission bits do not stop root, so the commands run in one child process as an unprivileged
user: this one if it is not root, else nobody (uid 65534, through util-linux's ``setpriv``). The
scratch tree is that user's own, each place in it closed with ``chmod``; the child runs every
command through the command line in-process (as ``cli_checks.invoke`` does, one process for all,
its caches cleared between commands) and hands back exit codes and output.
"""

from __future__ import annotations

import json
import os
import shutil
import subprocess
import sys
import tempfile
from pathlib import Path

import pytest
import trimesh
from cli_checks import SMOKE, T2, filled_records, invoke, snapshot

import graspcampaign
from graspcampaign.campaign import studyfile

NOBODY = 65534
#: What every sentence of a place this user may not open says after the place and what cannot
#: be done to it (core.words.PERMISSION_DENIED), without its full stop.
DENIED = ("permission denied (its permissions, or those of the directory holding it, keep this "
          "user out); give this user access (chmod, chown), or run the command as the user who "
          "owns it")

DRIVER = """
import json, sys
from typer.testing import CliRunner
from graspcampaign.campaign import studyfile
from graspcampaign.cli.main import app
out = {}
for name, (args, env) in json.loads(sys.argv[1]).items():
    studyfile.project_dirs.cache_clear()  # one process per command, as on the command line
    done = CliRunner().invoke(app, args, env={"COLUMNS": None, **env})
    out[name] = [done.exit_code, done.stdout, done.stderr]
print(json.dumps(out))
"""


def _as_user(env: dict[str, str]) -> list[str]:
    """The command prefix that runs a child as a user permission bits stop (skipped where none
    can be, or where that user cannot import the package: a clone in root's private home)."""
    if os.geteuid() != 0:
        return []
    if shutil.which("setpriv") is None:
        pytest.skip("as root, permission bits stop no one, and setpriv (to run as nobody) is missing")
    prefix = ["setpriv", f"--reuid={NOBODY}", f"--regid={NOBODY}", "--clear-groups"]
    probe = subprocess.run([*prefix, sys.executable, "-c", "import graspcampaign.cli.main"], env=env,
                           cwd="/", capture_output=True, timeout=120)
    if probe.returncode:
        pytest.skip(f"uid {NOBODY} cannot run the package from here: {probe.stderr[-200:]!r}")
    return prefix


def _give(tree: Path) -> None:
    """Make ``tree`` the child's user's own (as root: nobody's)."""
    if os.geteuid() == 0:
        for path in [tree, *tree.rglob("*")]:
            os.chown(path, NOBODY, NOBODY, follow_symlinks=False)


@pytest.fixture(scope="module")
def places(finished, tmp_path_factory):
    """A scratch tree of closed places, the commands run on it by the child (by case name) and
    the tree as it was before: ``(scratch, results, before)``."""
    scratch = Path(tempfile.mkdtemp(prefix="graspcampaign-unreadable-"))
    try:
        yield _run_cases(scratch, finished, tmp_path_factory.mktemp("sheet"))
    finally:
        for path in [scratch, *(p for p in scratch.rglob("*") if not p.is_symlink())]:
            path.chmod(0o700)  # open again, so that the tree can be removed
        shutil.rmtree(scratch)


def _run(scratch: Path, name: str, finished: Path) -> Path:
    """A copy of the finished smoke run as ``scratch/<name>/smoke/default``: its results root."""
    root = scratch / name
    shutil.copytree(finished / "smoke" / "default", root / "smoke" / "default")
    return root


def _run_cases(scratch, finished, sheets):
    cases, closed = {}, []
    # an intact shard, the manifest, the records folder this user may not open
    for name, place in (("shard", "records/*.parquet"), ("manifest", "manifest.json"),
                        ("records", "records")):
        root = _run(scratch, name, finished)
        closed.append(next((root / "smoke" / "default").glob(place)))
        for command in (["status", "smoke"], ["report", "smoke"], ["run", "smoke", *SMOKE]):
            cases[f"{name}:{command[0]}"] = ([*command, "--root", name], {})
    # a study folder this user may not list, beside a run it may read, under a root reported whole
    root = _run(scratch, "study", finished)
    shutil.copytree(finished / "baseline_grid", root / "baseline_grid")
    for page in finished.glob("*.*"):  # the index and headline pages, which list its runs
        shutil.copy(page, root)
    closed.append(root / "smoke")
    cases["study:report"] = (["report", "--root", "study"], {})
    # a run whose records/ this user may read but not write, resumed with a trial it lacks
    _run(scratch, "unwritable", finished)
    cases["unwritable:run"] = (["run", "smoke", *SMOKE[:1], "nodes=[144,390]", *SMOKE[2:],
                                "--allow-drift", "--root", "unwritable"], {})
    # a finished run whose records/ this user may read but not write: run has nothing to write;
    # and a measured run so kept, given the records it holds again
    _run(scratch, "complete", finished)
    cases["complete:run"] = (["run", "smoke", *SMOKE, "--allow-drift", "--root", "complete"], {})
    filled_records(sheets).to_csv(scratch / "again.csv", index=False)
    made = invoke("ingest", "test2_grasp", scratch / "again.csv", *T2, "--root", scratch / "measured")
    assert made.exit_code == 0, made.output
    cases["measured:ingest"] = (["ingest", "test2_grasp", "again.csv", *T2, "--root", "measured"], {})
    # a run whose report/ this user may not write
    _run(scratch, "no_report", finished)
    cases["no_report:report"] = (["report", "smoke", "--root", "no_report"], {})
    # files to read: a mesh and measured records this user may not read, and one in a folder it
    # may not search
    trimesh.creation.icosphere(subdivisions=2, radius=40.0).export(scratch / "ball.stl")
    (scratch / "hidden").mkdir()
    shutil.copy(scratch / "ball.stl", scratch / "hidden" / "ball.stl")
    filled_records(sheets).to_csv(scratch / "records.csv", index=False)
    cases["mesh:plan"] = (["plan", "ball.stl", "--mass-kg", "0.1"], {})
    cases["hidden:plan"] = (["plan", "hidden/ball.stl", "--mass-kg", "0.1"], {})
    shutil.copy(scratch / "ball.stl", scratch / "open.stl")
    cases["png:plan"] = (["plan", "open.stl", "--mass-kg", "0.1", "--png", "hidden/x.png"], {})
    cases["csv:ingest"] = (["ingest", "test2_grasp", "records.csv", "--root", "ingested"], {})
    # the config search path, a config home and the catalog cache in places this user may not open
    (scratch / "studies").mkdir()
    shutil.copytree(Path(studyfile.project_dirs()[0]).parent / "conf", scratch / "home" / "conf")
    shutil.copytree(studyfile.project_dirs()[1], scratch / "home" / "campaigns")
    cases["path:list"] = (["list", "--names"], {"GRASPCAMPAIGN_PATH": "studies"})
    cases["home:list"] = (["list", "--names"], {"GRASPCAMPAIGN_HOME": str(scratch / "home")})
    cases["cache:show"] = (["show", "smoke"], {"GRASPCAMPAIGN_CACHE": "hidden/cache"})
    (scratch / "user").mkdir()
    _give(scratch)
    before = _stored(scratch)
    closed += [scratch / "ball.stl", scratch / "records.csv", scratch / "studies",
               scratch / "home" / "conf", scratch / "hidden"]
    modes = {path: path.stat().st_mode for path in closed + [scratch / "unwritable" / "smoke" /
             "default" / "records", scratch / "no_report" / "smoke" / "default" / "report",
             scratch / "complete" / "smoke" / "default" / "records",
             scratch / "measured" / "test2_grasp" / "measured" / "records"]}
    for path in closed:
        path.chmod(0)
    for path in list(modes)[len(closed):]:
        path.chmod(0o555)  # read, not write
    source = Path(graspcampaign.__file__).parents[1]
    user = scratch / "user"  # the child's home and caches
    env = {"PATH": os.environ.get("PATH", ""), "PYTHONPATH": str(source), "HOME": str(user),
           "GRASPCAMPAIGN_CACHE": str(user / "cache"), "NUMBA_CACHE_DIR": str(user / "numba"),
           "OMP_NUM_THREADS": "1"}
    prefix = _as_user(env)
    done = subprocess.run([*prefix, sys.executable, "-c", DRIVER, json.dumps(cases)], cwd=scratch,
                          env=env, capture_output=True, text=True, timeout=600)
    for path, mode in modes.items():  # open again: a test run by a user may read them then
        path.chmod(mode)
    assert done.returncode == 0, done.stderr
    return json.loads(done.stdout.splitlines()[-1]), scratch, before, _stored(scratch)


def _stored(scratch: Path) -> dict[str, str]:
    """What is stored in the scratch tree (the child's home and caches aside)."""
    return {k: v for k, v in snapshot(scratch).items() if not k.startswith("user")}


def _refused(places, case: str, message: str) -> None:
    """``case`` exited 2 with ``error: message`` alone, and changed nothing under its results
    root (a file case: anything)."""
    results, scratch, before, after = places
    code, stdout, stderr = results[case]
    assert (code, stdout, stderr) == (2, "", f"error: {message}\n"), case
    root = case.split(":")[0] + "/" if (scratch / case.split(":")[0] / "smoke").is_dir() else ""
    assert {k: v for k, v in after.items() if k.startswith(root)} == \
        {k: v for k, v in before.items() if k.startswith(root)}


@pytest.mark.parametrize("command", ["status", "report", "run"])
def test_a_shard_this_user_may_not_read_is_named_not_quarantined(places, command):
    shard = next(Path(places[1], "shard", "smoke", "default", "records").glob("*.parquet"))
    _refused(places, f"shard:{command}", f"{shard.relative_to(places[1])}: {DENIED}.")


@pytest.mark.parametrize("command", ["status", "report", "run"])
def test_a_manifest_this_user_may_not_read_is_not_called_damaged(places, command):
    _refused(places, f"manifest:{command}", f"manifest/smoke/default/manifest.json: {DENIED}.")


@pytest.mark.parametrize("command", ["status", "report", "run"])
def test_a_records_folder_this_user_may_not_open_is_named(places, command):
    _refused(places, f"records:{command}", f"records/smoke/default/records: {DENIED}.")


def test_a_study_folder_this_user_may_not_list_is_named_and_the_others_reported(places):
    """Its runs were skipped unsaid (exit 0), and the index, rewritten, no longer listed them."""
    code, stdout, stderr = places[0]["study:report"]
    assert (code, stdout) == (2, "report: study/baseline_grid/default/report/report.md\n")
    assert stderr == ("warning: the headline and index pages were left as they were: run smoke "
                      f"cannot be read (study/smoke: {DENIED}.)\nerror: the report of smoke could "
                      f"not be written: study/smoke: {DENIED}.\n")
    results, scratch, before, after = places
    assert {k: v for k, v in after.items() if k.startswith("study/")} == \
        {k: v for k, v in before.items() if k.startswith("study/")}  # the pages too


def test_a_run_this_user_may_not_write_is_refused_before_its_manifest_changes(places):
    _refused(places, "unwritable:run", "run smoke/default at unwritable/smoke/default: "
             f"unwritable/smoke/default/records: cannot be written by this user: {DENIED}.")


def test_a_finished_run_this_user_may_not_write_has_nothing_to_do(places):
    """It was refused as the run above ("cannot write there"), though nothing was left to run."""
    results, scratch, before, after = places
    assert results["complete:run"] == [0, "smoke/default: 1 trial, 1 already recorded, 0 ran (0 ok, "
                                          "0 errors) in 0.0 s -> complete/smoke/default\n", ""]
    assert {k: v for k, v in after.items() if k.startswith("complete/")} == \
        {k: v for k, v in before.items() if k.startswith("complete/")}  # no session recorded


def test_records_ingested_again_into_a_run_this_user_may_not_write_are_said_stored(places):
    """It was "cannot write there": the file's trials are stored already, and would be refused."""
    first = (places[1] / "again.csv").read_text().splitlines()[1].split(",")[0]  # its trial_id
    _refused(places, "measured:ingest", f"again.csv, row 1, column 'trial_id': trial {first!r} is "
             "already stored in this run; measured records are never overwritten (ingest a "
             "corrected file into another run with --run).")


def test_a_report_folder_this_user_may_not_write_is_bad_input(places):
    """It named report.md, found when that was written after the figures; the folder is now
    probed first and named (fact42)."""
    _refused(places, "no_report:report", "the report of smoke/default could not be written: its "
             f"report folder no_report/smoke/default/report: cannot be written by this user: {DENIED}")


MESH, RECORDS = "a mesh file (STL, OBJ or PLY)", "a file of measured records (CSV, XLSX or Parquet)"


@pytest.mark.parametrize(("case", "message"), [
    ("mesh:plan", f"ball.stl cannot be read by this user: {DENIED}; give {MESH}."),
    ("hidden:plan", "hidden/ball.stl cannot be reached by this user (hidden cannot be searched): "
                    f"{DENIED}; give {MESH}."),
    ("csv:ingest", f"records.csv cannot be read by this user: {DENIED}; give {RECORDS}.")],
    ids=["mesh", "mesh in a closed folder", "records"])
def test_a_file_to_read_that_this_user_may_not_open_is_said_so(places, case, message):
    _refused(places, case, message)


def test_a_picture_path_in_a_folder_this_user_may_not_open_names_the_option(places):
    _refused(places, "png:plan", f"--png hidden/x.png: cannot be written by this user: {DENIED}.")


def test_a_search_path_entry_this_user_may_not_read_is_skipped_with_a_warning(places):
    code, stdout, stderr = places[0]["path:list"]
    assert code == 0 and "baseline_grid" in stdout.split()
    assert stderr == (f"warning: GRASPCAMPAIGN_PATH entry studies cannot be read by this user: "
                      f"{DENIED}; it is skipped.\n")


def test_a_config_home_this_user_may_not_read_is_named(places):
    home = places[1] / "home"
    _refused(places, "home:list", f"GRASPCAMPAIGN_HOME={home} has conf/, which cannot be read by "
             f"this user: {DENIED}; point it at a directory holding conf/ (with "
             "conf/config.yaml and the config groups) and campaigns/ (the study files), e.g. a copy "
             "of the shipped ones, or unset it to use those.")


def test_a_cache_this_user_may_not_reach_is_said_once_and_show_goes_on(places):
    code, stdout, stderr = places[0]["cache:show"]
    assert code == 0 and "study: smoke" in stdout
    assert stderr == ("warning: GRASPCAMPAIGN_CACHE=hidden/cache cannot be written (Permission "
                      "denied), so the catalog cache is not kept; list and show work without it, "
                      "recomputing what they need (slower).\n")
