"""What a run stores besides its records, and whether all of it is still there.

Besides ``records/`` a run stores a trial's per-step traces in ``tables/<name>/``, the shared
preparation of a body (e.g. a PSO identification) in ``prepared/`` and, once every trial is
recorded, its study-level tables in ``summary/<name>/``. A file or a directory of those parts that
goes missing (deleted by hand, lost in a copy) leaves every remaining file intact, so no check of
one file can see it; the report would then silently lack those rows. So the run keeps account:

- each records file written by ``run`` (or ``ingest``: its trials store nothing else) says in
  its Parquet metadata (``PARTS_KEY``), per trial, how many rows it stored in each trace table and
  the ``body_id`` of the preparation it used (row by row, :mod:`graspcampaign.campaign.account`);
  compaction merges the accounts, a rewrite keeps those of the trials it keeps
  (:mod:`graspcampaign.campaign.records`);
- ``summary/complete.json`` lists, besides every table ``finalize`` returned (``tables``), those
  it stored rows of (``written``).

:func:`part_problems` compares the two with what is stored: a trial whose trace rows are gone
(a whole table, or one file of it), a body whose preparation is gone, a summary table that was
written and is gone. A records file without an account (stored before it was kept) and a
``complete.json`` without ``written`` are read as before: nothing is asked of them
(docs/decisions.md, "A run keeps account of its other parts"); :func:`unaccounted` says which
trials ``status`` therefore cannot answer for.
"""

from __future__ import annotations

import contextlib
import json
import time
from collections import Counter
from pathlib import Path
from typing import Any

import pyarrow.parquet as pq

from graspcampaign.campaign import provenance
from graspcampaign.campaign.account import Account
from graspcampaign.campaign.grid import content_hash, stream_key
from graspcampaign.campaign.verify import READ_ERRORS, SOURCES_KEY, facts, shards
from graspcampaign.core.words import counted

COMPLETE = "complete.json"


def entry(rows: dict[str, int], body: str | None) -> dict[str, Any]:
    """One trial's entry of a records file's account (:meth:`Account.from_entries`): its rows
    per trace table (those it stored rows in) and the body id of its preparation (if it used
    one)."""
    return {**({"tables": rows} if rows else {}), **({"body": body} if body is not None else {})}


def _accounts(store) -> list[Account]:
    """The accounts of every live records file that has one (verified files: their facts)."""
    return [own.account for own in map(facts, store.listing("records")[0])
            if own.account is not None]


def part_problems(store, full: bool = True, manifest: dict | None = None) -> list:
    """What the run's accounts say is stored but is not: trace rows of recorded trials,
    preparations of the bodies they used, summary tables ``finalize`` wrote.

    ``full`` (``run``, ``report``): each trial's trace rows and the body ids stored, every file
    verified in full, against those accounted for, naming the first that differs. Else
    (``status``, which reads no more than the records): a part's directory missing, or its files'
    footers counting fewer rows than accounted for; files that are damaged are the full check's.
    Both: a finished run of a kind with a finalize stage (``manifest``: read if not given)
    without ``complete.json``.
    """
    from graspcampaign.campaign.integrity import Problem

    tables: dict[str, dict[str, int]] = {}
    bodies: set[str] = set()
    for held in _accounts(store):
        for name, rows in held.traces().items():
            tables.setdefault(name, {}).update(rows)
        bodies.update(held.used().values())
    out = []
    for name, rows in sorted(tables.items()):
        part = f"tables/{name}"
        trials = counted(len(rows), "recorded trial")
        if not (store.path / part).is_dir():
            what, gone = f"no {part} directory, where {trials} stored traces", sorted(rows)
        elif full:
            held: Counter = Counter()
            for path in store.listing(part)[0]:
                held.update(facts(path).rows_of())
            gone = sorted(trial for trial, n in rows.items() if held[trial] != n)
            what = "" if not gone else (
                f"{part} without the traces of {counted(len(gone), 'recorded trial')} "
                f"(first {gone[0]})" if not any(held[t] for t in gone) else
                f"{part} with other trace rows than {counted(len(gone), 'recorded trial')} stored "
                f"(first {gone[0]}: {held[gone[0]]} where it stored {rows[gone[0]]})")
        else:
            n, want, gone = _footer_rows(store.path / part), sum(rows.values()), []
            what = (f"{part} with {counted(n, 'trace row')} where {trials} stored {want}"
                    if n is not None and n < want else "")
        if what:
            out.append(Problem(store.path / part, what, "rerun", part, what, rerun=frozenset(gone)))
    where, used = store.path / "prepared", counted(len(bodies), "body", "bodies")
    if bodies and not where.is_dir():
        what = (f"no prepared directory, which holds the preparations of the {used} its recorded "
                "trials used")
    elif bodies and full:
        gone = sorted(bodies - _body_ids(store))
        what = (f"prepared without {counted(len(gone), 'preparation')} its recorded trials used "
                f"(first body {gone[0]})") if gone else ""
    else:
        n = _footer_rows(where) if bodies else None
        what = (f"prepared with {counted(n, 'preparation')} where its recorded trials used {used}"
                if n is not None and n < len(bodies) else "")
    if what:
        out.append(Problem(where, what, "recompute", "prepared", what))
    done = store.path / "summary" / COMPLETE
    manifest = provenance.read_manifest(store.manifest_path) if manifest is None else manifest
    if (manifest or {}).get("finished_at") and not done.is_file() and not provenance.ingested(
            manifest) and provenance.kind_facts_or_none(manifest["kind"]).get("finalize"):
        what = (f"no summary/{COMPLETE}, which a finished run of {manifest['kind']} stores when it "
                "computes its summary tables")
        out.append(Problem(done, what, "recompute", "summary", what))
    for name in _written(store):
        part = f"summary/{name}"
        stored = store.listing(part)[0] if full else shards(store.path / part, "*.parquet")
        if not stored:
            what = f"no {part} table, which summary/{COMPLETE} says was stored"
            out.append(Problem(store.path / part, what, "recompute", part, what))
    return out


