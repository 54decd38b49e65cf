"""``test1_bench``: the Test 1 bench-calibration protocol of paper §7 on the campaign engine.

One trial = one planned event of the commanded sheet (:func:`graspcampaign.rig.test1.
test1_schedule`, 19,168 events for the full protocol): its factors are the sheet's columns, so
the records carry the whole commanded event. Without a rig the trial runs the event on the
virtual bench (``source = virtual``): every attempt draws from ``(study seed, event_id,
attempt)`` exactly as :func:`graspcampaign.rig.test1.run_virtual_bench` does, aborted attempts
are re-run and logged in the ``attempts`` trace table, and the completed attempt is fitted
(Eq. 13, relaxation, friction, oblique or cyclic fit of its block). The engine's own per-trial
generator is not used: the event id, not the trial's position or scene, names the stream, so a
record equals the in-process path's fit of the same event.

Full waveforms are kept for a small documented subset (:func:`retained`, 62 events for the full
protocol, as the paper's workbook) in the ``waveforms`` trace table; every other trace can be
regenerated deterministically from the seed and its event id. Once all events are recorded,
:func:`finalize` regenerates the normal-indentation traces and stores the study-level tables in
``summary/``: the specimens' true constants, the damage-depth threshold per fatigued specimen
(used by Tests 2-3), the PSO re-identification (§7.5, 30 restarts per material), Table 5, the
PSO parameter sets' held-out error and the §7.6 transfer errors.

``graspcampaign schedule test1_bench`` writes the sheet; ``graspcampaign ingest test1_bench
FILES`` validates measured waveforms (every file completely, before anything is stored) and
fits them through the same code as the virtual path.
"""

from __future__ import annotations

from concurrent.futures import ThreadPoolExecutor
from dataclasses import dataclass
from functools import lru_cache
from typing import Any

import numpy as np
import pandas as pd

from graspcampaign.campaign.kind import TrialInput, TrialKind
from graspcampaign.campaign.schema import StudyCfg, check_value, config_field
from graspcampaign.core.bench_specimen import FINGERTIP_RADIUS
from graspcampaign.errors import ConfigError
from graspcampaign.rig.test1_protocol import SCHEDULE_COLUMNS

N_SPECIMENS = 12
"""Specimens per family (§7.1)."""

INDENTER_RADIUS_MM = 1e3 * FINGERTIP_RADIUS
"""The indenter radius [mm] the bench's fits and conversions use; every record carries it
(``indenter_radius_mm``), so the report reads it from the records."""


@dataclass
class Test1BenchParams:
    """Size of the protocol and the §7.5 PSO budget.

    ``materials``, ``specimens`` and ``environments`` restrict the sheet for pilots and tests
    (empty = all: 4 families, specimens 1-12, 3 environment groups); event ids, factors and
    splits of the kept events do not change. Specimens 11-12 are the unseen-specimen split.
    """

    materials: list[str] = config_field([])
    specimens: list[int] = config_field([])
    environments: list[str] = config_field([])
    pso_restarts: int = config_field(30, ge=1)  # §7.5: 30 per material
    pso_particles: int = config_field(40, ge=2)  # 40 x 1250 = 5e4 evaluations
    pso_iterations: int = config_field(1250, ge=1)
    pso_traces_per_run: int = config_field(12, ge=1)
    pso_max_reruns: int = config_field(30, ge=0)  # re-runs of diverged runs

    def __post_init__(self) -> None:
        from graspcampaign.rig.test1 import ENVIRONMENTS, MATERIALS

        for key, values, meta in (
            ("materials", self.materials, {"type": str, "choices": MATERIALS}),
            ("specimens", self.specimens, {"type": int, "ge": 1, "le": N_SPECIMENS}),
            ("environments", self.environments, {"type": str, "choices": ENVIRONMENTS}),
        ):
            for i, v in enumerate(values):
                check_value(f"params.{key}[{i}]", v, meta)
            if len(set(values)) != len(values):
                raise ConfigError(f"params.{key} lists a value twice: {list(values)!r}.")

    def selection(self) -> tuple[tuple[str, ...], tuple[int, ...], tuple[str, ...]]:
        """Materials, specimens and environments of the sheet (Table 4 / §7.1 order)."""
        from graspcampaign.rig.test1 import ENVIRONMENTS, MATERIALS

        mats = tuple(m for m in MATERIALS if not self.materials or m in self.materials)
        specs = tuple(sorted(self.specimens)) if self.specimens else tuple(
            range(1, N_SPECIMENS + 1))
        envs = tuple(e for e in ENVIRONMENTS if not self.environments or e in self.environments)
        return mats, specs, envs


