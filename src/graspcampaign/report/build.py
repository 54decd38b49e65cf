"""Build reports from records: one per run, the Table 1 headline page and an index."""

from __future__ import annotations

import importlib
import logging
import os
import re
import warnings
from collections.abc import Mapping
from pathlib import Path
from typing import Any

import pandas as pd

from graspcampaign.analysis.records import in_design_order
from graspcampaign.campaign.paths import (
    check_root,
    held_by_a_run,
    how_to_make,
    near_run,
    write_denied,
    write_file,
)
from graspcampaign.campaign.provenance import read_manifest, run_size
from graspcampaign.campaign.records import RunStore
from graspcampaign.core.words import PERMISSION_DENIED
from graspcampaign.errors import ConfigError, UserInputError, access_denied, disk_full
from graspcampaign.report import document as D
from graspcampaign.report import spec as S
from graspcampaign.report.document import NAV, Col, Document, Table, Text
from graspcampaign.report.headline import folders, headline_rows, runs_of, unlistable, write_headline
from graspcampaign.report.render import Run, provenance, reason, render
from graspcampaign.report.style import SOURCE_SHORT

log = logging.getLogger(__name__)

#: study -> "module:attribute" of its spec under ``graspcampaign.report.studies``
SPECS: dict[str, str] = {
    "smoke": "smoke:SPEC", "heuristic_weights": "weights:SPEC", "wrench_balance": "wrench:SPEC",
    "shapes": "quasi_static:SHAPES", "ablation": "quasi_static:ABLATION",
    "baseline_grid": "quasi_static:BASELINE_GRID", "grip_laws": "quasi_static:GRIP_LAWS",
    "pso_repeatability": "pso:SPEC", "gravity_settle": "dynamic:GRAVITY_SETTLE",
    "friction_mass": "dynamic:FRICTION_MASS", "dynamic_check": "dynamic_check:SPEC",
    "sensitivity": "sensitivity:SPEC",
    "mesh_resolution": "mesh_resolution:SPEC", "test2_grasp": "test2:SPEC",
    "test3_disturbance": "test3:SPEC", "surrogate": "surrogate:SPEC", "test1_bench": "test1:SPEC"}
#: trial kind -> spec for studies of that kind without a spec of their own
KIND_SPECS: dict[str, str] = {"quasi_static": "quasi_static:PLANNERS", "mesh_features": "smoke:SPEC",
                              "sensitivity": "sensitivity:SPEC", "mesh_resolution": "mesh_resolution:SPEC"}


class ReportBatch(list):
    """The written report paths (``report.md``); ``failed``: ``(run label, reason, bad input)`` of
    runs not written; ``broken``: a written report's ``(items, titles of those whose code failed)``
    (:func:`~graspcampaign.report.render.render`) by its path; ``pages``: the root pages written
    (index and headline, each format); ``formats``: the formats written; ``in_progress``: by its
    path, how much of a run another process was recording was recorded when its report was made."""

    def __init__(self, written=(), failed=(), formats=("md", "csv")):
        super().__init__(written)
        self.failed: list[tuple[str, str, bool]] = list(failed)
        self.broken: dict[Path, tuple[int, list[str]]] = {}
        self.pages: list[Path] = []
        self.in_progress: dict[Path, str] = {}
        self.formats = list(formats)


def spec_for(study: str, kind: str) -> S.ReportSpec | None:
    """Return the study's spec (by name, else by kind), or None (generic tables only)."""
    target = SPECS.get(study) or KIND_SPECS.get(kind)
    if target is None:
        return None
    module, attr = target.split(":")
    return getattr(importlib.import_module(f"graspcampaign.report.studies.{module}"), attr)


GENERIC = S.ReportSpec("any", [
    S.Section("Trials"),
    S.Table("status", "Trials by status (errored trials enter no success denominator)",
            lambda run: run.records.groupby("status").size().rename("n").reset_index()),
    S.Table("errors", "First errors", lambda run: run.records[run.records["status"] == "error"][
        [c for c in ("trial_id", "error_type", "error_message") if c in run.records]].head(20), empty=None),
])


