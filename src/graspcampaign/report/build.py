"""Build reports from records: one per run, plus ``<root>/index.md`` linking them.

Reads only ``manifest.json`` and the Parquet records; never runs a trial. Each trial kind has a
section builder (``SECTIONS``); kinds without one get the generic summary.
"""

from __future__ import annotations

import importlib
from pathlib import Path

import pandas as pd

from graspcampaign.campaign.provenance import read_manifest
from graspcampaign.campaign.records import RunStore
from graspcampaign.errors import UserInputError
from graspcampaign.report.document import Report, check_formats
from graspcampaign.report.headline import write_headline

SOURCE_LABEL = {
    "simulation": "simulation (this tool's numerical model)",
    "virtual": "VIRTUAL RIG: synthetic data from a stochastic model, not hardware measurements",
    "measured": "measured on hardware (ingested records)",
}

# trial kind -> "module:function(report, records, manifest, store)"
SECTIONS: dict[str, str] = {
    "gravity_settle": "graspcampaign.report.sections.dynamic:gravity_settle",
    "dynamic_grasp": "graspcampaign.report.sections.dynamic:friction_mass",
    "mesh_features": "graspcampaign.report.sections.smoke:section",
    "quasi_static": "graspcampaign.report.sections.quasi_static:section",
    "mesh_resolution": "graspcampaign.report.sections.mesh_resolution:section",
    "sensitivity": "graspcampaign.report.sections.sensitivity:section",
    "surrogate": "graspcampaign.report.sections.surrogate:section",
    "pso_repeatability": "graspcampaign.report.sections.pso:section",
    "wrench_balance": "graspcampaign.report.sections.wrench:section",
    "heuristic_weights": "graspcampaign.report.sections.weights:section",
    "test1_bench": "graspcampaign.report.sections.test1:section",
    "test2_grasp": "graspcampaign.report.sections.test2:section",
    "test3_disturbance": "graspcampaign.report.sections.test3:section",
}


def load_records(store: RunStore, part: str = "records") -> pd.DataFrame:
    """Return a run's records as a DataFrame."""
    return store.read(part).to_pandas()


def provenance_header(manifest: dict, records: pd.DataFrame) -> str:
    """Return the Markdown provenance block every report starts with."""
    statuses = records["status"].value_counts().to_dict() if len(records) else {}
    git = manifest.get("git") or {}
    lines = [
        f"- **Data source:** {SOURCE_LABEL.get(manifest.get('source'), manifest.get('source'))}",
        f"- **Trials:** {len(records)} recorded of {manifest.get('n_trials')} "
        f"({statuses.get('ok', 0)} ok, {statuses.get('error', 0)} errors; errored trials enter "
        "no success denominator)",
        f"- **Config hash:** `{manifest.get('config_hash')}`; **code:** "
        f"`{manifest.get('code_version')}`{' (dirty tree)' if git.get('dirty') else ''}",
        f"- **Started:** {manifest.get('started_at')}; **finished:** {manifest.get('finished_at')}",
        f"- **Host:** {(manifest.get('host') or {}).get('name')}",
    ]
    return "\n".join(lines)


def generic_section(report: Report, records: pd.DataFrame, manifest: dict, store: RunStore) -> None:
    """Summarise any run: trial counts by status and the first errors."""
    counts = records.groupby("status").size().rename("n").reset_index()
    report.table("status", counts, "Trials by status")
    errors = records[records["status"] == "error"]
    if len(errors):
        report.table("errors", errors[["trial_id", "error_type", "error_message"]].head(20),
                     "First errors")


def _runs(root: Path, studies: list[str] | None, run: str | None) -> list[RunStore]:
    if not root.is_dir():
        raise UserInputError(f"no results directory at {root}; run a study first.")
    names = studies or sorted(p.name for p in root.iterdir() if p.is_dir())
    stores = []
    for name in names:
        study_dir = root / name
        if studies and not study_dir.is_dir():
            raise UserInputError(f"no records for study {name!r} under {root}; run it first.")
        runs = [run] if run else sorted(p.name for p in study_dir.iterdir() if p.is_dir())
        for r in runs:
            store = RunStore(study_dir / r)
            if not store.exists():
                if run:
                    raise UserInputError(f"no run {r!r} of study {name!r} under {root}.")
                continue
            store.verify()  # a damaged file: refuse (DamagedRunError, exit 2), never report around it
            stores.append(store)
    return stores


def build_reports(studies: list[str] | None = None, run: str | None = None,
                  root: Path | str = "results", formats: list[str] | None = None) -> list[Path]:
    """Write ``report/`` for each selected run and the index; return the report paths."""
    root = Path(root)
    formats = check_formats(formats)
    written = []
    for store in _runs(root, studies, run):
        manifest = read_manifest(store.manifest_path)
        records = load_records(store)
        kind = manifest.get("kind")
        report = Report(f"{manifest['study']} — run `{manifest['run']}`", store.path / "report")
        report.text(provenance_header(manifest, records))
        if len(records):
            target = SECTIONS.get(kind)
            if target:
                module, attr = target.split(":")
                getattr(importlib.import_module(module), attr)(report, records, manifest, store)
            generic_section(report, records, manifest, store)
        written.append(report.write(formats))
    write_headline(root)
    _write_index(root)
    return written


def _write_index(root: Path) -> None:
    lines = ["# Reports", "", "Headline success rates beside the paper's Table 1: "
             "[headline.md](headline.md)", "",
             "| study | run | source | trials | report |", "|---|---|---|---|---|"]
    for report_dir in sorted(root.glob("*/*/report")):
        main = next((report_dir / f for f in ("report.md", "report.html", "tables.json")
                     if (report_dir / f).exists()), None)
        if main is None:
            continue
        manifest = read_manifest(report_dir.parent / "manifest.json") or {}
        rel = main.relative_to(root).as_posix()
        lines.append(f"| {manifest.get('study')} | {manifest.get('run')} | "
                     f"{manifest.get('source')} | {manifest.get('n_trials')} | [{rel}]({rel}) |")
    (root / "index.md").write_text("\n".join(lines) + "\n")
