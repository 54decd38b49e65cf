"""Bad input, round 11: what round 10 saw and left. A method factor no trial holds, a seed or a
task size past what the tools behind them take, an empty paper value, a path to read holding a
line break, a mesh saved as UTF-16, a row of only commas, the booleans a template promises.
Each refusal: exit 2, one sentence naming what is wrong and where, nothing stored changed
(``refused``)."""

from __future__ import annotations

import pytest
from cli_checks import refused

HEADER = "# @package _global_\n# schema: StudyCfg\n"


@pytest.mark.parametrize(("override", "name", "hint"), [
    # each was accepted: show printed the study, run ran it under a new config hash
    ("method_factors=[nosuch]", "nosuch", ""),
    ("method_factors=[planner,plannr]", "plannr", "did you mean 'planner'? "),
    # dynamic_check's own trial key, which a quasi_static trial does not hold
    ("method_factors=[planner,source_trial_id]", "source_trial_id", ""),
])
def test_a_method_factor_no_trial_holds_is_refused(results, override, name, hint):
    for command in ("show", "run"):
        refused(results, [command, "baseline_grid", override, "--root", results],
                f"method_factors names {name!r}, which is no factor and no key of a trial of kind "
                "'quasi_static', so it would change nothing but the config hash; "
                f"{hint}a method factor names a factor or trial key whose levels share one scene's "
                "random draws (this study's: mass_kg, mu, planner, shape).")


def test_a_method_factor_in_a_study_file_is_named_with_its_line(results, user_dir):
    path = user_dir / "mine.yaml"
    path.write_text(HEADER + "name: mine\nkind: mesh_features\nmethod_factors: [nosuch]\n"
                    "factors:\n  shape: [sphere]\n  nodes: [144]\n")
    refused(results, ["show", path, "--root", results],
            f"{path}, line 5: method_factors names 'nosuch', which is no factor and no key of a "
            "trial of kind 'mesh_features', so it would change nothing but the config hash; a "
            "method factor names a factor or trial key whose levels share one scene's random "
            "draws (this study's: nodes, shape).")
