"""Run a study: fan trials out over cores (joblib loky) or a Dask cluster, record, resume.

Trials are grouped into tasks of about ``runner.target_task_s`` seconds of compute (SPEC Sec. 5);
each finished task becomes one atomic Parquet shard, so a run killed at any moment resumes with no
trial lost or duplicated. A trial's record never depends on the backend, the worker count, the
order or a resume: its random stream comes from the study seed and its own scene (grid.py).
"""

from __future__ import annotations

import contextlib
import math
import os
import socket
import sys
import time
import traceback
import warnings
from collections.abc import Iterator
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any

from omegaconf import OmegaConf

from graspcampaign.campaign import provenance
from graspcampaign.campaign.account import Account
from graspcampaign.campaign.grid import Trial, content_hash, expand
from graspcampaign.campaign.integrity import check_run, expected_records, nothing_to_record
from graspcampaign.campaign.kind import TrialInput, TrialKind, get_kind
from graspcampaign.campaign.parts import check_preparations, entry, finalize, prepare_bodies
from graspcampaign.campaign.paths import (
    LOCK_FILE,
    check_case_twin,
    check_root,
    lock_exclusive,
    run_path,
    write_denied,
)
from graspcampaign.campaign.provenance import DriftError, check_drift  # noqa: F401 - DriftError: API
from graspcampaign.campaign.records import ERROR_COLUMNS, RunStore, config_metadata
from graspcampaign.campaign.schema import StudyCfg, check_config, check_design_rows
from graspcampaign.campaign.verify import one_check
from graspcampaign.core.words import PERMISSION_DENIED
from graspcampaign.errors import ConfigError, UserInputError


@dataclass
class RunSummary:
    """What a call to :func:`run_study` did."""

    study: str
    run: str
    path: Path
    n_trials: int
    n_already: int = 0
    n_ran: int = 0
    n_ok: int = 0
    n_error: int = 0
    n_prepared: int = 0
    stopped_early: bool = False
    first_error: str | None = None
    wall_time_s: float = 0.0
    errors: list[str] = field(default_factory=list)


def kind_params(study: StudyCfg, kind: TrialKind) -> Any:
    """Validate ``study.params`` against the kind's schema and return the params object."""
    if kind.params is None:
        if study.params:
            raise ConfigError(
                f"params.{next(iter(study.params))} is not a parameter of trial kind "
                f"{kind.name!r}, which takes none."
            )
        return {}
    from graspcampaign.campaign.compose import omegaconf_error_sentence

    try:
        merged = OmegaConf.merge(OmegaConf.structured(kind.params), study.params)
        obj = OmegaConf.to_object(merged)
    except Exception as exc:  # OmegaConf raises several unrelated types
        raise ConfigError(omegaconf_error_sentence(exc, prefix="params.")) from None
    check_config(obj, prefix="params.")
    return obj


def study_trials(study: StudyCfg, kind: TrialKind, params: Any) -> list[Trial]:
    """Return the study's trials: its Cartesian design, or the kind's explicit design.

    Raises
    ------
    ConfigError
        An explicit design (computed from ``params``) holding a physically impossible factor
        value (a known factor out of its plausible range, ``schema.FACTOR_SPECS``).
    """
    if kind.design is None:
        return expand(study, None)
    rows = kind.design(study, params)
    check_design_rows(rows)
    return expand(study, rows)


# -- the work one task does (runs in a worker process) -----------------------------------------
def _error_fields(exc: BaseException) -> dict[str, Any]:
    message = str(exc).strip().splitlines()[0] if str(exc).strip() else type(exc).__name__
    return {"status": "error", "error_type": type(exc).__name__, "error_message": message,
            "error_traceback": "".join(traceback.format_exception(exc))[-4000:]}


