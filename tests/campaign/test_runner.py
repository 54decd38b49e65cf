"""Runner: backends agree, errors are recorded, preparations run once, resume, drift."""

from __future__ import annotations

import kinds_for_tests  # noqa: F401  (registers the test kinds)
import pandas as pd
import pyarrow.parquet as pq
import pytest
from killed import Killed, kill_after
from legacy_hashing import old_hashing

from graspcampaign.campaign.records import RunStore
from graspcampaign.campaign.runner import DriftError, run_path, run_study

VOLATILE = ["wall_time_s", "worker", "host"]


def _records(summary) -> pd.DataFrame:
    df = RunStore(summary.path).read().to_pandas()
    return df.drop(columns=VOLATILE).sort_values("trial_id").reset_index(drop=True)


def test_sequential_and_loky_give_identical_records(study_factory):
    seq = run_study(study_factory(backend="sequential"), run="seq")
    loky1 = run_study(study_factory(backend="loky", n_jobs=1), run="loky1")
    loky2 = run_study(study_factory(backend="loky", n_jobs=2, runner={"batch_size": 3}),
                      run="loky2")
    ref = _records(seq).drop(columns=["run"])
    assert len(ref) == 16 and ref["trial_id"].is_unique
    for other in (loky1, loky2):
        pd.testing.assert_frame_equal(ref, _records(other).drop(columns=["run"]))


@pytest.mark.slow  # a LocalCluster takes seconds to start: `make test-full`
def test_dask_gives_the_records_of_the_sequential_run(study_factory):
    pytest.importorskip("distributed")
    seq = run_study(study_factory(backend="sequential"), run="seq")
    dask = run_study(study_factory(backend="dask", n_jobs=2, runner={"batch_size": 5}),
                     run="dask")
    pd.testing.assert_frame_equal(_records(seq).drop(columns=["run"]),
                                  _records(dask).drop(columns=["run"]))


def test_the_runner_writes_every_declared_record_column_with_its_type(study_factory):
    from graspcampaign.campaign.records import OPTIONAL_COLUMNS, RECORD_COLUMNS

    schema = pq.read_schema(next((run_study(study_factory()).path / "records").glob("*.parquet")))
    arrow = {"text": "string", "whole numbers": "int64", "numbers": "double"}
    declared = {**RECORD_COLUMNS, **OPTIONAL_COLUMNS}
    assert {c: str(schema.field(c).type) for c in declared} == {
        c: arrow[holds] for c, holds in declared.items()}


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
    with pytest.raises(DriftError, match=r"was started with a different resolved study config "
                                         r"\(seed 7 -> 8\); use a new run name.*--allow-drift"):
        run_study(study_factory(seed=8))
    run_study(study_factory(seed=8), allow_drift=True)


def test_a_description_is_not_part_of_the_config_hash(study_factory):
    from graspcampaign.campaign.provenance import config_hash

    assert config_hash(study_factory(description="a")) == config_hash(study_factory(description="b"))
    assert config_hash(study_factory(seed=7)) != config_hash(study_factory(seed=8))


def _run_stored_by_the_old_hashing(study):
    """Run ``study`` partly, as the code before the description left the hash stored it."""
    with old_hashing():
        run_study(study)


def test_a_run_stored_under_the_old_hash_resumes_and_reports_after_a_description_fix(
        study_factory, tmp_path):
    import json

    from graspcampaign.report.build import build_reports

    partial = {"mass_kg": [0.2], "mu": [0.1, 0.3], "planner": ["heuristic", "random"]}
    _run_stored_by_the_old_hashing(study_factory(factors=partial, description="stale text"))
    # the description changed, nothing else: no drift, and the run keeps one name for its config
    resumed = run_study(study_factory(factors=partial, description="the fixed text"))
    assert (resumed.n_already, resumed.n_ran) == (8, 0)
    manifest = json.loads((resumed.path / "manifest.json").read_text())
    assert {s["config_hash"] for s in manifest["sessions"]} == {manifest["config_hash"]}
    batch = build_reports(["unit"], root=tmp_path / "results", run="r1")
    assert not batch.failed and (resumed.path / "report" / "report.md").exists()


def test_a_real_change_to_a_run_stored_under_the_old_hash_is_still_drift(study_factory):
    _run_stored_by_the_old_hashing(study_factory(description="stale text"))
    with pytest.raises(DriftError, match=r"was started with a different resolved study config "
                                         r"\(seed 7 -> 8\); use a new run name"):
        run_study(study_factory(seed=8, description="the fixed text"))


def test_runner_settings_are_not_drift(study_factory):
    run_study(study_factory(backend="sequential"))
    again = run_study(study_factory(backend="loky", n_jobs=2))
    assert again.n_ran == 0



