"""Store validated records of a hardware protocol as a run: a rig's measurements
(``source = measured``) or a virtual rig's exports (``source = virtual``), one source per run.

The protocol's kind validates every file completely (``TrialKind.ingest``) before anything is
written, so bad input leaves what is stored untouched. Re-ingesting a trial that is already stored
is refused: measured records are never overwritten. The kind also sees the run's stored records,
so its own rules across files (e.g. one executed attempt per slot in Tests 2-3) hold across
``ingest`` calls too. A run holds the records of one config: an ingest under another resolved
config (a changed seed; a changed description is none) is refused as drift, as ``run`` refuses it; the
code version may change between ingests (the rig's records do not depend on it). The records
file keeps the account a run's keeps (:mod:`graspcampaign.campaign.parts`): its trials stored
nothing else.
"""

from __future__ import annotations

from pathlib import Path

from graspcampaign.campaign import provenance
from graspcampaign.campaign.account import Account
from graspcampaign.campaign.grid import content_hash
from graspcampaign.campaign.integrity import check_place
from graspcampaign.campaign.kind import get_kind
from graspcampaign.campaign.paths import check_case_twin, check_root, input_file_problem, shown
from graspcampaign.campaign.records import ERROR_COLUMNS, RunStore, config_metadata
from graspcampaign.campaign.runner import kind_params, run_lock, run_path, study_trials, unwritable
from graspcampaign.campaign.schema import StudyCfg
from graspcampaign.errors import UserInputError


def ingest_files(study: StudyCfg, paths: list[str], run: str = "measured",
                 given: tuple[str, list[str]] | None = None) -> tuple[int, Path, str]:
    """Validate ``paths`` with the study's protocol and append them to ``run``; ``given`` as in
    :func:`~graspcampaign.campaign.runner.run_study` (a new run's manifest records the design).

    Returns
    -------
    n_rows, run_path, source
        ``source``: the records' (``measured``, or ``virtual`` for a virtual rig's exports), which
        the run's manifest says too.
    """
    kind = get_kind(study.kind)
    if kind.ingest is None:
        raise UserInputError(f"study {study.name!r} has no measured records to ingest "
                             "(only hardware protocols do).")
    for path in paths:
        if (why := input_file_problem(Path(path))) is not None:
            raise UserInputError(f"{shown(path)} {why}; give a file of measured records (CSV, XLSX or "
                                 "Parquet).")
    files = [Path(path).resolve() for path in paths]  # a file named twice clashes with itself
    for i, path in enumerate(paths):
        if files[i] in files[:i]:
            first = paths[files.index(files[i])]
            again = "is given twice" if first == path else f"is {first} again"
            raise UserInputError(f"{path} {again}; give each file of measured records once.")
    check_root(study.output.root, "output.root", write=True)
    store = RunStore(run_path(study, run))
    check_case_twin(store.path, f"{study.name}/{run}")
    check_place(store)  # a file or a link leading nowhere where the run belongs: before the lock
    with run_lock(store, f"{study.name}/{run}"):  # read, checked and written by this process alone
        return _ingest(study, paths, store, run, given)


def _ingest(study: StudyCfg, paths: list[str], store: RunStore, run: str,
            given: tuple[str, list[str]] | None) -> tuple[int, Path, str]:
    """:func:`ingest_files` once the files are found and the run is held."""
    kind = get_kind(study.kind)
    params = kind_params(study, kind)
    manifest = store.check(["records"])  # a run that is not what its manifest says: refused
    if manifest is not None and not provenance.ingested(manifest):
        raise UserInputError(
            f"run {study.name}/{run} at {store.path} holds {manifest['source']} records (from "
            "`graspcampaign run`); measured records are stored in a run of their own, so choose "
            "another run name (--run NAME; default measured).")
    if manifest is not None and (refusal := provenance.ingest_refusal(manifest, study, f"{study.name}/{run}",
                                                                     store.path)):
        raise provenance.DriftError(refusal)
    stored = store.read().to_pandas() if manifest is not None else None
    rows = kind.ingest(study, params, paths, stored)
    stored_ids = set() if stored is None or "trial_id" not in stored else set(stored["trial_id"])
    clash = sorted({r["trial_id"] for r in rows} & stored_ids)
    if clash:
        raise UserInputError(f"trial {clash[0]!r} is already stored in {store.path}; measured "
                             f"records are never overwritten ({len(clash)} such trials).")
    if (denied := unwritable(store, f"{study.name}/{run}")) is not None:  # a clash is said first
        raise UserInputError(denied)
    for row in rows:
        row.setdefault("source", "measured")
        row.setdefault("status", "ok")
        row["study"], row["run"] = study.name, run  # the records of this run, whatever the file says
    source = rows[0]["source"] if rows else "measured"  # one source per run (check_one_source)
    if manifest is None:
        from graspcampaign.campaign.compose import as_given

        manifest = provenance.new_manifest(study, run, len(study_trials(study, kind, params)), source)
        manifest.update(as_given(*given, study) if given else {})
    chash = provenance.config_hash(study, manifest)
    # the account a run's records keep (campaign.parts), through its one encoding: an ingested
    # trial stores nothing besides its record (no trace, no preparation)
    store.write_shard("records", content_hash(sorted(r["trial_id"] for r in rows)), rows,
                      metadata=config_metadata(chash), strings=ERROR_COLUMNS,
                      account=Account.from_entries({row["trial_id"]: {} for row in rows}))
    manifest["sessions"].append({"ingested": [str(p) for p in paths], "rows": len(rows),
                                 "at": provenance.now_utc(), "config_hash": chash})
    manifest["n_recorded"] = len(stored_ids) + len(rows)
    provenance.write_manifest(store.manifest_path, manifest)
    return len(rows), store.path, manifest["source"]

