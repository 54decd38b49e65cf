"""Describe a study's design and a run's progress from its config and records alone."""

from __future__ import annotations

from pathlib import Path
from typing import Any

from graspcampaign.campaign.grid import design_axes, n_trials
from graspcampaign.campaign.kind import KINDS, get_kind, kind_available
from graspcampaign.campaign.provenance import read_manifest
from graspcampaign.campaign.records import RunStore
from graspcampaign.campaign.runner import _n_workers, kind_params, run_path, study_trials
from graspcampaign.campaign.schema import StudyCfg


def _fmt_seconds(seconds: float) -> str:
    if seconds < 120:
        return f"{seconds:.0f} s"
    if seconds < 7200:
        return f"{seconds / 60:.0f} min"
    return f"{seconds / 3600:.1f} h"


def study_size(study: StudyCfg) -> int:
    """Return a study's trial count (its Cartesian design or its kind's explicit schedule)."""
    if kind_available(study.kind) and get_kind(study.kind).design is not None:
        kind = get_kind(study.kind)
        return len(study_trials(study, kind, kind_params(study, kind)))
    return n_trials(study)


def design_text(study: StudyCfg, run: str | None = None) -> str:
    """Return the human-readable design of a study and the progress of its run."""
    ready = kind_available(study.kind)
    total = study_size(study)
    lines = [f"study: {study.name}", f"description: {' '.join(study.description.split())}"]
    state = "runnable" if ready else ("not yet runnable" if study.kind in KINDS else "unknown kind")
    lines.append(f"trial kind: {study.kind} ({state})")
    lines.append(f"study seed: {study.seed}   seeds per scene: {study.seeds}   "
                 f"repeats: {study.repeats}")
    lines.append("factors:")
    for name, levels in study.factors.items():
        role = " (method: shares scene draws)" if name in study.method_factors else ""
        lines.append(f"  {name} [{len(levels)}]{role}: {', '.join(map(str, levels))}")
    if study.zip:
        lines.append("zipped: " + "; ".join(" + ".join(g) for g in study.zip))
    if ready and get_kind(study.kind).design is not None:
        lines.append(f"design: the protocol's schedule = {total} trials")
    else:
        lines.append(f"axes: {' x '.join(str(len(a)) for a in design_axes(study))} = {total} trials")
    store = RunStore(run_path(study, run))
    done = len(store.recorded_ids()) if store.exists() else 0
    lines.append(f"run: {store.path} ({done} of {total} recorded)")
    if ready:
        per = get_kind(study.kind).seconds_per_trial
        remaining = (total - done) * per / _n_workers(study)
        lines.append(f"estimated time: {_fmt_seconds(remaining)} for {total - done} trials "
                     f"(~{per * 1e3:.0f} ms each on {_n_workers(study)} workers)")
    if study.paper:
        lines.append("paper: " + ", ".join(f"{k}={v}" for k, v in study.paper.items()))
    return "\n".join(lines)


def run_status(root: Path | str, study: str, run: str = "default") -> dict[str, Any]:
    """Summarise a run from its manifest and records only."""
    store = RunStore(Path(root) / study / run)
    manifest = read_manifest(store.manifest_path)
    if manifest is None:
        from graspcampaign.errors import UserInputError

        raise UserInputError(f"no run at {store.path}; run `graspcampaign run {study}` first.")
    table = store.read(columns=["status"])
    statuses = table.column("status").to_pylist() if table.num_rows else []
    return {
        "study": study,
        "run": run,
        "path": str(store.path),
        "source": manifest.get("source"),
        "n_trials": manifest.get("n_trials"),
        "n_recorded": len(statuses),
        "n_ok": statuses.count("ok"),
        "n_error": statuses.count("error"),
        "complete": len(statuses) == manifest.get("n_trials"),
        "config_hash": manifest.get("config_hash"),
        "code_version": manifest.get("code_version"),
        "started_at": manifest.get("started_at"),
        "finished_at": manifest.get("finished_at"),
    }