def unaccounted(store, manifest: dict, records: dict) -> str | None:
    """Why a lost trace file or preparation of some recorded trials cannot be named: their records
    files (of ``records``, the run's live ones and their facts) were stored before runs kept the
    account (none of an ingested run's: ``ingest`` stores nothing besides records), as a clause
    completing "…; " of ``status``'s ``checked``; None if every records file has its account. No
    account is made up for them after the fact."""
    bare = {path: own for path, own in records.items() if own.account is None}
    if not bare or provenance.ingested(manifest):
        return None
    first = min(bare).relative_to(store.path).as_posix()
    files = first if len(bare) == 1 else f"{counted(len(bare), 'records file')}, first {first},"
    n = sum(len(own.ids) for own in bare.values())
    return (f"the traces and preparations of {counted(n, 'recorded trial')} are not accounted "
            f"({files} stored before runs kept that account), so one of theirs lost cannot be "
            "named")


def _body_ids(store) -> set[str]:
    """The body ids of the run's stored preparations (its files verified in full: their
    facts)."""
    return set().union(*(own.bodies for own in store.verified("prepared").values()))


def _footer_rows(directory: Path) -> int | None:
    """The rows of the live Parquet files in ``directory`` by their footers alone (those a
    compacted file supersedes left out); None if a footer cannot be read (a damaged file is the
    full check's to name)."""
    footers = {}
    for path in shards(directory, "*.parquet"):
        try:
            footers[path.name] = pq.read_metadata(path)
        except READ_ERRORS:
            return None
    superseded = {name for meta in footers.values()
                  for name in json.loads((meta.metadata or {}).get(SOURCES_KEY) or b"[]")}
    return sum(meta.num_rows for name, meta in footers.items() if name not in superseded)


def _written(store) -> list[str]:
    """The summary tables ``finalize`` stored rows of (``written`` in ``complete.json``; none for
    one written before it was kept, or unreadable: what that means is the layout check's)."""
    done_file = store.path / "summary" / COMPLETE
    try:  # no regular file (a named pipe, whose read waits for ever): as one that cannot be read
        done = json.loads(done_file.read_text()) if done_file.is_file() else None
    except (OSError, ValueError):
        return []
    written = done.get("written") if isinstance(done, dict) else None
    return [str(name) for name in written] if isinstance(written, list) else []


# -- computing them (the runner) ----------------------------------------------------------------
def run_prepare(kind, study, params: Any, body: dict[str, Any]) -> dict[str, Any]:
    """Compute one shared preparation (e.g. an identification) for a body."""
    import numpy as np

    rng = np.random.default_rng(
        np.random.SeedSequence(study.seed, spawn_key=stream_key({"prepare": body}))
    )
    start = time.perf_counter()
    out = kind.prepare(study, params, body, rng)
    return {"body_id": content_hash(body), **body, **out,
            "wall_time_s": time.perf_counter() - start}


def prepare_bodies(kind, study, params, trials, store, map_unordered, summary) -> dict[str, Any]:
    """Compute (or read back) the shared preparation of every body the trials need and of every
    body a recorded trial used (seeded by the body alone, so one computed again is the one the
    recorded trials used): a drifted run's recorded trials outside its design keep theirs."""
    if kind.body_key is None or kind.prepare is None:
        return {}
    bodies = {content_hash(body): body for body in (kind.body_key(t.factors) for t in trials)}
    stored = store.read("prepared").to_pylist()
    have = {row["body_id"]: row for row in stored}
    bodies.update(_recorded_bodies(kind, store, trials, set(have) | set(bodies)))
    missing = [b for h, b in bodies.items() if h not in have]
    for row in map_unordered(run_prepare, [(kind, study, params, b) for b in missing]):
        store.write_shard("prepared", row["body_id"], [row])
        have[row["body_id"]] = row
        summary.n_prepared += 1
    return {h: have[h] for h in bodies}


