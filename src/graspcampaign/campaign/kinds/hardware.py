"""``test2_grasp`` and ``test3_disturbance``: the Tests 2-3 hardware protocols on the engine.

One trial = one row of the commanded sheet (:func:`graspcampaign.rig.protocol.test2_schedule`,
1785 rows; :func:`~graspcampaign.rig.protocol.test3_schedule`, 1245 rows): its factors are the
sheet's columns, the sheet's own id renamed ``rig_trial_id`` (the engine's ``trial_id`` is made
from the factor values, docs/records.md) and ``study`` left to the engine's column of that name.
Without a rig the trial runs on the virtual rig (``source = virtual``): the planner's
pre-execution predictions (:func:`graspcampaign.rig.plan.predict_trial`, deterministic from the
protocol seed and the row's ``plan_key``) and the measured outcome
(:func:`graspcampaign.rig.virtual.virtual_trial`) drawn from the engine's per-trial generator,
which depends on the study seed and the row only -- never on the worker or the order. Attempts the
sheet marks ``rig_fault`` abort before load; their re-runs are rows of their own.

There is no finalize stage: every Tests 2-3 statistic is computed by the report from the records,
so a run filled by ``graspcampaign ingest`` gets exactly the same report.

``graspcampaign schedule <study>`` writes the sheet with each row's plan (contacts, commanded grip
per finger, predicted thresholds); ``graspcampaign ingest <study> FILES`` validates measured
per-trial records (:func:`graspcampaign.rig.ingest.validate_records`: every file completely,
before anything is stored) and stores them beside the same predictions.
"""

from __future__ import annotations

import hashlib
import math
from dataclasses import dataclass
from functools import lru_cache
from pathlib import Path
from typing import Any

import numpy as np
import pandas as pd

from graspcampaign.campaign.kind import TrialInput, TrialKind
from graspcampaign.campaign.schema import StudyCfg, check_value, config_field
from graspcampaign.errors import ConfigError
from graspcampaign.rig.protocol_design import SCHEDULE_FRONT, TEST2_COLUMNS, TEST3_COLUMNS

TEST2 = "test2_grasp"
TEST3 = "test3_disturbance"
SHEET_ID = "rig_trial_id"
"""Record column holding the sheet's own trial id (the id a measured-records file uses)."""
TEST2_GROUPS = ("A", "B", "C", "D", "E", "M", "X")
BELIEF_ERRORS = ("paper", "none")
"""Belief readings of a virtual trial (:data:`graspcampaign.rig.belief.BELIEF_ERRORS`; kept here
so a study's params validate without importing the rig)."""
COUNTERFACTUAL_TABLE = "belief_none"
"""Trace table holding each trial's ``belief_error = none`` record."""
TEST3_BLOCKS = ("A", "B", "C", "D", "E")


def _object_ids() -> tuple[str, ...]:
    from graspcampaign.rig.protocol import SHAPE_ORDER

    return tuple(f"{s}-{k:02d}" for s in SHAPE_ORDER for k in range(1, 9))


def _check_beliefs(values: list[str]) -> None:
    _check_lists((("belief_error", values, {"type": str, "choices": BELIEF_ERRORS}),))
    if "paper" not in values:
        raise ConfigError(f"params.belief_error must list 'paper' (the records hold the planners' "
                          f"own beliefs; 'none' is their counterfactual), got {list(values)!r}.")


def _check_lists(items: tuple[tuple[str, list, dict], ...]) -> None:
    for key, values, meta in items:
        for i, v in enumerate(values):
            check_value(f"params.{key}[{i}]", v, meta)
        if len(set(values)) != len(values):
            raise ConfigError(f"params.{key} lists a value twice: {list(values)!r}.")


