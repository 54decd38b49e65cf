"""Parquet record store of one run: atomic shards, crash-safe compaction, quarantine.

Layout of ``<root>/<study>/<run>/``::

    manifest.json
    records/part-<task>.parquet       one shard per task (a batch of trials), written atomically
    records/compact-<hash>.parquet    shards merged at the end of a run
    prepared/...                      shared preparations (e.g. PSO identifications), same scheme
    tables/<name>/part-<task>.parquet per-step traces keyed by trial_id, named after their task
    quarantine/                       unreadable shards moved aside (their trials re-run)

A shard is written to a hidden temporary name (``.part-….parquet.tmp``, skipped by every reader)
and renamed into place, so a reader never sees half a file and a run killed at any moment loses
at most the tasks in flight. Page checksums are written and verified, so a corrupted body is
caught, not only a truncated footer. A compacted file lists its source shards in its metadata;
a source still present after a crash between "write compact" and "delete sources" is ignored and
removed, so no trial is ever read twice.
"""

from __future__ import annotations

import json
import logging
import os
import shutil
import warnings
from collections.abc import Iterable
from pathlib import Path
from typing import Any

import pyarrow as pa
import pyarrow.dataset as ds
import pyarrow.parquet as pq

from graspcampaign.campaign.grid import content_hash

log = logging.getLogger(__name__)

_SOURCES_KEY = b"graspcampaign.sources"
_FORMAT = ds.ParquetFileFormat(
    default_fragment_scan_options=ds.ParquetFragmentScanOptions(page_checksum_verification=True)
)


def table_from_rows(rows: list[dict[str, Any]], metadata: dict[str, str] | None = None) -> pa.Table:
    """Build an Arrow table from record dicts (columns in first-seen order)."""
    columns: dict[str, None] = {}
    for row in rows:
        columns.update(dict.fromkeys(row))
    table = pa.Table.from_pylist([{c: row.get(c) for c in columns} for row in rows])
    if metadata:
        table = table.replace_schema_metadata({k.encode(): v.encode() for k, v in metadata.items()})
    return table


def _write_atomic(table: pa.Table, path: Path) -> None:
    tmp = path.with_name(f".{path.name}.tmp")
    pq.write_table(table, tmp, compression="zstd", write_page_checksum=True)
    with open(tmp, "rb") as fh:
        os.fsync(fh.fileno())
    os.replace(tmp, path)


