"""Whether a run's stored files are what its manifest says: what commands trust, what `run` repairs.

:func:`graspcampaign.campaign.verify.verify_file` says one file is intact (every page read, its
checksums verified, its values against their digest). This module says the *run* is what its
manifest says, before anything counts or reports its records:

- its layout: the run directory, ``records/``, ``prepared/``, ``tables/<name>/`` and
  ``summary/<name>/`` are directories holding only Parquet shards (``part-*.parquet``,
  ``compact-*.parquet``; hidden temporary files aside), each intact;
- the manifest describes the run: its ``study`` and ``run`` are the directory's, its ``kind`` and
  ``study`` its config's, its ``config_hash`` the hash of its config, its ``source`` one its trial
  kind makes, and (a Cartesian design run under one config) it counts the trials stored;
- every record file is one the tool wrote: it has the columns every record has
  (:data:`RECORD_COLUMNS`) with their types, a ``status`` of :data:`STATUSES`, a well-formed
  ``trial_id`` on every row and, in a run that says so (``digests`` in the manifest), the digest of
  its values (checked by ``verify_file``);
- every record is the run's own: its ``study``, ``run``, ``kind`` and ``source`` are the
  manifest's, and the configs its shard was written under (``CONFIG_KEY`` in the shard's
  metadata) are ones the run ran with (and, for ``run``, its trial is in the design, as is every
  trial a trace file holds);
- no trial is recorded twice, in one records file or across files, no trial's traces are in
  two files of one trace table and no body's preparation in two files of ``prepared/``;
- no recorded trial went missing: the run stores at least the ``n_recorded`` trials its manifest
  counted when they were last written;
- no other part went missing: the traces, preparations and summary tables the run's records say
  it stored are there (:mod:`graspcampaign.campaign.parts`).

Reading never changes a run: :func:`check_run` raises :class:`DamagedRunError`, one sentence naming
the run, the first offending file and what to do. Only
:func:`graspcampaign.campaign.repair.repair`, called by the runner when a run starts or resumes,
changes it (and deletes no stored file). What cannot be repaired safely (a file in place of the run
directory, of ``tables/`` or of ``quarantine/``; a damaged or missing manifest) is refused.
"""

from __future__ import annotations

import json
import re
from dataclasses import dataclass
from pathlib import Path

import pyarrow as pa

from graspcampaign.campaign.parts import COMPLETE
from graspcampaign.campaign.paths import path_problem, run_command
from graspcampaign.campaign.provenance import (
    MISMATCH,
    ingested,
    kind_facts_or_none,
    one_config,
    overrides_given,
    read_manifest,
    record_sources,
    study_given,
)
from graspcampaign.campaign.records import OPTIONAL_COLUMNS, RECORD_COLUMNS
from graspcampaign.campaign.verify import Facts, facts, one_check, other_values
from graspcampaign.core.words import counted
from graspcampaign.errors import DamagedRunError, UserInputError

#: Names of stored shards, as the store writes them: "part-" and a content hash (10 hex digits,
#: ``grid.content_hash``: a task's trial ids, a body id) or "final", then a "-k" suffix where a
#: compacted file supersedes the name; "compact-" and a content hash. Anything else in a part
#: directory (hidden files aside) is not a shard, a copy of one under any sync tool's or file
#: manager's name ("compact-x (1).parquet", "part-x - Copy.parquet", OneDrive's "part-x-HOST.parquet")
#: neither.
SHARD = re.compile(r"(part-([0-9a-f]{10}|final)(-[1-9][0-9]*)?|compact-[0-9a-f]{10})\.parquet")
_PARTS = ("records", "prepared", "tables", "summary")
_HOLDS = {"text": lambda t: pa.types.is_string(t) or pa.types.is_large_string(t),
          "whole numbers": pa.types.is_integer,
          "numbers": lambda t: pa.types.is_integer(t) or pa.types.is_floating(t)}
#: A record's ``status`` (docs/records.md).
STATUSES = ("ok", "error")


@dataclass(frozen=True)
class Problem:
    """One way a run's stored files differ from what its manifest says.

    ``text`` completes "run S/R at P has ..."; ``reason`` is what the quarantine warning says.
    ``fix`` is what ``run`` does about it: "quarantine" (move the file aside; trials missing then
    run again), "duplicate" (move it aside; its trials stay recorded elsewhere), "missing" (run
    the missing trials again), "rerun" (drop the records of trials ``rerun`` whose traces are
    gone, so they run again), "recompute" (compute a preparation or summary table again) or
    "refuse".
    """

    path: Path
    text: str
    fix: str
    part: str = "records"
    reason: str = ""
    advice: str = ""
    #: trials recorded with other values in an earlier file: their records there go too
    conflicting: frozenset = frozenset()
    #: trials whose traces are gone (:mod:`graspcampaign.campaign.parts`): they run again
    rerun: frozenset = frozenset()


