"""Render a study's :class:`~graspcampaign.report.spec.ReportSpec` over one run's records.

:class:`Run` is what every item sees: the records, the executed trials, the manifest's config,
the typed paper values, the run's auxiliary tables and the tables computed so far. Each item is
rendered on its own: an item whose statistic cannot be computed (no executed trial, too few
clusters, a missing column, a non-finite heatmap) is replaced by one sentence giving the reason,
and the rest of the report is written.
"""

from __future__ import annotations

import logging
from dataclasses import dataclass, field
from functools import cached_property
from typing import Any

import pandas as pd

from graspcampaign.analysis.records import data_source, executed, status_counts
from graspcampaign.report.document import Document, Text

log = logging.getLogger(__name__)


@dataclass
class Run:
    """One run as the report items see it."""

    records: pd.DataFrame
    manifest: dict
    paper: Any = None
    store: Any = None  # campaign.records.RunStore, for the run's auxiliary tables
    figure_format: str = "png"
    tables: dict[str, pd.DataFrame] = field(default_factory=dict)
    failures: list[str] = field(default_factory=list)

    @cached_property
    def ok(self) -> pd.DataFrame:
        """The executed trials (:func:`graspcampaign.analysis.records.executed`)."""
        return executed(self.records)

    @property
    def config(self) -> dict:
        return self.manifest.get("config") or {}

    @property
    def params(self) -> dict:
        return self.config.get("params") or {}

    @cached_property
    def source(self) -> str:
        """simulation, virtual or measured (virtual as soon as one record says so)."""
        return data_source(self.records, self.manifest.get("source"))

    @property
    def seed(self) -> int:
        return int(self.config.get("seed", 0))

    @property
    def study(self) -> str:
        return str(self.manifest.get("study"))

    @property
    def cluster(self) -> str:
        """The object column trials cluster in: the shape in simulation, the object on a rig."""
        return "shape" if self.source == "simulation" else "object_id"

    @property
    def order(self) -> dict[str, list]:
        """The design's levels of every factor, in config order (table and figure order)."""
        return {k: list(v) for k, v in (self.config.get("factors") or {}).items()}

    def aux(self, name: str) -> pd.DataFrame:
        """Return the run's auxiliary table ``tables/<name>`` (empty if the run has none)."""
        return self.part(f"tables/{name}")

    def part(self, name: str) -> pd.DataFrame:
        """Return a stored part of the run (e.g. ``prepared``; empty if the run has none)."""
        if name not in self._aux:
            self._aux[name] = (self.store.read(name).to_pandas() if self.store is not None
                               else pd.DataFrame())
        return self._aux[name]

    @cached_property
    def _aux(self) -> dict[str, pd.DataFrame]:
        return {}


def reason(exc: BaseException) -> str:
    """One sentence saying why a statistic could not be computed."""
    if isinstance(exc, KeyError):
        return f"the records have no `{exc.args[0]}` column"
    text = str(exc).strip().splitlines()[0].rstrip(".") if str(exc).strip() \
        else type(exc).__name__
    from graspcampaign.errors import UserInputError

    plain = isinstance(exc, ValueError | UserInputError)
    return text if plain else f"{type(exc).__name__}: {text}"


def render(spec, run: Run, document: Document) -> Document:
    """Append every item of ``spec`` rendered over ``run`` to ``document``.

    A :class:`~graspcampaign.report.spec.Finding` is computed last (it may read every table of
    the report) and shown where it is declared, first in every study's spec.
    """
    from graspcampaign.report.spec import Finding

    slots = []
    for item in sorted(spec.items, key=lambda i: isinstance(i, Finding)):
        try:
            blocks = item.render(run)
        except Exception as exc:  # noqa: BLE001 - any failure of one item is reported, not fatal
            log.debug("report item %s failed", getattr(item, "name", item), exc_info=True)
            run.failures.append(f"{item.title}: {reason(exc)}")
            blocks = [Text(f"{item.title} not computed: {reason(exc)}.", "note")]
        for b in blocks:
            if hasattr(b, "frame"):
                run.tables[b.name] = b.frame
        slots.append((spec.items.index(item), blocks))
    document.blocks.extend(b for _, blocks in sorted(slots, key=lambda s: s[0]) for b in blocks)
    return document


def provenance(run: Run) -> list[tuple[str, str]]:
    """Return the provenance lines every report starts with."""
    m = run.manifest
    counts = status_counts(run.records)
    git = m.get("git") or {}
    excluded = ", ".join(f"{counts[k]} {w}" for k, w in (("error", "errored"),
                         ("aborted", "aborted"), ("other", "with another status")) if counts[k])
    return [
        ("Trials", f"{len(run.records)} recorded of {m.get('n_trials')}; {counts['executed']} "
                   f"executed" + (f"; {excluded}, excluded from every denominator"
                                  if excluded else "")),
        ("Config hash", f"`{m.get('config_hash')}`"),
        ("Code", f"`{m.get('code_version')}`" + (" (dirty tree)" if git.get("dirty") else "")),
        ("Started / finished", f"{m.get('started_at')} / {m.get('finished_at')}"),
        ("Host", str((m.get("host") or {}).get("name"))),
        ("Seed", str(run.seed)),
    ]