def check_preparations(store, manifest: dict, study) -> None:
    """Refuse a session (``study``, its config) whose settings a preparation depends on (all but
    the design's: :func:`~graspcampaign.campaign.provenance.preparation_hash`) are not those of
    every session of the run, when preparations its recorded trials used are gone or damaged:
    computed again they would be this session's (a PSO identification under other ``pso.*``
    settings), not the ones those trials used, and no file says which session computed each. A
    preparation is gone too where the repair will move its file aside (damaged, a copy's name,
    another file holding the body with other values: both moved). A drift of the design alone
    computes them as they were. Changes nothing.

    Raises
    ------
    DriftError
        Naming the first body, what changed and the command that computes them as they were
        (the run resumed as started, where its sessions so far ran its first settings), or a
        new run.
    """
    from graspcampaign.campaign.integrity import file_problems, layout_problems, owners
    from graspcampaign.campaign.verify import verify_file

    first, now = (provenance.preparation_hash(config) for config in
                  (manifest["config"], provenance.study_dict(study)))
    ran = {s.get("preparation_hash") or (first if s.get("config_hash") == manifest["config_hash"]
                                         else None) for s in manifest["sessions"]}
    if ran <= {now}:  # a session stored before sessions kept it: of the first config's hash
        return

    records = [facts(path) for path in store.listing("records")[0] if verify_file(path) is None]
    used = {body for own in records if own.account is not None
            for body in own.account.used().values()}
    # the files of prepared/ the repair keeps (a duplicate's bodies stay in the file it copies)
    aside = {p.path for p in [*layout_problems(store),
                              *file_problems(store, "prepared", owners(store, manifest))]}
    kept = [facts(path) for path in store.listing("prepared")[0] if path not in aside]
    gone = sorted(used - set().union(*(own.bodies for own in kept)))
    if not gone:
        return
    if ran == {first}:
        changed = provenance.config_changes(manifest["config"], study,
                                            free=provenance.PREPARATION_FREE)
        why = f"they were computed with the settings the run was started with ({', '.join(changed)})"
        resume = provenance.as_started(manifest, study, store.path).rstrip(", ")
        then = f"{resume} to compute them again as they were, or " if resume else ""
    else:
        why, then = "its sessions ran more than one config, and which computed each is not kept", ""
    raise provenance.DriftError(
        f"run {store.path.parent.name}/{store.path.name} at {store.path} has lost "
        f"{counted(len(gone), 'preparation')} its recorded trials used (first body {gone[0]}), "
        f"which this session cannot compute again as they were: {why}; {then}start a new run "
        "for this config (output.run=NAME or --run NAME).")


def _recorded_bodies(kind, store, trials, known: set[str]) -> dict[str, dict[str, Any]]:
    """``{body_id: body}`` of the bodies recorded trials used (their accounts) that are not
    ``known``: the body of a trial's factors read back from its record (its factors are columns
    of it, beside its outputs: those of the design's factors, or of the run's first config, whose
    body hashes to the id its account names). One that none does (a level stored as another
    number type) is refused naming what computes it: the config whose design holds it."""
    used = {trial: body for held in _accounts(store) for trial, body in held.used().items()
            if body not in known}
    if not used:
        return {}
    from graspcampaign.errors import DamagedRunError

    first = (provenance.read_manifest(store.manifest_path) or {}).get("config") or {}
    names = {frozenset(t.factors) for t in trials} | {frozenset(first.get("factors") or {})}
    out = {}
    for row in (r for r in store.read().to_pylist() if r["trial_id"] in used):
        for keys in names:
            with contextlib.suppress(KeyError):  # a factor this trial was not run with
                body = kind.body_key({k: row[k] for k in keys if k in row})
                if content_hash(body) == used[row["trial_id"]]:
                    out[used[row["trial_id"]]] = body
    lost = sorted(set(used.values()) - set(out))
    if lost:
        raise DamagedRunError(
            f"run {store.path.parent.name}/{store.path.name} at {store.path} has prepared without "
            f"{counted(len(lost), 'preparation')} its recorded trials outside this design used "
            f"(first body {lost[0]}), which cannot be told from their records; run it with the "
            "config that recorded them (without --allow-drift) to compute them again.",
            f"has prepared without {counted(len(lost), 'preparation')}")
    return out


def finalize(kind, study, params: Any, store) -> None:
    """Compute the study-level tables once all trials are recorded (skipped if stored) and store
    those not stored yet: a table moved aside or gone is stored again, the others stay as they
    are (computed from the same records)."""
    done = store.path / "summary" / COMPLETE
    if done.exists():
        return
    records = store.read().to_pandas()
    tables = kind.finalize(study, params, records, store)
    for name, rows in tables.items():
        if rows and not store.listing(f"summary/{name}")[0]:
            store.write_shard(f"summary/{name}", "final", rows)
    provenance.write_manifest(done, {"tables": sorted(tables), "at": provenance.now_utc(),
                                     "written": sorted(name for name, rows in tables.items() if rows)})
