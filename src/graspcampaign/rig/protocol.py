"""Tests 2-3 protocol designs: the commanded-trial sheets of paper §8.1 and §9.1.

:func:`test2_schedule` (grasp validation) and :func:`test3_disturbance` designs are returned as
pandas DataFrames, one row per commanded trial attempt, with

* a stable, content-derived ``trial_id`` (readable key + hash of the slot's design values; the
  seed only changes run order and which slots carry a rig fault, never an id);
* ``slot_id`` and ``attempt``: every executed slot has attempt 1; the paper's aborted slots
  (30 in Test 2, 15 in Test 3) get ``rig_fault = True`` on attempt 1 and an attempt-2 row that
  re-runs them, so the sheet has exactly the paper's commanded / executed counts;
* a randomised run order blocked by session and day (matched-set units stay in one session);
* a unit in every dimensional column name.

The design constants and the object set live in :mod:`graspcampaign.rig.protocol_design`, ids,
run order and rig faults in :mod:`graspcampaign.rig.protocol_order`; this module builds the two
sheets and re-exports the public names of both.

The paper fixes the totals; where it leaves a split open, the split chosen here is recorded in
``docs/decisions.md`` ("Tests 2-3 protocols and virtual rig (issue 9)") and in the constants below.

References
----------
Paper §8.1 (objects, groups A-E, matched ablation, baselines, pose error, 1785/1755), §8.6
(group C, group E speed levels 20/80/20), Table 6 (per-shape n), Table 7 (per-planner n),
§9.1-9.5 and Tables 8-9 (blocks, levels, n, coating probes, matched paired set, 1245/1230).
"""

from __future__ import annotations

import logging
import math
from typing import Any

import pandas as pd

from graspcampaign.core.statics import GRAVITY
from graspcampaign.rig.protocol_design import (
    BASELINES,
    COATING_LEVELS,
    DEFAULT_CLOSING_MM_PER_S,
    DEFAULT_LIFT_MM_PER_S,
    ENVELOPE_INDICES,
    FRICTION_LEVELS,
    HEAVY_INDICES,
    HOLD_S,
    LIFT_HEIGHT_MM,
    MATCHED_OBJECTS,
    OBJECT_MASSES_KG,
    OBJECT_MATERIALS,
    PAPER_COUNTS,
    PLANNER_LABELS,
    SESSION_SLOTS,
    SHAPE_ORDER,
    STUDY_TEST2,
    STUDY_TEST3,
    TEST2_C_CELLS,
    TEST2_C_PER_SHAPE,
    TEST2_COLUMNS,
    TEST2_D_OBJECTS,
    TEST2_E_CELLS,
    TEST2_E_PER_SHAPE,
    TEST2_M_CONDITIONS,
    TEST2_X_COUNTS,
    TEST3_A_CAP_N,
    TEST3_A_DIRECTIONS_DEG,
    TEST3_A_RAMPS_N_PER_S,
    TEST3_B_CELLS,
    TEST3_B_RAMP_N_PER_S,
    TEST3_C_CAP_NM,
    TEST3_C_RAMP_NM_PER_S,
    TEST3_COLUMNS,
    TEST3_D_CELLS,
    TEST3_D_DURATIONS_MS,
    TEST3_D_OBSERVE_S,
    TEST3_E_CELLS,
    TEST3_E_DURATION_S,
    TEST3_MATCHED,
    all_objects,
    envelope_objects,
    object_row,
    objects_table,
    shape_equivalent_radius,
)
from graspcampaign.rig.protocol_order import (
    check_seed,
    schedule_slots,
)

__all__ = [
    # the Test 2 and Test 3 schedules (this module)
    "test2_schedule",
    "test3_schedule",
    # re-exported: they live in graspcampaign.rig.protocol_design
    "COATING_LEVELS",
    "FRICTION_LEVELS",
    "HOLD_S",
    "LIFT_HEIGHT_MM",
    "MATCHED_OBJECTS",
    "OBJECT_MASSES_KG",
    "OBJECT_MATERIALS",
    "PAPER_COUNTS",
    "PLANNER_LABELS",
    "SHAPE_ORDER",
    "STUDY_TEST2",
    "STUDY_TEST3",
    "objects_table",
    "shape_equivalent_radius",
    "BASELINES",
    "DEFAULT_CLOSING_MM_PER_S",
    "DEFAULT_LIFT_MM_PER_S",
    "ENVELOPE_INDICES",
    "HEAVY_INDICES",
    "SESSION_SLOTS",
    "TEST2_C_CELLS",
    "TEST2_C_PER_SHAPE",
    "TEST2_D_OBJECTS",
    "TEST2_E_CELLS",
    "TEST2_E_PER_SHAPE",
    "TEST2_M_CONDITIONS",
    "TEST2_X_COUNTS",
    "TEST3_A_CAP_N",
    "TEST3_A_DIRECTIONS_DEG",
    "TEST3_A_RAMPS_N_PER_S",
    "TEST3_B_CELLS",
    "TEST3_B_RAMP_N_PER_S",
    "TEST3_C_CAP_NM",
    "TEST3_C_RAMP_NM_PER_S",
    "TEST3_D_CELLS",
    "TEST3_D_DURATIONS_MS",
    "TEST3_D_OBSERVE_S",
    "TEST3_E_CELLS",
    "TEST3_E_DURATION_S",
    "TEST3_MATCHED",
]

