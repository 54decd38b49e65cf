"""Parquet record store of one run: atomic shards, full verification, quarantine, compaction.

Layout of ``<root>/<study>/<run>/``::

    manifest.json
    records/part-<task>.parquet       one shard per task (a batch of trials), written atomically
    records/compact-<hash>.parquet    shards merged at the end of a run
    prepared/...                      shared preparations (e.g. PSO identifications), same scheme
    tables/<name>/part-<task>.parquet per-step traces keyed by trial_id, named after their task
    summary/<name>/part-final.parquet study-level tables computed once every trial is recorded
    quarantine/                       files moved aside by a repair (their trials re-run)

A shard is written to a hidden temporary name (``.part-….parquet.tmp``, skipped by every reader)
and renamed into place, so a reader never sees half a file and a run killed at any moment loses
at most the tasks in flight. Page checksums are written, and every file is read *in full* (every
column, every page, checksums verified) before anything uses it: before its trials count as
recorded, before it is compacted, before a report reads it. Verifying only the key column would
let a damaged value column through, and a compaction would then copy the garbage into a new file
with valid checksums. A file is read in full once per process while it is unchanged (its inode,
size, mtime and ctime; :mod:`graspcampaign.campaign.verify`, which keeps what the checks need of it
from that read), and again whenever it is read to be rewritten (compaction, removing rows).

A file that names other files in its metadata (``graspcampaign.sources``) supersedes them: a
compacted file lists its source shards, a rewritten file the file it replaces. A superseded file
still present after a crash between "write the new file" and "delete the old ones" is ignored and
removed, so no trial is ever read twice. A records file also names the configs of the sessions
that wrote it (``graspcampaign.config_hashes``), so a shard of another config is recognised.
A records file written by ``run`` or ``ingest`` also says what each of its trials stored in the
run's other parts (``graspcampaign.parts``, :mod:`graspcampaign.campaign.account`), merged by a
compaction (never with a shard stored before it was kept) and kept for the trials a rewrite keeps.
Every file the tool writes carries the SHA-256 of its values (``graspcampaign.content_sha256``,
:func:`content_digest`), checked whenever the file is verified: a file rewritten with other values
(a row removed, a value or a column changed) is damaged even though its page checksums are valid.

Reading never changes a run: a damaged file raises :class:`~graspcampaign.errors.DamagedRunError`
naming the run and the file. Whether the run as a whole is what its manifest says (its layout, no
file that is not a shard, no foreign or duplicate records, none missing) is
:meth:`RunStore.check`; only :meth:`RunStore.repair` (called by the runner when a run starts or
resumes) moves files to ``quarantine/`` and makes the rest consistent, so that exactly the
trials no longer recorded run again (:mod:`graspcampaign.campaign.integrity`,
:mod:`graspcampaign.campaign.repair`).
"""

from __future__ import annotations

import contextlib
import json
import os
from collections.abc import Iterable
from pathlib import Path
from typing import Any

import numpy as np
import pyarrow as pa
import pyarrow.parquet as pq

from graspcampaign.analysis.vocabulary import data_source
from graspcampaign.campaign.account import Account, encode, merge
from graspcampaign.campaign.former_names import current_names, renamed
from graspcampaign.campaign.grid import content_hash
from graspcampaign.campaign.verify import (
    CONFIG_KEY,
    CONTENT_KEY,
    PARTS_KEY,
    READ_ERRORS,
    SOURCES_KEY,
    Damaged,
    Facts,
    cached,
    content_digest,
    facts,
    read_file,
    reason,
    shards,
    supersedes,
    verify_file,
)
from graspcampaign.errors import DamagedRunError, StoreWriteError, disk_full

#: The columns every record has (docs/records.md; written by the runner and by ``ingest``) and
#: what they hold; the optional ones hold it when present (a column of missing values: any type).
RECORD_COLUMNS = {"trial_id": "text", "study": "text", "run": "text", "kind": "text",
                  "trial_index": "whole numbers", "scene_id": "text", "status": "text",
                  "source": "text"}
