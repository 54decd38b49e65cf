"""One stored file verified: every page read with its checksum, its values against their digest.

A file is read in full and hashed once per process while it is unchanged (its path, inode, size,
mtime and ctime): what the run checks need of it (:class:`Facts`: its schema and metadata, its
trial ids, the owners of its records) is kept from that one read, and any later read of the same
file reads only the columns asked for. A file changed since is verified again, and so is a file
changed within a clock tick of its verification (git's "racily clean" rule: a change in the same
tick could leave its key as it was) and a file read in full to be rewritten under a new digest.
One check of a run (:func:`one_check`) reads each file once, however new: the tick rule applies
between checks.
"""

from __future__ import annotations

import contextlib
import hashlib
import json
import os
import time
from dataclasses import dataclass
from pathlib import Path

import numpy as np
import pyarrow as pa
import pyarrow.compute as pc
import pyarrow.parquet as pq

from graspcampaign.campaign.account import Account, NotAnAccount, decode
from graspcampaign.errors import UserInputError, access_denied

SOURCES_KEY = b"graspcampaign.sources"
#: Metadata of a records file: the config hashes of the sessions that wrote its rows (a shard of
#: another config is not the run's, campaign.integrity), kept through compactions and rewrites.
CONFIG_KEY = b"graspcampaign.config_hashes"
#: Metadata of every file the tool writes: the SHA-256 of its values (:func:`content_digest`).
CONTENT_KEY = b"graspcampaign.content_sha256"
#: Metadata of a records file written by ``run``: what each of its trials stored in the run's
#: other parts (its trace rows per table, its preparation), :mod:`graspcampaign.campaign.parts`;
#: in the file's key-value metadata alone (:mod:`graspcampaign.campaign.account`).
PARTS_KEY = b"graspcampaign.parts"
# What pyarrow raises for a file it cannot read (bad footer, bad page, failed checksum, bad codec).
READ_ERRORS = (pa.ArrowException, OSError, ValueError, EOFError)
#: A trial id as ``grid.expand`` makes it: a readable key, "-", the 10-digit hash of the factors.
TRIAL_ID = r"^.+-[0-9a-f]{10}$"
_OWNERS = ("study", "run", "kind", "source", "status")
#: A verified file is remembered only if its last change (mtime, ctime) precedes the read by more
#: than this [ns], by whether its timestamps are whole seconds: FAT keeps 2 s ones, ext3 and HFS+
#: 1 s; finer ones may lag the change by a tick of the kernel's coarse clock (up to 10 ms).
TICK_NS = {True: 2 * 10**9, False: 50 * 10**6}


class Damaged(Exception):
    """A file that cannot be trusted; its text says why."""


#: pyarrow's words for a file that is no whole Parquet file (by how they start), in plain words
_NOT_PARQUET = "it does not end with a Parquet footer: cut short, or not a Parquet file"
_ARROW_WORDS = (("Parquet file size is 0 bytes", "it is empty"),
                ("Parquet magic bytes not found", _NOT_PARQUET), ("Parquet file size is", _NOT_PARQUET),
                ("Couldn't deserialize thrift", "its Parquet structure cannot be decoded: damaged, or "
                                                "not a Parquet file"))


def reason(exc: BaseException) -> str:
    """Why a file could not be read: the first line of ``exc``'s text (at most 120 characters),
    in plain words where pyarrow's are known (:data:`_ARROW_WORDS`)."""
    text = str(exc).strip().splitlines()[0] if str(exc).strip() else type(exc).__name__
    known = next((words for start, words in _ARROW_WORDS if text.startswith(start)), None)
    return known or (text if len(text) <= 120 else text[:117] + "...")


