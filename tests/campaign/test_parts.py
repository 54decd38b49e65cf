"""What a run's records say each trial stored besides its record (``campaign.parts``): a trial
storing no trace row is never missing one, a trace file gone makes exactly its trials run again,
and a run stored before the records said so is read as before."""

from __future__ import annotations

import json
import shutil

import kinds_for_tests  # noqa: F401  (registers the test kinds)
import pyarrow.parquet as pq
import pytest
from killed import Killed, kill_after

from graspcampaign.campaign.paths import run_path
from graspcampaign.campaign.records import RunStore, _write_atomic
from graspcampaign.campaign.runner import run_study
from graspcampaign.campaign.verify import PARTS_KEY
from graspcampaign.errors import DamagedRunError


def _accounts(store: RunStore) -> dict:
    """Every trial's entry, from the stored records files' metadata as docs/records.md describes
    it (read here with json and pyarrow alone): a mapping of trial ids (the form written before
    version 2), or lists aligned with the file's trial_id column."""
    out = {}
    for path in store.listing("records")[0]:
        out.update(_accounts_of(path))
    return out


def _accounts_of(path) -> dict:
    """Every trial's entry in the account of records file ``path`` (:func:`_accounts`)."""
    raw = pq.read_metadata(path).metadata.get(PARTS_KEY)
    value = json.loads(raw) if raw is not None else {}
    if "v" not in value:
        return value
    assert value["v"] == 2
    out = {}
    for row, trial in enumerate(_row_ids(path)):
        rows = {name: counts[row] for name, counts in value["tables"].items() if counts[row]}
        body = value["body"][row] if "body" in value else None
        out[trial] = {**({"tables": rows} if rows else {}),
                      **({"body": value["bodies"][body]} if body is not None else {})}
    return out


def _row_ids(path) -> list:
    """The trial id of each row of ``path``, in row order."""
    return pq.read_table(path, columns=["trial_id"]).column("trial_id").to_pylist()


def _ids(path) -> set:
    return set(_row_ids(path))


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


def _as_version_1(store: RunStore) -> None:
    """Rewrite the run's records files with their accounts as the release before version 2 wrote
    them: ``{trial_id: entry}`` in the Arrow schema's metadata (and so in the file's too)."""
    for path in store.listing("records")[0]:
        entries = _accounts_of(path)
        table = pq.read_table(path)
        old = json.dumps(entries, sort_keys=True, separators=(",", ":")).encode()
        _write_atomic(table.replace_schema_metadata({**table.schema.metadata, PARTS_KEY: old}), path)
        assert pq.read_schema(path).metadata[PARTS_KEY] == old


def _versions(store: RunStore) -> set:
    """The versions of the accounts of the run's records files (1: the mapping of trial ids)."""
    return {json.loads(pq.read_metadata(path).metadata[PARTS_KEY]).get("v", 1)
            for path in store.listing("records")[0]}


@pytest.mark.parametrize("version", [2, 1])
def test_the_trials_of_a_trace_file_gone_run_again_and_no_other(study_factory, monkeypatch, version):
    """A run killed after three tasks of three trials (a seed's two heuristic trials and a random
    one, or the reverse), one of its trace files deleted: the check names the table and the first
    trial; the resumed run drops exactly those trials' records (the heuristic trials of their
    records file keep theirs, and their accounts) and runs them again with the trials never run.
    Its records files stored by the release before (``version`` 1) are checked and mended alike:
    the file rewritten without the lost trials, and the compaction, write version 2."""
    study = study_factory(kind="test_pi_sparse_trace", runner={"batch_size": 3})
    clean = run_study(study_factory(kind="test_pi_sparse_trace", runner={"batch_size": 3}), run="clean")
    with monkeypatch.context() as m:
        kill_after(m, 3)
        with pytest.raises(Killed):
            run_study(study)
    store = RunStore(run_path(study))
    before = _accounts(store)
    if version == 1:
        _as_version_1(store)
    assert _versions(store) == {version} and _accounts(store) == before
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
    assert _versions(store) == {2}
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
    for path in store.listing("records")[0]:
        table = pq.read_table(path)
        meta = {k: v for k, v in table.schema.metadata.items() if k != PARTS_KEY}
        pq.write_table(table.replace_schema_metadata(meta), path, write_page_checksum=True)
    assert not _accounts(store)
    shutil.rmtree(store.path / "tables" / "trace")
    assert store.check() is not None
    again = run_study(study)
    assert again.n_ran == 0 and again.n_already == 16


