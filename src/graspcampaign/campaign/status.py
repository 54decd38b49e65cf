"""Describe a study's design and a run's progress from its config and records alone.

Used by ``graspcampaign show`` and ``status``, which answer in well under a second: nothing here
imports the numerical layers (the kind facts and explicit design sizes come from
:mod:`graspcampaign.campaign.catalog`), and the records are read only when the run exists.
"""

from __future__ import annotations

import os
import statistics
from pathlib import Path
from typing import Any

from graspcampaign.campaign.catalog import design_size, kind_facts
from graspcampaign.campaign.kind import KINDS, get_kind, kind_available
from graspcampaign.campaign.paths import (
    case_twin_problem,
    check_name,
    check_root,
    held_by_a_run,
    how_to_make,
    near_run,
    run_dir,
    run_path,
)
from graspcampaign.campaign.schema import StudyCfg, design_shape
from graspcampaign.campaign.studyfile import list_studies
from graspcampaign.core.words import counted, meant
from graspcampaign.errors import MissingSourceRunError, UserInputError


def _fmt_seconds(seconds: float) -> str:
    if seconds < 1:
        return f"{seconds * 1e3:.0f} ms" if seconds else "0 s"
    if seconds < 120:
        return f"{seconds:.0f} s"
    if seconds < 7200:
        return f"{seconds / 60:.0f} min"
    return f"{seconds / 3600:.1f} h"


def study_size(study: StudyCfg) -> int:
    """Return a study's trial count (its Cartesian design or its kind's explicit schedule)."""
    return design_size(study)


def opened_run(study: StudyCfg, run: str | None = None):
    """``(RunStore, manifest)`` of the study's run, checked against its manifest (a run that is not
    what its manifest says is refused); None when there is no run yet."""
    path = run_path(study, run)
    if not os.path.lexists(path.parent):  # no study directory, so no run (a file there, or a
        return None  # symbolic link leading nowhere: refused)
    from graspcampaign.campaign.records import RunStore

    store = RunStore(path)
    manifest = store.check(["records"])
    return None if manifest is None else (store, manifest)


_OPEN = object()  # "open the run here": callers that opened it pass what opened_run returned


def recorded_in(study: StudyCfg, run: str | None = None, opened=_OPEN) -> int:
    """Return how many of the study's current trials the run has recorded.

    Only the trial ids of the design as configured now (overrides included) count: a run of the
    full grid holds 2700 records, but ``mu=[0.3] seeds=2`` asks about 120 of them.
    """
    opened = opened_run(study, run) if opened is _OPEN else opened
    if opened is None:
        return 0
    from graspcampaign.campaign.provenance import config_hash, one_config
    from graspcampaign.campaign.runner import kind_params, study_trials

    store, manifest = opened
    recorded = store.recorded_ids()
    if not recorded:
        return 0
    # every session of the run had this very config: its records are all of this design (this
    # spares building a 19,168-event schedule just to count)
    if one_config(manifest, config_hash(study, manifest)):
        return len(recorded)
    kind = get_kind(study.kind)
    ids = {t.trial_id for t in study_trials(study, kind, kind_params(study, kind))}
    return len(ids & recorded)


def _mean_trial_s(store) -> float | None:
    """The mean wall time [s] of the run's recorded trials (None: none timed; wall_time_s is an
    optional record column, records.OPTIONAL_COLUMNS): the remaining time is their count times the
    mean, not the median, which a skewed run understates (test1_bench at paper scale: median
    0.5 ms, mean 2.3 ms). Measured runs never get here: they have no run-time estimate
    (:func:`design_text`)."""
    table = store.read(columns=["wall_time_s"])
    if "wall_time_s" not in table.column_names:
        return None
    times = table.column("wall_time_s").drop_null()
    return statistics.fmean(times.to_pylist()) if len(times) else None


def drift_refusal(study: StudyCfg, run: str | None = None, opened=_OPEN) -> str | None:
    """What the command that adds to ``study``'s run would say, refusing: ``run`` for a simulated
    run started with another config or code version
    (:func:`graspcampaign.campaign.provenance.check_drift`), ``ingest`` for a measured one started
    with another config; None if it would not, or there is no run yet."""
    opened = opened_run(study, run) if opened is _OPEN else opened
    from graspcampaign.campaign.provenance import DriftError, check_drift, ingest_refusal, ingested

    if opened is None:
        return None
    if ingested(opened[1]):
        label = f"{study.name}/{run or study.output.run}"
        refusal = ingest_refusal(opened[1], study, label, opened[0].path)
        return f"`ingest` would refuse: {refusal}" if refusal else None
    try:
        check_drift(opened[1], study, False, opened[0].path)
    except DriftError as exc:
        return f"`run` would refuse: {exc}"
    return None