def content_digest(table: pa.Table) -> str:
    """The SHA-256 of ``table``'s values: every column (by name) as its kind (integer, float,
    boolean, text, other), its null mask and its values in a fixed byte form, so that the digest
    is the same for the table written and the table read back, whatever the chunking, column
    order or integer width; any changed, removed or added row, column or value changes it."""
    digest = hashlib.sha256()
    for name in sorted(table.column_names):
        column = table.column(name).combine_chunks()
        kind = column.type
        valid = _values(column.is_valid(), pa.uint8(), "u1") if column.null_count else \
            np.ones(len(column), dtype="u1")
        if pa.types.is_integer(kind) or pa.types.is_floating(kind) or pa.types.is_boolean(kind):
            tag, width, dtype = ("i", pa.int64(), "<i8") if pa.types.is_integer(kind) else (
                ("f", pa.float64(), "<f8") if pa.types.is_floating(kind) else ("b", pa.uint8(), "u1"))
            data = _values(column, width, dtype, valid).tobytes()
        else:  # text and anything else, as JSON (nulls are in the mask)
            tag = "n" if pa.types.is_null(kind) else "s" if (
                pa.types.is_string(kind) or pa.types.is_large_string(kind)) else "j"
            data = json.dumps(column.to_pylist(), default=str).encode()
        for part in (name.encode(), tag.encode(), len(column).to_bytes(8, "little"),
                     np.packbits(valid).tobytes(), len(data).to_bytes(8, "little"), data):
            digest.update(part)
    return digest.hexdigest()


def _values(array: pa.Array, width: pa.DataType, dtype: str,
            valid: np.ndarray | None = None) -> np.ndarray:
    """The values of ``array`` cast to ``width`` as numpy ``dtype``, 0 where ``valid`` is 0 (read
    from the Arrow buffer: ``to_numpy`` and ``fill_null`` import pandas, which ``status`` never
    needs)."""
    array = array.cast(width, safe=False)
    data = array.buffers()[1]
    if data is None:
        return np.zeros(len(array), dtype=dtype)
    out = np.frombuffer(data, dtype=dtype, count=len(array),
                        offset=array.offset * np.dtype(dtype).itemsize)
    if array.null_count:
        out = np.where(valid.astype(bool), out, np.zeros(1, dtype=dtype))
    return out


@dataclass(frozen=True)
class Facts:
    """What the run checks need of a verified file: its schema (with its metadata), its rows with
    a ``trial_id`` column (0 without one), distinct ``trial_id`` values (a trace table holds many
    rows per trial: made distinct in Arrow, not in Python), the ``study``/``run``/``kind``/
    ``source``/``status`` values, the rows without a trial id and the first malformed one; a
    records file's account of the run's other parts, a file of preparations' body ids."""

    schema: pa.Schema
    n_rows: int
    ids: frozenset
    owners: dict
    n_null_ids: int = 0
    bad_id: str | None = None
    #: What each trial of a records file stored in the run's other parts (``PARTS_KEY``,
    #: :mod:`graspcampaign.campaign.account`), read once, when the file is verified
    #: (:func:`account_of`); None: a file written before this was kept (by ``run``, or
    #: ``ingest`` before it kept one too)
    account: Account | None = None
    #: the rows of each trial where some trial has more than one (a trace table's), else None
    counts: dict | None = None
    #: the distinct ``body_id`` values of a file without a ``trial_id`` column (preparations')
    bodies: frozenset = frozenset()

    def rows_of(self) -> dict:
        """The rows the file holds of each trial it holds."""
        return dict.fromkeys(self.ids, 1) if self.counts is None else self.counts

    @property
    def config_hashes(self) -> frozenset:
        """The configs of the sessions that wrote its records (``CONFIG_KEY``)."""
        return frozenset(_listed(self.schema, CONFIG_KEY))

    @property
    def digest(self) -> bool:
        """Whether it carries the digest of its values."""
        return CONTENT_KEY in (self.schema.metadata or {})


def _listed(schema: pa.Schema, key: bytes) -> list:
    raw = (schema.metadata or {}).get(key)
    return json.loads(raw) if raw else []


def supersedes(path: Path) -> list[str]:
    """The names of the files ``path`` supersedes (``SOURCES_KEY``): from its facts (the file is
    verified if it was not yet), or, if it is damaged, from its footer (raises one of
    :data:`READ_ERRORS` if that cannot be read either)."""
    try:
        schema = facts(path).schema
    except Damaged:
        schema = pq.read_schema(path)
    return _listed(schema, SOURCES_KEY)


def account_of(raw: bytes | None, ids: list, recorded: frozenset) -> Account | None:
    """The account stored as ``raw`` (``PARTS_KEY``, :mod:`graspcampaign.campaign.account`) by a
    file whose rows record trials ``ids`` (row order), of the trials ``recorded``, or None if it
    has none; raises :class:`Damaged` saying how it differs from what ``run`` writes (a check
    would else trust, or trip over, values the tool never writes)."""
    if raw is None:
        return None
    try:
        return decode(raw, ids, recorded)
    except NotAnAccount as exc:
        raise Damaged("its account of the run's other parts, metadata graspcampaign.parts, is "
                      f"not one the tool writes: {exc}") from None


