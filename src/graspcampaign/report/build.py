"""Build reports from records: one per run, the Table 1 headline page and an index.

Reads only ``manifest.json`` and the Parquet records; never runs a trial, fits a model or times
anything. A study's report is its :class:`~graspcampaign.report.spec.ReportSpec` (``SPECS``, by
study name; ``KIND_SPECS`` for other studies of a kind). Studies not yet ported to a spec keep
their section module through the **legacy path** (``LEGACY``, by trial kind) until they are.
One run whose report cannot be written never stops the others: :func:`build_reports` returns the
written pages and the failures, and the command line names each failed run and exits non-zero.
"""

from __future__ import annotations

import importlib
import io
import logging
from pathlib import Path
from typing import Any

import pandas as pd

from graspcampaign.campaign.provenance import read_manifest
from graspcampaign.campaign.records import RunStore
from graspcampaign.errors import ConfigError, UserInputError
from graspcampaign.report import spec as S
from graspcampaign.report.document import (
    Col,
    Document,
    Figure,
    Table,
    Text,
    check_figure_format,
    check_formats,
    markdown_table,
    page,
)
from graspcampaign.report.render import Run, provenance, reason, render

log = logging.getLogger(__name__)

#: study -> "module:attribute" of its spec under ``graspcampaign.report.studies``
SPECS: dict[str, str] = {
    "smoke": "smoke:SPEC",
    "heuristic_weights": "weights:SPEC",
    "wrench_balance": "wrench:SPEC",
    "shapes": "quasi_static:SHAPES",
    "ablation": "quasi_static:ABLATION",
    "baseline_grid": "quasi_static:BASELINE_GRID",
    "grip_laws": "quasi_static:GRIP_LAWS",
    "pso_repeatability": "pso:SPEC",
    "gravity_settle": "dynamic:GRAVITY_SETTLE",
    "friction_mass": "dynamic:FRICTION_MASS",
    "dynamic_check": "dynamic_check:SPEC",
    "sensitivity": "sensitivity:SPEC",
    "mesh_resolution": "mesh_resolution:SPEC",
}
#: trial kind -> spec for studies of that kind without a spec of their own
KIND_SPECS: dict[str, str] = {
    "quasi_static": "quasi_static:PLANNERS",
    "mesh_features": "smoke:SPEC",
    "sensitivity": "sensitivity:SPEC",
    "mesh_resolution": "mesh_resolution:SPEC",
}
#: LEGACY PATH (issue 14): trial kind -> "module:function(report, records, manifest, store)" of
#: the section modules not yet ported to a spec. Remove an entry when its study is ported.
LEGACY: dict[str, str] = {
    "surrogate": "graspcampaign.report.sections.surrogate:section",
    "test1_bench": "graspcampaign.report.sections.test1:section",
    "test2_grasp": "graspcampaign.report.sections.test2:section",
    "test3_disturbance": "graspcampaign.report.sections.test3:section",
}


class ReportBatch(list):
    """The written report paths, with ``failed``: ``(run label, reason)`` of runs not written."""

    def __init__(self, written=(), failed=()):
        super().__init__(written)
        self.failed: list[tuple[str, str, bool]] = list(failed)


def spec_for(study: str, kind: str) -> S.ReportSpec | None:
    """Return the study's spec (by name, else by kind), or None (legacy path / generic)."""
    target = SPECS.get(study) or KIND_SPECS.get(kind)
    if target is None:
        return None
    module, attr = target.split(":")
    return getattr(importlib.import_module(f"graspcampaign.report.studies.{module}"), attr)


def _status(run: Run) -> pd.DataFrame:
    return run.records.groupby("status").size().rename("n").reset_index()


def _errors(run: Run) -> pd.DataFrame:
    cols = [c for c in ("trial_id", "error_type", "error_message") if c in run.records]
    return run.records[run.records["status"] == "error"][cols].head(20)


GENERIC = S.ReportSpec("any", [
    S.Section("Trials"),
    S.Table("status", "Trials by status (errored trials enter no success denominator)", _status),
    S.Table("errors", "First errors", _errors, empty=None),
])


