"""Render a study's :class:`~graspcampaign.report.spec.ReportSpec` over one run's records."""

from __future__ import annotations

import logging
import os
import re
from collections.abc import Callable
from dataclasses import dataclass, field
from functools import cached_property
from typing import Any

import pandas as pd

from graspcampaign.analysis.records import executed, in_design_order, status_counts
from graspcampaign.analysis.vocabulary import data_source
from graspcampaign.campaign.paths import how_to_make
from graspcampaign.campaign.provenance import (
    design_change,
    ingested,
    last_design,
    overrides_given,
    paper_overrides,
    run_size,
    study_given,
)
from graspcampaign.core.bench_specimen import FINGERTIP_RADIUS
from graspcampaign.core.words import listed, meant
from graspcampaign.errors import UserInputError, access_denied, disk_full
from graspcampaign.report import format as fmt
from graspcampaign.report.document import Document, Figure, Section, Table, Text

log = logging.getLogger(__name__)


class Tables(dict):
    """The tables rendered so far, by name; one not rendered (its note says why) raises ValueError,
    the data's reason. When :func:`render` knows the spec's tables (``declared``; ``below``: those
    declared below the item being rendered), a name the spec declares nowhere (a misspelling) or
    only below the item reading it raises LookupError instead: the item's code failed."""

    declared: tuple[str, ...] = ()
    below: tuple[str, ...] = ()

    def __missing__(self, name: str):
        if name in self.below:
            raise LookupError(f"table {name} is declared below this item, so it is not computed yet; "
                              "declare it above the items that read it")
        if self.declared and name not in self.declared:
            raise LookupError(f"this report declares no table {name}; {meant(name, self.declared)}its "
                              f"tables: {listed(self.declared)}")
        raise ValueError(f"its table {name} was not computed")


@dataclass
class Run:
    """One run as the items see it: records, manifest, typed paper values, the run's store (for
    its auxiliary tables) and the tables rendered so far (``tables``, by name). Rendered: ``failures``
    says why each item not (fully) computed was not; ``items`` counts the tables, figures and
    findings, ``broken`` names those whose code failed (:func:`render`)."""

    records: pd.DataFrame
    manifest: dict
    paper: Any = None
    store: Any = None  # campaign.records.RunStore
    figure_format: str = "png"
    tables: dict[str, pd.DataFrame] = field(default_factory=Tables)
    failures: list[str] = field(default_factory=list)
    items: int = 0
    broken: list[str] = field(default_factory=list)
    _parts: dict[str, pd.DataFrame] = field(default_factory=dict, init=False, repr=False)

    config = property(lambda self: self.manifest.get("config") or {})
    params = property(lambda self: self.config.get("params") or {})
    seed = property(lambda self: int(self.config.get("seed", 0)))
    study = property(lambda self: str(self.manifest.get("study")))
    #: a virtual rig's exports stored by ``graspcampaign ingest`` (not rig measurements)
    ingested_exports = property(lambda self: self.source == "virtual" and ingested(self.manifest))

    @property
    def radius_mm(self) -> float:
        """The fingertip radius r [mm] of the run: the indenter radius its records carry (Test 1's
        ``indenter_radius_mm``), else the model's (Table 2's 5 mm where the config has none). A Test 1
        run stored before that column has the bench's (the bench never reads the config's model)."""
        recorded = set(self.records.get("indenter_radius_mm", pd.Series(dtype=float)).dropna())
        if len(recorded) > 1:
            raise ValueError(f"the records hold more than one indenter radius: {sorted(recorded)} mm")
        if recorded:
            return float(recorded.pop())
        model = {} if self.manifest.get("kind") == "test1_bench" else self.config.get("model") or {}
        return 1e3 * float(model.get("fingertip_radius_m", FINGERTIP_RADIUS))

    @cached_property
    def ok(self) -> pd.DataFrame:
        """The executed trials (:func:`graspcampaign.analysis.records.executed`)."""
        return executed(self.records)

    @cached_property
    def source(self) -> str:
        """simulation, virtual or measured (virtual as soon as one record says so)."""
        return data_source(self.records.get("source", ()), self.manifest.get("source"))

    @property
    def rig(self) -> str:
        """What a rig's values are, for axis labels and captions: "measured" only on hardware."""
        return "measured" if self.source == "measured" else "virtual-rig"

    @property
    def cluster(self) -> str:
        """The object column trials cluster in: the shape in simulation, the object on a rig."""
        return "shape" if self.source == "simulation" else "object_id"

    @property
    def order(self) -> dict[str, list]:
        """The design's levels of every factor, in config order (display order after the vocabulary's)."""
        return {k: list(v) for k, v in (self.config.get("factors") or {}).items()}

    def aux(self, name: str) -> pd.DataFrame:
        """Return the run's auxiliary table ``tables/<name>`` (empty if the run has none)."""
        return self.part(f"tables/{name}")

    def part(self, name: str) -> pd.DataFrame:
        """Return a stored part of the run (e.g. ``prepared``; empty if the run has none)."""
        return self.memo(name, lambda: in_design_order(self.store.read(name).to_pandas())
                         if self.store is not None else pd.DataFrame())

    def stored(self, name: str) -> pd.DataFrame:
        """Return the stored part ``name`` (:meth:`part`) an item cannot do without; raise the one
        ValueError naming the run, the part and what to do when the run has none."""
        if len(frame := self.part(name)):
            return frame
        # the commands as paths.how_to_make gives them: under the run's root, with the overrides it was
        # started with (without them `run` refuses the run as started with another config)
        study, run, given = study_given(self.manifest, self.study), self.manifest.get("run"), \
            overrides_given(self.manifest) or []
        root = "results" if (where := getattr(self.store, "path", None)) is None else where.parent.parent
        if name.startswith("summary/"):
            todo = ("the study writes it once every trial is recorded; "
                    + how_to_make(root, study, run, given, then="again to complete the run"))
        else:
            todo = ("the study stores it while the run's trials run and this run stored none; "
                    + how_to_make(root, study, "NEW", given, then="to record a new run"))
        raise ValueError(f"run {study}/{run} has no `{name}` table: {todo}")

    def memo(self, name: str, compute: Callable[[], Any]) -> Any:
        """Return ``compute()``, computed once per run under ``name`` (a frame several items read)."""
        if name not in self._parts:
            self._parts[name] = compute()
        return self._parts[name]


