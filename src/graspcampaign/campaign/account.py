"""A records file's account of what its trials stored in the run's other parts: its one encoding
and its one decoding.

``run`` writes with each records file what each of its trials stored besides its record: its rows
in each trace table ``tables/<name>/`` and the ``body_id`` of the ``prepared/`` row it used
(:mod:`graspcampaign.campaign.parts` compares that with what is stored). The file's Parquet
key-value metadata holds it as JSON under ``graspcampaign.parts``
(:data:`~graspcampaign.campaign.verify.PARTS_KEY`), in one of two forms:

- version 2, written now: one entry per row of the file, in row order (the file's ``trial_id``
  column names the trials, so no trial id is written again), the body ids listed once::

      {"v": 2, "tables": {name: [rows of each row's trial in tables/<name>/]},
       "bodies": [body_id, ...], "body": [index in bodies of each row's preparation, or null]}

  a table no trial of the file stored rows in is not named, and ``bodies`` and ``body`` are left
  out where no trial used a preparation. It is stored once, in the file's key-value metadata, and
  not also in the Arrow schema that pyarrow stores beside it (``ARROW:schema``), which held a
  second copy of it;
- version 1, the mapping written before it (stored in both places)::

      {trial_id: {"tables": {name: rows > 0}, "body": body_id}}

  each key of an entry optional; read as it was (an entry of a trial the file does not record
  is no part of it).

:func:`encode` is the one writer of the value (``run``'s shards, a compaction, a rewrite),
:func:`decode` the one reader (a records file's verification,
:func:`graspcampaign.campaign.verify.read_file`); what lies between is an :class:`Account`.
Shape letters: n, the trials accounted for; r, the rows of a file.

References
----------
docs/records.md (the run's files), docs/decisions.md ("A records file's account is one entry
per row, stored once").
"""

from __future__ import annotations

import json
from collections.abc import Iterable
from dataclasses import dataclass
from typing import Any

from graspcampaign.core.words import counted

#: The version :func:`encode` writes.
VERSION = 2


class NotAnAccount(ValueError):
    """A value that is no account the tool writes; its text says how it differs."""


@dataclass(frozen=True)
class Account:
    """What the trials of one records file stored besides their records.

    trials : (n,) str
        The trials accounted for, in the file's row order.
    tables : dict of str to (n,) int
        By trace table name, each trial's rows in ``tables/<name>/`` (0: none); a table no trial
        stored rows in may be absent.
    bodies : (n,) str or None
        The ``body_id`` of each trial's preparation (None: it used none).
    """

    trials: tuple
    tables: dict
    bodies: tuple

    @classmethod
    def from_entries(cls, entries: dict[str, dict[str, Any]]) -> Account:
        """The account of trials ``entries`` (``{trial_id: {"tables": {name: rows}, "body":
        body_id}}``, each key optional, as :func:`graspcampaign.campaign.parts.entry` makes
        one), in their order."""
        trials = tuple(entries)
        names = sorted({name for stored in entries.values() for name in stored.get("tables", ())})
        tables = {name: tuple(stored.get("tables", _NONE).get(name, 0) for stored in entries.values())
                  for name in names}
        return cls(trials, tables, tuple(stored.get("body") for stored in entries.values()))

    def entries(self) -> dict[str, dict[str, Any]]:
        """Each trial's entry, as :meth:`from_entries` takes it (a table it stored no row in
        not named; ``{}``: it stored neither trace nor preparation)."""
        out: dict[str, dict[str, Any]] = {}
        for i, trial in enumerate(self.trials):
            rows = {name: counts[i] for name, counts in self.tables.items() if counts[i]}
            body = self.bodies[i]
            out[trial] = {**({"tables": rows} if rows else {}),
                          **({"body": body} if body is not None else {})}
        return out

    def traces(self) -> dict[str, dict[str, int]]:
        """By trace table, the trials that stored rows in it and how many (tables without any
        left out)."""
        out = {}
        for name, counts in self.tables.items():
            rows = {trial: n for trial, n in zip(self.trials, counts, strict=True) if n}
            if rows:
                out[name] = rows
        return out

    def used(self) -> dict[str, str]:
        """The body id of the preparation each trial used, of those that used one."""
        return {trial: body for trial, body in zip(self.trials, self.bodies, strict=True)
                if body is not None}

    def for_rows(self, ids: Iterable[str | None]) -> Account:
        """The account of a file whose rows record trials ``ids`` (in row order): each row takes
        the entry of its trial here, a trial not accounted for here none (it stored nothing
        besides its record)."""
        ids = tuple(ids)
        if ids == self.trials:
            return self
        at = {trial: i for i, trial in enumerate(self.trials)}
        where = [at.get(trial) for trial in ids]
        tables = {name: tuple(0 if i is None else counts[i] for i in where)
                  for name, counts in self.tables.items()}
        return Account(ids, tables, tuple(None if i is None else self.bodies[i] for i in where))


def merge(accounts: Iterable[Account]) -> Account:
    """One account of the trials of ``accounts`` (a compaction's files), one after another."""
    accounts = list(accounts)
    names = sorted({name for each in accounts for name in each.tables})
    return Account(
        tuple(t for each in accounts for t in each.trials),
        {name: tuple(n for each in accounts
                     for n in each.tables.get(name, (0,) * len(each.trials))) for name in names},
        tuple(b for each in accounts for b in each.bodies))