def _rel(store, path: Path) -> str:
    return path.relative_to(store.path).as_posix()


def _hidden(path: Path) -> bool:
    return path.name.startswith((".", "_"))


def layout_problems(store) -> list[Problem]:
    """Files where the run's directories belong, and entries of part directories that are not
    shards (a renamed or foreign file, a stray directory)."""
    out = []
    for name in ("quarantine", *_PARTS):
        where = store.path / name
        if where.exists() and not where.is_dir():
            fix = "refuse" if name in ("quarantine", "tables") else "quarantine"
            out.append(Problem(where, f"a file {name} where its {name} directory belongs", fix,
                               name, "a file where a directory belongs"))
        elif where.is_symlink() and not where.exists():  # every write there fails: never repaired
            out.append(Problem(where, f"{name}/, which {path_problem(where)}", "refuse", name,
                               "a symbolic link leading nowhere", "remove the link or make it lead "
                               "to a directory, then resume the run"))
    dirs = [store.path / p for p in ("records", "prepared")]
    for group in ("tables", "summary"):
        top = store.path / group
        for entry in sorted(top.iterdir()) if top.is_dir() else []:
            if entry.is_dir():
                dirs.append(entry)
            elif not _hidden(entry) and not (group == "summary" and entry.name == COMPLETE):
                out.append(Problem(entry, f"a file {_rel(store, entry)} that is not a directory "
                                          f"of {group}", "quarantine", group, "not a directory"))
    for directory in (d for d in dirs if d.is_dir()):
        for entry in sorted(directory.iterdir()):
            if SHARD.fullmatch(entry.name) and (what := path_problem(entry, directory=False)):
                out.append(Problem(entry, f"{_rel(store, entry)}, named as a shard, which {what}",
                                   "quarantine", _rel(store, directory), f"it {what}"))
            elif not _hidden(entry) and not SHARD.fullmatch(entry.name):
                copy = re.fullmatch(r"(part|compact)-.*\.parquet", entry.name)
                why = ("named as a copy of a shard: not a name the tool writes"
                       if copy else "not a Parquet shard of the run")
                out.append(Problem(entry, f"a file {_rel(store, entry)} "
                                          f"{why if copy else 'that is ' + why}", "quarantine",
                                   _rel(store, directory), why))
    return out


def _ids(path: Path) -> tuple[int, frozenset]:
    """The row count and the distinct ``trial_id`` values of a verified file."""
    own = facts(path)
    return own.n_rows, own.ids


def owners(store, manifest: dict | None, config_hash: str | None = None,
           design: set[str] | None = None) -> dict[str, set]:
    """The study and run names, trial kind, sources and config hashes the run's records may
    carry, whether its files must carry the digest of their values, and (``design``: the trial
    ids of a Cartesian design every session of the run ran) the trials they may record."""
    hashes = {config_hash} if config_hash else set()
    if manifest:
        hashes |= {manifest.get("config_hash")} | {s.get("config_hash") for s in
                                                   manifest.get("sessions") or []}
    source = manifest["source"] if manifest else None
    return {"study": {store.path.parent.name, *([manifest["study"]] if manifest else [])},
            "run": {store.path.name, *([manifest["run"]] if manifest else [])},
            "kind": {manifest["kind"]} if manifest else set(),
            "source": set() if source is None else record_sources(source),
            "config_hash": hashes - {None}, "digests": bool(manifest and manifest.get("digests")),
            "design": design or set()}


def _foreign(own: Facts, allowed: dict[str, set]) -> str | None:
    """Why the records of a file (its verified facts ``own``) are not the run's own (another
    study, run, kind, source or config; a trial not in the design), or None."""
    for column, values in own.owners.items():  # status: a vocabulary, not an owner
        other = sorted(values - allowed.get(column, set()) - {None}, key=str)
        if other and allowed.get(column):
            return f"records of another {column} ({other[0]})"
    other = sorted(own.config_hashes - allowed["config_hash"])
    if other and allowed["config_hash"]:
        return f"records run with another config (hash {other[0]}, not one this run ran with)"
    return _outside_design(own, allowed)