def reason(exc: BaseException) -> str:
    """One sentence saying why a statistic could not be computed."""
    if isinstance(exc, KeyError):  # pandas names the columns in a list ("... : ['success']") or
        key = str(exc.args[0]) if exc.args else ""  # after "Column(s) not found: " (a groupby's)
        listed = re.search(r"\['([^']+)'|Columns? not found: '?([^',]+)", key)
        return f"the records have no `{next(filter(None, listed.groups())) if listed else key}` column"
    if isinstance(exc, OSError) and exc.filename and disk_full(exc):
        # what cli.guard says of a full disk; only a write fills one (a missing file may be a read)
        return (f"cannot write {exc.filename}: {os.strerror(exc.errno).lower()}; free some space there "
                "and run the command again")
    if (denied := access_denied(exc)) is not None:  # what cli.guard says of it: whose permissions
        return denied.rstrip(".")
    if isinstance(exc, OSError) and exc.filename and exc.errno:  # read or write: the file and why
        return f"{exc.filename}: {os.strerror(exc.errno).lower()}"
    text = str(exc).strip().splitlines()[0].rstrip(".") if str(exc).strip() else type(exc).__name__
    return text if isinstance(exc, ValueError | UserInputError) else f"{type(exc).__name__}: {text}"


def render(spec, run: Run, document: Document) -> Document:
    """Append every item of ``spec`` rendered over ``run`` to ``document``; a Finding is computed
    last (it may read every table of the report) and shown where it is declared.

    An item that raises is replaced by a note saying why, and a table showing a column its frame
    lacks gets a note under it; each joins ``run.failures``. A ValueError or KeyError, like a missing
    shown column, is the data's reason (no executed trial, a column a run whose trials all errored
    or recorded before it existed lacks: the item is legitimately empty); any other exception means
    the item's code failed: it joins ``run.broken``, as does an item reading a table (``run.tables``)
    the spec declares nowhere or only below it (:class:`Tables`)."""
    from graspcampaign.report.spec import Finding

    slots, names = {}, [(i, item.name) for i, item in enumerate(spec.items) if isinstance(item, Table)]
    # an item of another class (a wrapper with a render method) may render tables of any name
    known = all(isinstance(item, Table | Figure | Section | Text | Finding) for item in spec.items)
    run.tables.declared = tuple(n for _, n in names) if known else ()
    for i, item in sorted(enumerate(spec.items), key=lambda e: isinstance(e[1], Finding)):
        run.tables.below = () if isinstance(item, Finding) else tuple(n for j, n in names if j > i)
        run.items += not isinstance(item, Section | Text)
        try:
            slots[i] = item.render(run)
        except Exception as exc:  # noqa: BLE001 - one failing item is reported, never fatal
            log.debug("report item %s failed", getattr(item, "name", item), exc_info=True)
            run.failures.append(f"{item.title}: {reason(exc)}")
            run.broken += [] if isinstance(exc, ValueError | KeyError) else [item.title]
            slots[i] = [Text(f"{item.title} not computed: {reason(exc)}.", "note")]
        for table in [b for b in slots[i] if isinstance(b, Table)]:
            if note := table.absent():
                run.failures.append(note)
                slots[i].insert(slots[i].index(table) + 1, Text(note, "note"))
        run.tables.update({b.name: b.frame for b in slots[i] if isinstance(b, Table)})
    run.tables.below = ()
    document.blocks.extend(b for i in sorted(slots) for b in slots[i])
    return document