def run_task(kind: TrialKind, study: StudyCfg, run: str, params: Any,
             items: list[tuple[Trial, dict[str, Any] | None]], fail_fast: bool):
    """Run a batch of trials; return their record rows, trace-table rows and what each stored
    besides its record (:func:`~graspcampaign.campaign.parts.entry`)."""
    host, worker = socket.gethostname(), f"pid{os.getpid()}"
    rows: list[dict[str, Any]] = []
    tables: dict[str, list[dict[str, Any]]] = {}
    accounts: dict[str, dict[str, Any]] = {}
    for trial, prepared in items:
        row: dict[str, Any] = {
            "trial_id": trial.trial_id, "study": study.name, "run": run, "kind": kind.name,
            "trial_index": trial.index, "scene_id": trial.scene_id, "status": "ok",
            "error_type": None, "error_message": None, "error_traceback": None, "wall_time_s": None,
            "worker": worker, "host": host, "source": kind.source,
        }
        row.update(trial.factors)
        start, traced = time.perf_counter(), {}
        try:
            out = dict(kind.run(TrialInput(trial, study, params, prepared), trial.rng(study.seed)))
            for name, columns in out.pop("__tables__", {}).items():
                n = len(next(iter(columns.values()))) if columns else 0
                traced.update({name: n} if n else {})
                tables.setdefault(name, []).extend(
                    {"trial_id": trial.trial_id, **{c: v[i] for c, v in columns.items()}}
                    for i in range(n)
                )
            clash = set(out) & set(row)
            if clash:
                raise RuntimeError(f"trial kind output overwrites input columns {sorted(clash)}")
            row.update(out)
        except Exception as exc:  # a failing trial becomes an error record; the campaign goes on
            row.update(_error_fields(exc))
        row["wall_time_s"] = time.perf_counter() - start
        rows.append(row)
        accounts[trial.trial_id] = entry(traced, prepared["body_id"] if prepared else None)
        if fail_fast and row["status"] == "error":
            break
    return rows, tables, accounts


# -- backends -----------------------------------------------------------------------------------
@contextlib.contextmanager
def _executor(study: StudyCfg):
    """Yield ``map_unordered(fn, arg_tuples) -> iterator`` for the configured backend."""
    backend = study.runner.backend
    if backend == "sequential" or (backend == "loky" and study.runner.workers() == 1):
        yield lambda fn, args: (fn(*a) for a in args)
        return
    from joblib import Parallel, delayed, parallel_config

    if backend == "loky":
        with parallel_config(backend="loky", n_jobs=study.runner.n_jobs):
            yield lambda fn, args: Parallel(return_as="generator_unordered")(
                delayed(fn)(*a) for a in args
            )
        return
    try:
        from dask.distributed import Client, LocalCluster
    except ImportError:
        raise UserInputError(
            "runner.backend=dask needs the dask extra: pip install 'graspcampaign[dask]'."
        ) from None
    cluster = None
    if study.runner.address:
        client = _connect(Client, study.runner.address, study.runner.connect_timeout_s)
    else:
        cluster = LocalCluster(n_workers=study.runner.workers(), threads_per_worker=1, processes=True,
                               dashboard_address=None, host="127.0.0.1")
        client = Client(cluster)
    try:
        with parallel_config(backend="dask"):
            yield lambda fn, args: Parallel(n_jobs=-1, return_as="generator_unordered")(
                delayed(fn)(*a) for a in args
            )
    finally:
        client.close()
        if cluster is not None:
            cluster.close()


def _connect(client_type: type, address: str, timeout_s: float):
    """Connect to a Dask scheduler, or say in one sentence that none answers (the address's
    form is checked with the config, ``schema.check_study``; the handshake within the timeout by
    ``scheduler.check_scheduler``, since the client waits for it without one)."""
    from graspcampaign.campaign.scheduler import check_scheduler

    check_scheduler(address, timeout_s)
    try:
        return client_type(address, timeout=timeout_s)
    except (OSError, TimeoutError) as exc:
        raise UserInputError(
            f"runner.address = {address!r}: no Dask scheduler answered within {timeout_s:g} s "
            f"({type(exc).__name__}); start one (dask scheduler) or drop runner.address to run "
            "on a local cluster."
        ) from None


def _chunks(items: list, size: int) -> Iterator[list]:
    for i in range(0, len(items), size):
        yield items[i : i + size]


def task_size(study: StudyCfg, kind: TrialKind, n_pending: int) -> int:
    """Trials per task: ~target_task_s of compute, but enough tasks to balance the workers."""
    if study.runner.batch_size:
        return study.runner.batch_size
    by_time = max(1, round(study.runner.target_task_s / max(kind.seconds_per_trial, 1e-6)))
    balance = max(1, math.ceil(n_pending / (4 * study.runner.workers())))
    return max(1, min(by_time, balance))


