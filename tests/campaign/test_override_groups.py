"""An override of a whole config group refused before Hydra reads it (``override_groups``)."""

from __future__ import annotations

import pytest

from graspcampaign.campaign import override_groups
from graspcampaign.campaign.override import check_overrides
from graspcampaign.errors import ConfigError


@pytest.fixture
def listed(monkeypatch):
    """The config groups whose options (the files of ``conf/<group>/``) are listed."""
    groups, options = [], override_groups.group_options
    monkeypatch.setattr(override_groups, "group_options",
                        lambda group: groups.append(group) or options(group))
    return groups


def test_an_override_choosing_an_option_lists_no_groups_options(listed):
    """Each group override listed its group's folder for a sentence it did not say."""
    check_overrides(["model=firm", "runner=local", "evaluator.n_cand=3", "seeds=2"])
    assert listed == []


def test_a_refused_group_override_lists_the_options_of_its_group_only(listed):
    with pytest.raises(ConfigError, match=r"^override 'model=null' gives the config group model null, "
                                          r"which is no option; choose one of its options \(model=OPTION; "
                                          r"options: (\w+, )+\w+\)\.$"):
        check_overrides(["runner=local", "model=null"])
    assert listed == ["model"]