class RunStore:
    """The files of one run of one study."""

    def __init__(self, path: Path | str):
        self.path = Path(path)

    # -- layout ---------------------------------------------------------------------------------
    @property
    def manifest_path(self) -> Path:
        return self.path / "manifest.json"

    def _dir(self, part: str) -> Path:
        return self.path / part

    def exists(self) -> bool:
        return self.manifest_path.exists()

    # -- writing --------------------------------------------------------------------------------
    def write_shard(self, part: str, name: str, rows: list[dict[str, Any]],
                    metadata: dict[str, str] | None = None) -> Path:
        """Write ``rows`` as ``<part>/part-<name>.parquet`` atomically and return its path."""
        directory = self._dir(part)
        directory.mkdir(parents=True, exist_ok=True)
        path = directory / f"part-{name}.parquet"
        _write_atomic(table_from_rows(rows, metadata), path)
        return path

    # -- reading --------------------------------------------------------------------------------
    def _files(self, part: str) -> list[Path]:
        """Return the live shards of ``part`` (compacted sources left by a crash excluded)."""
        directory = self._dir(part)
        if not directory.is_dir():
            return []
        compacts = sorted(directory.glob("compact-*.parquet"))
        sources: set[str] = set()
        for path in compacts:
            meta = self._schema_or_quarantine(path)
            if meta is None:
                continue
            raw = (meta.metadata or {}).get(_SOURCES_KEY)
            if raw:
                sources.update(json.loads(raw))
        live = [p for p in compacts if p.exists()]
        live += [p for p in sorted(directory.glob("part-*.parquet")) if p.name not in sources]
        return live

    def _schema_or_quarantine(self, path: Path) -> pa.Schema | None:
        try:
            return pq.read_schema(path)
        except (pa.ArrowInvalid, OSError) as exc:
            self._quarantine(path, exc)
            return None

    def _quarantine(self, path: Path, exc: Exception) -> None:
        target = self._dir("quarantine") / path.relative_to(self.path).as_posix().replace("/", "__")
        target.parent.mkdir(parents=True, exist_ok=True)
        shutil.move(str(path), target)
        warnings.warn(
            f"unreadable shard {path} moved to {target} ({exc}); its trials will run again",
            stacklevel=2,
        )

    def read(self, part: str = "records", columns: list[str] | None = None) -> pa.Table:
        """Read every live shard of ``part`` into one table with the union of their schemas."""
        while True:
            files = self._files(part)
            schemas = [(p, self._schema_or_quarantine(p)) for p in files]
            if any(s is None for _, s in schemas):
                continue  # something was quarantined: list again
            if not schemas:
                return pa.table({})
            schema = pa.unify_schemas(
                [s.remove_metadata() for _, s in schemas], promote_options="permissive"
            )
            try:
                dataset = ds.dataset([str(p) for p in files], schema=schema, format=_FORMAT)
                cols = None if columns is None else [c for c in columns if c in schema.names]
                return dataset.to_table(columns=cols)
            except (pa.ArrowInvalid, OSError):
                bad = self._find_corrupt(files)
                if bad is None:
                    raise

    def _find_corrupt(self, files: Iterable[Path]) -> Path | None:
        for path in files:
            try:
                pq.read_table(path, page_checksum_verification=True)
            except (pa.ArrowInvalid, OSError) as exc:
                self._quarantine(path, exc)
                return path
        return None

    def recorded_ids(self, part: str = "records", key: str = "trial_id") -> set[str]:
        """Return the ids already stored in ``part``."""
        table = self.read(part, columns=[key])
        if key not in table.column_names:
            return set()
        return set(table.column(key).to_pylist())

    # -- maintenance ----------------------------------------------------------------------------
    def clean(self) -> None:
        """Remove temporary files and compacted sources a crash may have left behind."""
        if not self.path.is_dir():
            return
        for tmp in self.path.rglob(".*.tmp"):
            tmp.unlink(missing_ok=True)
        for part in self._parts():
            live = {p.name for p in self._files(part)}
            for path in self._dir(part).glob("part-*.parquet"):
                if path.name not in live:
                    path.unlink(missing_ok=True)
        self._drop_orphan_tables()

    def _parts(self) -> list[str]:
        parts = [p for p in ("records", "prepared") if self._dir(p).is_dir()]
        tables = self._dir("tables")
        if tables.is_dir():
            parts += [f"tables/{d.name}" for d in sorted(tables.iterdir()) if d.is_dir()]
        return parts

    def _record_shard_names(self) -> set[str]:
        """Names of every record shard ever committed (live parts and compacted sources)."""
        names: set[str] = set()
        directory = self._dir("records")
        for path in directory.glob("compact-*.parquet") if directory.is_dir() else []:
            raw = (pq.read_schema(path).metadata or {}).get(_SOURCES_KEY)
            names.update(json.loads(raw) if raw else [])
        names.update(p.name for p in directory.glob("part-*.parquet")) if directory.is_dir() else None
        return names

    def _drop_orphan_tables(self) -> None:
        """Delete trace shards whose records shard was never committed (killed in between)."""
        tables = self._dir("tables")
        if not tables.is_dir():
            return
        committed = self._record_shard_names()
        for path in tables.glob("*/part-*.parquet"):
            if path.name not in committed:
                path.unlink(missing_ok=True)

    def compact(self, part: str = "records") -> None:
        """Merge the live part shards of ``part`` into one compacted file, crash-safely."""
        directory = self._dir(part)
        parts = [p for p in self._files(part) if p.name.startswith("part-")]
        if len(parts) < 2:
            return
        tables = [pq.read_table(p) for p in parts]
        schema = pa.unify_schemas([t.schema.remove_metadata() for t in tables],
                                  promote_options="permissive")
        merged = pa.concat_tables(
            [t.replace_schema_metadata(None) for t in tables], promote_options="permissive"
        ).cast(schema)
        names = sorted(p.name for p in parts)
        merged = merged.replace_schema_metadata({_SOURCES_KEY: json.dumps(names).encode()})
        _write_atomic(merged, directory / f"compact-{content_hash(names)}.parquet")
        for path in parts:
            path.unlink(missing_ok=True)

    def compact_all(self) -> None:
        """Compact records, preparations and every trace table."""
        for part in self._parts():
            self.compact(part)