#: Record columns stored as strings in every shard, even when no trial of the shard errored.
ERROR_COLUMNS = ("error_type", "error_message", "error_traceback")
OPTIONAL_COLUMNS = {**dict.fromkeys(ERROR_COLUMNS, "text"), "wall_time_s": "numbers"}


def config_metadata(config_hash: str) -> dict[str, str]:
    """Metadata of a records shard written by a session of config ``config_hash``."""
    return {CONFIG_KEY.decode(): json.dumps([config_hash])}


def table_from_rows(rows: list[dict[str, Any]], metadata: dict[str, str] | None = None,
                    strings: tuple[str, ...] = ()) -> pa.Table:
    """Build an Arrow table from record dicts (columns in first-seen order).

    ``strings`` are columns stored as strings even when every value is missing (a column of
    Nones would otherwise be Null-typed, and a reader would see the record schema change with
    the data); absent ones are added, empty.
    """
    columns: dict[str, None] = {}
    for row in rows:
        columns.update(dict.fromkeys(row))
    columns.update(dict.fromkeys(strings))
    # a flag measured on some rows only (Test 1's slipped_measured) arrives from pandas as NaN
    # where it is missing: that is a missing flag, not a number (pyarrow would refuse the column,
    # or type it double when the NaN comes first)
    flags = {c for row in rows for c, v in row.items() if isinstance(v, bool | np.bool_)}
    table = pa.Table.from_pylist([{c: _cell(row.get(c), c in flags) for c in columns} for row in rows])
    for name in strings:
        i = table.schema.get_field_index(name)
        if table.schema.field(i).type != pa.string():
            table = table.set_column(i, name, table.column(i).cast(pa.string()))
    if metadata:
        table = table.replace_schema_metadata({k.encode(): v.encode() for k, v in metadata.items()})
    return table


def _cell(value: Any, flag: bool) -> Any:
    """``value``, or None for a NaN in a flag column."""
    return None if flag and isinstance(value, float | np.floating) and np.isnan(value) else value


def _write_atomic(table: pa.Table, path: Path, account: Account | None = None) -> None:
    """Write ``table`` (stamped with its :func:`content_digest`) as ``path`` via a hidden temporary
    file, with the ``account`` of its trials (:func:`~graspcampaign.campaign.account.encode`: in
    the file's key-value metadata alone, not again in the Arrow schema pyarrow stores there); a
    failed write (a full disk) removes it, leaves ``path`` as it was and raises
    :class:`StoreWriteError` naming the file and why."""
    tmp = path.with_name(f".{path.name}.tmp")
    table = table.replace_schema_metadata(
        {**(table.schema.metadata or {}), CONTENT_KEY: content_digest(table).encode()})
    with writing(path, tmp):
        with pq.ParquetWriter(tmp, table.schema, compression="zstd",
                              write_page_checksum=True) as writer:
            writer.write_table(table)
            if account is not None:
                writer.add_key_value_metadata(
                    {PARTS_KEY: encode(account, table.column("trial_id").to_pylist())})
        with open(tmp, "rb") as fh:
            os.fsync(fh.fileno())
        os.replace(tmp, path)


@contextlib.contextmanager
def writing(path: Path, tmp: Path | None = None):
    """Turn an ``OSError`` while writing ``path`` into a :class:`StoreWriteError` naming it,
    after removing the temporary file ``tmp`` (nothing half-written stays behind)."""
    try:
        yield
    except OSError as exc:
        if tmp is not None:
            with contextlib.suppress(OSError):
                tmp.unlink(missing_ok=True)
        why = os.strerror(exc.errno) if exc.errno else str(exc) or type(exc).__name__
        free = disk_full(exc)
        raise StoreWriteError(
            f"cannot write {path}: {why[:1].lower()}{why[1:]}; what was stored before is kept, so "
            f"{'free some space there and ' if free else ''}run the command again.") from None