@dataclass
class Test2GraspParams:
    """Size of the Test 2 sheet: empty lists and ``fraction = 1`` are the full protocol.

    ``objects`` keeps the slots on these object ids (``sphere-01`` ... ``handle-08``), ``groups``
    the slots of these groups (A-E, M the matched ablation, X the further baseline trials), and
    ``fraction`` a deterministic share of the remaining *units*: a slot with its re-run, or a
    whole matched cell (all planners of one object, condition and repeat), chosen by a hash of the
    unit, so pilots and tests keep complete matched pairs. Ids and factors of kept rows do not
    change. ``belief_error`` lists the belief readings each virtual trial is executed under:
    ``paper`` (the planners' own beliefs, :mod:`graspcampaign.rig.belief`) fills the records and
    must be listed; ``none`` (every planner believes the actual quantities) is the counterfactual
    kept in the trace table ``belief_none`` (module docstring).
    """

    objects: list[str] = config_field([])
    groups: list[str] = config_field([])
    fraction: float = config_field(1.0, gt=0.0, le=1.0)
    belief_error: list[str] = config_field(list(BELIEF_ERRORS))

    def __post_init__(self) -> None:
        _check_lists((("objects", self.objects, {"type": str, "choices": _object_ids()}),
                      ("groups", self.groups, {"type": str, "choices": TEST2_GROUPS})))
        _check_beliefs(self.belief_error)

    def selection(self) -> tuple[tuple[str, ...], tuple[str, ...], float]:
        return tuple(sorted(self.objects)), tuple(sorted(self.groups)), float(self.fraction)


@dataclass
class Test3DisturbanceParams:
    """Size of the Test 3 sheet: empty lists and ``fraction = 1`` are the full protocol.

    As :class:`Test2GraspParams`, with ``blocks`` (A-E) in place of groups; a matched unit is one
    object and disturbance for all five planners; ``belief_error`` as there.
    """

    objects: list[str] = config_field([])
    blocks: list[str] = config_field([])
    fraction: float = config_field(1.0, gt=0.0, le=1.0)
    belief_error: list[str] = config_field(list(BELIEF_ERRORS))

    def __post_init__(self) -> None:
        _check_lists((("objects", self.objects, {"type": str, "choices": _object_ids()}),
                      ("blocks", self.blocks, {"type": str, "choices": TEST3_BLOCKS})))
        _check_beliefs(self.belief_error)

    def selection(self) -> tuple[tuple[str, ...], tuple[str, ...], float]:
        return tuple(sorted(self.objects)), tuple(sorted(self.blocks)), float(self.fraction)


# -- the sheet ---------------------------------------------------------------------------------
def unit_key(row: dict[str, Any]) -> str:
    """The unit a reduced sheet keeps or drops whole: a matched cell, else the slot."""
    if bool(row.get("matched")):
        return f"{row['object_id']}|{row['condition']}|{row['repeat']}"
    return str(row["slot_id"])


def _keep_fraction(key: str, fraction: float) -> bool:
    if fraction >= 1.0:
        return True
    word = int.from_bytes(hashlib.sha256(key.encode()).digest()[:8], "little")
    return word / 2.0**64 < fraction


@lru_cache(maxsize=8)
def _sheet(study: str, seed: int, objects: tuple, groups: tuple, fraction: float) -> pd.DataFrame:
    from graspcampaign.rig.protocol import test2_schedule, test3_schedule

    sheet = test2_schedule(seed) if study == TEST2 else test3_schedule(seed)
    keep = np.ones(len(sheet), dtype=bool)
    if objects:
        keep &= sheet["object_id"].isin(objects).to_numpy()
    if groups:
        keep &= sheet["group" if study == TEST2 else "block"].isin(groups).to_numpy()
    if fraction < 1.0:
        keys = [unit_key(r) for r in sheet[["matched", "object_id", "condition", "repeat",
                                            "slot_id"]].to_dict("records")]
        keep &= np.array([_keep_fraction(k, fraction) for k in keys], dtype=bool)
    return sheet[keep].reset_index(drop=True)


def protocol_schedule(study: StudyCfg, params: Any) -> pd.DataFrame:
    """Return the study's commanded sheet (a copy; cached per seed and selection)."""
    if study.kind not in (TEST2, TEST3):
        raise ConfigError(f"study {study.name!r} has kind {study.kind!r}, not a Tests 2-3 protocol.")
    sheet = _sheet(study.kind, int(study.seed), *params.selection())
    if sheet.empty:  # a run of no trial, a sheet of no row: nothing a reduction is for
        chosen = [f"params.{name}=[{','.join(getattr(params, name))}]"
                  for name in ("objects", "groups", "blocks") if getattr(params, name, None)]
        chosen += [f"params.fraction={params.fraction!r}"] if params.fraction < 1.0 else []
        raise ConfigError(f"{', '.join(chosen)} {'selects' if len(chosen) == 1 else 'select'} no "
                          f"trial of the {study.kind} sheet; select more (empty lists and "
                          "fraction 1.0 are the full protocol).", key="params")
    return sheet.copy()