def _paper(run_paper: dict | None, study: str, notes: list[str]) -> Any:
    """The run's typed paper values; an old run's mismatching block falls back to the study file."""
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


def report_run(store: RunStore, root: Path, formats: list[str], figure_format: str,
               ) -> tuple[Path, int, list[str], str | None]:
    """Write one run's report under ``<run>/report/``; return its main page, its number of items,
    the titles of those whose code failed (``Run.broken``) and, for a run another process held
    while it was read (``paths.held_by_a_run``), how much of it was recorded then."""
    busy = held_by_a_run(store.path)  # asked before and after the records are read
    manifest = store.check()  # never a report of records that are not what the manifest says
    if not manifest:
        raise UserInputError(f"{store.manifest_path} is missing.")
    _check_report_folder(store)
    records, notes = in_design_order(store.read("records").to_pandas()), []
    progress = None  # of a run another process is recording: how much was recorded when read
    if busy or held_by_a_run(store.path):
        progress = f"{len(records)} of {run_size(manifest)} recorded when this report was made"
    study, kind = str(manifest.get("study")), str(manifest.get("kind"))
    like = (manifest.get("config") or {}).get("compare_with") or study  # its paper values' study
    run = Run(records, manifest, _paper((manifest.get("config") or {}).get("paper"), like, notes),
              store, figure_format)
    up = "../" * (len(store.path.relative_to(root).parts) + 1)
    doc = Document(f"{study} — run {manifest.get('run')}", run.source,
                   provenance(run) + ([("Run in progress", progress)] if progress else [])
                   + [("Note", n) for n in notes], nav=[(t, up + h) for t, h in NAV])
    if not len(records):
        doc.blocks.append(Text("No trial of this run is recorded yet.", "note"))
    else:
        spec = spec_for(study if study in SPECS else like, kind)  # else that of the study it compares with
        if spec is not None:
            render(spec, run, doc)
        render(GENERIC, run, doc)
    for failure in run.failures:
        log.warning("report %s/%s: %s", study, manifest.get("run"), failure)
    return doc.write(store.path / "report", formats, figure_format), run.items, run.broken, progress


def _check_report_folder(store: RunStore) -> None:
    """Refuse, before any figure is drawn, a run whose ``report/`` (or a folder in it, or the run's
    directory that would hold it) this process cannot write: one sentence naming the folder, bad
    input (exit 2) as the run's other refusals; the other runs are still reported."""
    folder = store.path / "report"
    places = ([Path(where) for where, _, _ in os.walk(folder)] if folder.is_dir() else [store.path])
    for place in places:
        if (why := write_denied(place)) is not None:
            advice = "" if PERMISSION_DENIED in why else ("; make it writable for this user, or run "
                                                          "the command as the user who owns the run")
            raise UserInputError(f"its report folder {place}: {why}{advice}.")


