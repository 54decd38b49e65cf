"""Command line: exit codes, one-sentence errors, nothing written on bad input."""

from __future__ import annotations

import json
import re

import pytest
from typer.testing import CliRunner

from graspcampaign.cli.main import app

runner = CliRunner()


def _invoke(*args):
    return runner.invoke(app, list(args), catch_exceptions=False)


def test_list_shows_every_study_and_runnability():
    result = _invoke("list")
    assert result.exit_code == 0
    for study in ("smoke", "baseline_grid", "test2_grasp", "surrogate"):
        assert study in result.stdout
    from graspcampaign.campaign.kind import KINDS

    assert ("not yet" in result.stdout) == any(v is None for v in KINDS.values())


def test_show_prints_design_without_running(tmp_path):
    result = _invoke("show", "smoke", "nodes=[144]", f"output.root={tmp_path}")
    assert result.exit_code == 0, result.output
    assert "= 5 trials" in result.stdout
    assert "(0 of 5 recorded)" in result.stdout
    assert "estimated time" in result.stdout
    assert not any(tmp_path.iterdir())


@pytest.mark.parametrize(
    ("override", "message"),
    [
        ("+factors.mass_kg=[-0.2]", r"factors\.mass_kg\[0\] = -0\.2 is out of range; allowed: > 0\.0"),
        ("+factors.mu=[-0.1]", r"factors\.mu\[0\] = -0\.1 is out of range; allowed: >= 0\.0"),
        ("nodes=[5]", r"factors\.nodes\[0\] = 5 is out of range; allowed: >= 12"),
        ("seeds=0", r"seeds = 0 is out of range; allowed: >= 1"),
        ("+factors.planner=[telepathy]", r"factors\.planner\[0\] has unknown value 'telepathy'; "
                                         r"allowed values: heuristic"),
        ("shape=[cube]", r"factors\.shape\[0\] has unknown value 'cube'; allowed values: sphere, "
                         r"ellipsoid, rounded_cube, pear, handle\.$"),
        ("colour=red", r"colour is not a known key of the study config \(override rejected\)\.$"),
        ("model.lambda1=soft", r"model\.lambda1: Value 'soft' of type 'str' could not be converted"),
        ("runner.backend=spark", r"runner\.backend has unknown value 'spark'; allowed values: loky"),
        ("+factors.flavour=[1]", r"factors\.flavour is not a known factor; known factors:"),
        ("nodes=[144", r"cannot parse override 'nodes=\[144'"),
    ],
)
def test_bad_overrides_exit_2_naming_the_key_and_write_nothing(tmp_path, override, message):
    for command in ("run", "show"):
        result = _invoke(command, "smoke", override, f"output.root={tmp_path}")
        assert result.exit_code == 2, result.output
        assert re.match(r"error: " + message, result.stderr), result.stderr
        assert result.stderr.count("\n") == 1  # one sentence, no traceback
    assert not any(tmp_path.iterdir())


def test_unknown_study_is_bad_input():
    result = _invoke("run", "warp_drive")
    assert result.exit_code == 2
    assert "unknown study 'warp_drive'; available studies: ablation" in result.stderr


def test_not_yet_runnable_study_is_refused_and_writes_nothing(tmp_path, monkeypatch):
    from graspcampaign.campaign import kind

    monkeypatch.setitem(kind.KINDS, "test3_disturbance", None)  # as before its kind existed
    listing = _invoke("list")
    assert "not yet" in listing.stdout
    result = _invoke("run", "test3_disturbance", f"output.root={tmp_path}")
    assert result.exit_code == 2
    assert "trial kind 'test3_disturbance' is not implemented yet" in result.stderr
    assert not any(tmp_path.iterdir())


def test_run_status_and_report_smoke(tmp_path):
    args = ("smoke", "nodes=[144]", "runner.backend=sequential", f"output.root={tmp_path}")
    result = _invoke("run", *args)
    assert result.exit_code == 0, result.output
    assert "5 trials, 0 already recorded, 5 ran (5 ok, 0 errors)" in result.stdout
    again = _invoke("run", *args)
    assert "5 already recorded, 0 ran" in again.stdout
    status = _invoke("status", "smoke", "--json", "--root", str(tmp_path))
    info = json.loads(status.stdout)
    assert info["n_ok"] == 5 and info["complete"] and info["source"] == "simulation"
    report = _invoke("report", "smoke", "--root", str(tmp_path))
    assert report.exit_code == 0, report.output
    md = (tmp_path / "smoke" / "default" / "report" / "report.md").read_text()
    assert "Data source:** simulation" in md
    assert (tmp_path / "index.md").exists()