def encode(account: Account, ids: Iterable[str | None]) -> bytes:
    """The stored account (version 2) of a records file whose rows record trials ``ids``, in row
    order: each row takes the entry of its trial in ``account`` (:meth:`Account.for_rows`)."""
    rows = account.for_rows(ids)
    bodies = sorted({body for body in rows.bodies if body is not None})
    at = {body: i for i, body in enumerate(bodies)}
    value: dict[str, Any] = {"v": VERSION, "tables": {
        name: list(counts) for name, counts in rows.tables.items() if any(counts)}}
    if bodies:
        value.update(bodies=bodies, body=[at.get(body) for body in rows.bodies])
    return json.dumps(value, sort_keys=True, separators=(",", ":")).encode()


def decode(raw: bytes, ids: list[str | None], recorded: frozenset) -> Account:
    """The account stored as ``raw`` by a file whose rows record trials ``ids`` (row order; None
    where a row has no trial id), of the trials ``recorded`` (its distinct ids).

    Raises
    ------
    NotAnAccount
        How ``raw`` differs from what :func:`encode` (or, version 1, the release before it)
        writes: a check would else trust, or trip over, values the tool never writes.
    """
    try:
        value = json.loads(raw)
    except ValueError:
        raise NotAnAccount("it is not JSON") from None
    if not isinstance(value, dict):
        raise NotAnAccount("it is no mapping of trial ids")
    if "v" not in value:  # version 1: no trial id is "v" (verify.TRIAL_ID)
        return _of_entries(value, recorded)
    if type(value["v"]) is not int or value["v"] != VERSION:
        raise NotAnAccount(f"it is of version {json.dumps(value['v'])[:20]}, not {VERSION}")
    return _of_rows(value, ids)


def _of_rows(value: dict, ids: list[str | None]) -> Account:
    """The version 2 account ``value`` of a file whose rows record ``ids``."""
    n, other = len(ids), sorted(set(value) - {"v", "tables", "bodies", "body"})
    if other:
        raise NotAnAccount(f"it has a key {other[0]!r}, not one of v, tables, bodies and body")
    tables = value.get("tables", _NONE)
    if type(tables) is not dict:
        raise NotAnAccount(f"tables is {json.dumps(tables)[:40]}, not a mapping of trace table "
                           "names")
    for name, counts in tables.items():
        _check_rows(counts, n, f"table {name}", "a whole number of 0 or more", {int},
                    lambda c: c >= 0)
    if ("bodies" in value) != ("body" in value):
        raise NotAnAccount(f"it has {'bodies' if 'bodies' in value else 'body'} without "
                           f"{'body' if 'bodies' in value else 'bodies'}")
    bodies, index = value.get("bodies", []), value.get("body", [None] * n)
    if type(bodies) is not list or not all(type(b) is str for b in bodies):
        raise NotAnAccount(f"bodies is {json.dumps(bodies)[:40]}, not a list of body ids")
    _check_rows(index, n, "body", f"null or a place in its {counted(len(bodies), 'body', 'bodies')}",
                {int, type(None)}, lambda i: i is None or 0 <= i < len(bodies))
    at = {None: None, **dict(enumerate(bodies))}
    used = tuple(map(at.__getitem__, index))
    if None not in ids:
        return Account(tuple(ids), {name: tuple(c) for name, c in tables.items()}, used)
    keep = [i for i, trial in enumerate(ids) if trial is not None]  # a row without its trial
    return Account(tuple(ids[i] for i in keep),
                   {name: tuple(c[i] for i in keep) for name, c in tables.items()},
                   tuple(used[i] for i in keep))


def _check_rows(values: Any, n: int, what: str, each: str, kinds: set, fits) -> None:
    """Raise :class:`NotAnAccount` unless ``values`` is a list of ``n`` values, each of a type of
    ``kinds`` (compared exactly: a bool is no count) that ``fits`` (``what``: the name of the
    list, ``each``: what each value should be)."""
    if type(values) is not list:
        raise NotAnAccount(f"{what} is {json.dumps(values)[:40]}, not a list of one value per "
                           "row of the file")
    if len(values) != n:
        raise NotAnAccount(f"{what} has {counted(len(values), 'value')} for the file's "
                           f"{counted(n, 'row')}")
    # by the distinct types, then the distinct values (a list of a large run's 20,000 rows holds
    # a few), each made in C; the row is looked for only when one does not fit
    if set(map(type, values)) <= kinds and all(fits(v) for v in set(values)):
        return
    row = next(i for i, v in enumerate(values) if type(v) not in kinds or not fits(v))
    raise NotAnAccount(f"{what} has {json.dumps(values[row])[:20]} at row {row}, not {each}")


def _of_entries(value: dict, recorded: frozenset) -> Account:
    """The version 1 account ``value`` (``{trial_id: entry}``), of the trials ``recorded``."""
    trial = next((trial for trial, stored in value.items() if not _an_entry(stored)), None)
    if trial is not None:
        raise NotAnAccount(f"trial {trial} has {json.dumps(value[trial])[:80]}, not its rows per "
                           "trace table (whole numbers above 0) and the body id of its preparation")
    # a trial it does not record is no part of it (a rewrite kept the entries of the trials kept)
    return Account.from_entries(value if value.keys() <= recorded else {
        trial: stored for trial, stored in value.items() if trial in recorded})


def _an_entry(stored: Any) -> bool:
    """Whether ``stored`` is one trial's entry as version 1 wrote it (types compared exactly: one
    entry per trial of a run, 20,000 in a large one, each checked on every first read)."""
    if type(stored) is not dict or not stored.keys() <= _ENTRY_KEYS:
        return False
    tables = stored.get("tables", _NONE)
    if type(tables) is not dict or type(stored.get("body", "")) is not str:
        return False
    return all(type(n) is int and n > 0 for n in tables.values())


_ENTRY_KEYS, _NONE = frozenset({"tables", "body"}), {}
