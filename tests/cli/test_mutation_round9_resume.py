"""Mutation round 9: the commands a refusal advises to resume a run (``provenance.study_given``,
``overrides_given``, ``_as_started``, ``paths.run_command``), checked by running what they say or
against what the run's manifest holds (docs/decisions.md, mutation round 9)."""

from __future__ import annotations

import json
import re
import shlex
import shutil
from pathlib import Path

from cli_checks import SMOKE, invoke, mesh_study, refused

from graspcampaign.campaign.provenance import code_version

THEN = "use a new run name (output.run=NAME or --run NAME) or pass --allow-drift to mix them."


def _smoke_run(root: Path, **manifest) -> Path:
    """The tiny smoke run under ``root``, its manifest's fields set to ``manifest``; its manifest."""
    made = invoke("run", "smoke", *SMOKE, "--root", root)
    assert made.exit_code == 0, made.output
    path = root / "smoke" / "default" / "manifest.json"
    path.write_text(json.dumps({**json.loads(path.read_text()), **manifest}))
    return path


def _advised(message: str) -> list[str]:
    found = re.search(r"resume the run \((.*)\) to ", message)
    assert found, message
    return shlex.split(found.group(1))


def test_an_empty_study_file_in_the_manifest_names_the_study(tmp_path):
    """A manifest's ``study_file`` of "" names no file: the advice names the study (a command naming
    the study '' is refused), and running it mends the run."""
    root = tmp_path / "results"
    _smoke_run(root, study_file="")
    shutil.rmtree(root / "smoke" / "default" / "records")
    refused_now = invoke("status", "smoke", "--root", root)
    assert refused_now.exit_code == 2
    words = _advised(refused_now.stderr)
    assert words == ["graspcampaign", "run", "smoke", *SMOKE, "--run", "default", "--root", str(root)]
    assert invoke(*words[1:]).exit_code == 0
    assert json.loads(invoke("status", "smoke", "--root", root, "--json").stdout)["complete"] is True


def test_overrides_holding_other_than_text_are_not_given_again(tmp_path):
    """A manifest whose ``overrides`` hold a number (a hand edit; a list, as the manifest check asks)
    keeps no overrides a command could give: the advice names the study alone, in one sentence,
    where a command was built of the number (shlex.join's TypeError, a traceback)."""
    root = tmp_path / "results"
    _smoke_run(root, overrides=[1, *SMOKE])
    shutil.rmtree(root / "smoke" / "default" / "records")
    refused_now = invoke("status", "smoke", "--root", root)
    assert refused_now.exit_code == 2 and refused_now.stderr.startswith("error: ")
    assert _advised(refused_now.stderr) == ["graspcampaign", "run", "smoke", "--run", "default",
                                            "--root", str(root)]


def test_a_run_of_another_code_version_is_told_no_command_that_would_be_refused_again(tmp_path):
    """`run` refuses a run of another code version whatever its overrides, so neither refusal offers
    "resume it as started": the command it names would be refused again for the code version."""
    root = tmp_path / "results"
    _smoke_run(root, code_version="0.0.1+0123456789ab")
    code = f"code version (0.0.1+0123456789ab -> {code_version()})"
    run_dir = root / "smoke" / "default"
    refused(root, ["run", "smoke", *SMOKE, "--root", root],  # the code alone differs
            f"run {run_dir} was started with a different {code}; {THEN}")
    again = invoke("run", "smoke", "--root", root)  # its overrides left out: the config differs too
    assert again.exit_code == 2
    assert re.fullmatch(rf"error: run {re.escape(str(run_dir))} was started with a different resolved "
                        rf"study config \([^()]*\) and {re.escape(code)}; {re.escape(THEN)}\n",
                        again.stderr), again.stderr


def _moved_study_file(tmp_path: Path, monkeypatch) -> Path:
    """A run started from ``studies/mine.yaml``, the file then moved to ``moved/mine.yaml`` and its
    nodes changed; the results root."""
    for folder in ("studies", "moved", "work"):
        (tmp_path / folder).mkdir()
    monkeypatch.chdir(tmp_path / "work")
    mesh_study(tmp_path / "studies", "factors:\n  shape: [sphere]\n  nodes: [144]\n")
    root = tmp_path / "results"
    made = invoke("run", "../studies/mine.yaml", "runner.backend=sequential", "--root", root)
    assert made.exit_code == 0, made.output
    (tmp_path / "studies" / "mine.yaml").unlink()
    mesh_study(tmp_path / "moved", "factors:\n  shape: [sphere]\n  nodes: [390]\n")
    return root


def test_a_drift_whose_study_file_is_gone_offers_no_command(tmp_path, monkeypatch):
    """The run's study file no longer exists where it was started from: no command composes it, so
    the drift refusal offers none (the file's absence was raised in its place)."""
    root = _moved_study_file(tmp_path, monkeypatch)
    refused(root, ["run", "../moved/mine.yaml", "runner.backend=sequential", "--root", root],
            f"run {root / 'mine' / 'default'} was started with a different resolved study config "
            f"(factors.nodes [144] -> [390]); {THEN}")


def test_a_run_whose_manifest_keeps_no_overrides_is_not_said_how_it_was_started(tmp_path, monkeypatch):
    """A run stored before manifests kept the overrides (or made by the API) was started by a command
    no one recorded: "resume it as started" would claim one, even where the study's default design
    composes to its config."""
    root = tmp_path / "results"
    for folder in ("studies", "work"):
        (tmp_path / folder).mkdir()
    monkeypatch.chdir(tmp_path / "work")
    mesh_study(tmp_path / "studies", "factors:\n  shape: [sphere]\n  nodes: [144]\n")
    assert invoke("run", "../studies/mine.yaml", "--root", root).exit_code == 0
    manifest = root / "mine" / "default" / "manifest.json"
    manifest.write_text(json.dumps({k: v for k, v in json.loads(manifest.read_text()).items()
                                    if k != "overrides"}))
    refused(root, ["run", "../studies/mine.yaml", "nodes=[390]", "--root", root],
            f"run {root / 'mine' / 'default'} was started with a different resolved study config "
            f"(factors.nodes [144] -> [390]); {THEN}")


def test_a_missing_run_under_the_default_root_is_made_without_root(tmp_path, monkeypatch):
    """The default root needs no --root (``root_options``); the command names none."""
    monkeypatch.chdir(tmp_path)
    refused(tmp_path, ["status", "smoke"],
            "no run at results/smoke/default; run `graspcampaign run smoke` first.")