def _tree(root):
    return {p: p.read_bytes() for p in sorted(root.rglob("*")) if p.is_file()}


def test_killed_run_with_a_damaged_value_column_reruns_exactly_that_shard(
        study_factory, monkeypatch):
    from damage import corrupt_value_column

    clean = _records(run_study(study_factory(runner={"batch_size": 3}), run="clean"))
    study = study_factory(runner={"batch_size": 3})
    with monkeypatch.context() as m:
        kill_after(m, 3)
        with pytest.raises(Killed):
            run_study(study)
    records = sorted((run_path(study) / "records").glob("part-*.parquet"))
    assert len(records) == 3 and not list(records[0].parent.glob("compact-*"))
    damaged = records[1]
    lost = set(pq.read_table(damaged, columns=["trial_id"]).column("trial_id").to_pylist())
    corrupt_value_column(damaged, "pi_estimate")
    with pytest.warns(UserWarning, match=f"damaged file {damaged} moved to"):
        resumed = run_study(study)
    assert resumed.n_already == 9 - len(lost) and resumed.n_ran == 16 - 9 + len(lost)
    quarantined = run_path(study) / "quarantine" / f"records__{damaged.name}"
    assert quarantined.is_file()
    pd.testing.assert_frame_equal(clean.drop(columns=["run"]),
                                  _records(resumed).drop(columns=["run"]))


def test_finished_run_with_a_damaged_shard_is_refused_by_report_then_resumed(study_factory):
    from damage import corrupt_value_column
    from typer.testing import CliRunner

    from graspcampaign.cli.main import app

    clean = _records(run_study(study_factory(), run="clean"))
    study = study_factory()
    summary = run_study(study)
    (compact,) = (summary.path / "records").glob("compact-*.parquet")
    corrupt_value_column(compact, "pi_estimate")
    root = summary.path.parent.parent
    before = _tree(root)
    result = CliRunner().invoke(app, ["report", "unit", "--run", "r1", "--root", str(root)])
    assert result.exit_code == 2
    assert result.stderr == (
        f"error: run unit/r1 at {summary.path} has a damaged file records/{compact.name} "
        "(could not verify page integrity, CRC checksum verification failed for page_ordinal 0); "
        f"resume the run (graspcampaign run unit --run r1 --root {root}) to quarantine the file "
        "and run its trials again.\n")
    assert _tree(root) == before
    with pytest.warns(UserWarning, match="damaged file"):
        resumed = run_study(study)
    assert resumed.n_already == 0 and resumed.n_ran == 16
    pd.testing.assert_frame_equal(clean.drop(columns=["run"]),
                                  _records(resumed).drop(columns=["run"]))
    assert CliRunner().invoke(app, ["report", "unit", "--run", "r1", "--root", str(root)]
                              ).exit_code == 0


def test_damaged_trace_file_reruns_the_trials_it_held(study_factory, monkeypatch):
    from damage import corrupt_value_column

    clean_summary = run_study(study_factory(kind="test_pi_trace", runner={"batch_size": 4}),
                              run="clean")
    study = study_factory(kind="test_pi_trace", runner={"batch_size": 4})
    with monkeypatch.context() as m:
        kill_after(m, 2)
        with pytest.raises(Killed):
            run_study(study)
    path = run_path(study)
    trace = sorted((path / "tables" / "trace").glob("part-*.parquet"))[0]
    lost = set(pq.read_table(trace, columns=["trial_id"]).column("trial_id").to_pylist())
    corrupt_value_column(trace, "value")
    with pytest.warns(UserWarning, match="damaged file"):
        resumed = run_study(study)
    assert resumed.n_already == 8 - len(lost) and resumed.n_ran == 8 + len(lost)
    store, clean_store = RunStore(path), RunStore(clean_summary.path)
    for part in ("records", "tables/trace"):
        ours = store.read(part).to_pandas().drop(columns=VOLATILE + ["run"], errors="ignore")
        ref = clean_store.read(part).to_pandas().drop(columns=VOLATILE + ["run"], errors="ignore")
        key = ["trial_id", "step"] if part != "records" else ["trial_id"]
        pd.testing.assert_frame_equal(ours.sort_values(key).reset_index(drop=True),
                                      ref.sort_values(key).reset_index(drop=True))


def test_error_columns_are_strings_even_when_no_trial_errored(study_factory):
    import pyarrow as pa

    summary = run_study(study_factory())
    table = RunStore(summary.path).read()
    for name in ("error_type", "error_message", "error_traceback"):
        assert table.schema.field(name).type == pa.string()
        assert table.column(name).null_count == table.num_rows
