"""Mutation round 9: ``paths.run_command`` keeps ``--root`` where an override sets the results root
in any of Hydra's forms (docs/decisions.md, mutation round 9)."""

from __future__ import annotations

import shlex

import pytest
from hydra.core.override_parser.overrides_parser import OverridesParser

from graspcampaign.campaign.paths import run_command


@pytest.mark.parametrize("override", ["output.root=elsewhere", "++output.root=elsewhere"])
def test_an_override_setting_the_root_keeps_the_default_root_named(override):
    """``++output.root=X`` (Hydra's force-add) sets output.root as ``output.root=X`` does: its key,
    by Hydra's own parser, is output.root. Without ``--root results`` the command would resume the
    run under X, another run."""
    assert OverridesParser.create().parse_override(override).key_or_group == "output.root"
    command = run_command("smoke", [override], "default", "results")
    assert shlex.split(command) == ["graspcampaign", "run", "smoke", override, "--run", "default",
                                    "--root", "results"]
    assert run_command("smoke", ["seeds=2"], "default", "results") == (
        "graspcampaign run smoke seeds=2 --run default")
