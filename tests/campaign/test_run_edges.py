"""A run's bookkeeping at its edges (mutation testing, round 7): a task stopping at its first
error, the trials per task, a resumed session's count, the manifest written whole or not at all,
a changed code version, a run of the default design, a session's design count."""

from __future__ import annotations

import errno
import json
import math
import pathlib

import kinds_for_tests  # noqa: F401  (registers the test kinds)
import pyarrow.parquet as pq
import pytest

from graspcampaign.campaign import provenance
from graspcampaign.campaign.kind import get_kind
from graspcampaign.campaign.paths import run_path
from graspcampaign.campaign.records import RunStore
from graspcampaign.campaign.runner import run_study, task_size
from graspcampaign.campaign.status import run_status
from graspcampaign.errors import DamagedRunError, StoreWriteError


def test_fail_fast_stops_within_a_task_at_its_first_error(study_factory):
    """One task holding every trial: with fail_fast it records the trials up to its first error
    and none after it (the first trial, mu = 13, fails here)."""
    summary = run_study(study_factory(factors={"mu": [13.0, 0.1]}, seeds=3,
                                      runner={"batch_size": 6}), fail_fast=True)
    statuses = pq.read_table(summary.path / "records").column("status").to_pylist()
    assert statuses == ["error"]
    assert (summary.n_ran, summary.n_error, summary.stopped_early) == (1, 1, True)


@pytest.mark.parametrize("n_jobs", [1, 2, 3])
def test_a_run_is_cut_into_at_most_four_tasks_per_worker(study_factory, n_jobs):
    """Enough trials per task that no worker gets more than four tasks (SPEC Sec. 5: the tasks
    balance the workers), whatever the number of pending trials; at least one trial a task."""
    study = study_factory(backend="loky", n_jobs=n_jobs, runner={"target_task_s": 1e6})
    kind, workers = get_kind(study.kind), study.runner.workers()
    for pending in range(1, 60):
        size = task_size(study, kind, pending)
        assert size >= 1 and math.ceil(pending / size) <= 4 * workers, (pending, size)


def test_a_run_resumed_to_the_end_of_a_larger_design_is_complete(study_factory):
    """The session that last ran the run counts every trial of its design it finds recorded, those
    stored before it too: status then calls the run complete, as it would an uninterrupted one."""
    run_study(study_factory())
    run_study(study_factory(seeds=3), allow_drift=True)
    status = run_status(study_factory().output.root, "unit", "r1")
    assert (status["n_trials"], status["n_recorded"], status["complete"]) == (24, 24, True)


