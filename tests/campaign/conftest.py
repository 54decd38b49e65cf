"""Fixtures shared by the campaign tests."""

from __future__ import annotations

import kinds_for_tests  # noqa: F401  (registers the test kinds)
import pytest

from graspcampaign.campaign.paths import run_path
from graspcampaign.campaign.records import RunStore
from graspcampaign.campaign.runner import run_study


@pytest.fixture
def finished(study_factory):
    """A finished run of the test kind (16 trials): its study, store and compacted records file."""
    study = study_factory()
    run_study(study)
    store = RunStore(run_path(study))
    (compact,) = (store.path / "records").glob("compact-*.parquet")
    return study, store, compact
