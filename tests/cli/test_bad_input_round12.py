"""Bad input, round 12: what session 33 saw and left. A near miss of a config key named alike
wherever it is typed, ... Each refusal: exit 2, one sentence naming what is wrong and where,
nothing stored changed (``refused``)."""

from __future__ import annotations

from pathlib import Path

import pytest
from cli_checks import SMOKE, invoke, refused

HEADER = "# @package _global_\n# schema: StudyCfg\n"
KEYS = ("name, kind, description, seed, seeds, repeats, factors, zip, method_factors, params, paper, "
        "compare_with, extension, model, evaluator, features, pso, runner, output")


@pytest.mark.parametrize(("override", "said"), [
    # a top-level key was quoted ('seed'), a dotted one not (runner.progress)
    ("seedz=1", "seedz is neither a known key of the study config nor a factor of this study "
     "(factors: nodes, shape); did you mean seed? override rejected."),
    ("+seedz=1", f"seedz is not a known key of the study config (override '+seedz=1' rejected); "
     f"did you mean seed? known keys: {KEYS}."),
    ("runer.n_jobs=1", f"runer is not a known key of the study config (override 'runer.n_jobs=1' "
     f"rejected); did you mean runner? known keys: {KEYS}."),
])
def test_a_near_miss_of_a_config_key_is_named_as_typed_at_any_depth(results, override, said):
    refused(results, ["show", "smoke", override, "--root", results], said)


def test_deleting_a_key_the_study_does_not_set_says_what_deleting_would_do(results):
    # it said the schema's default "would take" compare_with's place "without a word", of a
    # study whose compare_with already was that default
    refused(results, ["show", "smoke", "~compare_with", "--root", results],
            "override '~compare_with' deletes compare_with, a key every study has: it would only "
            "put back the schema's default (\"\"), which a study that does not set compare_with "
            "already holds; set the value you want instead (compare_with=...).")


@pytest.fixture
def home_dir(tmp_path, monkeypatch):
    """A home directory (``HOME``) and a current directory apart from it."""
    home, here = tmp_path / "home", tmp_path / "here"
    home.mkdir()
    here.mkdir()
    monkeypatch.setenv("HOME", str(home))
    monkeypatch.chdir(here)
    return home


def test_a_quoted_tilde_in_a_path_option_is_the_home_directory(home_dir):
    # each made a directory named '~' in the current directory
    done = invoke("run", "smoke", *SMOKE, "--root", "~/runs")
    assert done.exit_code == 0, done.output
    assert (home_dir / "runs" / "smoke" / "default" / "manifest.json").is_file()
    for args in (["status", "smoke", "--root", "~/runs"], ["report", "smoke", "--root", "~/runs"],
                 ["schedule", "test2_grasp", "--out", "~/day1"]):
        done = invoke(*args)
        assert done.exit_code == 0, done.output
    assert (home_dir / "runs" / "smoke" / "default" / "report" / "report.md").is_file()
    assert (home_dir / "day1.csv").is_file()
    assert list(Path.cwd().iterdir()) == []


@pytest.mark.parametrize(("args", "said"), [
    (["show", "smoke", "--root", "~nosuchuser/runs"], "--root ~nosuchuser/runs starts with "
     "~nosuchuser, a home directory that cannot be found; give its path in full."),
    (["schedule", "test2_grasp", "--out", "~nosuchuser/day1"], "--out ~nosuchuser/day1 starts "
     "with ~nosuchuser, a home directory that cannot be found; give its path in full."),
    (["plan", "~nosuchuser/ball.obj", "--mass-kg", "0.1"], "mesh ~nosuchuser/ball.obj starts with "
     "~nosuchuser, a home directory that cannot be found; give its path in full."),
])
def test_a_path_option_in_the_home_of_no_user_is_refused(home_dir, args, said):
    refused(home_dir, args, said)
    assert list(Path.cwd().iterdir()) == []