@lru_cache(maxsize=8)
def _sheet(seed: int, mats: tuple, specs: tuple, envs: tuple) -> pd.DataFrame:
    from graspcampaign.rig.test1 import test1_schedule

    return test1_schedule(seed, materials=list(mats), specimens=list(specs),
                          environments=list(envs))


def protocol_schedule(study: StudyCfg, params: Test1BenchParams) -> pd.DataFrame:
    """Return the study's commanded-event sheet (a copy; cached per seed and selection)."""
    return _sheet(int(study.seed), *params.selection()).copy()


def design(study: StudyCfg, params: Test1BenchParams) -> list[dict[str, Any]]:
    """One trial per planned event; the factors are the sheet's columns (scalars, SI-suffixed)."""
    return protocol_schedule(study, params).to_dict("records")


# -- retained traces -----------------------------------------------------------------------------
def retained(event: dict[str, Any], params: Test1BenchParams) -> bool:
    """Whether an event's full waveform is kept in the ``waveforms`` trace table.

    On each material's lowest-numbered specimen in the normal-lab group (or the first group of
    the study), repeat 0: normal presses to 1.5 mm at 0.5, 1 and 10 mm/s (Fig. 23a); the 60 s
    and 180 s holds at 1 mm, 10 mm/s (Fig. 25a); slides at load level 1 at 0.5 and 10 mm/s
    (Fig. 24b); the four flat oblique angles; fatigue cycles 1, 96, 101 and 196 (first and last
    measured cycle of each level). Plus the first material's 0.5 mm/s slide in every other
    environment group. 15 per material + 2 = 62 events for the full protocol (the paper's
    workbook keeps 62).
    """
    mats, specs, envs = params.selection()
    env0 = "normal_lab" if "normal_lab" in envs else envs[0]
    b = event["block"]
    if event["specimen"] != specs[0]:
        return False
    if b == "sliding" and event["material"] == mats[0] and event["environment"] != env0:
        return (event["speed_mm_per_s"] == 0.5 and event["load_level"] == 1
                and event["repeat"] == 0)
    if event["environment"] != env0 or event["repeat"] != 0:
        return False
    if b == "normal":
        return event["depth_mm"] == 1.5 and event["speed_mm_per_s"] in (0.5, 1.0, 10.0)
    if b == "relaxation":
        return event["depth_mm"] == 1.0 and event["speed_mm_per_s"] == 10.0
    if b == "sliding":
        return event["load_level"] == 1 and event["speed_mm_per_s"] in (0.5, 10.0)
    if b == "oblique":
        return event["surface"] == "flat"
    if b == "cyclic":
        return event["cycle_index"] in (1, 96, 101, 196)
    return False


# -- one trial -------------------------------------------------------------------------------
def _native(value: Any) -> Any:
    return value.item() if isinstance(value, np.generic) else value


def fit_outputs(fit: dict[str, Any], factors: dict[str, Any]) -> dict[str, Any]:
    """A fit row's outputs: everything but the event's factors and the row's source."""
    return {k: _native(v) for k, v in fit.items() if k not in factors and k != "source"}


def run(inp: TrialInput, rng: np.random.Generator) -> dict[str, Any]:
    """Run one planned event on the virtual bench: attempts until one completes, then its fit.

    ``rng`` (the engine's per-trial stream) is not used: each attempt draws from
    ``(study seed, event_id, attempt)``, exactly as the in-process path.
    """
    from graspcampaign.rig.test1 import run_events

    event = inp.trial.factors
    attempts, fits, waves = run_events([event], inp.study.seed, keep_waveforms=True)
    out: dict[str, Any] = {
        "indenter_radius_mm": INDENTER_RADIUS_MM,
        "event_status": "completed" if fits else "not_completed",
        "n_attempts": len(attempts),
        "n_aborted": sum(a["status"] == "aborted" for a in attempts),
        "trace_kept": bool(waves) and retained(event, inp.params),
    }
    if fits:
        out.update(fit_outputs(fits[0], event))
    tables: dict[str, dict[str, list]] = {"attempts": {
        "event_id": [a["event_id"] for a in attempts],
        "attempt": [a["attempt"] for a in attempts],
        "attempt_status": [a["status"] for a in attempts],
        "anomaly": [a["anomaly"] for a in attempts],
        "n_samples": [a["n_samples"] for a in attempts],
    }}
    if out["trace_kept"]:
        from graspcampaign.rig.test1 import WAVEFORM_COLUMNS

        w = waves[0]
        n = len(w["time_s"])
        tables["waveforms"] = {"event_id": [event["event_id"]] * n,
                               "attempt": [w["attempt"]] * n,
                               **{c: w[c].tolist() for c in WAVEFORM_COLUMNS[1:]}}
    out["__tables__"] = tables
    return out


