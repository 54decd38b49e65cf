"""What a run's records say each trial stored besides its record (``campaign.parts``): a trial
storing no trace row is never missing one, a trace file gone makes exactly its trials run again,
and a run stored before the records said so is read as before."""

from __future__ import annotations

import shutil

import kinds_for_tests  # noqa: F401  (registers the test kinds)
import pyarrow.parquet as pq
import pytest
from killed import Killed, kill_after

from graspcampaign.campaign.records import RunStore
from graspcampaign.campaign.runner import run_study
from graspcampaign.campaign.studyfile import run_path
from graspcampaign.campaign.verify import PARTS_KEY, facts
from graspcampaign.errors import DamagedRunError


def _accounts(store: RunStore) -> dict:
    """Every trial's account, from the stored records files' metadata as written."""
    out = {}
    for path in store._listing("records")[0]:
        out.update(facts(path).accounts or {})
    return out


def _ids(path) -> set:
    return set(pq.read_table(path, columns=["trial_id"]).column("trial_id").to_pylist())


def test_a_trial_that_stores_no_trace_row_is_never_called_damaged(study_factory):
    """The random planner's trials store two trace rows each, the heuristic's none (an empty
    table; tasks of heuristic trials alone write no trace file): the records account for exactly
    that, and the run is whole."""
    summary = run_study(study_factory(kind="test_pi_sparse_trace", runner={"batch_size": 2}))
    store = RunStore(summary.path)
    assert store.check() is not None
    records = store.read(columns=["trial_id", "planner"]).to_pylist()
    random = {r["trial_id"] for r in records if r["planner"] == "random"}
    assert len(random) == 8 and len(records) == 16
    assert _accounts(store) == {r["trial_id"]: {"tables": {"trace": 2}} if r["trial_id"] in random
                                else {} for r in records}
    assert set(store.read("tables/trace").column("trial_id").to_pylist()) == random


def test_the_trials_of_a_trace_file_gone_run_again_and_no_other(study_factory, monkeypatch):
    """A run killed after three tasks of three trials (a seed's two heuristic trials and a random
    one, or the reverse), one of its trace files deleted: the check names the table and the first
    trial; the resumed run drops exactly those trials' records (the heuristic trials of their
    records file keep theirs, and their accounts) and runs them again with the trials never run."""
    study = study_factory(kind="test_pi_sparse_trace", runner={"batch_size": 3})
    clean = run_study(study_factory(kind="test_pi_sparse_trace", runner={"batch_size": 3}), run="clean")
    with monkeypatch.context() as m:
        kill_after(m, 3)
        with pytest.raises(Killed):
            run_study(study)
    store = RunStore(run_path(study))
    shards = sorted((store.path / "tables" / "trace").glob("part-*.parquet"))
    assert shards
    lost = _ids(shards[0])
    (twin,) = [p for p in (store.path / "records").glob("part-*.parquet") if _ids(p) & lost]
    assert _ids(twin) - lost  # trials that stay recorded
    shards[0].unlink()
    done = store.recorded_ids()
    with pytest.raises(DamagedRunError) as refused:
        store.check()
    assert (f"has tables/trace without the traces of {len(lost)} recorded trial"
            f"{'s' if len(lost) > 1 else ''} (first {min(lost)}); resume the run") in str(refused.value)
    with pytest.warns(UserWarning, match="tables/trace without the traces"):
        resumed = run_study(study)
    assert resumed.n_already == len(done) - len(lost) and resumed.n_ran == 16 - resumed.n_already
    assert store.check() is not None
    clean_store = RunStore(clean.path)
    assert _accounts(store) == _accounts(clean_store)
    assert set(_accounts(store)) == store.recorded_ids()
    columns = ["trial_id", "pi_estimate", "first_draw"]
    assert (store.read(columns=columns).sort_by("trial_id")
            == clean_store.read(columns=columns).sort_by("trial_id"))
    trace = ["trial_id", "step", "value"]
    assert (store.read("tables/trace", trace).sort_by([("trial_id", "ascending"), ("step", "ascending")])
            == clean_store.read("tables/trace", trace).sort_by([("trial_id", "ascending"),
                                                                ("step", "ascending")]))


def test_a_run_stored_before_the_accounts_is_read_as_before(study_factory):
    """Records files without the account (a run stored before it was kept): a trace table gone
    is not asked for (nothing says it was stored), the run checks and resumes as before."""
    study = study_factory(kind="test_pi_trace")
    store = RunStore(run_study(study).path)
    for path in store._listing("records")[0]:
        table = pq.read_table(path)
        meta = {k: v for k, v in table.schema.metadata.items() if k != PARTS_KEY}
        pq.write_table(table.replace_schema_metadata(meta), path, write_page_checksum=True)
    assert not _accounts(store)
    shutil.rmtree(store.path / "tables" / "trace")
    assert store.check() is not None
    again = run_study(study)
    assert again.n_ran == 0 and again.n_already == 16


def test_one_function_reads_the_body_ids_of_a_run_and_of_one_file():
    """integrity (one file of preparations) and parts (the run's) each had a ``_body_ids`` of the
    same logic; ``parts.body_ids`` serves both, a table without the column holding none."""
    import pyarrow as pa

    from graspcampaign.campaign import integrity, parts

    assert integrity.body_ids is parts.body_ids
    assert parts.body_ids(pa.table({"body_id": ["b1", "b2", "b1"]})) == frozenset({"b1", "b2"})
    assert parts.body_ids(pa.table({})) == frozenset()
