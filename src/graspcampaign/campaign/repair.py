"""What ``run`` changes of a run before it runs: what makes it differ from its manifest moved aside.

:func:`graspcampaign.campaign.integrity.check_run` says whether a run is what its manifest says and
never changes it; :func:`repair`, called by the runner when a run starts or resumes, makes it so.
It deletes no stored file: a damaged file, a file that is not a shard, a shard of another run or
config and a duplicate shard are moved to ``quarantine/``, and the trials whose records are then
missing run again (a duplicate's trials stay recorded in the shard it duplicates); the trials whose
traces are gone (:mod:`graspcampaign.campaign.parts`) have their records dropped and run again.
"""

from __future__ import annotations

import contextlib
import logging
import os
import warnings
from pathlib import Path

import pyarrow.parquet as pq

from graspcampaign.campaign.integrity import SHARD, file_problems, layout_problems, owners
from graspcampaign.campaign.parts import COMPLETE, part_problems
from graspcampaign.campaign.verify import facts, one_check, verify_file
from graspcampaign.errors import StoreWriteError

log = logging.getLogger(__name__)

#: What happens to the trials of a file moved aside, by the part it was in.
_THEN = {"records": "its trials no longer recorded will run again",
         "tables": "its trials no longer recorded will run again",
         "prepared": "it is computed again", "summary": "it is computed again"}


def _trials_of_trace(store, path: Path) -> set[str]:
    """The trials whose traces a trace file moved aside held: from its key pages, else from the
    records file of the same task, else every recorded trial (the caller keeps those with a row in
    the table's other files; re-running a trial that had none costs time, never a wrong record)."""
    try:  # not a regular file (a named pipe would block the read): from the records file
        if path.is_file():
            return set(pq.read_table(path, columns=["trial_id"],
                                     page_checksum_verification=True).column("trial_id").to_pylist())
    except Exception:  # noqa: BLE001 - pyarrow raises several types for a damaged or foreign file
        pass
    twin = store.path / "records" / path.name  # a task's traces and records share its name
    if twin.is_file() and SHARD.fullmatch(twin.name) and verify_file(twin) is None:
        return facts(twin).ids
    return store.recorded_ids()


def _quarantine(store, path: Path, reason: str, what: str, then: str) -> Path:
    """Move ``path`` to ``quarantine/``, never over an earlier quarantined file, and warn:
    "<what> <path> moved to <target> (<reason>); <then>". A rename, never a copy: a copy left
    beside a file that could not be removed would count twice; what cannot be moved is refused,
    nothing moved or made."""
    directory = store.part_dir("quarantine")
    stem = path.relative_to(store.path).as_posix().replace("/", "__")
    target, k, made = directory / stem, 1, not directory.exists()
    while target.exists():
        base, dot, suffix = stem.rpartition(".")
        target = directory / (f"{base}~{k}.{suffix}" if dot else f"{stem}~{k}")
        k += 1
    try:
        directory.mkdir(parents=True, exist_ok=True)
        os.rename(path, target)
    except OSError as exc:
        if made:
            with contextlib.suppress(OSError):
                directory.rmdir()
        raise StoreWriteError(f"cannot move {path} to {target} ({reason}): "
                              f"{os.strerror(exc.errno).lower()}; it stays where it is, so make "
                              f"{path.parent} and {directory} writable and run the command "
                              "again.") from None
    warnings.warn(f"{what} {path} moved to {target} ({reason}); {then}", stacklevel=3)
    log.warning("quarantined %s as %s: %s", path, target, reason)
    return target