def _outside_design(own: Facts, allowed: dict[str, set], what: str = "records") -> str | None:
    """Why the ``what`` of a file (records, or a trace table's traces) are not the run's own as
    the design tells (a trial not in it), or None. A trace file says only its trials (a column
    named as an owner, ``kind``, may be a quantity of its own there): the design alone tells."""
    other = sorted(own.ids - allowed["design"])
    if other and allowed["design"]:
        return f"{what} of {counted(len(other), 'trial')} not in the study's design ({other[0]})"
    return None


def _not_records(own: Facts, allowed: dict) -> str | None:
    """Why a file (its verified facts ``own``) is not a records file the tool wrote (a column
    every record has missing or of another type, a status or trial id it never writes, no digest
    where the run has them), or None. Only for a run (a manifest)."""
    if not allowed["kind"]:
        return None
    for column, holds in [*RECORD_COLUMNS.items(), *OPTIONAL_COLUMNS.items()]:
        kind = own.schema.field(column).type if column in own.schema.names else None
        if kind is None:
            if column in RECORD_COLUMNS:
                return f"no column {column}, which every record has"
        elif not _HOLDS[holds](kind) and not (column in OPTIONAL_COLUMNS and pa.types.is_null(kind)):
            return f"column {column} of type {kind}, not {holds}"
    other = sorted(own.owners.get("status", set()) - set(STATUSES), key=str)
    if other:
        return f"status {other[0]!r}, not {' or '.join(STATUSES)}"
    if own.n_null_ids:
        return f"{counted(own.n_null_ids, 'record')} without a trial_id"
    if own.bad_id is not None:
        return (f"trial_id {own.bad_id!r}, which the tool never makes: its ids end in '-' and "
                "the 10-digit hash of the trial's factors")
    return None


def _no_digest(own: Facts, allowed: dict) -> str | None:
    if allowed["digests"] and not own.digest:
        return "no digest of its values, which every file of this run gets when it is written"
    return None


def file_problems(store, part: str, allowed: dict[str, set]) -> list[Problem]:
    """Damaged files of ``part``; in records also foreign files and files recording a trial
    twice; in records and trace tables trials, in ``prepared/`` bodies, stored in two files (the
    earlier file is kept: compacted files first, then shards, each by name; with other values,
    neither is trusted)."""
    out = [Problem(path, f"a damaged file {_rel(store, path)} ({why})", "quarantine", part, why)
           for path, why in store.damaged(part)]
    bad = {p.path for p in out}
    if part not in ("records", "prepared") and not part.startswith("tables/"):
        return out + [Problem(path, f"a file {_rel(store, path)} with {why}", "quarantine", part,
                              why) for path in store.listing(part)[0] if path not in bad
                      and (why := _no_digest(facts(path), allowed))]
    seen: dict[str, Path] = {}
    for path in (p for p in store.listing(part)[0] if p not in bad and SHARD.fullmatch(p.name)):
        rel, own = _rel(store, path), facts(path)  # one read of a file too new to be remembered
        unlike = _not_records(own, allowed) if part == "records" else None
        # a trace file of trials outside the design is moved aside as a records file is (its
        # rows were dropped as a crash's leftovers: the file gone without a word)
        foreign = (None if unlike or part == "prepared" else _foreign(own, allowed)
                   if part == "records" else _outside_design(own, allowed, "traces"))
        unlike = unlike or (None if foreign else _no_digest(own, allowed))
        if unlike or foreign:
            out.append(Problem(path, f"a file {rel} with {unlike}" if unlike else
                               f"a file {rel} holding {foreign}", "quarantine", part,
                               unlike or foreign))
            continue
        n, unique = own.n_rows, own.ids if part != "prepared" else own.bodies
        if part == "records" and len(unique) < n:
            said = f"records {counted(n - len(unique), 'trial')} twice"
            out.append(Problem(path, f"a file {rel} that {said}", "quarantine", part, f"it {said}"))
            continue
        twice = unique & seen.keys()
        # a trace file or preparation of the same trials or bodies with other values (another
        # run's): neither is trusted
        key = "body_id" if part == "prepared" else "trial_id"
        other = other_values(path, {seen[t] for t in twice}, twice, key) if twice else None
        if other and part == "prepared":  # both moved aside: each body is computed again
            for file, also in ((path, other[0]), (other[0], path)):
                if any(named.path == file for named in out):  # the earlier file, by a third copy
                    continue
                why = (f"{counted(len(twice), 'preparation')} of bodies also in {_rel(store, also)} "
                       f"with other values (column {other[1]})")
                out.append(Problem(file, f"a file {_rel(store, file)} holding {why}", "recompute",
                                   part, why))
            continue
        if other:
            why = (f"{counted(len(twice), 'trial')} also in {_rel(store, other[0])} with other "
                   f"values (column {other[1]})")
            held = "recording" if part == "records" else "holding the traces of"
            out.append(Problem(path, f"a file {rel} {held} {why}", "quarantine", part, why,
                               conflicting=frozenset(twice)))
            continue
        if twice:
            first = _rel(store, seen[min(twice)])
            each = "preparation" if part == "prepared" else "trial"
            scope = f"every {each}" if twice == unique else \
                f"{len(twice)} of its {counted(len(unique), each)}"
            why = f"{scope} also in {first}"
            out.append(Problem(path, f"a duplicate file {rel} ({why})",
                               "duplicate" if twice == unique else "quarantine", part, why))
            continue
        seen.update(dict.fromkeys(unique, path))
    return out