def _paper(run_paper: dict | None, study: str, notes: list[str]) -> Any:
    from graspcampaign.campaign.paper import check_paper, study_paper

    try:
        return check_paper(study, run_paper, "the run's paper block")
    except ConfigError as exc:
        try:
            paper = study_paper(study)
        except (ConfigError, OSError) as exc2:
            notes.append(f"paper values unavailable ({exc}; {exc2})")
            return None
        notes.append(f"this run's paper block does not match the current schema ({exc}); the "
                     f"paper's values come from campaigns/{study}.yaml")
        return paper


def report_run(store: RunStore, root: Path, formats: list[str], figure_format: str) -> Path:
    """Write one run's report under ``<run>/report/``; return its main page."""
    try:
        manifest = read_manifest(store.manifest_path)
    except ValueError as exc:
        raise UserInputError(f"{store.manifest_path} is not valid JSON ({exc}).") from None
    if not manifest:
        raise UserInputError(f"{store.manifest_path} is missing.")
    records = store.read("records").to_pandas()
    study, kind = str(manifest.get("study")), str(manifest.get("kind"))
    like = (manifest.get("config") or {}).get("compare_with") or study  # its paper values' study
    notes: list[str] = []
    paper = _paper((manifest.get("config") or {}).get("paper"), like, notes)
    run = Run(records, manifest, paper, store, figure_format)
    up = "../" * (len(store.path.relative_to(root).parts) + 1)
    doc = Document(f"{study} — run {manifest.get('run')}", run.source,
                   provenance(run) + [("Note", n) for n in notes],
                   nav=[("Index", f"{up}index.html"), ("Table 1 headline", f"{up}headline.html")])
    if not len(records):
        doc.blocks.append(Text("No trial of this run is recorded yet.", "note"))
    else:
        spec = spec_for(study, kind) if study in SPECS else spec_for(like, kind)
        if spec is not None:
            render(spec, run, doc)
        elif kind in LEGACY:
            _legacy(kind, run, doc)
        render(GENERIC, run, doc)
    for failure in run.failures:
        log.warning("report %s/%s: %s", study, manifest.get("run"), failure)
    return doc.write(store.path / "report", formats, figure_format)


def safe_manifest(path: Path) -> dict:
    """Return the manifest at ``path``, or {} when it is missing or unreadable."""
    try:
        return read_manifest(path) or {}
    except (OSError, ValueError):
        return {}


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
                  root: Path | str = "results", formats: list[str] | str | None = None,
                  figure_format: str = "png") -> ReportBatch:
    """Write every selected run's report, then the headline page and the index.

    Returns the written main pages; ``.failed`` lists ``(study/run, reason, bad_input)`` of the
    runs whose report could not be written (the others are written regardless).
    """
    root = Path(root)
    formats = check_formats(formats)
    figure_format = check_figure_format(figure_format)
    batch = ReportBatch()
    for store in _runs(root, studies, run):
        label = store.path.relative_to(root).as_posix()
        try:
            batch.append(report_run(store, root, formats, figure_format))
        except Exception as exc:  # noqa: BLE001 - one broken run never stops the others
            log.debug("report of %s failed", label, exc_info=True)
            batch.failed.append((label, reason(exc), isinstance(exc, UserInputError)))
    from graspcampaign.report.headline import write_headline

    write_headline(root, formats)
    write_index(root, formats)
    return batch


