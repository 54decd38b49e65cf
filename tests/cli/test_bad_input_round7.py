"""Bad input, round 7: deleting a whole config group (``~runner``), an option given twice, an
empty output path, a filled-in measured-records template written over.
Each case: exit 2, one sentence naming what is wrong and where, nothing stored changed
(``refused``)."""

from __future__ import annotations

from pathlib import Path

import pytest
from cli_checks import refused

CONF = Path(__file__).parents[2] / "conf"  # the project's config groups, one folder each


@pytest.mark.parametrize("override", ["~runner", "~model=table2", "~runner=default"])
def test_deleting_a_config_group_is_refused_naming_its_options(results, override):
    """``~runner`` exited 0 (Hydra drops the group's file and the schema's values stand in) and
    ``~runner=default`` said "Could not delete 'runner=default'. No match in the defaults list."."""
    group = override[1:].partition("=")[0]
    options = ", ".join(sorted(path.stem for path in (CONF / group).glob("*.yaml")))
    refused(results, ["show", "smoke", override, "--root", results],
            f"override {override!r} deletes the config group {group}, which every study needs; set "
            f"one of its options instead ({group}=OPTION; options: {options}).")