def expected_records(manifest: dict) -> int:
    """How many trials the manifest says are stored at least (0 if it cannot tell)."""
    if "n_recorded" in manifest:
        return manifest["n_recorded"]
    # a manifest of an earlier version: a run finished under one config recorded every trial
    return manifest["n_trials"] if manifest["finished_at"] and one_config(manifest) else 0


def problems(store, manifest: dict | None, parts: list[str] | None = None, *,
             accounts: bool = True) -> list[Problem]:
    """Every problem of the run's ``parts`` (default: all), layout first; reads only.
    ``accounts``: with what the records' accounts say is stored but is gone
    (:func:`~graspcampaign.campaign.parts.part_problems`, which asks it of a run whose records
    are whole)."""
    found = [p for p in layout_problems(store)
             if parts is None or p.fix == "refuse" or p.part in parts]
    flagged = {p.path for p in found}
    allowed = owners(store, manifest)
    for part in (p for p in store.part_names() if parts is None or p in parts):
        found += [p for p in file_problems(store, part, allowed) if p.path not in flagged]
    # trials missing besides those of a records file named above (they run again with it)
    if manifest is not None and (parts is None or "records" in parts) and not any(
            p.part == "records" for p in found):
        stored = set().union(*(_ids(path)[1] for path in store.listing("records")[0]))
        want = expected_records(manifest)
        if len(stored) < want:
            records = store.path / "records"
            empty = "" if stored else " (records/ is missing)" if not records.is_dir() else \
                " (records/ is empty)"
            found.append(Problem(records, f"missing records: its manifest counts {want} recorded "
                                          f"trials but {len(stored)} are stored{empty}", "missing"))
        elif counted := _miscounted(manifest, len(stored)):
            found.append(Problem(store.manifest_path, MISMATCH.format(counted), "refuse",
                                 advice="restore the file from a backup"))
    if accounts and manifest is not None and not found and (parts is None or "records" in parts):
        from graspcampaign.campaign.parts import part_problems  # it names Problem

        found += part_problems(store, full=parts is None, manifest=manifest)
    return found


def _cartesian(kind: str) -> bool:
    """Whether trial kind ``kind`` has a Cartesian design (False: an explicit one, or unknown)."""
    return kind_facts_or_none(kind).get("design") is False


def _miscounted(manifest: dict, n_stored: int) -> str | None:
    """Why the manifest's ``n_trials`` cannot be the run's, or None: a Cartesian design run under
    one config stores at most ``n_trials`` trials, and exactly that many once finished (an
    explicit design may grow with its source, ``dynamic_check``; another config has another)."""
    if not (one_config(manifest) and _cartesian(manifest["kind"])):
        return None
    n = manifest["n_trials"]
    if n_stored > n or (manifest["finished_at"] and n_stored != n):
        return (f"n_trials is {n}, but {'the finished run stores' if n_stored < n else 'it stores'} "
                f"{n_stored} trials of its one config")
    return None


def _advice(store, problem: Problem, manifest: dict | None) -> str:
    """What to do about ``problem`` of the run ``store``: ingest's remedies for an ingested run,
    else the command that resumes this run (:func:`~graspcampaign.campaign.paths.run_command`:
    with the overrides its manifest keeps, which `run` needs to take it as the same config)."""
    run, root = store.path.name, store.path.parent.parent
    study = study_given(manifest, store.path.parent.name)  # a study file given by path: that path
    by_ingest = isinstance(manifest, dict) and ingested(manifest)
    if problem.advice:
        return problem.advice
    if problem.fix == "refuse":
        return "move it aside, then resume the run"
    if by_ingest:  # run would refuse to add to it: the files are ingested again
        if problem.fix == "missing":
            return ("restore the records from a backup, or move the run directory aside and ingest "
                    "every file again")
        if problem.text.startswith("a damaged file records/"):
            return "move it out of the run directory and ingest the file that held its records again"
        return "move it out of the run directory"
    resume = f"resume the run ({run_command(study, overrides_given(manifest) or [], run, root)}) to"
    return {"duplicate": f"{resume} quarantine the duplicate",
            "missing": f"{resume} run the missing trials again",
            "rerun": f"{resume} run those trials again",
            "recompute": f"{resume} compute it again"}.get(
                problem.fix, f"{resume} quarantine the file and run its trials again")