def design_text(config: dict) -> str:
    """The run's design as it was run (its manifest's config, overrides included): each factor's
    levels (their count beyond four), then the seeds and repeats; "" for a protocol's schedule."""
    factors = [f"{k} {', '.join(map(str, v)) if len(v) <= 4 else f'({len(v)} levels)'}"
               for k, v in (config.get("factors") or {}).items() if isinstance(v, list)]
    return "; ".join([*factors, *(f"{k} {config[k]}" for k in ("seeds", "repeats")
                                  if factors and config.get(k, 1) != 1)])


def drifted(manifest: dict) -> list[str]:
    """The config hashes, in order, of the sessions that resumed the run under another config."""
    hashes = [h for x in manifest.get("sessions") or [] if (h := x.get("config_hash"))]
    return [h for i, h in enumerate(hashes) if h != manifest.get("config_hash") and h not in hashes[:i]]


def drift_text(manifest: dict, drift: list[str]) -> str:
    """The header's "Drift" line: the other configs, and which session each line above describes
    (the trial count: the design of the session that ran the run last, ``run_size``)."""
    last = last_design(manifest)
    which = (f"the design and hash above are the first session's, the trial count the design of the "
             f"session that ran it last (`{last.get('config_hash')}`)" if last else
             "the design, hash and trial count above are the first session's")
    return (f"resumed under another config ({', '.join(f'`{h}`' for h in drift)}) with --allow-drift: "
            f"{which}; the records hold the trials of each")


def provenance(run: Run) -> list[tuple[str, str]]:
    """Return the provenance lines every report starts with."""
    m, counts = run.manifest, status_counts(run.records)
    excluded = ", ".join(f"{counts[k]} {w}" for k, w in (
        ("error", "errored"), ("aborted", "aborted"), ("other", "with another status")) if counts[k])

    def given(value: Any, code: bool = False) -> str:  # a missing entry (an ingested run's) marked "—"
        return fmt.MISSING if fmt.is_missing(value) else f"`{value}`" if code else str(value)

    return [("Trials", f"{len(run.records)} recorded of {given(run_size(m))}; {counts['executed']} "
                       "executed" + (f"; {excluded}, excluded from every denominator" if excluded else "")),
            *([("Design", design)] if (design := design_text(m.get("config") or {})) else []),
            *([("Reduced/modified run", f"overrides `{change[0]}`; {change[1]}")]
              if (change := design_change(m)) else []),
            *([("Paper values", f"{listed([f'`{o}`' for o in given_paper])} given on the command line: "
                                "the paper's values shown here are those given, not the study file's")]
              if (given_paper := paper_overrides(m)) else []),
            ("Config hash", given(m.get("config_hash"), code=True)),
            *([("Drift", drift_text(m, drift))] if (drift := drifted(m)) else []),
            ("Code", given(m.get("code_version"), code=True) + (" (dirty tree)" if (m.get("git") or {}).get(
                "dirty") else "")),
            ("Started / finished", f"{given(m.get('started_at'))} / {given(m.get('finished_at'))}"),
            ("Host", given((m.get("host") or {}).get("name"))), ("Seed", str(run.seed))]