class RunStore:
    """The files of one run of one study."""

    def __init__(self, path: Path | str):
        self.path = Path(path)

    # -- layout ---------------------------------------------------------------------------------
    @property
    def manifest_path(self) -> Path:
        return self.path / "manifest.json"

    def part_dir(self, part: str) -> Path:
        """The directory of ``part`` (``records``, ``prepared``, ``tables/<name>``, ...)."""
        return self.path / part

    def part_names(self, summaries: bool = True) -> list[str]:
        """The parts the run holds (``summaries``: with those of ``summary/``), records first."""
        parts = [p for p in ("records", "prepared") if self.part_dir(p).is_dir()]
        for group in ("tables", "summary") if summaries else ("tables",):
            directory = self.part_dir(group)
            if directory.is_dir():
                parts += [f"{group}/{d.name}" for d in sorted(directory.iterdir()) if d.is_dir()]
        return parts

    # -- writing --------------------------------------------------------------------------------
    def write_shard(self, part: str, name: str, rows: list[dict[str, Any]],
                    metadata: dict[str, str] | None = None,
                    strings: tuple[str, ...] = (), account: Account | None = None) -> Path:
        """Write ``rows`` as ``<part>/part-<name>.parquet`` atomically, with the ``account`` of
        what their trials stored in the run's other parts (records written by ``run``), and
        return its path.

        A name a compacted file lists as superseded gets a suffix (``part-<name>-1.parquet``):
        a file of that name would be ignored as a leftover of the compaction. What a compacted
        file supersedes comes from its verified facts (:func:`~graspcampaign.campaign.verify.facts`:
        read once while it is unchanged; a run session writes its shards within one check, so
        even a file too new to be remembered is read once, docs/decisions.md).
        """
        directory, k = self.part_dir(part), 0
        superseded = self._superseded(part)[0]
        while f"part-{name}{f'-{k}' if k else ''}.parquet" in superseded:
            k += 1
        path = directory / f"part-{name}{f'-{k}' if k else ''}.parquet"
        with writing(path):
            directory.mkdir(parents=True, exist_ok=True)
        _write_atomic(table_from_rows(rows, metadata, strings), path, account)
        return path

    # -- listing and verification ---------------------------------------------------------------
    def listing(self, part: str) -> tuple[list[Path], list[tuple[Path, str]]]:
        """Return the live files of ``part`` (unverified; :meth:`verified` verifies them) and those
        whose footer cannot be read; a file another names as a source is superseded: not live."""
        directory = self.part_dir(part)
        if not directory.is_dir():
            return [], []
        files = shards(directory, "compact-*.parquet") + shards(directory, "part-*.parquet")
        sources, unreadable = self._superseded(part)
        bad = {p for p, _ in unreadable}
        return [p for p in files if p.name not in sources and p not in bad], unreadable

    def _superseded(self, part: str) -> tuple[set[str], list[tuple[Path, str]]]:
        """The names the compacted files of ``part`` supersede, and the compacted files whose
        footer cannot be read."""
        sources: set[str] = set()
        unreadable = []
        for path in shards(self.part_dir(part), "compact-*.parquet"):
            try:
                sources.update(supersedes(path))
            except READ_ERRORS as exc:
                unreadable.append((path, reason(exc)))
        return sources, unreadable

    def damaged(self, part: str) -> list[tuple[Path, str]]:
        """Return ``(file, reason)`` for every live file of ``part`` that fails full verification."""
        live, out = self.listing(part)
        for path in live:
            why = verify_file(path)
            if why is not None:
                out.append((path, why))
        return out

    def verify(self) -> None:
        """Check every file of the run in full (never changes anything).

        Raises
        ------
        DamagedRunError
            For the first damaged file, naming the run and the file.
        """
        for part in self.part_names():
            bad = self.damaged(part)
            if bad:
                raise self._damage_error(*bad[0])

    def _damage_error(self, path: Path, reason: str) -> DamagedRunError:
        from graspcampaign.campaign.integrity import Problem, refusal

        rel = path.relative_to(self.path).as_posix()
        return refusal(self, [Problem(path, f"a damaged file {rel} ({reason})", "quarantine",
                                      rel.rsplit("/", 1)[0], reason)])

    def check(self, parts: list[str] | None = None) -> dict | None:
        """Return the run's manifest after checking the run is what it says (None: no run).

        Layout, every file of ``parts`` (default all) verified in full, records of this run and
        config only, no trial twice, none missing (:mod:`graspcampaign.campaign.integrity`).

        Raises
        ------
        DamagedRunError
            Naming the run, the first offending file and what to do; nothing is changed.
        """
        from graspcampaign.campaign.integrity import check_run

        return check_run(self, parts)

    # -- reading --------------------------------------------------------------------------------
    @contextlib.contextmanager
    def _refusing(self, path: Path):
        """Turn :class:`~graspcampaign.campaign.verify.Damaged` for ``path`` into the run's
        DamagedRunError naming it."""
        try:
            yield
        except Damaged as exc:
            raise self._damage_error(path, str(exc)) from None

    def _live(self, part: str) -> list[Path]:
        """The live files of ``part`` (raises DamagedRunError for an unreadable compacted file)."""
        live, unreadable = self.listing(part)
        if unreadable:
            raise self._damage_error(*unreadable[0])
        return live

    def verified(self, part: str) -> dict[Path, Facts]:
        """The live files of ``part`` and their facts, each verified in full (raises
        DamagedRunError)."""
        out = {}
        for path in self._live(part):
            with self._refusing(path):
                out[path] = facts(path)
        return out

    def read(self, part: str = "records", columns: list[str] | None = None) -> pa.Table:
        """Read every live file of ``part`` into one table with the union of their schemas.

        Every file is verified in full first, whatever ``columns`` asks for (once per process,
        :func:`~graspcampaign.campaign.verify.read_file`); a column that some files lack is null
        there. Columns renamed since a file was written read under their current names
        (:mod:`graspcampaign.campaign.former_names`; ``columns`` names them so too).

        Raises
        ------
        DamagedRunError
            If a file of ``part`` is damaged (nothing is moved; see :meth:`repair`).
        """
        return self.read_with_facts(part, columns)[0]

    def read_records(self, manifest: dict, columns: list[str]) -> tuple[pa.Table, str]:
        """The records' ``columns`` (:meth:`read`) and the run's data source (:meth:`source`),
        from one listing of its files (raises DamagedRunError)."""
        table, read = self.read_with_facts("records", columns)
        return table, self.source(manifest, read.values())

    def read_with_facts(self, part: str, columns: list[str] | None) -> tuple[pa.Table, dict[Path, Facts]]:
        """:meth:`read`'s table and the files it was read from with their verified facts (sources,
        accounts), from one listing; each file's columns under their current names
        (:func:`~graspcampaign.campaign.former_names.current_names`). Raises as :meth:`read`."""
        names, read = self.former_names(part), []
        stored = columns if columns is None else [
            *columns, *(former for former, current in names.items() if current in columns)]
        for path in self._live(part):
            with self._refusing(path):
                table, own = read_file(path, stored)
                read.append((current_names(table, names), own, path))
        if not read:
            return pa.table({}), {}
        schema = pa.unify_schemas([table.schema.remove_metadata() for table, _, _ in read],
                                  promote_options="permissive")
        if columns is not None:
            schema = pa.schema([schema.field(c) for c in columns if c in schema.names])
        tables = []
        for table, _, _ in read:
            for field in schema:
                if field.name not in table.column_names:
                    table = table.append_column(field, pa.nulls(table.num_rows, field.type))
            tables.append(table.select(schema.names).replace_schema_metadata(None))
        return (pa.concat_tables(tables, promote_options="permissive").cast(schema),
                {path: own for _, own, path in read})

    def dataset(self, part: str = "records"):
        """Return a ``pyarrow.dataset.Dataset`` over the verified files of ``part`` (large runs).

        Filters and column selections are pushed down to the files; nothing is read until asked.
        """
        import pyarrow.dataset as ds

        live, former = self.verified(part), self.former_names(part)
        if any(name in own.schema.names for own in live.values() for name in former):
            return ds.dataset(self.read(part))  # stored before a rename: its columns renamed, in memory
        schema = pa.unify_schemas([own.schema.remove_metadata() for own in live.values()],
                                  promote_options="permissive") if live else pa.schema([])
        fmt = ds.ParquetFileFormat(default_fragment_scan_options=ds.ParquetFragmentScanOptions(
            page_checksum_verification=True))
        return ds.dataset([str(p) for p in live], schema=schema, format=fmt)

    def former_names(self, part: str = "records") -> dict[str, str]:
        """The former -> current column names of ``part`` of the run's trial kind (its manifest's;
        none without a manifest), :data:`~graspcampaign.campaign.former_names.FORMER_NAMES`."""
        from graspcampaign.campaign.provenance import read_manifest

        manifest = read_manifest(self.manifest_path)
        return renamed(manifest.get("kind") if manifest else None, part)

    def source(self, manifest: dict, records: Iterable[Facts] | None = None) -> str:
        """The data source of the run's records (SPEC §4): ``virtual`` as soon as one record says
        so, else the manifest's (``analysis.vocabulary.data_source``), from the sources each records
        file's verified facts hold (``records``: those of files already read, :meth:`read_with_facts`;
        default every live records file's): no column is read again."""
        records = self.verified("records").values() if records is None else records
        held = set().union(*(own.owners.get("source", ()) for own in records))
        return data_source(held, manifest.get("source"))

    def recorded_ids(self, part: str = "records") -> set[str]:
        """Return the trial ids stored in ``part`` (every file verified in full first)."""
        return set().union(*(own.ids for own in self.verified(part).values()))

    # -- maintenance ----------------------------------------------------------------------------
    def clean(self) -> None:
        """Remove temporary files and superseded files a crash may have left behind."""
        if not self.path.is_dir():
            return
        for tmp in self.path.rglob(".*.tmp"):
            tmp.unlink(missing_ok=True)
        for part in self.part_names(summaries=False):
            live, unreadable = self.listing(part)
            keep = {p.name for p in live} | {p.name for p, _ in unreadable}
            # only shards a compaction or rewrite superseded: any other file is quarantined
            for pattern in ("compact-*.parquet", "part-*.parquet"):
                for path in self.part_dir(part).glob(pattern):
                    if path.name not in keep and path.is_file():
                        path.unlink(missing_ok=True)

    def repair(self, manifest: dict | None = None, config_hash: str | None = None,
               design: set[str] | None = None) -> list[tuple[Path, Path, str]]:
        """Quarantine what makes the run differ from its manifest and make the rest consistent
        (:func:`graspcampaign.campaign.repair.repair`); return (file, moved to, reason)."""
        from graspcampaign.campaign.repair import repair

        return repair(self, manifest, config_hash, design)

    def _rewrite(self, path: Path, table: pa.Table, tag: Any, account: Account | None) -> None:
        """Replace ``path`` by ``table`` (read from it, with its metadata; ``account``: its
        facts') crash-safely: the new file supersedes the old one and whatever the old one
        superseded, so no crash in between can make a row count twice; it keeps the account of
        the trials it keeps."""
        if table.num_rows:
            meta = table.schema.metadata or {}
            sources = [path.name, *json.loads(meta.get(SOURCES_KEY) or b"[]")]
            name = f"compact-{content_hash([path.name, tag])}.parquet"
            table = table.replace_schema_metadata(
                {SOURCES_KEY: json.dumps(sources).encode(),
                 **({CONFIG_KEY: meta[CONFIG_KEY]} if CONFIG_KEY in meta else {})})
            _write_atomic(table, path.parent / name, account)
        path.unlink(missing_ok=True)

    def drop_rows(self, part: str, ids: set[str]) -> None:
        """Remove the rows of trials ``ids`` from every file of ``part``."""
        self._filter_rows(part, ids, keep=False)

    def keep_rows(self, part: str, ids: set[str]) -> None:
        """Keep only the rows of trials ``ids`` in every file of ``part``."""
        self._filter_rows(part, ids, keep=True)

    def _filter_rows(self, part: str, ids: set[str], keep: bool) -> None:
        """Keep only (``keep``) or remove the rows of trials ``ids`` in every file of ``part``;
        a verified file is read again only if its trial ids say that it changes, one not yet
        verified is read once."""
        import pyarrow.compute as pc

        value_set = pa.array(sorted(ids), pa.string())
        tag = ["keep", content_hash(sorted(ids))] if keep else ["drop", sorted(ids)]
        for path in self.listing(part)[0]:
            with self._refusing(path):
                known = cached(path)  # else the one full read that verifies it is its table
                table, own = (None, known) if known else read_file(path, again=True)
                if (own.ids <= ids and not own.n_null_ids) if keep else own.ids.isdisjoint(ids):
                    continue
                table = read_file(path, again=True)[0] if table is None else table
            rows = pc.is_in(table.column("trial_id"), value_set=value_set)
            self._rewrite(path, table.filter(rows if keep else pc.invert(rows)), tag, own.account)

    def compact(self, part: str = "records") -> None:
        """Merge the live part shards of ``part`` into one compacted file, crash-safely; records
        shards with an account and those without one (stored before it was kept) into one each.

        Every shard is verified in full again (:func:`~graspcampaign.campaign.verify.read_file`):
        a compacted file is never written from a shard that was not checked as it is read.
        """
        parts = [p for p in self.listing(part)[0] if p.name.startswith("part-")]
        if len(parts) < 2:
            return
        shards = []
        for path in parts:
            with self._refusing(path):
                shards.append((path, *read_file(path, again=True)))
        # merged into an account, a trial of a file without one would be accounted as having
        # stored nothing else (made up after the fact): its traces lost would never be named
        for group in ([s for s in shards if s[2].account is not None],
                      [s for s in shards if s[2].account is None]):
            if len(group) > 1:
                self._merge(part, group)

    def _merge(self, part: str, shards: list[tuple[Path, pa.Table, Facts]]) -> None:
        """Merge ``shards`` (path, table, facts) of ``part`` into one compacted file."""
        tables = [table for _, table, _ in shards]
        schema = pa.unify_schemas([t.schema.remove_metadata() for t in tables],
                                  promote_options="permissive")
        configs = sorted({h for t in tables for h in json.loads(
            (t.schema.metadata or {}).get(CONFIG_KEY) or b"[]")})
        merged = pa.concat_tables(
            [t.replace_schema_metadata(None) for t in tables], promote_options="permissive"
        ).cast(schema)
        names = sorted(path.name for path, _, _ in shards)
        merged = merged.replace_schema_metadata(
            {SOURCES_KEY: json.dumps(names).encode(),
             **({CONFIG_KEY: json.dumps(configs).encode()} if configs else {})})
        held = [own.account for _, _, own in shards if own.account is not None]
        _write_atomic(merged, self.part_dir(part) / f"compact-{content_hash(names)}.parquet",
                      merge(held) if held else None)
        for path, _, _ in shards:
            path.unlink(missing_ok=True)

    def compact_all(self) -> None:
        """Compact records, preparations and every trace table."""
        for part in self.part_names(summaries=False):
            self.compact(part)
