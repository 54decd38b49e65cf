"""What the bad-input tests of the command line share: run a command, fingerprint a results root,
and assert a refusal (exit 2, the whole one-sentence message, nothing stored changed); the tiny
runs the bad-store tests damage, and the advice a damaged run is refused with.

Imported by name (``from cli_checks import ...``), as pytest puts this directory on the path.
"""

from __future__ import annotations

import contextlib
import hashlib
import os
import shutil
import signal
import stat
import subprocess
from pathlib import Path

import numpy as np
import pandas as pd
import pytest
from typer.testing import CliRunner

from graspcampaign.cli.main import app

runner = CliRunner()

#: the tiny baseline_grid run: one scene, the proposed planner and Ferrari-Canny, a cheap PSO
BG = ["seeds=1", "shape=[sphere]", "mass_kg=[0.2]", "mu=[0.3]", "planner=[heuristic,ferrari_canny]",
      "pso.n_particles=2", "pso.n_iterations=1", "runner.backend=sequential", "runner.batch_size=1"]
SMOKE = ["shape=[sphere]", "nodes=[144]", "runner.backend=sequential"]

#: the Test 2 selection the measured-file tests fill in, and Test 1's (one material, specimen and
#: environment)
T2 = ["--set", "params.fraction=0.06"]
T1 = ["--set", "params.materials=[gel]", "--set", "params.specimens=[1]", "--set",
      "params.environments=[normal_lab]"]
#: a Test 1 event of the :data:`T1` selection: a normal press to 0.75 mm at 0.5 mm/s, held 0.2 s,
#: logged at 100 Hz
EVENT = "t1-49ea66f7c6ce"


def filled_records(tmp_path: Path, study: str = "test2_grasp", rows: slice = slice(0, 2)) -> pd.DataFrame:
    """Rows ``rows`` of ``study``'s measured-records template (``schedule --template``, the
    :data:`T2` selection), filled in as one stable trial each: the per-finger values and their means
    agree (``MEAN_REL_TOL``); Test 3's disturbance columns as a censored ramp. The template is left
    at ``tmp_path/sheet-template.csv`` (``--out tmp_path/sheet``), which a test may read."""
    made = invoke("schedule", study, *T2[1::2], "--template", "--out", tmp_path / "sheet")
    assert made.exit_code == 0, made.output
    sheet = pd.read_csv(tmp_path / "sheet-template.csv", keep_default_na=False).iloc[rows].assign(
        aborted=False, outcome="stable", success=True, stable=True, slip_flag=False,
        drop_flag=False, damage_flag=False, contact_loss_flag=False, peak_slip_mm=0.1,
        sf_actual=1.5, g_geo_actual=0.5, normal_force_1_n=0.5, normal_force_2_n=0.52,
        normal_force_3_n=0.54, normal_force_mean_n=0.52, deformation_1_mm=1.0,
        deformation_2_mm=1.1, deformation_3_mm=1.2, deformation_mean_mm=1.1,
        max_indentation_mm=1.3, contact_point_error_mm=0.4)
    if study == "test3_disturbance":
        sheet = sheet.assign(threshold_measured_n=2.0, threshold_measured_nm=0.0,
                             threshold_censored=True, first_finger_measured=0,
                             rotation_at_limit_deg=0.0)
    return sheet.reset_index(drop=True)


def bench_press(n: int = 301) -> pd.DataFrame:
    """A press of :data:`EVENT` as the bench logs it (§7.1): from 0.1 mm off the specimen to
    0.75 mm into it and back (deepest, 0.65 mm, at its middle sample), its force compressive but
    for a small adhesion pull-off at separation."""
    depth = 0.75 * np.sin(np.linspace(0.0, np.pi, n)) - 0.1
    force = np.where(depth > 0, 2.0 * np.clip(depth, 0, None) ** 1.5, 0.0)
    force[-5:] = -0.012  # the pull-off
    return pd.DataFrame({"event_id": EVENT, "time_s": np.arange(n) * 1e-2, "displacement_mm": depth,
                         "normal_force_n": force, "tangential_force_n": 0.0,
                         "tangential_displacement_mm": 0.0})