def _native(value: Any) -> Any:
    return value.item() if isinstance(value, np.generic) else value


def design(study: StudyCfg, params: Any) -> list[dict[str, Any]]:
    """One trial per sheet row; the factors are its columns (scalars), its id as ``rig_trial_id``."""
    sheet = protocol_schedule(study, params).drop(columns=["study"])
    sheet = sheet.rename(columns={"trial_id": SHEET_ID})
    return [{k: _native(v) for k, v in r.items()} for r in sheet.to_dict("records")]


def rig_row(factors: dict[str, Any], study: str) -> dict[str, Any]:
    """The sheet row of a trial's factors, as :mod:`graspcampaign.rig` expects it."""
    row = {k: v for k, v in factors.items() if k not in (SHEET_ID, "seed")}
    row["trial_id"] = factors[SHEET_ID]
    row["study"] = study
    return row


def _outputs(d: dict[str, Any]) -> dict[str, Any]:
    return {k: _native(v) for k, v in d.items() if k != "source"}


# -- one trial -----------------------------------------------------------------------------------
def execute(row: dict[str, Any], rng: np.random.Generator,
            belief_errors: tuple[str, ...] = BELIEF_ERRORS) -> dict[str, dict[str, Any]]:
    """Plan one sheet row and execute it on the virtual rig under each belief reading.

    One 64-bit seed is drawn from ``rng`` and every reading executes from a generator of that
    seed, so the readings share the pose error, the force-tracking errors and (up to the point the
    grips make them diverge) the sensor noise: a paired counterfactual.

    Returns
    -------
    dict
        ``{belief_error: record}``, each record the prediction columns followed by the measured
        ones (:func:`graspcampaign.rig.virtual.virtual_trial`).
    """
    from graspcampaign.rig.plan import predict_trial
    from graspcampaign.rig.virtual import virtual_trial

    seed = int(rng.integers(0, 2**63))
    predictions = _outputs(predict_trial(row))
    out = {}
    for belief in belief_errors:
        measured = virtual_trial(row, predictions, np.random.default_rng(seed),
                                 belief_error=belief)
        out[belief] = {**predictions, **_outputs(measured), "belief_error": belief}
    return out


def run(inp: TrialInput, rng: np.random.Generator) -> dict[str, Any]:
    """Plan the row (cached per object and planner) and execute it on the virtual rig.

    The record is the ``paper`` reading; with ``none`` in ``params.belief_error`` the trial also
    writes its ``none`` reading as one row of the trace table ``belief_none``.
    """
    row = rig_row(inp.trial.factors, inp.study.kind)
    beliefs = tuple(getattr(inp.params, "belief_error", ("paper",)))
    readings = execute(row, rng, beliefs)
    out = dict(readings["paper"])
    if "none" in readings:
        out["__tables__"] = {COUNTERFACTUAL_TABLE: {k: [v] for k, v in readings["none"].items()}}
    return out


def records_under_belief(records: pd.DataFrame, counterfactual: pd.DataFrame) -> pd.DataFrame:
    """Return the trace table ``belief_none`` shaped like the records (moved to
    :func:`graspcampaign.analysis.hardware.records_under_belief`, which the report uses too;
    imported lazily so a trial worker does not load the statistics stack)."""
    from graspcampaign.analysis.hardware import records_under_belief as reshape

    return reshape(records, counterfactual)


# -- hardware side: schedule, export, ingest -----------------------------------------------------
def schedule(study: StudyCfg, params: Any) -> pd.DataFrame:
    """The commanded sheet with each row's plan, written by ``graspcampaign schedule``.

    The sheet's columns, then the planner's pre-execution predictions (contacts and normals in the
    object frame [mm], commanded grip per finger, SF_predicted, predicted forces, deformations,
    thresholds and first finger to slip): what the rig executes and what it is scored against.
    """
    from graspcampaign.rig.plan import predict_trial

    sheet = protocol_schedule(study, params)
    plans = pd.DataFrame([predict_trial(r) for r in sheet.to_dict("records")])
    plans = plans.drop(columns=["plan_time_s"])
    return pd.concat([sheet, plans], axis=1)


