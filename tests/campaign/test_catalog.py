"""The catalog cache gives exactly what the code gives, and is recomputed when the code changes."""

from __future__ import annotations

import json

import pytest

from graspcampaign.campaign import catalog
from graspcampaign.campaign.compose import compose_study
from graspcampaign.campaign.kind import get_kind
from graspcampaign.campaign.runner import kind_params, study_trials
from graspcampaign.core.mesh import SHAPES
from graspcampaign.core.planner import PLANNERS


def test_cached_facts_equal_the_code(tmp_path, monkeypatch):
    monkeypatch.setenv("GRASPCAMPAIGN_CACHE", str(tmp_path))
    for _ in range(2):  # computed, then read back from the file
        assert catalog.registry_names("shape") == tuple(SHAPES)
        assert catalog.registry_names("planner") == tuple(PLANNERS)
        facts = catalog.kind_facts("test2_grasp")
        kind = get_kind("test2_grasp")
        assert facts == {"seconds_per_trial": kind.seconds_per_trial, "design": True,
                         "source": kind.source, "factors": list(kind.factors),
                         "params": catalog.params_spec(kind.params), "stages": kind.stages}
        assert [f[0] for f in facts["params"]["fields"]] == ["objects", "groups", "fraction",
                                                             "belief_error"]
        study = compose_study("test2_grasp", ["params.fraction=0.1"])
        assert catalog.design_size(study) == len(study_trials(study, kind, kind_params(study, kind)))
    data = json.loads((tmp_path / "catalog.json").read_text())
    assert data["source"] == catalog.source_hash() and data["registries"]["shape"] == list(SHAPES)


def test_a_cache_of_another_code_version_is_ignored(tmp_path, monkeypatch):
    monkeypatch.setenv("GRASPCAMPAIGN_CACHE", str(tmp_path))
    (tmp_path / "catalog.json").write_text(json.dumps(
        {"source": "older-code", "registries": {"shape": ["teapot"]}}))
    assert catalog.registry_names("shape") == tuple(SHAPES)
    assert json.loads((tmp_path / "catalog.json").read_text())["source"] == catalog.source_hash()


def test_an_unwritable_cache_only_costs_time(tmp_path, monkeypatch):
    blocker = tmp_path / "file"
    blocker.write_text("not a directory")
    monkeypatch.setenv("GRASPCAMPAIGN_CACHE", str(blocker / "cache"))
    with pytest.warns(UserWarning, match=r"GRASPCAMPAIGN_CACHE=.*/file/cache cannot be written "
                                         r"\(Not a directory\), so the catalog cache is not kept"):
        assert catalog.registry_names("planner") == tuple(PLANNERS)


def _rows_equal_composed(names):
    from graspcampaign.campaign.status import study_size
    from graspcampaign.campaign.studyfile import study_files

    for name, path in study_files().items():
        if name in names:
            row = catalog.study_row(path)
            study = compose_study(name)
            assert (row["kind"], row["trials"]) == (study.kind, study_size(study)), name


def test_list_rows_equal_the_composed_studies():
    # every Cartesian study, and one protocol schedule (Test 2, 1785 rows)
    _rows_equal_composed({"ablation", "baseline_grid", "friction_mass", "gravity_settle",
                          "heuristic_weights", "pso_repeatability", "shapes", "smoke",
                          "surrogate", "wrench_balance", "test2_grasp"})


@pytest.mark.slow  # builds the 19,168-event Test 1 schedule and the other protocol designs
def test_list_rows_equal_the_composed_studies_with_explicit_designs():
    _rows_equal_composed({"mesh_resolution", "sensitivity", "test1_bench", "test3_disturbance"})