#: the two comment lines a study file begins with (its package and its schema)
HEADER = "# @package _global_\n# schema: StudyCfg\n"


def mesh_study(folder: Path, body: str) -> Path:
    """The user's study file ``folder/mine.yaml``: a mesh_features study named mine, ``body`` from
    its line 5 on."""
    path = folder / "mine.yaml"
    path.write_text(HEADER + "name: mine\nkind: mesh_features\n" + body, encoding="utf-8")
    return path


def replaced(overrides: list[str], *new: str) -> list[str]:
    """``overrides`` with ``new`` in place of those of the same keys (a key is named once)."""
    keys = {item.partition("=")[0] for item in new}
    return [item for item in overrides if item.partition("=")[0] not in keys] + list(new)


def grid_run(root: Path) -> Path:
    """The directory of the tiny baseline_grid run under ``root``."""
    return root / "baseline_grid" / "default"


#: :data:`BG` as a shell takes it (a word with brackets quoted), as a suggested command gives it
BG_QUOTED = ("seeds=1 'shape=[sphere]' 'mass_kg=[0.2]' 'mu=[0.3]' 'planner=[heuristic,ferrari_canny]' "
             "pso.n_particles=2 pso.n_iterations=1 runner.backend=sequential runner.batch_size=1")


def quarantined(root: Path, path: Path) -> Path:
    """Where resuming the tiny baseline_grid run under ``root`` moves its file ``path`` aside: into
    quarantine/, named by its path in the run with each ``/`` as ``__``."""
    run = grid_run(root)
    return run / "quarantine" / path.relative_to(run).as_posix().replace("/", "__")


def resume_grid(root: Path):
    """Resume the tiny baseline_grid run under ``root`` (made with :data:`BG`), as the advice a
    damaged run is refused with says; it exits 0."""
    result = invoke("run", "baseline_grid", *BG, "runner.progress=false", "--root", root)
    assert result.exit_code == 0, result.output
    return result


def resumed(root: Path, moved: Path, why: str, *, damaged: bool = False,
            then: str = "its trials no longer recorded will run again"):
    """:func:`resume_grid`, its only warning that the file ``moved`` went to quarantine
    (:func:`quarantined`) for reason ``why`` (a "damaged file" when ``damaged``), and ``then``
    what runs again; the result and where the file went."""
    result = resume_grid(root)
    target = quarantined(root, moved)
    kind = "damaged file" if damaged else "file"
    assert result.stderr == f"warning: {kind} {moved} moved to {target} ({why}); {then}\n"
    return result, target


def resume_advice(root: Path, then: str = "quarantine the file and run its trials again") -> str:
    """The advice a damaged baseline_grid run (made with :data:`BG`) is refused with: resume it,
    with the overrides it was started with, to ``then``."""
    return (f"resume the run (graspcampaign run baseline_grid {BG_QUOTED} --run default --root "
            f"{root}) to {then}.")


@contextlib.contextmanager
def deadline(seconds: float | None):
    """Fail (instead of hanging or filling the memory) if the block takes longer than this."""
    if seconds is None:
        yield
        return

    def expired(signum, frame):
        raise TimeoutError(f"still running after {seconds} s")

    previous = signal.signal(signal.SIGALRM, expired)
    signal.setitimer(signal.ITIMER_REAL, seconds)
    try:
        yield
    finally:
        signal.setitimer(signal.ITIMER_REAL, 0)
        signal.signal(signal.SIGALRM, previous)


@contextlib.contextmanager
def immutable(path: Path):
    """``path`` made immutable (``chattr +i``: no file in it can be added, renamed or removed,
    even by root, as on a read-only share) for the block; the test is skipped where that cannot
    be done (not root, a file system without the attribute)."""
    chattr = shutil.which("chattr")
    if chattr is None or subprocess.run([chattr, "+i", path], capture_output=True).returncode:
        pytest.skip("chattr +i is not available here")
    try:
        yield
    finally:
        subprocess.run([chattr, "-i", path], check=True)


def invoke(*args, seconds: float | None = None):
    """Run ``graspcampaign *args`` (each as a string), exceptions propagating, within ``seconds``,
    printing as into a pipe: COLUMNS unset (pytest-xdist's workers set it to 80)."""
    with deadline(seconds):
        return runner.invoke(app, [str(a) for a in args], catch_exceptions=False,
                             env={"COLUMNS": None})