# -- the campaign -------------------------------------------------------------------------------
class _Progress:
    """Progress of a run: a bar on a terminal, else one line at most every ``interval_s``.

    Without a terminal (make, CI, a batch job) a bar would print nothing useful; a line with
    done/total, failures, rate and ETA every ``interval_s`` keeps the log short and alive.
    """

    def __init__(self, total: int, done: int, enabled: bool, label: str, interval_s: float = 30.0):
        self.total, self.done, self.failed, self.label = total, done, 0, label
        self.bar = enabled and sys.stderr.isatty()
        self.lines = enabled and not self.bar
        self.interval_s = interval_s
        self._t0 = self._last = time.perf_counter()
        self._done0 = done
        if not self.bar:
            return
        from rich.progress import (
            BarColumn,
            MofNCompleteColumn,
            Progress,
            TextColumn,
            TimeElapsedColumn,
            TimeRemainingColumn,
        )

        self._bar = Progress(TextColumn("{task.description}"), BarColumn(), MofNCompleteColumn(),
                             TextColumn("failed {task.fields[failed]}"),
                             TextColumn("{task.fields[rate]}"), TimeElapsedColumn(),
                             TextColumn("ETA"), TimeRemainingColumn(), transient=False)
        self._bar.start()
        self._task = self._bar.add_task(label, total=total, completed=done, failed=0, rate="")

    def _rate(self) -> float:
        return (self.done - self._done0) / max(time.perf_counter() - self._t0, 1e-9)

    def advance(self, n: int, failed: int) -> None:
        self.done += n
        self.failed += failed
        if self.bar:
            self._bar.advance(self._task, n)
            self._bar.update(self._task, failed=self.failed, rate=f"{self._rate():.1f} trials/s")
        elif self.lines and (time.perf_counter() - self._last >= self.interval_s
                             or self.done >= self.total):
            self._last = time.perf_counter()
            self.print_line()

    def print_line(self) -> None:
        rate = self._rate()
        eta = (self.total - self.done) / rate if rate > 0 else math.inf
        eta_text = f"{eta:.0f} s" if math.isfinite(eta) else "unknown"
        print(f"{self.label}: {self.done}/{self.total} trials ({100 * self.done / max(self.total, 1):.0f}%), "
              f"{self.failed} failed, {rate:.1f} trials/s, ETA {eta_text}", file=sys.stderr,
              flush=True)

    def close(self) -> None:
        if self.bar:
            self._bar.stop()