def export_records(records: pd.DataFrame, study: str) -> pd.DataFrame:
    """Return stored records as a measured-records file (the ingest schema, sheet ids).

    Used to hand the virtual rig's records to ``graspcampaign ingest`` (and as a template for a
    rig's own files): one row per recorded attempt, the columns of
    :func:`graspcampaign.rig.record_schema.record_columns`, ``trial_id`` the sheet's id.
    """
    from graspcampaign.rig.record_schema import record_columns

    ok = records[records["status"] == "ok"] if "status" in records else records
    out = pd.DataFrame({c: ok[c] if c in ok else None for c in record_columns(study)
                        if c != "trial_id"})
    out.insert(0, "trial_id", ok[SHEET_ID].to_numpy())
    return out.reset_index(drop=True)


def template(study: StudyCfg, params: Any, sheet: pd.DataFrame) -> tuple[pd.DataFrame, pd.DataFrame]:
    """The measured-records sheet to fill in: one row per commanded trial (its sheet id), every
    measured column empty; and its columns with type, unit, allowed values (the ingest schema)."""
    from graspcampaign.rig.record_schema import record_template

    schedule = pd.DataFrame({"study": study.kind, "trial_id": sheet["trial_id"]})
    return record_template(schedule)


def _measured_value(value: Any, kind: str) -> Any:
    """A validated cell as the engine records it (ints as int, missing as None)."""
    if value is None or (isinstance(value, float) and math.isnan(value)):
        return None
    if kind == "int":
        return int(value)
    return _native(value)


def _rerun_trial(study: StudyCfg, trials: dict, sheet_id: str, slot: str, attempt: int):
    """An engine trial for a re-run the sheet did not foresee (``<slot_id>-a<k>``)."""
    from graspcampaign.campaign.grid import expand

    first = next(t for t in trials.values() if t.factors["slot_id"] == slot)
    factors = {**first.factors, SHEET_ID: sheet_id, "attempt": attempt, "rig_fault": False}
    return expand(study, [factors])[0]


def ingest(study: StudyCfg, params: Any, paths: list[str],
           stored: pd.DataFrame | None = None) -> list[dict[str, Any]]:
    """Validate measured-records files completely, then return their engine records.

    Each file is checked by :func:`graspcampaign.rig.ingest.validate_records` (header and units,
    types and ranges, known sheet ids, no duplicates, one executed attempt per slot, outcome
    consistent with its flags); across files a trial id and a slot's executed attempt may appear
    once, and a slot with an executed record among ``stored`` (the run's records already stored,
    from an earlier ``ingest``) may not get another. The first problem raises ``IngestError``
    naming the file, the 1-based data row and the column; nothing is stored then.

    Returns
    -------
    list of dict
        One record per row, keyed by the engine's ``trial_id`` of the same sheet row (a re-run
        ``<slot_id>-a<k>`` the sheet did not foresee gets the id its factors give), with the
        sheet's factors, the planner's predictions (recomputed: deterministic from the seed and
        the row) and the measured columns; ``source`` is the file's column (virtual-rig exports
        say ``virtual``), ``measured`` otherwise.
    """
    from graspcampaign.campaign.kind import get_kind
    from graspcampaign.campaign.runner import study_trials
    from graspcampaign.rig.ingest import IngestError, check_one_source, validate_records
    from graspcampaign.rig.plan import predict_trial
    from graspcampaign.rig.record_schema import schema_for

    sheet = protocol_schedule(study, params)
    kinds = {f.name: f.kind for f in schema_for(study.kind)}
    frames: list[tuple[str, pd.DataFrame]] = []
    seen_ids: dict[str, str] = {}
    seen_slots: dict[str, str] = {}
    entries: list[tuple[str, int, str, str, bool]] = []
    for path in paths:
        label = Path(path).name
        table = validate_records(path, sheet, file_label=label)
        for i, (tid, slot, aborted) in enumerate(zip(table["trial_id"], table["slot_id"],
                                                     table["aborted"], strict=True)):
            if tid in seen_ids:
                raise IngestError(f"{label}, row {i + 1}, column 'trial_id': trial '{tid}' is "
                                  f"already in {seen_ids[tid]} (one record per trial).")
            seen_ids[tid] = label
            if not aborted:
                if slot in seen_slots:
                    raise IngestError(f"{label}, row {i + 1}, column 'aborted': slot '{slot}' "
                                      f"already has an executed record in {seen_slots[slot]}.")
                seen_slots[slot] = label
            entries.append((label, i + 1, tid, slot, bool(aborted)))
        frames.append((label, table))
    _check_against_stored(entries, stored)
    # each file holds one source (validate_records); the files and the stored records must agree
    check_one_source([(label, 1, table["source"].iloc[0]) for label, table in frames], stored)
    trials = {t.factors[SHEET_ID]: t for t in study_trials(study, get_kind(study.kind), params)}
    rows = []
    for _, table in frames:
        for rec in table.to_dict("records"):
            sheet_id = rec["trial_id"]
            trial = trials.get(sheet_id) or _rerun_trial(study, trials, sheet_id,
                                                         rec["slot_id"], int(rec["attempt"]))
            predictions = _outputs(predict_trial(rig_row(trial.factors, study.kind)))
            measured = {k: _measured_value(v, kinds.get(k, "")) for k, v in rec.items()
                        if k not in ("trial_id", "slot_id", "attempt", "source")}
            rows.append({"trial_id": trial.trial_id, "kind": study.kind,
                         "trial_index": trial.index, "scene_id": trial.scene_id,
                         **trial.factors, "source": str(rec.get("source") or "measured"),
                         **predictions, **measured})
    return rows