def write_index(root: Path, formats: list[str]) -> None:
    """Write ``index.md`` (and ``index.html``) linking every run's report and the headline."""
    rows, links = [], []
    for report_dir in sorted(root.glob("*/*/report")):
        manifest = safe_manifest(report_dir.parent / "manifest.json")
        pages = {f: report_dir / f"report.{f}" for f in ("md", "html")}
        if not any(p.exists() for p in pages.values()):
            continue
        rows.append([str(manifest.get("study")), str(manifest.get("run")),
                     str(manifest.get("source")), str(manifest.get("n_trials"))])
        links.append({f: p.relative_to(root).as_posix() for f, p in pages.items() if p.exists()})
    head = ["study", "run", "source", "trials", "report"]
    md = [r + [f"[{lk.get('md', lk.get('html'))}]({lk.get('md', lk.get('html'))})"]
          for r, lk in zip(rows, links, strict=True)]
    (root / "index.md").write_text(
        "# Reports\n\nHeadline success rates beside the paper's Table 1: "
        "[headline.md](headline.md)\n\n" + markdown_table(head, md) + "\n")
    if "html" in formats:
        import html

        body = "".join(
            "<tr>" + "".join(f"<td>{html.escape(c)}</td>" for c in r) + (
                f"<td><a href='{html.escape(lk['html'])}'>report</a></td>" if "html" in lk
                else "<td>—</td>") + "</tr>" for r, lk in zip(rows, links, strict=True))
        table = ("<div class='table'><table><thead><tr>" + "".join(
            f"<th>{h}</th>" for h in head) + f"</tr></thead><tbody>{body}</tbody></table></div>")
        (root / "index.html").write_text(page(
            "Reports", "", "<p>Every run's report; headline success rates beside the paper's "
            "Table 1 on the <a href='headline.html'>headline page</a>.</p>" + table,
            [("Index", "index.html"), ("Table 1 headline", "headline.html")]))


# ------------------------------------------------------------------------------------------
# LEGACY PATH: section modules not yet ported to a spec (see LEGACY); remove with the last one
# ------------------------------------------------------------------------------------------
class LegacyReport:
    """The section modules' old ``Report`` API (text, table, figure) writing into a Document.

    Legacy tables are shown as their own display frame (marked ``legacy`` on the page), not
    derived from the CSV by the one formatter; porting the study to a spec removes them.
    """

    def __init__(self, doc: Document, run: Run):
        self.doc, self.run, self.tables = doc, run, {}

    def text(self, markdown: str) -> None:
        self.doc.blocks.append(Text(markdown.strip()))

    def table(self, name: str, df: pd.DataFrame, caption: str,
              display: pd.DataFrame | None = None) -> None:
        self.tables[name] = df
        shown = (df if display is None else display).astype(object).where(
            lambda d: d.notna(), "")
        self.doc.blocks.append(Table(name, caption, df.reset_index(drop=True), [
            Col(str(c), str(c)) for c in shown.columns], shown.astype(str).to_numpy().tolist()))
        self.run.tables[name] = df

    def figure(self, name: str, fig, caption: str) -> None:
        from graspcampaign.report.style import SOURCE_SHORT

        if getattr(fig, "_suptitle", None) is None:
            fig.suptitle(f"data: {SOURCE_SHORT.get(self.run.source)}", x=0.995, ha="right",
                         fontsize=7.5)
        images = {}
        for f in dict.fromkeys(("png", self.run.figure_format)):
            buf = io.BytesIO()
            fig.savefig(buf, format=f, dpi=130, bbox_inches="tight",
                        metadata={"Software": "graspcampaign"} if f == "png" else {"Date": None})
            images[f] = buf.getvalue()
        if getattr(fig.canvas, "manager", None) is not None:
            import matplotlib.pyplot as plt

            plt.close(fig)
        self.doc.blocks.append(Figure(name, caption, images))


def _legacy(kind: str, run: Run, doc: Document) -> None:
    module, attr = LEGACY[kind].split(":")
    section = getattr(importlib.import_module(module), attr)
    manifest = {**run.manifest, "config": {**run.config, "paper": run.paper}}  # typed values
    try:
        section(LegacyReport(doc, run), run.records, manifest, run.store)
    except Exception as exc:  # noqa: BLE001 - the parts written so far are kept
        log.debug("legacy section %s failed", kind, exc_info=True)
        run.failures.append(f"section {kind}: {reason(exc)}")
        doc.blocks.append(Text(f"The rest of this section could not be computed: "
                               f"{reason(exc)}.", "note"))