def run_study(study: StudyCfg, *, run: str | None = None, allow_drift: bool = False,
              fail_fast: bool = False, progress: bool | None = None,
              given: tuple[str, list[str]] | None = None) -> RunSummary:
    """Run every trial of ``study`` not yet recorded in its run directory.

    ``given``, the study and overrides as the command line gave them, goes into a new run's
    manifest with the design they change (:func:`~graspcampaign.campaign.compose.as_given`).

    Nothing is written before the run can start: the results root, the run's manifest and the
    layout of its files are checked, the run is locked and the backend is up (a Dask scheduler
    answered), first; a refused run leaves no directory of its own behind.
    Then what makes the run differ from its manifest is quarantined (``campaign.integrity``)
    and the trials not recorded run.

    Raises
    ------
    StudyNotRunnableError
        If the study's trial kind is not implemented (nothing is written).
    DriftError
        If the run exists with a different resolved config or code version.
    DamagedRunError
        If the run cannot be repaired safely (a damaged or missing manifest, a file in place of
        the run directory); nothing is written.
    """
    check_root(study.output.root, "output.root", write=True)
    kind = get_kind(study.kind)
    params = kind_params(study, kind)
    run = study.output.run if run is None else run
    trials = study_trials(study, kind, params)
    path = run_path(study, run)
    check_case_twin(path, f"{study.name}/{run}")
    store = RunStore(path)
    _checked_manifest(store, study, run, allow_drift)
    show = study.runner.progress if progress is None else progress
    t0 = time.perf_counter()

    with contextlib.ExitStack() as held:
        # held first: a run held elsewhere is refused before a Dask cluster starts or is awaited;
        # the lock removes the directories it made if the backend is refused
        held.enter_context(run_lock(store, f"{study.name}/{run}"))
        # read (again) under the lock: another run of it may have written since the check above
        manifest = _checked_manifest(store, study, run, allow_drift)
        chash = provenance.config_hash(study, manifest)
        # a finished run this user may not write (another's): nothing to run, nothing written
        if (denied := unwritable(store, f"{study.name}/{run}")) and nothing_to_record(
                store, manifest, chash, {t.trial_id for t in trials}):
            return RunSummary(study.name, run, path, len(trials), n_already=len(trials))
        if denied:
            raise UserInputError(denied)
        map_unordered = held.enter_context(_executor(study))  # no cluster started for a refused run
        session = {"started_at": provenance.now_utc(), "host": socket.gethostname(),
                   "backend": study.runner.backend, "n_jobs": study.runner.n_jobs,
                   "config_hash": chash, "n_trials": len(trials), "finished_at": None,
                   "preparation_hash": provenance.preparation_hash(provenance.study_dict(study))}
        expected = expected_records(manifest) if manifest is not None else 0
        if manifest is None:
            from graspcampaign.campaign.compose import as_given

            manifest = provenance.new_manifest(study, run, len(trials), kind.source)
            manifest.update(as_given(*given, study) if given else {})
        # a file that differs from the manifest is moved aside before anything in it counts as
        # recorded; only then are superseded shards removed (a foreign file supersedes nothing).
        # Every session so far ran this config and the design is Cartesian: a recorded trial
        # outside it is no trial of this run (an explicit design may follow its source run)
        same = provenance.one_config(manifest, chash) and kind.design is None
        moved = store.repair(manifest, chash, {t.trial_id for t in trials} if same else None)
        store.clean()
        done = store.recorded_ids()
        if len(done) < expected and not moved:  # what was moved aside said so itself
            warnings.warn(f"run {study.name}/{run} at {path}: its manifest counts {expected} "
                          f"recorded trials but {len(done)} are stored; the missing ones run "
                          "again", stacklevel=2)
        manifest["sessions"].append(session)
        manifest["n_recorded"] = len(done)
        provenance.write_manifest(store.manifest_path, manifest)

        pending = [t for t in trials if t.trial_id not in done]
        summary = RunSummary(study.name, run, path, len(trials), n_already=len(trials) - len(pending))
        # every trial's body: a recorded trial's preparation lost (quarantined) is computed again
        prepared = prepare_bodies(kind, study, params, trials, store, map_unordered, summary)
        size = task_size(study, kind, len(pending))
        tasks = [
            [(t, prepared.get(content_hash(kind.body_key(t.factors))) if kind.body_key else None)
             for t in chunk]
            for chunk in _chunks(pending, size)
        ]
        bar = _Progress(len(trials), summary.n_already, show, f"{study.name}/{run}",
                        study.runner.progress_interval_s)
        try:
            with one_check():  # each task's write_shard asks the compacted files: read each once
                results = map_unordered(run_task, [(kind, study, run, params, items, fail_fast)
                                                   for items in tasks])
                for rows, tables, accounts in results:
                    # named after its trials; a name a compacted file supersedes gets a suffix (write_shard)
                    name = content_hash([r["trial_id"] for r in rows])
                    for table_name, table_rows in tables.items():
                        if table_rows:
                            store.write_shard(f"tables/{table_name}", name, table_rows)
                    store.write_shard("records", name, rows, strings=ERROR_COLUMNS,
                                      metadata=config_metadata(chash),
                                      account=Account.from_entries(accounts))
                    n_err = sum(r["status"] == "error" for r in rows)
                    summary.n_ran += len(rows)
                    summary.n_error += n_err
                    summary.n_ok += len(rows) - n_err
                    bar.advance(len(rows), n_err)
                    for r in rows:
                        if r["status"] == "error":
                            summary.errors.append(f"{r['trial_id']}: {r['error_type']}: "
                                                  f"{r['error_message']}")
                    if fail_fast and n_err:
                        summary.stopped_early = True
                        break
        finally:
            bar.close()
        # every trial recorded, even if fail_fast stopped at the last one: nothing was left out
        complete = summary.n_already + summary.n_ran == len(trials)
        if complete and kind.finalize is not None:
            finalize(kind, study, params, store)
        store.compact_all()
        summary.wall_time_s = time.perf_counter() - t0
        session.update(finished_at=provenance.now_utc(), ran=summary.n_ran, errors=summary.n_error,
                       recorded=summary.n_already + summary.n_ran)  # of its design: run_complete
        manifest["n_recorded"] = len(done) + summary.n_ran
        # finished: every trial of the design it now runs recorded (a drifted design may be larger)
        manifest["finished_at"] = session["finished_at"] if complete else None
        provenance.write_manifest(store.manifest_path, manifest)
        check_run(store)  # never a run its own checks refuse: DamagedRunError (exit 2) if it is
    return summary