# -- study-level tables ------------------------------------------------------------------------
def _n_jobs(study: StudyCfg) -> int:
    return study.runner.workers()  # joblib's reading of n_jobs (-2: every core but one)


def completed_fits(records: pd.DataFrame) -> pd.DataFrame:
    """Records of events that completed and were fitted (trial errors and aborts excluded)."""
    ok = records[records["status"] == "ok"]
    if "event_status" in ok:
        ok = ok[ok["event_status"] == "completed"]
    return ok.reset_index(drop=True)


def _rows(df: pd.DataFrame | None) -> list[dict[str, Any]]:
    if df is None or df.empty:
        return []
    return [{k: _native(v) for k, v in r.items()} for r in df.to_dict("records")]


def finalize(study: StudyCfg, params: Test1BenchParams, records: pd.DataFrame, store=None
             ) -> dict[str, list[dict[str, Any]]]:
    """Study-level tables of §7.4-7.6 from the recorded fits and regenerated normal traces.

    * ``truths``: the virtual bench's true constants per specimen and environment;
    * ``damage_depth``: damage-depth threshold of every fatigued specimen (§7.4; Tests 2-3);
    * ``pso_runs``: §7.5 re-identification on the training split's normal traces, every
      logged run (diverged ones flagged, re-runs added); ``table5``: mean, SD, CV of the
      converged runs; ``pso_transfer``: each run's normal-force error on the held-out
      (unseen specimen, unseen speed) traces;
    * ``transfer``: §7.6 transfer errors of the per-event fits' training calibration.

    The normal-indentation traces are regenerated from ``(seed, event_id, attempt)`` (the
    records keep only a few), in parallel over ``runner.n_jobs`` local processes; every PSO
    run is one task for those processes, and the transfer errors are computed in a thread
    meanwhile.
    """
    from graspcampaign.rig import test1 as T

    seed = int(study.seed)
    fits = completed_fits(records)
    sched = protocol_schedule(study, params)
    n_jobs = _n_jobs(study)
    out: dict[str, list[dict[str, Any]]] = {"truths": _rows(T.specimen_truths(seed, sched))}
    if (fits["block"] == "cyclic").any():
        out["damage_depth"] = _rows(T.damage_depths(fits))
    normal = sched[sched["block"] == "normal"]
    waves = None
    if not len(normal):
        out["transfer"] = _rows(T.transfer_errors(fits, waves))
        return out
    waves = T.run_virtual_bench(normal, seed, n_jobs=n_jobs, keep_waveforms=True,
                                fit=False).waveforms
    train = normal[normal["split"] == "train"]
    # the §7.6 transfer errors are serial pandas work that does not depend on the PSO: with
    # workers, they run in a thread of this process while the PSO runs fill the workers
    with ThreadPoolExecutor(max_workers=1) as pool:
        transfer = pool.submit(T.transfer_errors, fits, waves) if n_jobs > 1 else None
        # every PSO run is one task (runs draw independent streams (seed, "pso", material,
        # run): the result does not depend on n_jobs)
        runs = T.pso_reidentify(waves[waves["event_id"].isin(set(train["event_id"]))], train,
                                seed, n_restarts=params.pso_restarts,
                                n_particles=params.pso_particles,
                                n_iterations=params.pso_iterations,
                                traces_per_run=params.pso_traces_per_run,
                                max_reruns=params.pso_max_reruns, n_jobs=n_jobs)
        if len(runs):
            out["pso_runs"] = _rows(runs)
            out["table5"] = _rows(T.table5(runs))
            out["pso_transfer"] = _rows(T.pso_transfer_errors(runs, waves, sched))
        out["transfer"] = _rows(transfer.result() if transfer is not None
                                else T.transfer_errors(fits, waves))
    return out