def _check_against_stored(entries: list[tuple[str, int, str, str, bool]],
                          stored: pd.DataFrame | None) -> None:
    """Refuse a trial that is already stored (measured records are never overwritten) and an
    executed attempt of a slot that has an executed record among ``stored``.

    ``entries`` are (file label, 1-based row, sheet trial id, slot, aborted).
    """
    from graspcampaign.rig.ingest import IngestError

    if stored is None or not {SHEET_ID, "slot_id", "aborted"} <= set(stored.columns):
        return
    stored_ids = set(stored[SHEET_ID])
    done = stored[stored["aborted"] == False]  # noqa: E712  (None on errored rows)
    executed = dict(zip(done["slot_id"], done[SHEET_ID], strict=True))
    for label, row, tid, slot, aborted in entries:
        if tid in stored_ids:
            raise IngestError(f"{label}, row {row}, column 'trial_id': trial '{tid}' is already stored "
                              "in this run; measured records are never overwritten (ingest a "
                              "corrected file into another run with --run).")
        if not aborted and slot in executed:
            raise IngestError(f"{label}, row {row}, column 'aborted': slot '{slot}' already has an "
                              f"executed record in the run's stored records (trial "
                              f"'{executed[slot]}').")


_COMMON = dict(source="virtual", seconds_per_trial=0.004, design=design, schedule=schedule,
               ingest=ingest, template=template)


def sheet_keys(columns: tuple[str, ...]) -> tuple[str, ...]:
    """The keys of a trial of a Tests 2-3 protocol: its schedule's columns as :func:`design`
    keeps them (``study`` dropped, ``trial_id`` as :data:`SHEET_ID`)."""
    return tuple(SHEET_ID if c == "trial_id" else c for c in (*SCHEDULE_FRONT, *columns)
                 if c != "study")


TEST2_GRASP = TrialKind(
    name=TEST2, run=run, params=Test2GraspParams,
    description="Test 2 grasp validation (§8): one commanded slot, planned and executed on the "
                "virtual rig", trial_keys=sheet_keys(TEST2_COLUMNS), **_COMMON)
TEST3_DISTURBANCE = TrialKind(
    name=TEST3, run=run, params=Test3DisturbanceParams,
    description="Test 3 disturbance robustness (§9): one commanded slot, planned, lifted and "
                "disturbed on the virtual rig", trial_keys=sheet_keys(TEST3_COLUMNS), **_COMMON)
