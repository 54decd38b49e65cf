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

The paper fixes the totals; where it leaves a split open, the split chosen here is recorded in
``docs/decisions.md`` ("Tests 2-3 protocols and virtual rig (issue 9)") and in the constants below.

References
----------
Paper §8.1 (objects, groups A-E, matched ablation, baselines, pose error, 1785/1755), §8.6
(group C, group E speed levels 20/80/20), Table 6 (per-shape n), Table 7 (per-planner n),
§9.1-9.5 and Tables 8-9 (blocks, levels, n, coating probes, matched paired set, 1245/1230).
"""

from __future__ import annotations

import functools
import hashlib
import json
import logging
import math
from collections import Counter, defaultdict
from typing import Any

import numpy as np
import pandas as pd

from graspcampaign.core.statics import GRAVITY

__all__ = [
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
    "test2_schedule",
    "test3_schedule",
]

logger = logging.getLogger(__name__)

STUDY_TEST2 = "test2_grasp"
STUDY_TEST3 = "test3_disturbance"

SHAPE_ORDER = ("sphere", "ellipsoid", "rounded_cube", "pear", "handle")
"""The five shape families of §8.1 (the paper's "concave" shape is our ``handle``)."""
OBJECT_MATERIALS = ("gel", "gel", "silicone_soft", "silicone_soft", "bio_foam", "bio_foam",
                    "silicone_ref", "silicone_ref")
"""Material of objects 1-8 of every shape: two per Table 4 family (§8.1: four materials)."""
OBJECT_MASSES_KG = (0.05, 0.10, 0.20, 0.60, 0.10, 0.15, 0.25, 0.60)
"""Ballasted mass of objects 1-8 of every shape [kg] (decision, docs/decisions.md): inside the
envelope the calibrated planner predicts for each material -- 0.5 and 0.8 times the heaviest mass
it can lift at SF 1.5 with G_geo = 1 under the damage cap (gel 0.12, silicone-soft 0.25, foam 0.19,
silicone-ref 0.33 kg), rounded to 0.05 kg -- except the second object of each silicone, ballasted
to the paper's 0.6 kg maximum: group C's "lowest-friction materials with the highest masses"."""
HEAVY_INDICES = (4, 8)
ENVELOPE_INDICES = (1, 2, 3, 5, 6, 7)
"""Objects used by the validation groups (everything below the 0.6 kg failure-boundary ballast)."""

PLANNER_LABELS = {"heuristic": "proposed", "no_pso": "no-PSO", "centroid": "centroid",
                  "force_balance": "force-balance", "random": "random"}
"""Registry name -> the paper's name of the five planners (§8.1)."""
BASELINES = ("no_pso", "centroid", "force_balance", "random")

FRICTION_LEVELS = ("natural", "high", "medium", "low")
"""Contact surface: the object's own material, or a surface coating (§8.6 three friction levels of
Test 2: natural/medium/low; §9.2 coatings of Test 3: high/medium/low)."""
COATING_LEVELS = ("low", "medium", "high")

MATCHED_OBJECTS = ("sphere-01", "sphere-05", "ellipsoid-03", "ellipsoid-07", "rounded_cube-02",
                   "rounded_cube-06", "pear-01", "pear-07", "handle-03", "handle-05")
"""The ten objects of the matched sets of Tests 2 and 3: two per shape, all four materials."""

PAPER_COUNTS = {
    STUDY_TEST2: {"commanded": 1785, "executed": 1755, "aborted": 30,
                  "planners": {"heuristic": 819, "centroid": 474, "no_pso": 90,
                               "force_balance": 90, "random": 282},
                  "groups": {"A": 120, "B": 240, "C": 144, "D": 105, "E": 120, "M": 90},
                  "shapes": {"sphere": 183, "ellipsoid": 135, "rounded_cube": 231, "pear": 111,
                             "handle": 159}},
    STUDY_TEST3: {"commanded": 1245, "executed": 1230, "aborted": 15,
                  "planners": {"heuristic": 830, "centroid": 100, "no_pso": 100,
                               "force_balance": 100, "random": 100},
                  "blocks": {"A": 300, "B": 180, "C": 90, "D": 160, "E": 100}},
}
"""The paper's design counts (§8.1, Table 6-7; §9.1, Tables 8-9)."""

# ------------------------------------------------------------------ Test 2 design constants
TEST2_C_PER_SHAPE = {"sphere": 6, "ellipsoid": 36, "rounded_cube": 66, "pear": 6, "handle": 30}
"""Group C (144) per shape: with A, B, D, E and the matched set, every shape's proposed total is
Table 6's n (183/135/231/111/159)."""
TEST2_C_CELLS = ((4, "natural"), (8, "natural"), (3, "medium"), (7, "medium"), (3, "low"),
                 (7, "low"))
"""Group C cells (object index, friction level), cycled: the 0.6 kg silicones at natural friction
and the lighter silicones on the medium and low coatings -- 48 trials per friction level."""
TEST2_D_OBJECTS = ("sphere-07", "ellipsoid-06", "rounded_cube-01", "rounded_cube-07", "pear-03",
                   "handle-05", "handle-07")
"""Group D (repeatability): seven objects x 15 repeats = 105."""
TEST2_E_PER_SHAPE = {"sphere": 24, "ellipsoid": 6, "rounded_cube": 57, "pear": 12, "handle": 21}
TEST2_E_CELLS = ((10.0, 30.0), (5.0, 30.0), (10.0, 30.0), (20.0, 30.0), (10.0, 10.0),
                 (10.0, 50.0))
"""Group E (closing, lift) speeds [mm/s], cycled: 20/80/20 trials per closing level and per lift
level (§8.6), one factor at a time around the default (10, 30)."""
TEST2_M_CONDITIONS = {"c1": ("natural", 0.0), "c2": ("natural", 10.0), "c3": ("medium", 0.0)}
"""The matched set's three conditions (friction level, pose error [mm])."""
TEST2_X_COUNTS = {"centroid": 384, "random": 192}
"""Baseline trials outside the matched set (group X), so centroid = 474 and random = 282."""
DEFAULT_CLOSING_MM_PER_S = 10.0
DEFAULT_LIFT_MM_PER_S = 30.0
HOLD_S = 3.0
"""Hold after lift before grading / before the disturbance [s] (§9.1: 3 s)."""
LIFT_HEIGHT_MM = 50.0
"""Lift height [mm] (§8.3: "the object lifts smoothly to 50 mm")."""

# ------------------------------------------------------------------ Test 3 design constants
TEST3_A_DIRECTIONS_DEG = tuple(float(a) for a in range(0, 360, 45))
TEST3_A_RAMPS_N_PER_S = (0.2, 0.6, 1.0)
TEST3_A_CAP_N = 15.0
TEST3_B_CELLS = (("down", 0.25, 40), ("down", 0.50, 60), ("down", 0.75, 40), ("up", 0.50, 20),
                 ("up", 1.00, 20))
TEST3_B_RAMP_N_PER_S = 0.5
TEST3_C_RAMP_NM_PER_S = 0.01
TEST3_C_CAP_NM = 1.0
TEST3_D_CELLS = ((0.8, 40), (1.0, 40), (1.2, 60), (1.4, 10), (1.8, 10))
TEST3_D_DURATIONS_MS = (100.0, 200.0)
TEST3_D_OBSERVE_S = 2.0
TEST3_E_CELLS = ((1.0, 1.0), (1.0, 2.0), (2.0, 1.0), (2.0, 2.0))
"""Sinusoid (frequency [Hz], amplitude [N]), 25 trials each."""
TEST3_E_DURATION_S = 5.0
TEST3_MATCHED = (
    ("A", {"direction_deg": 0.0}), ("A", {"direction_deg": 180.0}),
    ("B", {"direction": "down", "load_frac_w": 0.25}), ("B", {"direction": "down", "load_frac_w": 0.5}),
    ("B", {"direction": "up", "load_frac_w": 1.0}),
    ("C", {}),
    ("D", {"load_frac_w": 1.0, "pulse_duration_ms": 100.0}),
    ("D", {"load_frac_w": 1.2, "pulse_duration_ms": 200.0}),
    ("E", {"frequency_hz": 1.0, "amplitude_n": 1.0}), ("E", {"frequency_hz": 2.0, "amplitude_n": 2.0}),
)
"""The ten identical disturbances of the matched paired set (one per object and planner)."""

SESSION_SLOTS = 45
"""Trial slots per session (decision: a half-day at ~4 min per trial); two sessions per day."""

_HASH_LEN = 10


# --------------------------------------------------------------------------------------------
# Objects
# --------------------------------------------------------------------------------------------
def objects_table() -> pd.DataFrame:
    """Return the 40 objects of §8.1: 5 shapes x 8, two per material, ballast up to 0.6 kg."""
    rows = []
    for shape in SHAPE_ORDER:
        for k in range(1, 9):
            rows.append({"object_id": f"{shape}-{k:02d}", "shape": shape, "object_index": k,
                         "material": OBJECT_MATERIALS[k - 1], "mass_kg": OBJECT_MASSES_KG[k - 1],
                         "heavy": k in HEAVY_INDICES})
    return pd.DataFrame(rows)


@functools.lru_cache(maxsize=16)
def shape_equivalent_radius(shape: str, n_nodes: int = 390) -> float:
    """Return the area-equivalent radius of the shape's equatorial section [m].

    ``d_opt / sqrt(3)`` of :func:`graspcampaign.core.metric.default_d_opt` (50 mm on the sphere):
    the lever of the Test 3 proof torque ``W R_eq``.
    """
    from graspcampaign.core.mesh import make_object
    from graspcampaign.core.metric import default_d_opt

    return float(default_d_opt(make_object(shape, n_nodes)) / math.sqrt(3.0))


def _object(object_id: str) -> dict[str, Any]:
    shape, k = object_id.rsplit("-", 1)
    k = int(k)
    return {"object_id": object_id, "shape": shape, "object_index": k,
            "material": OBJECT_MATERIALS[k - 1], "mass_kg": OBJECT_MASSES_KG[k - 1]}


def _envelope_objects() -> list[str]:
    return [f"{s}-{k:02d}" for s in SHAPE_ORDER for k in ENVELOPE_INDICES]


def _all_objects() -> list[str]:
    return [f"{s}-{k:02d}" for s in SHAPE_ORDER for k in range(1, 9)]


# --------------------------------------------------------------------------------------------
# Ids, run order, rig faults
# --------------------------------------------------------------------------------------------
def _canonical(obj: Any) -> str:
    return json.dumps(obj, sort_keys=True, separators=(",", ":"), default=str)


def _digest(obj: Any, length: int = _HASH_LEN) -> str:
    return hashlib.sha256(_canonical(obj).encode()).hexdigest()[:length]


_SHORT = {"heuristic": "prop", "no_pso": "nopso", "centroid": "cent", "force_balance": "fb",
          "random": "rand"}


def _with_ids(slots: list[dict[str, Any]], study: str, prefix: str, key: str) -> None:
    """Give every slot a readable, content-derived id; identical slots get repeat indices."""
    seen: Counter = Counter()
    for s in slots:
        design = {k: v for k, v in s.items() if k not in ("repeat", "unit")}
        cell = _canonical(design)
        s["repeat"] = seen[cell]
        seen[cell] += 1
        digest = _digest({"study": study, **design, "repeat": s["repeat"]})
        s["slot_id"] = f"{prefix}{s[key]}-{s['object_id']}-{_SHORT[s['planner']]}-{digest}"


def _plan_keys(slots: list[dict[str, Any]]) -> None:
    """Plans are shared per (object, planner); the random planner draws a new triple per slot."""
    for s in slots:
        if s["planner"] == "random":
            s["plan_key"] = f"{s['object_id']}:random:{s['slot_id']}"
        else:
            s["plan_key"] = f"{s['object_id']}:{s['planner']}"


def _order(slots: list[dict[str, Any]], rng: np.random.Generator, n_faults: int) -> list[dict]:
    """Shuffle units into sessions of SESSION_SLOTS, shuffle inside sessions, add fault re-runs."""
    units: dict[str, list[int]] = defaultdict(list)
    for i, s in enumerate(slots):
        units[s.get("unit") or s["slot_id"]].append(i)
    keys = list(units)
    rng.shuffle(keys)
    sessions: list[list[int]] = [[]]
    for k in keys:
        if sessions[-1] and len(sessions[-1]) + len(units[k]) > SESSION_SLOTS:
            sessions.append([])
        sessions[-1].extend(units[k])
    faulty = set(rng.choice(len(slots), size=n_faults, replace=False).tolist())
    rows: list[dict] = []
    order = 0
    for index, members in enumerate(sessions):
        members = list(members)
        rng.shuffle(members)
        reruns = []
        day, half = divmod(index, 2)
        session = f"d{day + 1:02d}-{'am' if half == 0 else 'pm'}"
        for position, i in enumerate(members, start=1):
            order += 1
            row = {**slots[i], "attempt": 1, "rig_fault": i in faulty, "day": day + 1,
                   "session": session, "session_position": position, "run_order": order}
            rows.append(row)
            if i in faulty:
                reruns.append(i)
        for i in reruns:  # aborted slots are re-run at the end of their session
            order += 1
            rows.append({**slots[i], "attempt": 2, "rig_fault": False, "day": day + 1,
                         "session": session, "session_position": len(members) + 1 + reruns.index(i),
                         "run_order": order})
    return rows


def _finish(rows: list[dict], study: str, seed: int, columns: list[str]) -> pd.DataFrame:
    for r in rows:
        r["trial_id"] = r["slot_id"] if r["attempt"] == 1 else f"{r['slot_id']}-a{r['attempt']}"
        r["study"] = study
        r["protocol_seed"] = int(seed)
        r["planner_label"] = PLANNER_LABELS[r["planner"]]
        r.pop("unit", None)
    df = pd.DataFrame(rows)
    front = ["trial_id", "slot_id", "attempt", "rig_fault", "study", "protocol_seed", "run_order",
             "day", "session", "session_position"]
    rest = [c for c in columns if c not in front]
    extra = [c for c in df.columns if c not in front + rest]
    return df[front + rest + extra].reset_index(drop=True)


def _schedule(slots: list[dict[str, Any]], study: str, prefix: str, key: str, seed: int,
              columns: list[str]) -> pd.DataFrame:
    """Id, plan-key, order (with the paper's rig faults) and tabulate one study's slots."""
    _with_ids(slots, study, prefix, key)
    _plan_keys(slots)
    rows = _order(slots, _rng(seed, study), PAPER_COUNTS[study]["aborted"])
    return _finish(rows, study, seed, columns)


def _check_seed(seed: object) -> int:
    if isinstance(seed, bool) or not isinstance(seed, (int, np.integer)) or seed < 0:
        raise ValueError(f"seed must be a non-negative int, got {seed!r}")
    return int(seed)


def _rng(seed: int, study: str) -> np.random.Generator:
    word = int.from_bytes(hashlib.sha256(study.encode()).digest()[:4], "little")
    return np.random.default_rng(np.random.SeedSequence([seed, word]))


# --------------------------------------------------------------------------------------------
# Test 2
# --------------------------------------------------------------------------------------------
def _t2_slot(group: str, object_id: str, planner: str = "heuristic", *, friction: str = "natural",
             pose: float = 0.0, closing: float = DEFAULT_CLOSING_MM_PER_S,
             lift: float = DEFAULT_LIFT_MM_PER_S, matched: bool = False, condition: str = "",
             unit: str | None = None) -> dict[str, Any]:
    return {"group": group, **_object(object_id), "planner": planner, "friction_level": friction,
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
    envelope = _envelope_objects()
    for planner, count in TEST2_X_COUNTS.items():
        for i in range(count):
            pose = (0.0, 10.0)[(i // len(envelope)) % 2]
            slots.append(_t2_slot("X", envelope[i % len(envelope)], planner, pose=pose))
    return slots


TEST2_COLUMNS = ["group", "object_id", "shape", "object_index", "material", "mass_kg", "planner",
                 "planner_label", "plan_key", "friction_level", "pose_err_mm",
                 "closing_speed_mm_per_s", "lift_speed_mm_per_s", "hold_s", "matched", "condition",
                 "repeat"]


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
    seed = _check_seed(seed)
    return _schedule(_test2_slots(), STUDY_TEST2, "t2", "group", seed, TEST2_COLUMNS)


# --------------------------------------------------------------------------------------------
# Test 3
# --------------------------------------------------------------------------------------------
def _t3_slot(block: str, object_id: str, planner: str = "heuristic", *, friction: str = "natural",
             probe: str = "", matched: bool = False, condition: str = "", **levels) -> dict:
    obj = _object(object_id)
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
    envelope = _envelope_objects()
    everything = _all_objects()

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


TEST3_COLUMNS = ["block", "disturbance", "disturbance_kind", "probe", "object_id", "shape",
                 "object_index", "material", "mass_kg", "planner", "planner_label", "plan_key",
                 "friction_level", "pose_err_mm", "closing_speed_mm_per_s", "lift_speed_mm_per_s",
                 "hold_s", "direction_deg", "load_frac_w", "load_n", "ramp_rate_n_per_s",
                 "ramp_cap_n", "torque_ramp_nm_per_s", "torque_cap_nm", "pulse_duration_ms",
                 "frequency_hz", "amplitude_n", "duration_s", "proof_force_n", "proof_torque_nm",
                 "matched", "condition", "repeat"]


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
    seed = _check_seed(seed)
    proposed = _test3_proposed()
    baselines = []
    for s in proposed:
        if s["matched"]:
            s["unit"] = f"M|{s['object_id']}|{s['condition']}"
            baselines += [{**s, "planner": p} for p in BASELINES]
    return _schedule(proposed + baselines, STUDY_TEST3, "t3", "block", seed, TEST3_COLUMNS)