def _runs(root: Path, studies: list[str] | None, run: str | Mapping[str, str] | None,
          ) -> tuple[list[RunStore], list[tuple[str, str, bool]]]:
    """The runs to report, each checked against its manifest first (``RunStore.check``), and the
    ``(label, reason, True)`` of those that cannot be read.

    A named study or run (``studies`` or ``run`` given) that is missing or cannot be read raises
    before anything is written; with neither, every run under ``root`` is looked at and one that
    cannot be read is a failure while the others are reported.
    """
    if not root.is_dir():
        raise UserInputError(f"no results directory at {root}; run a study first.")
    try:
        directories = folders(root, strict=True)
    except OSError as exc:
        raise UserInputError(f"cannot list the runs under {root} "
                             f"({exc.strerror or type(exc).__name__}).") from None
    named, stores, failed = bool(studies) or run is not None, [], []
    for name in dict.fromkeys(studies) if studies else [d.name for d in directories]:
        wanted = run.get(name) if isinstance(run, Mapping) else run
        if studies and not os.path.isdir(root / name):
            raise UserInputError(f"no records for study {name!r} under {root}; "
                                 f"{how_to_make(root, name, wanted)}")
        if wanted is None and (why := unlistable(root / name)):  # its runs cannot be found
            if named:
                raise UserInputError(why)
            failed.append((name, why, True))
            continue
        # walking, a folder is a run only if it looks like one (/sys/firmware/acpi is none)
        for r in [wanted] if wanted is not None else [d.name for d in runs_of(root / name)]:
            store = RunStore(root / name / r)
            try:  # a damaged file, a foreign or duplicate shard, missing records: never reported
                manifest = store.check()
            except UserInputError as exc:
                if named:
                    raise
                failed.append((f"{name}/{r}", reason(exc), True))
                continue
            if manifest is None:
                if wanted is not None:
                    raise UserInputError(f"no run {r!r} of study {name!r} under {root}; "
                                         f"{near_run(root, name, r)}{how_to_make(root, name, r)}")
                continue
            stores.append(store)
    if not stores and not failed:
        raise UserInputError(f"no runs under {root}; run a study first (graspcampaign run STUDY "
                             f"--root {root}).")
    if not stores and len(failed) > 1 and not any(os.path.isdir(root / label) for label, _, _ in failed):
        raise UserInputError(f"no runs under {root}: its {len(failed)} entries where runs would be "
                             f"({failed[0][0]}, …) are files, not run directories, so it is no results "
                             f"root; give the root your runs are in, or make one with graspcampaign run "
                             f"STUDY --root {root}.")
    return stores, failed


def _report_or_failure(store: RunStore, root: Path, formats: list[str], figure_format: str):
    """``((report page, items, broken), None)``, or ``(None, (run label, reason, bad input))`` if it
    failed."""
    label = store.path.relative_to(root).as_posix()
    try:
        return report_run(store, root, formats, figure_format), None
    except Exception as exc:  # noqa: BLE001 - one broken run never stops the others
        log.debug("report of %s failed", label, exc_info=True)
        bad_input = disk_full(exc) or access_denied(exc) or isinstance(exc, UserInputError)
        return None, (label, reason(exc), bool(bad_input))


def _report_in_worker(*args):
    """:func:`_report_or_failure` in a worker process, its package logger as quiet as the CLI's."""
    package_log = logging.getLogger("graspcampaign")
    if not package_log.handlers:
        package_log.addHandler(logging.NullHandler())
    return _report_or_failure(*args)


def build_reports(studies: list[str] | None = None, run: str | Mapping[str, str] | None = None,
                  root: Path | str = "results", formats: list[str] | str | None = None,
                  figure_format: str = "png", n_jobs: int = 1) -> ReportBatch:
    """Write every selected run's report, then the headline page and the index; ``.failed`` of
    the result lists the runs whose report could not be written (the others are written).

    ``run``: the run of every study, or ``{study: run}``. Every named study and run is checked
    before anything is written. The headline and index pages summarise every run under ``root``:
    they are rewritten only when a report was written and every run they summarise can be read,
    else left as they were (a warning names the run), so a damaged run never replaces what they
    said of it. The runs' reports are independent: with ``n_jobs`` other than 1 they are written
    in that many processes (joblib loky; -1: one per core), the same files as one by one."""
    root, formats = check_root(root, write=True), D.check_formats(formats)  # it writes the index
    figure_format = D.check_formats(figure_format, D.FIGURE_FORMATS, "figure format",
                                    "--figure-format", one=True)[0]
    batch = ReportBatch(formats=formats)
    stores, unreadable = _runs(root, studies, run)
    batch.failed += unreadable
    if n_jobs == 1 or len(stores) < 2:
        outcomes = [_report_or_failure(store, root, formats, figure_format) for store in stores]
    else:
        from joblib import Parallel, delayed

        n_jobs = min(n_jobs, len(stores)) if n_jobs > 0 else n_jobs  # loky starts every one asked
        outcomes = Parallel(n_jobs=n_jobs)(delayed(_report_in_worker)(store, root, formats, figure_format)
                                           for store in stores)
    for written, failure in outcomes:
        if failure is None:
            page, items, titles, busy = written
            batch.append(page)
            batch.broken[page] = (items, titles)
            if busy:
                batch.in_progress[page] = busy
        else:
            batch.failed.append(failure)
    unlisted = [(label, why) for label, why, _ in unreadable if "/" not in label]  # a study's folder
    if len(batch) and write_root_pages(root, formats, unlisted):
        batch.pages = [root / f"{name}.{ext}" for name in ("index", "headline")
                       for ext in _root_pages(root, formats)]
    return batch