def _facts(table: pa.Table, account: bytes | None) -> Facts:
    """The facts of ``table``, read from a file whose key-value metadata holds ``account``
    (``PARTS_KEY``, None if it has none)."""
    ids = table.column("trial_id") if "trial_id" in table.column_names else None
    owners = {c: set(_unique(table, c).to_pylist()) for c in _OWNERS if c in table.column_names}
    if ids is None:
        account_of(account, [None] * table.num_rows, frozenset())
        bodies = frozenset(_unique(table, "body_id").to_pylist()) if (
            "body_id" in table.column_names) else frozenset()
        return Facts(table.schema, 0, frozenset(), owners, bodies=bodies)
    unique = _unique(table, "trial_id").drop_null()
    bad = None
    if pa.types.is_string(ids.type):  # the first malformed id: unique keeps the order of rows
        wrong = unique.filter(pc.invert(pc.match_substring_regex(unique, TRIAL_ID)))
        bad = wrong[0].as_py() if len(wrong) else None
    known = frozenset(unique.to_pylist())
    counts = None
    if len(known) < len(ids) - ids.null_count:  # a trace table's: its rows per trial
        tally = pc.value_counts(ids.combine_chunks().drop_null())
        counts = dict(zip(tally.field("values").to_pylist(), tally.field("counts").to_pylist(),
                          strict=True))
    return Facts(table.schema, len(ids), known, owners, ids.null_count, bad,
                 account_of(account, ids.to_pylist() if account else [], known), counts)


def _unique(table: pa.Table, name: str) -> pa.Array:
    """The distinct values of column ``name`` (raises :class:`Damaged` naming a column of lists
    or structs: no record holds one there)."""
    try:
        return pc.unique(table.column(name))
    except READ_ERRORS:
        raise Damaged(f"its {name} column holds values of type {table.column(name).type}, "
                      "not text") from None


_VERIFIED: dict[str, tuple[tuple, Facts]] = {}
"""The files verified in this process: by absolute path, the key of the version verified (inode,
size, mtime, ctime: a file replaced, or rewritten with its old mtime set back, is another key, as
``os.utime`` sets no ctime) and its facts. Storing a new version of a path evicts the old one."""


def _key(stat: os.stat_result) -> tuple:
    return stat.st_ino, stat.st_size, stat.st_mtime_ns, stat.st_ctime_ns


_CHECK: dict[str, tuple[tuple, Facts]] | None = None
"""The files verified in the check under way (:func:`one_check`), as :data:`_VERIFIED`, including
those too new to be remembered past it."""


@contextlib.contextmanager
def one_check():
    """Within it, a file is verified once while its key is unchanged, even one changed within a
    clock tick of the read (never remembered past the check): one check asks a file several
    questions (damaged? superseding what? whose records? which trials?) of one reading of it."""
    global _CHECK
    outer = _CHECK
    _CHECK = {} if outer is None else outer
    try:
        yield
    finally:
        _CHECK = outer


def cached(path: Path) -> Facts | None:
    """The facts of ``path`` if it was verified in this process (or this check) as it is now,
    else None."""
    name = os.path.abspath(path)
    try:
        key = _key(os.stat(path))
    except OSError:
        return None
    for known in (_VERIFIED.get(name), (_CHECK or {}).get(name)):
        if known is not None and known[0] == key:
            return known[1]
    return None