def design_text(study: StudyCfg, run: str | None = None, overrides: list[str] = ()) -> str:
    """Return the human-readable design of a study and the progress of its run; ``overrides``, as
    typed, follow the description (which tells the study file's design, not theirs)."""
    ready = kind_available(study.kind)
    facts = kind_facts(study.kind) if ready else None
    try:
        total = study_size(study)
    except MissingSourceRunError as exc:  # a design read from a run not made (or finished) yet
        total, waiting = None, exc
    lines = [f"study: {study.name}", f"description: {' '.join(study.description.split())}"]
    if overrides:
        lines.append(f"overrides: {' '.join(overrides)} (the description is of the study file's "
                     "design; what follows is with them)")
    state = "runnable" if ready else ("not yet runnable" if study.kind in KINDS else "unknown kind")
    lines.append(f"trial kind: {study.kind} ({state})")
    lines.append(f"study seed: {study.seed}   seeds per scene: {study.seeds}   "
                 f"repeats: {study.repeats}")
    lines.append("factors:" if study.factors else "factors: none")
    for name, levels in study.factors.items():
        role = " (method: shares scene draws)" if name in study.method_factors else ""
        lines.append(f"  {name} [{len(levels)}]{role}: {', '.join(map(str, levels))}")
    if study.zip:
        lines.append("zipped: " + "; ".join(" + ".join(g) for g in study.zip))
    if total is None:  # described all the same: what is missing is a line, not a refusal
        lines.append(f"design: not known until its source run is recorded: {waiting}")
    elif facts and facts["design"]:
        lines.append(f"design: the protocol's schedule = {counted(total, 'trial')}")
    else:
        axes = " x ".join(f"{name} {size}" for name, size in design_shape(study).items())
        lines.append(f"axes: {axes} = {counted(total, 'trial')}")
    from graspcampaign.campaign.provenance import ingested

    opened = opened_run(study, run) if ready else None  # the run opened and checked once
    if total is None:  # its trial ids are the source's: count what is stored
        done = len(opened[0].recorded_ids()) if opened is not None else 0
        lines.append(f"run: {run_path(study, run)} ({done} recorded)")
    else:
        done = recorded_in(study, run, opened)
        lines.append(f"run: {run_path(study, run)} ({done} of {total} recorded)")
    if refusal := drift_refusal(study, run, opened):
        lines.append(f"note: {refusal}")
    elif opened is None and (twin := case_twin_problem(run_path(study, run),
                                                       f"{study.name}/{run or study.output.run}")):
        lines.append(f"note: `run` and `ingest` would refuse: {twin}")
    if total is None:
        lines.append("estimated time: none before the design is known (see design)")
    elif facts and opened is not None and ingested(opened[1]):  # its trials come from a rig, not `run`
        lines.append(f"estimated time: none: `run` adds no trials to an ingested run; its "
                     f"{counted(total - done, 'trial')} not recorded come from `ingest`")
    elif facts:
        per, workers = facts["seconds_per_trial"], study.runner.workers()
        basis = "as the trial kind estimates"
        if done and (measured := _mean_trial_s(opened[0])) is not None:
            per, basis = measured, "mean of the trials recorded"
        remaining = (total - done) * per / workers
        stages = f"; trials only, not counted: {facts['stages']}" if facts.get("stages") else ""
        lines.append(f"estimated time: {_fmt_seconds(remaining)} for {counted(total - done, 'trial')} "
                     f"(~{_fmt_seconds(per)} each, {basis}, on {counted(workers, 'worker')}){stages}")
    if study.paper:  # Test 2's block is 3,000 characters: lines of about 100, no pair split
        pairs = _paper_pairs(study.paper)
        lines.append(f"paper: {pairs[0]}")
        for pair in pairs[1:]:
            if len(lines[-1]) + len(pair) > 98:
                lines[-1] += ","
                lines.append(f"  {pair}")
            else:
                lines[-1] += f", {pair}"
    return "\n".join(lines)


