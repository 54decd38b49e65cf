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
                         "optional_factors": None, "trial_keys": list(kind.trial_keys),
                         "params": catalog.params_spec(kind.params), "stages": kind.stages,
                         "finalize": False}
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


@pytest.mark.parametrize(("seeds", "backend", "expected"), [
    (30, "runner.backend=sequential", "90 s for 30 trials (~3 s each, as the trial kind estimates, "
                                      "on 1 worker)"),
    (30, "runner.n_jobs=2", "45 s for 30 trials (~3 s each, as the trial kind estimates, on 2 workers)"),
    (2000, "runner.backend=sequential", "100 min for 2000 trials (~3 s each,"),
    (2500, "runner.backend=sequential", "2.1 h for 2500 trials (~3 s each,")])
def test_show_estimates_the_time_the_workers_share(tmp_path, monkeypatch, seeds, backend, expected):
    """At 3 s a trial: 30 trials take 90 s on one worker (under 2 min it reads in seconds), 45 s
    on two; 2000 take 6000 s, 100 min (under 2 h in minutes); 2500 take 7500 s, 2.1 h."""
    from graspcampaign.campaign import status

    facts = catalog.kind_facts(compose_study("smoke").kind)
    monkeypatch.setattr(status, "kind_facts", lambda name: {**facts, "seconds_per_trial": 3.0})
    study = compose_study("smoke", ["shape=[sphere]", "nodes=[144]", f"seeds={seeds}", backend,
                                    f"output.root={tmp_path}"])
    line = next(x for x in status.design_text(study).splitlines() if x.startswith("estimated time: "))
    assert line.startswith(f"estimated time: {expected}")


def test_the_paper_block_keeps_an_empty_table_as_its_key():
    """Nested keys dotted, lists as written, and an empty table kept as ``key={}`` (it is part of
    the study file: dropping it would show a paper block other than the file's)."""
    from graspcampaign.campaign.status import _paper_pairs

    assert _paper_pairs({"rates": {}, "test": {"n": 830, "ci": [0.1, 0.2]}}) == [
        "rates={}", "test.n=830", "test.ci=[0.1, 0.2]"]


def test_the_paper_block_is_wrapped_at_a_hundred_characters(tmp_path):
    """Test 2's paper block is ~3,000 characters: `show` wraps it into lines of at most 100 (a
    pair is never split), each continuation line indented."""
    from graspcampaign.campaign.status import design_text

    text = design_text(compose_study("test2_grasp", [f"output.root={tmp_path}"]))
    block = text[text.index("\npaper: ") + 1:].splitlines()
    assert len(block) > 10 and max(map(len, block)) <= 100
    assert all(line.startswith("  ") for line in block[1:])


@pytest.mark.parametrize("name", ["mesh_resolution", "sensitivity", "test1_bench", "test2_grasp",
                                  "test3_disturbance"])
def test_a_designed_kind_declares_the_keys_its_trials_hold(name):
    # the protocols declared none (their trial keys were known only once the schedule was built),
    # so method_factors went unchecked for them; the declaration is read without building it
    from graspcampaign.campaign.schema import FACTOR_SPECS

    study = compose_study(name, [])
    kind = get_kind(name)
    rows = kind.design(study, kind_params(study, kind))
    held = {key for row in rows for key in row} - {*FACTOR_SPECS, "seed", "repeat"}
    assert held == set(kind.trial_keys) - {*FACTOR_SPECS, "seed", "repeat"}
    assert set(kind.trial_keys) <= {key for row in rows for key in row}
