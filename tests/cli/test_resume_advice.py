"""The command a damaged run's refusal advises is one a user can follow literally: run as given
(split as a shell splits it), it resumes this run, overrides and all, and mends it."""

from __future__ import annotations

import json
import re
import shlex
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
