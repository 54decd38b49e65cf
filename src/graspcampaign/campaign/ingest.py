"""Store validated measured records of a hardware protocol as a run (``source = measured``).

The protocol's kind validates every file completely (``TrialKind.ingest``) before anything is
written, so bad input leaves what is stored untouched. Re-ingesting a trial that is already stored
is refused: measured records are never overwritten. The kind also sees the run's stored records,
so its own rules across files (e.g. one executed attempt per slot in Tests 2-3) hold across
``ingest`` calls too.
"""

from __future__ import annotations

from pathlib import Path

from graspcampaign.campaign import provenance
from graspcampaign.campaign.grid import content_hash
from graspcampaign.campaign.kind import get_kind
from graspcampaign.campaign.paths import check_root
from graspcampaign.campaign.records import RunStore
from graspcampaign.campaign.runner import ERROR_COLUMNS, kind_params, run_path, study_trials
from graspcampaign.campaign.schema import StudyCfg
from graspcampaign.errors import UserInputError


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
    check_root(study.output.root, "output.root", write=True)
    params = kind_params(study, kind)
    store = RunStore(run_path(study, run))
    stored = store.read().to_pandas() if store.exists() else None
    rows = kind.ingest(study, params, paths, stored)
    stored_ids = set() if stored is None or "trial_id" not in stored else set(stored["trial_id"])
    clash = sorted({r["trial_id"] for r in rows} & stored_ids)
    if clash:
        raise UserInputError(f"trial {clash[0]!r} is already stored in {store.path}; measured "
                             f"records are never overwritten ({len(clash)} such trials).")
    manifest = provenance.read_manifest(store.manifest_path)
    if manifest is None:
        manifest = provenance.new_manifest(study, run, len(study_trials(study, kind, params)),
                                           "measured")
    for row in rows:
        row.setdefault("source", "measured")
        row.setdefault("status", "ok")
        row.setdefault("study", study.name)
        row.setdefault("run", run)
    store.write_shard("records", content_hash(sorted(r["trial_id"] for r in rows)), rows,
                      strings=ERROR_COLUMNS)
    manifest["sessions"].append({"ingested": [str(p) for p in paths], "rows": len(rows),
                                 "at": provenance.now_utc()})
    provenance.write_manifest(store.manifest_path, manifest)
    return len(rows), store.path

