"""The command a damaged run's refusal advises is one a user can follow literally: run as given
(split as a shell splits it), it resumes this run, overrides and all, and mends it."""

from __future__ import annotations

import json
import re
import shlex
import shutil
from pathlib import Path

from cli_checks import SMOKE, invoke


def _advised(message: str) -> list[str]:
    """The words of the command in a refusal's "resume the run (COMMAND) to ..." advice."""
    found = re.search(r"resume the run \((.*)\) to ", message)
    assert found, message
    return shlex.split(found.group(1))


def test_a_damaged_run_with_overrides_is_mended_by_the_command_its_refusal_gives(tmp_path):
    root = tmp_path / "my results"  # a space: the root is one word only when quoted
    made = invoke("run", "smoke", *SMOKE, "--root", root)
    assert made.exit_code == 0, made.output
    for shard in (root / "smoke" / "default" / "records").glob("*.parquet"):
        shard.unlink()
    refused = invoke("status", "smoke", "--root", root)
    assert refused.exit_code == 2
    words = _advised(refused.stderr)
    resumed = invoke(*words[1:])
    assert resumed.exit_code == 0, resumed.output  # the old command was refused as drift
    assert words == ["graspcampaign", "run", "smoke", *SMOKE, "--run", "default", "--root", str(root)]
    status = invoke("status", "smoke", "--root", root, "--json")
    assert status.exit_code == 0, status.output
    assert json.loads(status.stdout)["complete"] is True


def test_an_interrupted_runs_resume_command_keeps_its_overrides_and_root(monkeypatch, tmp_path):
    monkeypatch.chdir(tmp_path)
    from graspcampaign.campaign import runner

    def interrupted(*args, **kwargs):
        raise KeyboardInterrupt

    monkeypatch.setattr(runner, "run_study", interrupted)
    root = Path("results")  # the default root needs no --root, unless an override sets another
    stopped = invoke("run", "smoke", "output.root=elsewhere", *SMOKE, "--root", root)
    assert stopped.exit_code == 130
    said = stopped.stderr.split("resume with: ", 1)[1].strip()
    assert shlex.split(said) == ["graspcampaign", "run", "smoke", "output.root=elsewhere", *SMOKE,
                                 "--root", "results"]


def test_a_run_resumed_without_its_overrides_is_told_the_command_that_resumes_it(tmp_path):
    root = tmp_path / "my results"
    assert invoke("run", "smoke", *SMOKE, "--root", root).exit_code == 0
    refused = invoke("run", "smoke", "--root", root)  # the overrides it was started with left out
    assert refused.exit_code == 2
    found = re.search(r"resume it as started \((.*)\), use a new run name", refused.stderr)
    assert found, refused.stderr  # the old sentence offered only a new run name or --allow-drift
    words = shlex.split(found.group(1))
    assert words == ["graspcampaign", "run", "smoke", *SMOKE, "--run", "default", "--root", str(root)]
    resumed = invoke(*words[1:])
    assert resumed.exit_code == 0, resumed.output


def test_a_drift_the_overrides_cannot_undo_offers_no_command(tmp_path):
    """A run whose own overrides no longer compose to its config (here its config hash, as a study
    file edited since would leave it) is not told a command that would be refused again."""
    root = tmp_path / "results"
    assert invoke("run", "smoke", *SMOKE, "--root", root).exit_code == 0
    manifest = root / "smoke" / "default" / "manifest.json"
    stored = json.loads(manifest.read_text())
    manifest.write_text(json.dumps({**stored, "overrides": [*stored["overrides"], "seed=99"]}))
    refused = invoke("run", "smoke", "--root", root)
    assert refused.exit_code == 2 and "was started with a different" in refused.stderr
    assert "resume it as started" not in refused.stderr


def _study_file(tmp_path: Path, monkeypatch) -> tuple[Path, Path]:
    """The user's study file ``mine.yaml`` in ``tmp_path/studies``, the directory ``run`` is started
    in (``tmp_path/work``, the current directory) and the absolute results root."""
    from cli_checks import mesh_study

    (tmp_path / "studies").mkdir()
    (tmp_path / "work").mkdir()
    monkeypatch.chdir(tmp_path / "work")
    mesh_study(tmp_path / "studies", "factors:\n  shape: [sphere, ellipsoid]\n  nodes: [144, 390]\n")
    return tmp_path / "studies" / "mine.yaml", tmp_path / "results"


MINE = ["nodes=[144]", "runner.backend=sequential"]


def test_a_damaged_run_started_from_a_study_file_is_mended_by_the_command_its_refusal_gives(
        tmp_path, monkeypatch):
    """The advice named the study by its run directory, ``mine``, which ``run`` does not find (no
    study of that name on the search path); it names the file by its absolute path, which ``run``
    finds from any directory."""
    path, root = _study_file(tmp_path, monkeypatch)
    made = invoke("run", "../studies/mine.yaml", *MINE, "--root", root)
    assert made.exit_code == 0, made.output
    shutil.rmtree(root / "mine" / "default" / "records")
    refused = invoke("status", "mine", "--root", root)
    assert refused.exit_code == 2
    words = _advised(refused.stderr)
    assert words == ["graspcampaign", "run", str(path), *MINE, "--run", "default", "--root", str(root)]
    monkeypatch.chdir(tmp_path)  # another directory than the run was started in
    resumed = invoke(*words[1:])
    assert resumed.exit_code == 0, resumed.output
    status = invoke("status", "mine", "--root", root, "--json")
    assert status.exit_code == 0, status.output
    assert json.loads(status.stdout)["complete"] is True
    # a manifest stored before it kept the study file is read as before: the advice names the study
    manifest = root / "mine" / "default" / "manifest.json"
    stored = json.loads(manifest.read_text())
    manifest.write_text(json.dumps({k: v for k, v in stored.items() if k != "study_file"}))
    shutil.rmtree(root / "mine" / "default" / "records")
    refused = invoke("status", "mine", "--root", root)
    assert refused.exit_code == 2 and _advised(refused.stderr)[:3] == ["graspcampaign", "run", "mine"]


def test_a_drifted_run_started_from_a_study_file_is_told_the_command_that_resumes_it(tmp_path,
                                                                                    monkeypatch):
    """The drift refusal composed the study by its name to see whether the run's overrides resume
    it, found no such study and offered no command."""
    path, root = _study_file(tmp_path, monkeypatch)
    assert invoke("run", "../studies/mine.yaml", *MINE, "--root", root).exit_code == 0
    refused = invoke("run", "../studies/mine.yaml", "--root", root)  # its overrides left out
    assert refused.exit_code == 2
    found = re.search(r"resume it as started \((.*)\), use a new run name", refused.stderr)
    assert found, refused.stderr
    words = shlex.split(found.group(1))
    assert words == ["graspcampaign", "run", str(path), *MINE, "--run", "default", "--root", str(root)]
    resumed = invoke(*words[1:])
    assert resumed.exit_code == 0, resumed.output
    assert "2 already recorded, 0 ran" in resumed.stdout
