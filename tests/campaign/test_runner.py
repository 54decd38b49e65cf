"""Runner: backends agree, errors are recorded, preparations run once, resume, drift."""

from __future__ import annotations

import kinds_for_tests  # noqa: F401  (registers the test kinds)
import pandas as pd
import pytest

from graspcampaign.campaign.records import RunStore
from graspcampaign.campaign.runner import DriftError, run_study

VOLATILE = ["wall_time_s", "worker", "host"]


def _records(summary) -> pd.DataFrame:
    df = RunStore(summary.path).read().to_pandas()
    return df.drop(columns=VOLATILE).sort_values("trial_id").reset_index(drop=True)


def test_sequential_loky_and_dask_give_identical_records(study_factory, tmp_path):
    pytest.importorskip("distributed")
    seq = run_study(study_factory(backend="sequential"), run="seq")
    loky1 = run_study(study_factory(backend="loky", n_jobs=1), run="loky1")
    loky2 = run_study(study_factory(backend="loky", n_jobs=2, runner={"batch_size": 3}),
                      run="loky2")
    dask = run_study(study_factory(backend="dask", n_jobs=2, runner={"batch_size": 5}),
                     run="dask")
    ref = _records(seq).drop(columns=["run"])
    assert len(ref) == 16 and ref["trial_id"].is_unique
    for other in (loky1, loky2, dask):
        pd.testing.assert_frame_equal(ref, _records(other).drop(columns=["run"]))


def test_planners_of_a_scene_see_the_same_draws(study_factory):
    df = _records(run_study(study_factory()))
    per_scene = df.groupby("scene_id")["first_draw"].nunique()
    assert (per_scene == 1).all() and len(per_scene) == 8


def test_trial_error_is_recorded_and_campaign_goes_on(study_factory):
    summary = run_study(study_factory(factors={"mu": [0.1, 13.0]}, seeds=2))
    df = _records(summary)
    assert summary.n_error == 2 and summary.n_ok == 2
    err = df[df["status"] == "error"]
    assert set(err["error_type"]) == {"ValueError"}
    assert set(err["error_message"]) == {"mu = 13 is unlucky"}
    assert err["pi_estimate"].isna().all()


def test_fail_fast_stops(study_factory):
    summary = run_study(study_factory(factors={"mu": [13.0, 0.1]}, seeds=3,
                                      runner={"batch_size": 1}), fail_fast=True)
    assert summary.stopped_early and summary.n_ran == 1


def test_traces_are_stored_keyed_by_trial(study_factory):
    summary = run_study(study_factory(kind="test_pi_trace"))
    store = RunStore(summary.path)
    trace = store.read("tables/trace").to_pandas()
    records = store.read().to_pandas()
    assert len(trace) == 3 * len(records)
    assert set(trace["trial_id"]) == set(records["trial_id"])


def test_preparation_runs_once_per_body_and_is_reused(study_factory):
    study = study_factory(kind="test_pi_prepared")
    first = run_study(study)
    assert first.n_prepared == 2  # two masses
    prepared = RunStore(first.path).read("prepared").to_pandas()
    records = _records(first)
    for _, row in prepared.iterrows():
        used = records.loc[records["mass_kg"] == row["mass_kg"], "identified_scale"]
        assert (used == row["identified_scale"]).all()
    again = run_study(study)
    assert again.n_ran == 0 and again.n_prepared == 0


def test_resume_skips_recorded_and_matches_uninterrupted(study_factory):
    full = _records(run_study(study_factory(), run="full"))
    partial_study = study_factory(factors={"mass_kg": [0.2], "mu": [0.1, 0.3],
                                           "planner": ["heuristic", "random"]})
    run_study(partial_study, run="resumed")
    resumed = run_study(study_factory(), run="resumed", allow_drift=True)
    assert resumed.n_already == 8 and resumed.n_ran == 8
    pd.testing.assert_frame_equal(full.drop(columns=["run"]),
                                  _records(resumed).drop(columns=["run"]))


def test_changed_config_is_refused_without_allow_drift(study_factory):
    run_study(study_factory())
    with pytest.raises(DriftError, match="was started with a different resolved study config; "
                                         "use a new run name.*--allow-drift"):
        run_study(study_factory(seed=8))
    run_study(study_factory(seed=8), allow_drift=True)


def test_runner_settings_are_not_drift(study_factory):
    run_study(study_factory(backend="sequential"))
    again = run_study(study_factory(backend="loky", n_jobs=2))
    assert again.n_ran == 0