# -- hardware side: schedule and ingest ----------------------------------------------------------
def schedule(study: StudyCfg, params: Test1BenchParams) -> pd.DataFrame:
    """The commanded-event sheet written by ``graspcampaign schedule test1_bench``."""
    return protocol_schedule(study, params)


def template(study: StudyCfg, params: Test1BenchParams, sheet: pd.DataFrame
             ) -> tuple[pd.DataFrame, pd.DataFrame]:
    """The waveform sheet a bench fills in (no rows: one row per sample) and its columns."""
    from graspcampaign.rig.test1 import waveform_template

    return waveform_template()


def ingest(study: StudyCfg, params: Test1BenchParams, paths: list[str],
           stored: pd.DataFrame | None = None) -> list[dict[str, Any]]:
    """Validate waveform files completely, then fit every event (the in-process fit path).

    An event already among ``stored`` (the run's records) is refused, as is a file whose
    ``source`` differs from another file's or from the stored records' (one source per run).

    Each file is checked by :func:`graspcampaign.rig.test1.validate_waveforms` (columns,
    units, numbers, finite values, rig ranges, known event ids, duplicate samples, increasing
    time); an event may appear in one file only. The first problem raises ``IngestError``
    naming the file, the 1-based data row and the column; nothing is fitted or stored then.

    Returns
    -------
    list of dict
        One record per event, keyed by the engine's ``trial_id`` of the same planned event;
        ``source`` is the file's ``source`` column when it has one (virtual-bench exports say
        ``virtual``), ``measured`` otherwise.
    """
    from pathlib import Path

    from graspcampaign.campaign.kind import get_kind
    from graspcampaign.campaign.runner import study_trials
    from graspcampaign.rig import test1 as T
    from graspcampaign.rig.ingest import check_one_source

    sched = protocol_schedule(study, params)
    known = set(sched["event_id"])
    done = set() if stored is None or "event_id" not in stored else set(stored["event_id"])
    frames, owner, sources = [], {}, []
    for path in paths:
        label = Path(path).name
        table = T.validate_waveforms(path, known, file_label=label, schedule=sched)
        first = table.drop_duplicates("event_id")
        for i, eid in zip(first.index, first["event_id"], strict=True):
            if eid in owner:
                raise T.IngestError(f"{label}, row {i + 1}, column 'event_id': event '{eid}' "
                                    f"is already in {owner[eid]} (one file per event).")
            if eid in done:
                raise T.IngestError(f"{label}, row {i + 1}, column 'event_id': event '{eid}' is already "
                                    "stored in this run; measured records are never overwritten "
                                    "(ingest a corrected file into another run with --run).")
            owner[eid] = label
        # each file holds one source (validate_waveforms); the files and the stored records must agree
        sources.append((label, 1, table["source"].iloc[0] if "source" in table else "measured"))
        frames.append(table)
    check_one_source(sources, stored)
    fits = T.fit_waveforms(pd.concat(frames, ignore_index=True), sched)
    trials = {t.factors["event_id"]: t
              for t in study_trials(study, get_kind(study.kind), params)}
    rows = []
    for fit in fits.to_dict("records"):
        trial = trials[fit["event_id"]]
        row = {"trial_id": trial.trial_id, "kind": study.kind, "trial_index": trial.index,
               "scene_id": trial.scene_id, **trial.factors,
               "source": str(fit.get("source") or "measured"),
               "indenter_radius_mm": INDENTER_RADIUS_MM, "event_status": "completed",
               "n_attempts": int(fit["attempt"]), "n_aborted": int(fit["attempt"]) - 1,
               "trace_kept": False}
        row.update(fit_outputs(fit, trial.factors))
        rows.append(row)
    return rows


TEST1_BENCH = TrialKind(
    name="test1_bench",
    run=run,
    params=Test1BenchParams,
    source="virtual",
    # generate + fit per event after issue 16; a paper-scale run's mean wall_time_s is 0.7-1.4 ms
    # on this 2-core machine when quiet, 2.3-3.7 ms under load (docs/decisions.md)
    seconds_per_trial=0.001,
    design=design,
    trial_keys=SCHEDULE_COLUMNS,  # a trial is a row of the commanded-event sheet
    finalize=finalize,
    schedule=schedule,
    ingest=ingest,
    template=template,
    description="Test 1 bench protocol (§7): one planned event on the virtual bench, fitted",
    stages="the PSO re-identification of each material and the summaries after the trials "
           "(Sec. 7.5; at paper scale longer than the trials; docs/decisions.md)",
)