def test_a_manifest_write_stopped_midway_leaves_the_manifest_as_it_was(tmp_path, monkeypatch):
    path = tmp_path / "run" / "manifest.json"
    provenance.write_manifest(path, {"n_trials": 1})
    before = path.read_bytes()
    real = pathlib.Path.write_text

    def half_then_full(self, text, *args, **kwargs):  # the disk fills halfway through
        real(self, text[: len(text) // 2], *args, **kwargs)
        raise OSError(errno.ENOSPC, "No space left on device")

    monkeypatch.setattr(pathlib.Path, "write_text", half_then_full)
    with pytest.raises(StoreWriteError, match="no space left on device; what was stored before"):
        provenance.write_manifest(path, {"n_trials": 2, "more": "x" * 100})
    assert path.read_bytes() == before
    assert sorted(p.name for p in path.parent.iterdir()) == ["manifest.json"]


@pytest.mark.parametrize("field", ["n_trials", "n_recorded"])
def test_a_negative_count_in_a_manifest_is_refused(study_factory, field):
    study = study_factory()
    run_study(study)
    store = RunStore(run_path(study))
    manifest = json.loads(store.manifest_path.read_text())
    store.manifest_path.write_text(json.dumps({**manifest, field: -1}))
    with pytest.raises(DamagedRunError, match=rf"damaged manifest.json \({field} is -1, not a whole "
                                              r"number of trials\)"):
        store.check()


def test_a_run_of_another_code_version_is_refused_naming_both(study_factory):
    study = study_factory()
    run_study(study)
    store = RunStore(run_path(study))
    manifest = json.loads(store.manifest_path.read_text())
    store.manifest_path.write_text(json.dumps({**manifest, "code_version": "0.0.1+abc"}))
    with pytest.raises(provenance.DriftError, match=r"was started with a different code version "
                                                    r"\(0\.0\.1\+abc -> "):
        run_study(study)


def test_a_run_of_its_study_files_design_states_no_change():
    """Overrides of where and how trials run leave the design the study file's: no change to show."""
    manifest = {"config_hash": "h", "n_trials": 4, "overrides": ["runner.n_jobs=2"],
                "default_design": {"config_hash": "h", "n_trials": 4}}
    assert provenance.design_change(manifest) is None
    assert provenance.design_change({**manifest, "config_hash": "g"}) == (
        "", "4 of the study's 4 trials")


def test_a_session_whose_trial_count_is_true_or_false_names_no_design():
    manifest = {"n_trials": 8, "sessions": [{"n_trials": 8, "recorded": 8},
                                            {"n_trials": True, "recorded": 1}]}
    assert provenance.run_size(manifest) == 8
    assert provenance.run_complete(manifest, 8)


def test_a_resumed_run_computes_no_preparation_again(study_factory):
    """Trials added to a run (here by a larger design) reuse the stored preparation of their body:
    none is computed twice, and the run holds one per body, as an uninterrupted run does."""
    first = run_study(study_factory(kind="test_pi_prepared"))
    again = run_study(study_factory(kind="test_pi_prepared", seeds=3), allow_drift=True)
    assert (first.n_prepared, again.n_prepared, again.n_ran) == (2, 0, 8)
    body_ids = RunStore(again.path).read("prepared").column("body_id").to_pylist()
    assert len(body_ids) == len(set(body_ids)) == 2


def test_a_run_resumed_under_a_smaller_design_counts_only_its_trials(study_factory):
    """``--allow-drift`` to a design of 8 of the 16 trials stored: the session finds its 8
    recorded, runs none, and finishes the run; status calls it complete."""
    run_study(study_factory())
    summary = run_study(study_factory(seeds=1), allow_drift=True)
    assert (summary.n_trials, summary.n_already, summary.n_ran) == (8, 8, 0)
    manifest = json.loads((summary.path / "manifest.json").read_text())
    assert manifest["sessions"][-1]["recorded"] == 8 and manifest["finished_at"] is not None
    assert run_status(study_factory().output.root, "unit", "r1")["complete"]


def test_a_repair_that_moved_a_file_warns_once(study_factory):
    """The trials of a file moved aside are missing and run again: the move says so, and the
    manifest's count is not repeated as a second warning."""
    study = study_factory()
    run_study(study)
    store = RunStore(run_path(study))
    (compact,) = (store.path / "records").glob("compact-*.parquet")
    compact.write_bytes(compact.read_bytes()[:100])
    with pytest.warns(UserWarning) as warned:
        run_study(study)
    texts = [str(w.message) for w in warned]
    assert len(texts) == 1 and "moved to" in texts[0], texts


def test_a_cached_design_size_is_the_size_of_that_config(tmp_path, monkeypatch):
    """The catalog caches an explicit design's size per config: another config of the study
    (another fraction of Test 2's objects) is counted, not answered from the cache."""
    from graspcampaign.campaign import catalog
    from graspcampaign.campaign.compose import compose_study
    from graspcampaign.campaign.runner import kind_params, study_trials

    monkeypatch.setenv("GRASPCAMPAIGN_CACHE", str(tmp_path))
    sizes = []
    for fraction in ("0.1", "0.2", "0.1"):
        study = compose_study("test2_grasp", [f"params.fraction={fraction}"])
        kind = get_kind(study.kind)
        sizes.append(catalog.design_size(study))
        assert sizes[-1] == len(study_trials(study, kind, kind_params(study, kind)))
    assert sizes[0] == sizes[2] != sizes[1]


# -- what is cached and counted: catalog, compose, status ----------------------------------------
def test_the_source_hash_sees_a_module_renamed_with_its_contents(tmp_path, monkeypatch):
    """Two package trees holding the same bytes under other file names hash differently (a module
    moved changes what imports find)."""
    import graspcampaign
    from graspcampaign.campaign import catalog

    hashes = []
    for name in ("a.py", "b.py"):
        tree = tmp_path / name.split(".")[0] / "graspcampaign"
        tree.mkdir(parents=True)
        (tree / "__init__.py").write_text("")
        (tree / name).write_text("x = 1\n")
        monkeypatch.setattr(graspcampaign, "__file__", str(tree / "__init__.py"))
        catalog.source_hash.cache_clear()
        hashes.append(catalog.source_hash())
    catalog.source_hash.cache_clear()
    assert hashes[0] != hashes[1]


def test_a_composed_study_changed_by_its_caller_leaves_the_next_one_as_composed():
    from graspcampaign.campaign.compose import compose_study

    for _ in range(2):  # the first one composed, the second one from the cache
        study = compose_study("smoke")
        seed, study.seed = study.seed, study.seed + 1
        study.factors.clear()
        again = compose_study("smoke")
        assert again.seed == seed and again.factors


def test_a_conf_file_edited_between_two_compositions_is_read_again(tmp_path, monkeypatch):
    """The composed-study cache is keyed on the conf files' contents too: editing a config group's
    default between two compositions in one process gives the edited value."""
    import shutil

    from graspcampaign.campaign.compose import compose_study
    from graspcampaign.campaign.studyfile import project_dirs

    conf, campaigns = project_dirs()
    shutil.copytree(conf, tmp_path / "conf")
    shutil.copytree(campaigns, tmp_path / "campaigns")
    monkeypatch.setenv("GRASPCAMPAIGN_HOME", str(tmp_path))
    project_dirs.cache_clear()  # read once per process: read the home just set
    try:
        before = compose_study("smoke").evaluator.seed_depth_m
        evaluator = tmp_path / "conf" / "evaluator" / "default.yaml"
        evaluator.write_text(evaluator.read_text().replace("seed_depth_m: 0.0005",
                                                           "seed_depth_m: 0.0007"))
        after = compose_study("smoke").evaluator.seed_depth_m
    finally:
        monkeypatch.undo()
        project_dirs.cache_clear()
    assert (before, after) == (0.0005, 0.0007)


def test_recorded_counts_only_the_trials_of_the_design_asked_about(study_factory):
    """``recorded_in`` a run of 16 trials: all 16 for its own config, 8 for a design of one of its
    two masses, and 16 of the 24 of a design with a third seed."""
    from graspcampaign.campaign.status import recorded_in

    run_study(study_factory())
    assert recorded_in(study_factory()) == 16
    half = study_factory(factors={"mass_kg": [0.2], "mu": [0.1, 0.3],
                                  "planner": ["heuristic", "random"]})
    assert recorded_in(half) == 8
    assert recorded_in(study_factory(seeds=3)) == 16


def test_status_counts_the_records_stored_not_the_manifests_count(study_factory):
    """A run killed after writing shards, before its manifest counted them: status reports the
    trials stored."""
    study = study_factory()
    run_study(study)
    store = RunStore(run_path(study))
    manifest = json.loads(store.manifest_path.read_text())
    manifest["sessions"][-1].update(finished_at=None, recorded=None, ran=None)
    store.manifest_path.write_text(json.dumps({**manifest, "n_recorded": 0, "finished_at": None}))
    status = run_status(study.output.root, "unit", "r1")
    assert (status["n_recorded"], status["n_ok"], status["complete"]) == (16, 16, False)


def test_a_fail_fast_run_whose_error_is_its_last_trial_is_finished(study_factory):
    """fail_fast stops at the first error; when that is the design's last trial nothing is left
    to stop, so the run is finished as one without fail_fast (its finish time set, its kind's
    finalize run): it was left unfinished while ``status`` called it complete (mutation round 7,
    N6). The one task runs mu = 0.1 then mu = 13, which fails."""
    summary = run_study(study_factory(factors={"mu": [0.1, 13.0]}, seeds=1,
                                      runner={"batch_size": 6}), fail_fast=True)
    assert (summary.n_ran, summary.n_error, summary.stopped_early) == (2, 1, True)
    manifest = json.loads((summary.path / "manifest.json").read_text())
    assert manifest["finished_at"] is not None
    assert manifest["finished_at"] == manifest["sessions"][-1]["finished_at"]