@one_check()
def repair(store, manifest: dict | None = None, config_hash: str | None = None,
           design: set[str] | None = None) -> list[tuple[Path, Path, str]]:
    """Quarantine what makes the run differ from its manifest and make the rest consistent.

    - a records file that is damaged, foreign, not a shard or records a trial twice: moved
      aside; its trials are no longer recorded, so they run again; a duplicate records file:
      moved aside, its trials stay recorded in the file it duplicates;
    - the same in a trace table (``tables/``), and the records of the trials it held are dropped
      so that they run again with their traces (an exact duplicate drops nothing);
    - trace rows of a trial that has no record are dropped;
    - a preparation moved aside is recomputed; a summary table once every trial is recorded;
    - what the records' accounts say is stored but is gone (:func:`_recount`): the records of
      trials whose traces are gone are dropped so that they run again; a summary table gone is
      computed again, a preparation gone is computed by the runner.

    ``config_hash`` is the config of the session about to run (its shards are the run's own);
    ``design`` the trial ids of its design when every session ran it (a file recording another
    trial is not the run's).
    What :func:`check_run` refuses is left to it (the runner calls it first).

    Returns
    -------
    list of (file, quarantined as, reason), and (part, part, what is gone) for a part that lost
    what the records' accounts say it stored
    """
    moved: list[tuple[Path, Path, str]] = []
    lost: set[str] = set()
    for _ in range(10):  # moving a file aside can make superseded shards live again: look again
        allowed = owners(store, manifest, config_hash, design)
        found = [p for p in layout_problems(store) if p.fix != "refuse"]
        flagged = {p.path for p in found}
        for part in store.part_names():
            found += [p for p in file_problems(store, part, allowed) if p.path not in flagged]
        if not found:
            break
        aside = {p.path for p in found}
        for problem in found:
            group = problem.part.split("/")[0]
            if group == "tables" and problem.fix != "duplicate" and problem.part != "tables":
                others = [p for p in store.listing(problem.part)[0] if p not in aside]
                # trials whose traces another file of the table holds (a copy's) lost none
                lost |= _trials_of_trace(store, problem.path) - set().union(
                    *(facts(other).ids for other in others))
            if group == "summary":
                (store.path / "summary" / COMPLETE).unlink(missing_ok=True)
            what = {"duplicate": "duplicate file"}.get(
                problem.fix, "damaged file" if problem.text.startswith("a damaged") else "file")
            kept = "its preparations stay in " if group == "prepared" else \
                "its trials stay recorded in "
            then = (kept + problem.reason.split(" also in ")[-1]
                    if problem.fix == "duplicate" else "it held no part of the run"
                    if problem.part in ("tables", "summary") else _THEN[group])
            target = _quarantine(store, problem.path, problem.reason, what, then)
            lost |= problem.conflicting  # neither record of a trial recorded twice is trusted
            moved.append((problem.path, target, problem.reason))
    moved += _recount(store, lost, {p.relative_to(store.path).parent.as_posix() for p, _, _ in moved})
    if not moved and not (store.path / "tables").is_dir():
        return moved
    if lost:
        store.drop_rows("records", lost)
    recorded = store.recorded_ids()
    for part in store.part_names(summaries=False):
        if part.startswith("tables/"):
            store.keep_rows(part, recorded)
    return moved


def _recount(store, lost: set[str], aside: set[str]) -> list[tuple[Path, Path, str]]:
    """What the run's accounts say is stored but is gone (:func:`~graspcampaign.campaign.parts.
    part_problems`), made good: the trials whose traces are gone join ``lost`` (their records are
    dropped, so they run again), a summary table gone is computed again with the others not stored
    (a preparation gone is computed again by the runner anyway). Returns (part, part, what is
    gone) for each, with a warning; none for a part a file was moved ``aside`` from (its warning
    said what happens)."""
    out = []
    for problem in part_problems(store):
        rerun = problem.rerun - lost  # those of a file moved aside above were named with it
        if not rerun if problem.fix == "rerun" else problem.part in aside:
            continue
        lost |= rerun
        if problem.part.startswith("summary/"):
            (store.path / "summary" / COMPLETE).unlink(missing_ok=True)
        then = "those trials run again" if rerun else "it is computed again"
        warnings.warn(f"run {store.path.parent.name}/{store.path.name} at {store.path} has "
                      f"{problem.text}; {then}", stacklevel=3)
        out.append((problem.path, problem.path, problem.reason))
    return out