def _paper_pairs(paper: dict[str, Any], prefix: str = "") -> list[str]:
    """``key=value`` pairs of the paper block, nested keys dotted (no Python reprs); an empty
    dict as ``key={}``."""
    pairs = []
    for key, value in paper.items():
        if isinstance(value, dict) and value:
            pairs += _paper_pairs(value, f"{prefix}{key}.")
        elif isinstance(value, list):
            pairs.append(f"{prefix}{key}=[{', '.join(map(str, value))}]")
        else:
            pairs.append(f"{prefix}{key}={value}")
    return pairs


def check_known(root: Path | str, study: str) -> None:
    """Refuse a study name that is neither on the config search path nor stored under ``root``,
    naming the available studies (and the nearest one), or a study file's path given for its
    name (``run`` and ``show`` take a path; what is stored is under the study's name)."""
    if isinstance(study, str) and (Path(study).suffix.lower() in (".yaml", ".yml") or os.sep in study):
        from graspcampaign.campaign.studyfile import read_yaml, study_and_run

        if (apart := study_and_run(study, root)) is not None:
            raise UserInputError(apart)

        try:
            name = read_yaml(Path(study)).get("name")
        except UserInputError:  # not read: its file's stem, which a study's name usually is
            name = None
        which = (f"{name}, the value of name: in the study file" if isinstance(name, str) and name
                 else f"the value of name: in the study file; {Path(study).stem} if the file is "
                      "named after it")
        raise UserInputError(f"study {study!r} is a path; give the study's name ({which}), under "
                             "which its runs are stored.")
    check_name(study, "study")
    if (Path(root) / study).is_dir() or study in (known := list_studies()):
        return
    raise UserInputError(f"unknown study {study!r}: not on the config search path and no records "
                         f"under {root}; {meant(study, known)}available "
                         f"studies: {', '.join(known)}.")


def open_run(root: Path | str, study: str, run: str, option_prefix: str = "--"):
    """Return ``(RunStore, manifest)`` of a stored run whose records are what its manifest says.

    ``option_prefix`` starts the names the messages give ``root`` and ``run``: ``--`` for the
    command line's options, ``""`` for the Python API's arguments.

    Raises
    ------
    UserInputError
        A bad root or run name; a study that is neither known nor in ``root`` (with the available
        studies); no run there (with the command that makes one); a run whose records are not what
        its manifest says (``DamagedRunError``).
    """
    check_root(root, f"{option_prefix}root")
    check_name(run, f"{option_prefix}run")
    check_known(root, study)
    from graspcampaign.campaign.records import RunStore

    store = RunStore(run_dir(root, study, run))
    manifest = store.check(["records"])  # a run that is not what its manifest says: refused
    if manifest is None:
        raise UserInputError(f"no run at {store.path}; {near_run(root, study, store.path.name)}"
                             f"{how_to_make(root, study, run)}")
    return store, manifest


def run_status(root: Path | str, study: str, run: str = "default") -> dict[str, Any]:
    """Summarise a run from its manifest and records only (``checked`` says so).

    Raises
    ------
    UserInputError
        No such run; for a study that is neither known nor in ``root``, the available studies.
    """
    from graspcampaign.campaign.parts import unaccounted
    from graspcampaign.campaign.provenance import run_complete, run_size

    store, manifest = open_run(root, study, run)
    # pyarrow only: status answers fast; the files listed once, for the accounts too
    table, records = store.read_with_facts("records", ["status"])
    statuses = table.column("status").to_pylist() if table.num_rows else []
    return {
        "study": study,
        "run": run,
        "path": str(store.path),
        "source": store.source(manifest, records.values()),  # as the run's report says
        "n_trials": run_size(manifest),  # of the design it now runs (--allow-drift may change it)
        "n_recorded": len(statuses),
        "n_ok": statuses.count("ok"),
        "n_error": statuses.count("error"),
        "complete": run_complete(manifest, len(statuses)),
        "in_progress": held_by_a_run(store.path),  # another process is running or ingesting it now
        "config_hash": manifest.get("config_hash"),
        "code_version": manifest.get("code_version"),
        "started_at": manifest.get("started_at"),
        "finished_at": manifest.get("finished_at"),
        "checked": "; ".join(filter(None, (CHECKED, unaccounted(store, manifest, records)))),
    }


#: What ``status`` checked of a run (it answers from the records: a loss or damage only the other
#: parts' files show in full is ``report``'s and ``run``'s to name).
CHECKED = ("records/ in full; tables/, prepared/ and summary/ by their directories and their "
           "files' footers (report and run verify every file)")