logger = logging.getLogger(__name__)


# --------------------------------------------------------------------------------------------
# Test 2
# --------------------------------------------------------------------------------------------
def _t2_slot(group: str, object_id: str, planner: str = "heuristic", *, friction: str = "natural",
             pose: float = 0.0, closing: float = DEFAULT_CLOSING_MM_PER_S,
             lift: float = DEFAULT_LIFT_MM_PER_S, matched: bool = False, condition: str = "",
             unit: str | None = None) -> dict[str, Any]:
    return {"group": group, **object_row(object_id), "planner": planner, "friction_level": friction,
            "pose_err_mm": float(pose), "closing_speed_mm_per_s": float(closing),
            "lift_speed_mm_per_s": float(lift), "hold_s": HOLD_S, "matched": matched,
            "condition": condition, "unit": unit}


def _test2_slots() -> list[dict[str, Any]]:
    slots: list[dict[str, Any]] = []
    # A: sphere validation, 6 envelope spheres x pose {0, 10} x 10.
    for k in ENVELOPE_INDICES:
        for pose in (0.0, 10.0):
            slots += [_t2_slot("A", f"sphere-{k:02d}", pose=pose) for _ in range(10)]
    # B: shape generalisation, 4 shapes x 6 objects x pose {0, 10} x 5.
    for shape in SHAPE_ORDER[1:]:
        for k in ENVELOPE_INDICES:
            for pose in (0.0, 10.0):
                slots += [_t2_slot("B", f"{shape}-{k:02d}", pose=pose) for _ in range(5)]
    # C: failure boundary, cells cycled within each shape.
    for shape in SHAPE_ORDER:
        for i in range(TEST2_C_PER_SHAPE[shape]):
            k, friction = TEST2_C_CELLS[i % len(TEST2_C_CELLS)]
            slots.append(_t2_slot("C", f"{shape}-{k:02d}", friction=friction))
    # D: repeatability, 7 objects x 15.
    for object_id in TEST2_D_OBJECTS:
        slots += [_t2_slot("D", object_id) for _ in range(15)]
    # E: speed sensitivity, cells cycled over the whole group (exact 20/80/20 marginals); each
    # run of six consecutive trials puts one object through all six cells, so the speed levels
    # are not confounded with objects.
    i = 0
    for shape in SHAPE_ORDER:
        for _ in range(TEST2_E_PER_SHAPE[shape]):
            closing, lift = TEST2_E_CELLS[i % len(TEST2_E_CELLS)]
            k = ENVELOPE_INDICES[(i // len(TEST2_E_CELLS)) % len(ENVELOPE_INDICES)]
            slots.append(_t2_slot("E", f"{shape}-{k:02d}", closing=closing, lift=lift))
            i += 1
    # M: matched ablation, 10 objects x 3 conditions x 3 repeats x 5 planners (one unit per cell).
    for object_id in MATCHED_OBJECTS:
        for cond, (friction, pose) in TEST2_M_CONDITIONS.items():
            for r in range(3):
                unit = f"M|{object_id}|{cond}|{r}"
                slots += [_t2_slot("M", object_id, planner, friction=friction, pose=pose,
                                   matched=True, condition=cond, unit=unit)
                          for planner in PLANNER_LABELS]
    # X: further centroid and random trials on the 30 envelope objects, pose alternating.
    envelope = envelope_objects()
    for planner, count in TEST2_X_COUNTS.items():
        for i in range(count):
            pose = (0.0, 10.0)[(i // len(envelope)) % 2]
            slots.append(_t2_slot("X", envelope[i % len(envelope)], planner, pose=pose))
    return slots


def test2_schedule(seed: int = 0) -> pd.DataFrame:
    """Return the Test 2 (grasp validation, §8) commanded-trial sheet.

    Parameters
    ----------
    seed : int
        Protocol seed: run order, session packing and which slots carry the rig faults.

    Returns
    -------
    pandas.DataFrame
        1785 rows (1755 slots, 30 of them with a rig-fault attempt and an attempt-2 re-run), in
        run order. Columns: ids and order (``trial_id, slot_id, attempt, rig_fault, study,
        protocol_seed, run_order, day, session, session_position``) then the design
        (``group`` A-E, M matched, X further baseline trials; ``object_id, shape, object_index,
        material, mass_kg, planner, planner_label, plan_key, friction_level, pose_err_mm,
        closing_speed_mm_per_s, lift_speed_mm_per_s, hold_s, matched, condition, repeat``).
    """
    seed = check_seed(seed)
    return schedule_slots(_test2_slots(), STUDY_TEST2, "t2", "group", seed, TEST2_COLUMNS)


# --------------------------------------------------------------------------------------------
# Test 3
# --------------------------------------------------------------------------------------------
def _t3_slot(block: str, object_id: str, planner: str = "heuristic", *, friction: str = "natural",
             probe: str = "", matched: bool = False, condition: str = "", **levels) -> dict:
    obj = object_row(object_id)
    weight = obj["mass_kg"] * GRAVITY
    slot = {"block": block, **obj, "planner": planner, "friction_level": friction, "probe": probe,
            "pose_err_mm": 0.0, "closing_speed_mm_per_s": DEFAULT_CLOSING_MM_PER_S,
            "lift_speed_mm_per_s": DEFAULT_LIFT_MM_PER_S, "hold_s": HOLD_S,
            "matched": matched, "condition": condition, "disturbance": "", "disturbance_kind": "",
            "direction_deg": 0.0, "load_frac_w": math.nan, "load_n": math.nan,
            "ramp_rate_n_per_s": math.nan, "ramp_cap_n": math.nan,
            "torque_ramp_nm_per_s": math.nan, "torque_cap_nm": math.nan,
            "pulse_duration_ms": math.nan, "frequency_hz": math.nan, "amplitude_n": math.nan,
            "duration_s": math.nan, "proof_force_n": math.nan, "proof_torque_nm": math.nan}
    if block == "A":
        slot.update(disturbance="lateral_pull", disturbance_kind="lateral",
                    direction_deg=levels["direction_deg"], ramp_rate_n_per_s=levels["ramp"],
                    ramp_cap_n=TEST3_A_CAP_N, proof_force_n=weight, load_n=weight, load_frac_w=1.0)
    elif block == "B":
        frac = levels["load_frac_w"]
        slot.update(disturbance=f"vertical_{levels['direction']}", disturbance_kind=levels["direction"],
                    load_frac_w=frac, load_n=frac * weight, ramp_rate_n_per_s=TEST3_B_RAMP_N_PER_S,
                    duration_s=frac * weight / TEST3_B_RAMP_N_PER_S + HOLD_S)
    elif block == "C":
        proof = weight * shape_equivalent_radius(obj["shape"])
        slot.update(disturbance="yaw_torsion", disturbance_kind="yaw",
                    torque_ramp_nm_per_s=TEST3_C_RAMP_NM_PER_S, torque_cap_nm=TEST3_C_CAP_NM,
                    proof_torque_nm=proof)
    elif block == "D":
        frac = levels["load_frac_w"]
        slot.update(disturbance="impulse", disturbance_kind="lateral", load_frac_w=frac,
                    load_n=frac * weight, pulse_duration_ms=levels["pulse_duration_ms"],
                    duration_s=levels["pulse_duration_ms"] / 1000.0 + TEST3_D_OBSERVE_S)
    elif block == "E":
        slot.update(disturbance="sinusoid", disturbance_kind="lateral",
                    frequency_hz=levels["frequency_hz"], amplitude_n=levels["amplitude_n"],
                    load_n=levels["amplitude_n"], duration_s=TEST3_E_DURATION_S)
    return slot


def _matched_condition_key(block: str, levels: dict) -> str:
    parts = [block] + [f"{k}={levels[k]:g}" if isinstance(levels[k], float) else f"{k}={levels[k]}"
                       for k in sorted(levels)]
    return "|".join(parts)


def _test3_proposed() -> list[dict[str, Any]]:
    slots: list[dict[str, Any]] = []
    matched_objects = set(MATCHED_OBJECTS)
    envelope = envelope_objects()
    everything = all_objects()

    def matched_slot(block, object_id, extra=None, **levels):
        key = _matched_condition_key(block, levels)
        return _t3_slot(block, object_id, matched=True, condition=key, **levels, **(extra or {}))

    # A natural: every envelope object x 8 directions; ramp rates cycled.
    i = 0
    for object_id in envelope:
        for direction in TEST3_A_DIRECTIONS_DEG:
            ramp = TEST3_A_RAMPS_N_PER_S[i % len(TEST3_A_RAMPS_N_PER_S)]
            if object_id in matched_objects and direction in (0.0, 180.0):
                slots.append(matched_slot("A", object_id, {"ramp": TEST3_A_RAMPS_N_PER_S[1]},
                                          direction_deg=direction))
            else:
                slots.append(_t3_slot("A", object_id, direction_deg=direction, ramp=ramp))
            i += 1
    # A coating probes: 20 per coating, direction 0.
    for i in range(60):
        slots.append(_t3_slot("A", envelope[i % len(envelope)], friction=COATING_LEVELS[i % 3],
                              probe="coating", direction_deg=0.0,
                              ramp=TEST3_A_RAMPS_N_PER_S[(i // 3) % 3]))
    # B: matched cells first, then the remaining counts over all 40 objects.
    cursor = 0
    for direction, frac, n in TEST3_B_CELLS:
        levels = {"direction": direction, "load_frac_w": frac}
        is_matched = ("B", levels) in TEST3_MATCHED
        cell = []
        if is_matched:
            cell += [matched_slot("B", o, **levels) for o in MATCHED_OBJECTS]
        while len(cell) < n:
            cell.append(_t3_slot("B", everything[cursor % len(everything)], **levels))
            cursor += 1
        slots += cell
    # C natural: matched yaw on the ten objects, then 50 more over envelope objects; 30 probes.
    cell = [matched_slot("C", o) for o in MATCHED_OBJECTS]
    others = [o for o in envelope if o not in matched_objects]
    cell += [_t3_slot("C", others[j % len(others)]) for j in range(60 - len(cell))]
    slots += cell
    for i in range(30):
        slots.append(_t3_slot("C", envelope[(7 * i) % len(envelope)], friction=COATING_LEVELS[i % 3],
                              probe="coating"))
    # D: pulses, durations alternating; matched cells first.
    cursor = 0
    for frac, n in TEST3_D_CELLS:
        cell = []
        for duration in TEST3_D_DURATIONS_MS:
            levels = {"load_frac_w": frac, "pulse_duration_ms": duration}
            if ("D", levels) in TEST3_MATCHED:
                cell += [matched_slot("D", o, **levels) for o in MATCHED_OBJECTS]
        j = 0
        while len(cell) < n:
            duration = TEST3_D_DURATIONS_MS[j % 2]
            cell.append(_t3_slot("D", everything[cursor % len(everything)], load_frac_w=frac,
                                 pulse_duration_ms=duration))
            cursor += 1
            j += 1
        slots += cell
    # E: sinusoids, 25 per (frequency, amplitude); matched cells first.
    cursor = 0
    for freq, amp in TEST3_E_CELLS:
        levels = {"frequency_hz": freq, "amplitude_n": amp}
        cell = []
        if ("E", levels) in TEST3_MATCHED:
            cell += [matched_slot("E", o, **levels) for o in MATCHED_OBJECTS]
        while len(cell) < 25:
            cell.append(_t3_slot("E", everything[cursor % len(everything)], **levels))
            cursor += 1
        slots += cell
    return slots


def test3_schedule(seed: int = 0) -> pd.DataFrame:
    """Return the Test 3 (disturbance robustness, §9) commanded-trial sheet.

    Parameters
    ----------
    seed : int
        Protocol seed: run order, session packing and which slots carry the rig faults.

    Returns
    -------
    pandas.DataFrame
        1245 rows (1230 slots, 15 with a rig-fault attempt and its re-run), in run order: 830
        proposed-planner trials (A 240 + 60 coating probes, B 180, C 60 + 30 probes, D 160,
        E 100) and 100 per baseline planner (the matched paired set: ten objects x the ten
        disturbances of ``TEST3_MATCHED``, the proposed planner's counterparts being part of its
        blocks). Disturbance columns are NaN where a block does not use them:
        ``direction_deg`` (lateral azimuth), ``load_frac_w`` (load in units of the object's
        weight), ``load_n``, ``ramp_rate_n_per_s``, ``ramp_cap_n`` (A: 15 N),
        ``torque_ramp_nm_per_s``, ``torque_cap_nm``, ``pulse_duration_ms``, ``frequency_hz``,
        ``amplitude_n``, ``duration_s`` and the retention proof loads ``proof_force_n`` (A: one
        weight) and ``proof_torque_nm`` (C: the weight at the shape's equivalent radius).
    """
    seed = check_seed(seed)
    proposed = _test3_proposed()
    baselines = []
    for s in proposed:
        if s["matched"]:
            s["unit"] = f"M|{s['object_id']}|{s['condition']}"
            baselines += [{**s, "planner": p} for p in BASELINES]
    return schedule_slots(proposed + baselines, STUDY_TEST3, "t3", "block", seed, TEST3_COLUMNS)