def snapshot(root: Path) -> dict[str, str] | None:
    """Everything under ``root`` (None when ``root`` is no directory), as it is, not as what it
    points to: a regular file by its content hash, a symlink by its target, a directory, a named
    pipe or other special file by its kind."""
    if not root.is_dir():
        return None
    return {p.relative_to(root).as_posix(): _entry(p) for p in sorted(root.rglob("*"))}


def _entry(path: Path) -> str:
    mode = path.lstat().st_mode
    if stat.S_ISREG(mode):
        return hashlib.sha256(path.read_bytes()).hexdigest()
    if stat.S_ISLNK(mode):
        return f"symlink to {os.readlink(path)}"
    return "directory" if stat.S_ISDIR(mode) else stat.filemode(mode)


def refused(root: Path, args, message: str, *, warnings: str = "", seconds: float = 20.0) -> None:
    """``graspcampaign *args`` exits 2 with ``error: message`` (after ``warnings``) on stderr,
    nothing on stdout, and no file under ``root`` created, changed or removed, within ``seconds``
    (bad input is refused before any work: a slow refusal is a hang or a design being built)."""
    before = snapshot(root)
    result = invoke(*args, seconds=seconds)
    assert result.exit_code == 2, result.output
    assert result.stderr == f"{warnings}error: {message}\n" and result.stdout == ""
    assert snapshot(root) == before


def unfinished_source(root: Path, monkeypatch) -> Path:
    """Run baseline_grid (``BG``) under ``root`` and stop it by Ctrl-C while its second trial's
    shard is written: an unfinished source run for dynamic_check; return its directory."""
    from graspcampaign.campaign.records import RunStore

    write_shard, written = RunStore.write_shard, []

    def interrupted(self, kind, *args, **kwargs):
        if kind == "records" and written.append(kind) is None and len(written) == 2:
            raise KeyboardInterrupt
        return write_shard(self, kind, *args, **kwargs)

    monkeypatch.setattr(RunStore, "write_shard", interrupted)
    assert invoke("run", "baseline_grid", *BG, "--root", root).exit_code == 130
    monkeypatch.setattr(RunStore, "write_shard", write_shard)
    return root / "baseline_grid" / "default"


# The finished runs of the ``kept`` fixture (conftest.py), whose copies test_lost_parts.py and
# test_damaged_round3.py damage
KEPT_T2 = ["params.fraction=0.02", "runner.backend=sequential", "runner.batch_size=4"]
KEPT_SURROGATE = ["seeds=16", "runner.backend=sequential"]
#: the tiny baseline_grid run, first of a sphere and a pear, then resumed with an ellipsoid too
KEPT_FIRST, KEPT_THEN = replaced(BG, "shape=[sphere,pear]"), replaced(BG, "shape=[sphere,pear,ellipsoid]")
KEPT_OVERRIDES = {"test2_grasp": KEPT_T2, "surrogate": KEPT_SURROGATE,
                  "baseline_grid": [*KEPT_THEN, "--allow-drift"]}


def report_tables(root: Path, study: str) -> dict[str, bytes]:
    """The report's tables of the study's run, by file name, as written."""
    folder = root / study / "default" / "report" / "tables"
    return {p.name: p.read_bytes() for p in sorted(folder.iterdir())}


#: the overrides each run was started with (the kept fixture's; baseline_grid: its first
#: session's, KEPT_FIRST), as a shell takes them
KEPT_STARTED = {"test2_grasp": " ".join(KEPT_T2), "surrogate": " ".join(KEPT_SURROGATE),
                "baseline_grid": BG_QUOTED.replace("'shape=[sphere]' ", "") + " 'shape=[sphere,pear]'"}


def kept_advice(root: Path, study: str, then: str) -> str:
    """The advice of a damaged run of ``study``: resume it, with the overrides it was started with
    (a drifted baseline_grid: its first session's), to ``then``."""
    return (f"resume the run (graspcampaign run {study} {KEPT_STARTED[study]} runner.progress=false "
            f"--run default --root {root}) to {then}.")
