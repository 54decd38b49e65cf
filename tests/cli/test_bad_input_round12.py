"""Bad input, round 12: what session 33 saw and left. A near miss of a config key named alike
wherever it is typed, ... Each refusal: exit 2, one sentence naming what is wrong and where,
nothing stored changed (``refused``)."""

from __future__ import annotations

import pytest
from cli_checks import refused

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