def refusal(store, found: list[Problem], manifest: dict | None = None) -> DamagedRunError:
    """The one sentence for a run with ``found`` problems: the first named, the others counted."""
    if manifest is None:
        try:  # a partial manifest is enough to choose the advice
            manifest = json.loads(store.manifest_path.read_text())
        except (OSError, ValueError):
            manifest = None
    n = len(found) - 1
    more = f" (and {counted(n, 'more problem')})" if n else ""
    return DamagedRunError(f"run {store.path.parent.name}/{store.path.name} at {store.path} has "
                           f"{found[0].text}{more}; {_advice(store, found[0], manifest)}.",
                           f"has {found[0].text}{more}")


def check_place(store) -> None:
    """Refuse a run whose directory, or its study's, cannot be one: a file in its place, or a
    symbolic link leading nowhere (its run said "no run" and advised the `run` that then failed to
    make it, for ever); checked by :func:`check_run`, and by `ingest` before it holds the run.

    Raises
    ------
    DamagedRunError
        Naming the run, what is in its place and what to do; nothing is changed.
    """
    label = f"run {store.path.parent.name}/{store.path.name} at {store.path}"
    study = store.path.parent
    if study.exists() and not study.is_dir():  # "run it first" then failed to write, for ever
        raise DamagedRunError(f"{label} cannot be stored: {study} is a file, not the study's "
                              "directory; move it aside.", "lies in a file, not a study directory")
    if store.path.exists() and not store.path.is_dir():
        raise DamagedRunError(f"{label} is a file, not a run directory; move it aside or choose "
                              "another run name (--run NAME).", "is a file, not a run directory")
    if (why := path_problem(store.path)) is not None:  # a symbolic link leading nowhere, its own
        own = why.startswith("is ")  # or (its parent) the study's
        raise DamagedRunError(f"{label} cannot be stored: {'it ' * own}{why}; remove the link"
                              f"{' or choose another run name (--run NAME)' * own}.", why)


@one_check()
def check_run(store, parts: list[str] | None = None, *, repairable: bool = False) -> dict | None:
    """Return the run's manifest after checking that the run is what it says; None if no run.

    ``parts``: the parts to check (default all; ``status`` and ``show`` check ``["records"]``).
    ``repairable``: refuse only what :func:`repair` cannot fix (the runner's check).

    Raises
    ------
    DamagedRunError
        The run cannot be trusted as stored; nothing is changed.
    """
    check_place(store)
    label = f"run {store.path.parent.name}/{store.path.name} at {store.path}"
    manifest = read_manifest(store.manifest_path)
    if manifest is None:
        if any(_holds_files(store.path / p) for p in _PARTS):
            raise DamagedRunError(
                f"{label} has stored files but no manifest.json, so what they hold cannot be "
                "checked; restore the file from a backup, or move the run directory aside and run "
                "the study again.", "has stored files but no manifest.json")
        return None
    # what repair cannot fix is in the layout or the manifest's count, which needs the records
    # checked (no other part can make it refuse); what the accounts say is gone, repair mends
    # (its recount asks it once, of every file verified in full)
    found = problems(store, manifest, ["records"] if repairable else parts,
                     accounts=not repairable)
    found = [p for p in found if not repairable or p.fix == "refuse"]
    if found:
        raise refusal(store, found, manifest)
    return manifest


def _holds_files(path: Path) -> bool:
    if path.is_file():
        return True
    return path.is_dir() and any(p.is_file() for p in path.rglob("*") if not _hidden(p))


def nothing_to_record(store, manifest: dict | None, config_hash: str, trial_ids: set[str]) -> bool:
    """Whether a run has nothing left to record: finished under this config alone (its manifest),
    passing its checks (nothing to repair), holding every trial of ``trial_ids``."""
    if manifest is None or manifest.get("finished_at") is None or not one_config(manifest, config_hash):
        return False
    try:
        check_run(store)
    except UserInputError:  # damaged, or a file this user may not read: not known complete
        return False
    return trial_ids <= store.recorded_ids()
