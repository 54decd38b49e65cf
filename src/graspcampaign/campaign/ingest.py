"""Store validated measured records of a hardware protocol as a run (``source = measured``).

The protocol's kind validates every file completely (``TrialKind.ingest``) before anything is
written, so bad input leaves what is stored untouched. Re-ingesting a trial that is already stored
is refused: measured records are never overwritten. For protocols whose records carry ``slot_id``
and ``aborted`` (Tests 2-3), an executed attempt of a slot that already has an executed record in
the run is refused too, whichever ``ingest`` call stored the first one (one executed attempt per
slot, §8-9).
"""

from __future__ import annotations

from pathlib import Path

from graspcampaign.campaign import provenance
from graspcampaign.campaign.grid import content_hash
from graspcampaign.campaign.kind import get_kind
from graspcampaign.campaign.records import RunStore
from graspcampaign.campaign.runner import kind_params, run_path, study_trials
from graspcampaign.campaign.schema import StudyCfg
from graspcampaign.errors import UserInputError

_FILE_ID = "rig_trial_id"  # the trial id of a protocol's own sheet and files (kinds.hardware)


def ingest_files(study: StudyCfg, paths: list[str], run: str = "measured") -> tuple[int, Path]:
    """Validate ``paths`` with the study's protocol and append them to ``run``.

    Returns
    -------
    n_rows, run_path
    """
    kind = get_kind(study.kind)
    if kind.ingest is None:
        raise UserInputError(f"study {study.name!r} has no measured records to ingest "
                             "(only hardware protocols do).")
    for path in paths:
        if not Path(path).is_file():
            raise UserInputError(f"{path}: no such file.")
    params = kind_params(study, kind)
    rows = kind.ingest(study, params, paths)
    store = RunStore(run_path(study, run))
    stored = store.recorded_ids() if store.exists() else set()
    clash = sorted({r["trial_id"] for r in rows} & stored)
    if clash:
        raise UserInputError(f"trial {clash[0]!r} is already stored in {store.path}; measured "
                             f"records are never overwritten ({len(clash)} such trials).")
    if stored:
        _refuse_second_executed_attempt(rows, store)
    manifest = provenance.read_manifest(store.manifest_path)
    if manifest is None:
        manifest = provenance.new_manifest(study, run, len(study_trials(study, kind, params)),
                                           "measured")
    for row in rows:
        row.setdefault("source", "measured")
        row.setdefault("status", "ok")
        row.setdefault("study", study.name)
        row.setdefault("run", run)
    store.write_shard("records", content_hash(sorted(r["trial_id"] for r in rows)), rows)
    manifest["sessions"].append({"ingested": [str(p) for p in paths], "rows": len(rows),
                                 "at": provenance.now_utc()})
    provenance.write_manifest(store.manifest_path, manifest)
    return len(rows), store.path


def _refuse_second_executed_attempt(rows: list[dict], store: RunStore) -> None:
    """Raise if a new executed row's slot already has an executed record stored in ``store``.

    Trials are named by the id the user's file gives them (``rig_trial_id``) when the records
    carry it, else by the engine's ``trial_id``.
    """
    new = {r["slot_id"]: r for r in rows if "slot_id" in r and r.get("aborted") is False}
    if not new:
        return
    table = store.read(columns=["trial_id", _FILE_ID, "slot_id", "aborted"]).to_pandas()
    if not {"slot_id", "aborted"} <= set(table.columns):
        return
    done = table[(table["aborted"] == False) & table["slot_id"].isin(list(new))]  # noqa: E712
    if len(done):
        first = done.iloc[0]
        row = new[first["slot_id"]]
        raise UserInputError(
            f"trial {row.get(_FILE_ID) or row['trial_id']!r} is an executed attempt of slot "
            f"{first['slot_id']!r}, which already has an executed record "
            f"({first.get(_FILE_ID) or first['trial_id']!r}) in {store.path}; only one attempt "
            "per slot may be executed.")
