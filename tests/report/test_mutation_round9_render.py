"""Mutation round 9: the report's command for a run that lacks a part gives the overrides the run's
manifest keeps as ``provenance.overrides_given`` reads them (docs/decisions.md, mutation round 9):
a list of text, else none. It read ``overrides`` itself, and built its command of a number (a
TypeError, reported as the item's broken code) or of a text's characters."""

from __future__ import annotations

from pathlib import Path

import pandas as pd
import pyarrow as pa
import pytest

from graspcampaign.report.render import Run
from graspcampaign.report.studies import dynamic


class NoParts:
    """A run's store holding no part, under a results root of its own."""

    path = Path("/data/runs/friction_mass/r1")

    def read(self, part: str) -> pa.Table:
        return pa.table({})


@pytest.mark.parametrize("overrides", [[1, "seeds=2"], "seeds=2", None])
def test_overrides_that_are_not_a_list_of_text_are_not_given_again(overrides):
    records = pd.DataFrame({"trial_id": ["t0"], "status": ["ok"], "mu": [0.3], "panel": ["mu_mass"]})
    manifest = {"study": "friction_mass", "run": "r1", "config": {"factors": {}}, "overrides": overrides}
    with pytest.raises(ValueError) as raised:
        dynamic.ends(Run(records, manifest, store=NoParts()))
    assert str(raised.value) == (
        "run friction_mass/r1 has no `tables/steps` table: the study stores it while the run's trials "
        "run and this run stored none; run `graspcampaign run friction_mass --run NEW --root /data/runs` "
        "to record a new run.")
