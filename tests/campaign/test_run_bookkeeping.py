"""A run's bookkeeping the mutation run found unpinned: how many trials a manifest vouches for, what
enters the config hash, the values' digest, the run lock, and the duplicate and missing-trial
checks at their edge (one trial twice, one trial missing).

Expected values come from the stored records read with pyarrow, not from the tool's own counts.
"""

from __future__ import annotations

import dataclasses
import json

import kinds_for_tests  # noqa: F401  (registers the test kinds)
import pyarrow as pa
import pyarrow.compute as pc
import pyarrow.parquet as pq
import pytest
from damage import as_written

from graspcampaign.campaign import integrity, provenance
from graspcampaign.campaign.paths import run_path
from graspcampaign.campaign.records import RunStore
from graspcampaign.campaign.runner import run_lock, run_study
from graspcampaign.campaign.verify import content_digest
from graspcampaign.errors import UserInputError


def _stored_ids(store: RunStore) -> set:
    return set(pq.read_table(store.path / "records", columns=["trial_id"])["trial_id"].to_pylist())


def _manifest(store: RunStore) -> dict:
    return json.loads(store.manifest_path.read_text())


def test_a_resumed_session_keeps_counting_the_trials_stored_before_it(finished):
    study, store, _ = finished
    run_study(study)  # nothing left to run: the second session runs 0 trials
    assert _manifest(store)["n_recorded"] == len(_stored_ids(store)) == 16


def test_an_earlier_manifest_vouches_for_every_trial_only_if_one_config_finished_it(finished):
    _, store, _ = finished
    legacy = {k: v for k, v in _manifest(store).items() if k != "n_recorded"}  # no count then
    assert integrity.expected_records(legacy) == legacy["n_trials"] == 16
    other = {**legacy, "sessions": [*legacy["sessions"], {"config_hash": "0123456789abcdef"}]}
    assert integrity.expected_records(other) == 0  # which config recorded which trial: unknown
    assert integrity.expected_records({**legacy, "finished_at": None}) == 0


def test_every_part_of_the_config_but_the_runner_output_and_description_enters_its_hash(study_factory):
    config = provenance.study_dict(study_factory())
    digest = provenance.config_digest(config)
    for field in dataclasses.fields(type(study_factory())):
        changed = provenance.config_digest({**config, field.name: "changed"})
        assert (changed == digest) == (field.name in ("runner", "output", "description")), field.name


def test_the_changes_a_preparation_depends_on_are_found_past_any_number_of_design_changes(
        study_factory):
    """check_preparations names the settings a preparation depends on that changed: the changes
    outside ``free`` (PREPARATION_FREE: the design among them) are told apart by key, not by
    reading the text back, so a hundred factors changed before pso (dataclass order) hide none."""
    study = study_factory()
    config = provenance.study_dict(study)
    recorded = {**config, "factors": {f"f{i}": [i] for i in range(101)},
                "pso": {**config["pso"], "n_particles": config["pso"]["n_particles"] + 1}}
    n = config["pso"]["n_particles"]
    assert provenance.config_changes(recorded, study, free=provenance.PREPARATION_FREE) == [
        f"pso.n_particles {n + 1} -> {n}"]
    assert provenance.config_changes(recorded, study)[0] == "factors.f0 [0] -> <unset>"


def test_the_values_digest_ignores_column_order_and_sees_a_renamed_column(finished):
    table = pq.read_table(finished[2])
    digest = content_digest(table)
    assert content_digest(table.select(table.column_names[::-1])) == digest
    renamed = table.rename_columns([f"{c}_x" if c == "trial_id" else c for c in table.column_names])
    assert content_digest(renamed) != digest


def test_a_run_held_by_one_lock_refuses_a_second(finished):
    study, store, _ = finished
    with run_lock(store, f"{study.name}/r1"):
        with pytest.raises(UserInputError, match=rf"^run unit/r1 at {store.path} is being run by "
                                                 r"another process; wait for it to finish"):
            with run_lock(store, f"{study.name}/r1"):
                pass
    with run_lock(store, f"{study.name}/r1"):  # released with the first
        pass


def test_one_trial_recorded_twice_in_a_file_is_found(finished):
    _, store, compact = finished
    table = pq.read_table(compact)
    as_written(pa.concat_tables([table, table.slice(0, 1)]), compact)
    found = [p.text for p in integrity.problems(store, _manifest(store))]
    assert any(f"records/{compact.name} that records 1 trial twice" in t for t in found), found


def test_one_missing_trial_is_found(finished):
    _, store, compact = finished
    table = pq.read_table(compact)
    first = table["trial_id"][0]
    as_written(table.filter(pc.not_equal(table["trial_id"], first)), compact)
    found = [p.text for p in integrity.problems(store, _manifest(store))]
    assert "missing records: its manifest counts 16 recorded trials but 15 are stored" in found, found


def test_three_copies_of_a_preparation_with_other_values_name_each_file_once(study_factory):
    """Two copies of a run's preparations, each with other values: the earlier file was named once
    by each copy, and run, moving it aside twice, failed on the second move (no such file). Each
    of the three is named once, all move aside, and the preparations computed again are the
    run's own (seeded by the body alone)."""
    study = study_factory(kind="test_pi_prepared")
    run_study(study)
    store = RunStore(run_path(study))
    (own,) = (store.path / "prepared").glob("*.parquet")
    table = pq.read_table(own)
    at = table.column_names.index("identified_scale")
    copies = [own.with_name(f"part-{c * 10}.parquet") for c in "ab"]
    for factor, copy in enumerate(copies, start=2):
        as_written(table.set_column(at, "identified_scale", pc.multiply(table.column(at), factor)),
                   copy)
    named = [p.path for p in integrity.problems(store, _manifest(store)) if p.part == "prepared"]
    assert sorted(named) == sorted([own, *copies])
    with pytest.warns(UserWarning, match="moved to") as moved:
        assert run_study(study).n_prepared == table.num_rows
    assert len(moved) == 3, [str(w.message) for w in moved]
    (again,) = (store.path / "prepared").glob("*.parquet")
    columns = ["body_id", "identified_scale"]
    assert pq.read_table(again, columns=columns).sort_by("body_id").equals(
        table.select(columns).sort_by("body_id"))