def read_file(path: Path, columns: list[str] | None = None, *,
              again: bool = False) -> tuple[pa.Table, Facts]:
    """The columns of ``path`` (default all; those it lacks are left out) and its facts.

    The first read of the file as it is now (:data:`_VERIFIED`) reads every column of every page
    with page checksums verified and checks its values against the digest stored with them (a
    file the tool wrote; older files have none); later reads read only ``columns``, unless
    ``again``: a table read to be rewritten under a new digest (compaction, removing rows) is
    verified whatever this process knows of it, so that no value changed since it was verified
    gets a digest of its own. The file is opened once: what is read is the version keyed, and
    only by this thread (no pre-buffering, no threads: arrow's workers holding buffers of the
    Python file could free them after the interpreter began to exit, which aborted the process).
    It is remembered as verified only if it did not change during the read nor within a clock
    tick (:data:`TICK_NS`) before it.

    Raises
    ------
    Damaged
        Why the file cannot be trusted (first line of pyarrow's error).
    UserInputError
        The file's permissions keep this process out (:func:`~graspcampaign.errors.access_denied`):
        it is not damaged, so it is neither quarantined nor are its trials run again.
    """
    name, start = os.path.abspath(path), time.time_ns()
    try:
        with open(path, "rb") as handle:
            key = _key(os.fstat(handle.fileno()))
            file = pq.ParquetFile(handle, page_checksum_verification=True, pre_buffer=False)
            known = _VERIFIED.pop(name, (None, None))  # put back if verified
            if known[0] == key and not again:
                _VERIFIED[name] = known
                return file.read(columns=_present(columns, known[1].schema), use_threads=False), known[1]
            table = file.read(use_threads=False)
            # the account is in the file's key-value metadata, not (version 2) the Arrow schema's
            account = (file.metadata.metadata or {}).get(PARTS_KEY)
            settled = _key(os.fstat(handle.fileno())) == key
        written = (table.schema.metadata or {}).get(CONTENT_KEY)
        if written is not None and written.decode(errors="replace") != content_digest(table):
            raise Damaged("its values differ from those written: their SHA-256 is not the one "
                          "stored with them")
        own = _facts(table, account)
    except PermissionError as exc:  # an intact file this user may not open is no damage
        raise UserInputError(access_denied(exc)) from None
    except READ_ERRORS as exc:
        raise Damaged(reason(exc)) from None
    changed = max(key[2:])
    if settled and changed < start - TICK_NS[changed % 10**9 == 0]:
        _VERIFIED[name] = key, own
    elif settled and _CHECK is not None:
        _CHECK[name] = key, own
    return table.select(_present(columns, table.schema)), own


def _present(columns: list[str] | None, schema: pa.Schema) -> list[str]:
    return schema.names if columns is None else [c for c in columns if c in schema.names]


def shards(directory: Path, pattern: str) -> list[Path]:
    """The regular files of ``directory`` matching ``pattern``, sorted: those a read may open (a
    named pipe named as a shard blocked every command reading the run for ever, a directory failed
    it; :func:`~graspcampaign.campaign.integrity.layout_problems` names them)."""
    return sorted(path for path in directory.glob(pattern) if path.is_file())


def verify_file(path: Path) -> str | None:
    """Why ``path`` cannot be trusted (:func:`read_file`), or None if it is intact."""
    try:
        facts(path)
    except Damaged as exc:
        return str(exc)
    return None


def facts(path: Path) -> Facts:
    """The facts of ``path``, verified (raises :class:`Damaged`)."""
    return cached(path) or read_file(path, [])[1]


#: What a record says of where and how long it ran, not of its trial (docs/records.md).
EXECUTION_COLUMNS = ("wall_time_s", "worker", "host")


def other_values(path: Path, earlier: set[Path], ids: set[str],
                 key: str = "trial_id") -> tuple[Path, str] | None:
    """The first of the ``earlier`` files and column where the records of trials ``ids`` in it
    and in ``path`` differ (every column but :data:`EXECUTION_COLUMNS`, one only in one of them
    too), or None: the same trial recorded twice with other values. ``key``: the column naming
    what ``ids`` are (``body_id`` for preparations)."""

    def rows(table: pa.Table, keep: pa.Array) -> pa.Table:
        return table.filter(pc.is_in(table.column(key), value_set=keep)).sort_by(key)

    own = read_file(path)[0]  # read once, compared with each earlier file
    for file in sorted(earlier):
        theirs = rows(read_file(file)[0], pa.array(sorted(ids), pa.string()))
        mine = rows(own, theirs.column(key).combine_chunks())
        shared = set(mine.column_names) & set(theirs.column_names)
        differ = (set(mine.column_names) ^ set(theirs.column_names)) | {
            n for n in shared if content_digest(mine.select([n])) != content_digest(theirs.select([n]))}
        differ -= set(EXECUTION_COLUMNS)
        if differ:
            return file, min(differ)
    return None