def _checked_manifest(store: RunStore, study: StudyCfg, run: str, allow_drift: bool):
    """The run's manifest (None for a new run), refused if the run is damaged, holds ingested
    records or was started with another config."""
    manifest = check_run(store, repairable=True)
    if manifest is not None:
        if provenance.ingested(manifest):
            raise UserInputError(
                f"run {study.name}/{run} at {store.path} holds {manifest['source']} records "
                "(ingested); `run` never adds simulated or virtual trials to them, so choose "
                "another run name (--run NAME).")
        check_drift(manifest, study, allow_drift, store.path)
        check_preparations(store, manifest, study)  # a drift allowed cannot remake them
    return manifest


@contextlib.contextmanager
def run_lock(store: RunStore, label: str) -> Iterator[None]:
    """Hold the run for this process alone (an advisory lock on ``<run>/.lock`` that the system
    releases when the run ends or its process dies), so two runs or ingests of one run never record
    a trial twice. The file is opened for writing, as NFS needs for an exclusive lock, and removed
    by its holder at the end, as are the directories made for a run that stays empty: a lock file
    so removed after this process opened it, or its directory so removed before, is made and
    opened again (two new runs of one run at once: the one refused by its backend removes both)."""
    made = [p for p in (store.path, *store.path.parents) if not p.exists()]  # deepest first
    if made and (why := write_denied(made[-1].parent)) is not None:  # chattr +i, a read-only mount
        raise UserInputError(_denied(store, label, made[-1].parent, why))
    lock, handle, held = store.path / LOCK_FILE, None, False
    try:
        for _ in range(_LOCK_ATTEMPTS):
            with contextlib.suppress(FileNotFoundError):  # the directory was removed meanwhile
                store.path.mkdir(parents=True, exist_ok=True)
                handle = os.open(lock, os.O_RDWR | os.O_CREAT, 0o644)
            if handle is None:
                continue
            try:
                lock_exclusive(handle)  # a status probing the run meanwhile: not a run
            except BlockingIOError:
                raise UserInputError(f"run {label} at {store.path} is being run by another process; "
                                     "wait for it to finish (status shows its progress), or choose "
                                     "another run name (--run NAME).") from None
            except OSError as exc:  # a file system without locks (NFS mounted with nolock, some SMB)
                warnings.warn(f"run {label}: {lock} cannot be locked on its file system "
                              f"({exc.strerror}); run it from one process at a time, since two at "
                              "once would each record every trial.", stacklevel=3)
                held = True
            else:
                with contextlib.suppress(FileNotFoundError):  # its holder removed it on ending
                    held = os.path.samestat(os.fstat(handle), os.stat(lock))
            if held:
                break
            os.close(handle)  # not the lock file there now: open that one
            handle = None
        else:
            raise UserInputError(f"run {label} at {store.path}: its lock file was removed "
                                 f"{_LOCK_ATTEMPTS} times while this run opened it; run it from "
                                 "one process at a time.")
        yield
    finally:
        if held:  # removed while still held: a process that opened it before then opens it again
            lock.unlink()
        if handle is not None:
            os.close(handle)
        for directory in made:
            with contextlib.suppress(OSError):  # not empty: it holds what was stored
                directory.rmdir()


def unwritable(store: RunStore, label: str) -> str | None:
    """The sentence refusing to write a run (or to ingest into it) one of whose directories this
    user may not write in (another user's run), or None: found before anything is written, where
    the first shard's write failed after the manifest had recorded a session. Its report/ is left
    to `report`."""
    for where, folders, _ in os.walk(store.path):
        folders[:] = [f for f in folders if Path(where, f) != store.path / "report"]
        if (why := write_denied(Path(where))) is not None:
            return _denied(store, label, where, why)
    return None


def _denied(store: RunStore, label: str, where: Path | str, why: str) -> str:
    """The refusal of a run whose directory ``where`` cannot be written, ``why``."""
    advice = "" if PERMISSION_DENIED in why else ("; make it writable for this user, or run the "
                                                  "command as the user who owns the run")
    return f"run {label} at {store.path}: {where}: {why}{advice}."  # permission denied says what to do


#: Times a run opens its lock afresh after another process removed it (or its directory) meanwhile.
_LOCK_ATTEMPTS = 10