def write_root_pages(root: Path, formats: list[str], unlisted: list[tuple[str, str]]) -> bool:
    """Write the headline and index pages, unless a run they summarise cannot be read and the
    pages as they are show it: then leave both as they were (what they said of the run was
    computed from it when it could be read), warn naming the run, and return False. A run the
    pages do not show yet is written with its row marked "the run cannot be read". ``unlisted``:
    ``(study, why)`` of the study folders whose runs cannot be found (``_runs``), as such runs."""
    unreadable: list[tuple[str, str]] = list(unlisted)
    frame = headline_rows(root, unreadable)
    root_pages = _root_pages(root, formats)
    index = {page: index_rows(root, page, unreadable) for page in root_pages}
    pages = [root / f"{name}.{ext}" for name in ("headline", "index") for ext in ("csv", "md", "html")]
    shown = " ".join(p.read_text(errors="replace") for p in pages if p.is_file())
    unreadable = [(label, why) for label, why in unreadable
                  if re.search(rf"(?<![\w.-]){re.escape(label)}/([^/\s]+/)?report/report\.", shown)]
    if unreadable:
        label, why = unreadable[0]
        more = f" (and {len(unreadable) - 1} more)" if len(unreadable) > 1 else ""
        warnings.warn(f"the headline and index pages were left as they were: run {label} cannot "
                      f"be read{more} ({why})", stacklevel=2)
        return False
    write_headline(root, root_pages, frame)
    for page, rows in index.items():
        write_index_page(root, page, rows)
    return True


def _root_pages(root: Path, formats: list[str]) -> list[str]:
    """The formats of the index and headline pages: those asked for (md, html), else md, and those
    an earlier report wrote (an index.html left as it was would no longer list every run)."""
    return [f for f in ("md", "html") if f in formats or (root / f"index.{f}").is_file()] or ["md"]


def index_rows(root: Path, page: str, unreadable: list[tuple[str, str]]) -> pd.DataFrame:
    """The index rows: every run's report page (``page``: md or html) with its study, run, source
    (its records', as its page says) and trial count; a run whose manifest or records cannot be
    read is added to ``unreadable``."""
    rows = []
    for report in sorted(root.glob(f"*/*/report/report.{page}")):
        run_dir = report.parent.parent
        try:
            m = read_manifest(run_dir / "manifest.json") or {}
            source = RunStore(run_dir).source(m)
        except UserInputError as exc:
            unreadable.append((run_dir.relative_to(root).as_posix(), reason(exc)))
            m, source = {}, None
        rows.append([m.get("study", run_dir.parent.name), m.get("run", run_dir.name),
                     SOURCE_SHORT.get(source, source), run_size(m),
                     report.with_suffix(".html").relative_to(root).as_posix()])
    return pd.DataFrame(rows, columns=["study", "run", "source", "trials", "report"])


def write_index_page(root: Path, page: str, frame: pd.DataFrame) -> None:
    """Write ``index.<page>`` (md or html) linking every run's report page of that format and the
    headline (only that page: the other format's index lists the runs with a page of its own)."""
    doc = Document("Reports", "", [], [
        Text("Headline success rates beside the paper's Table 1: [Table 1 headline](headline.md)"),
        Table("index", "Every run's report", frame, [
            Col("study", "study"), Col("run", "run", link="report"), Col("source", "source"),
            Col("trials", "trials")], csv=None)])
    write_file(root / f"index.{page}", doc.html() if page == "html" else doc.markdown())