def _stored_once_row_by_row(store: RunStore) -> None:
    """Each records file of a test_pi_prepared_trace run holds its account once (in the file's
    key-value metadata, not in the Arrow schema pyarrow stores beside it), one entry per row: the
    trace rows each trial stores (1 + its index mod 3) and the body id of the preparation of its
    mass (read from prepared/); no trial id written in it."""
    prepared = {}
    for path in store.listing("prepared")[0]:
        prepared.update((r["mass_kg"], r["body_id"]) for r in pq.read_table(path).to_pylist())
    assert len(prepared) == 2
    for path in store.listing("records")[0]:
        raw = pq.read_metadata(path).metadata[PARTS_KEY]
        assert PARTS_KEY not in pq.read_schema(path).metadata
        rows = pq.read_table(path, columns=["trial_id", "trial_index", "mass_kg"]).to_pylist()
        assert not any(r["trial_id"].encode() in raw for r in rows)
        value = json.loads(raw)
        assert value["v"] == 2 and set(value) == {"v", "tables", "bodies", "body"}
        assert value["tables"] == {"trace": [1 + r["trial_index"] % 3 for r in rows]}
        assert [value["bodies"][i] for i in value["body"]] == [prepared[r["mass_kg"]] for r in rows]


def test_a_records_file_holds_its_account_once_one_entry_per_row(study_factory, monkeypatch):
    """Its trials' ids were written again in the account (about 65 bytes a trial), and the
    account twice (the file's metadata and pyarrow's stored Arrow schema): the shards a run
    writes, and the file compacting them, now hold it once, row by row."""
    study = study_factory(kind="test_pi_prepared_trace", runner={"batch_size": 3})
    with monkeypatch.context() as m:
        kill_after(m, 3)
        with pytest.raises(Killed):
            run_study(study)
    store = RunStore(run_path(study))
    assert len(store.listing("records")[0]) == 3
    _stored_once_row_by_row(store)
    run_study(study)
    assert [p.name[:8] for p in store.listing("records")[0]] == ["compact-"]
    _stored_once_row_by_row(store)
    assert store.check() is not None


def test_a_resumed_run_asks_its_accounts_once_and_reads_its_preparations_once(study_factory,
                                                                              monkeypatch, request):
    """A finished run resumed: the runner's checks before the repair asked the accounts
    (part_problems) twice more, though the repair, which asks them in full, mends whatever they
    name; and prepared/ was read five times after its verification (the body ids of its files
    for the duplicate check, for the accounts' check, each again in the run's final check, then
    its rows for the trials to run). Now the accounts are asked by the repair and the final
    check, and each file of prepared/ is read twice: verified, then its rows."""
    import graspcampaign.campaign.parts as parts
    import graspcampaign.campaign.repair as repair

    study = study_factory(kind="test_pi_prepared_trace")
    store = RunStore(run_study(study).path)
    # resumed as by a new process, past the clock tick of the files' last change: one resumed at
    # once read prepared/ again each time (a file changed within the tick is never remembered),
    # and the count passed or failed with the machine's speed
    request.getfixturevalue("past_the_tick")
    asked, opened = [], []
    ask, open_file = parts.part_problems, pq.ParquetFile

    def asking(*args, **kwargs):
        asked.append(kwargs.get("full", True))
        return ask(*args, **kwargs)

    def opening(source, *args, **kwargs):
        opened.append(str(getattr(source, "name", source)))
        return open_file(source, *args, **kwargs)

    monkeypatch.setattr(parts, "part_problems", asking)
    monkeypatch.setattr(repair, "part_problems", asking)
    monkeypatch.setattr(pq, "ParquetFile", opening)
    again = run_study(study)
    assert again.n_ran == 0 and again.n_already == 16
    assert asked == [True, True]
    (file,) = store.listing("prepared")[0]
    assert opened.count(str(file)) == 2
