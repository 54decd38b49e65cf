"""The design of Tests 2-3: study names, the object set (shapes, materials, ballasted masses),
planners, friction and coating levels, the groups' counts and levels, and the paper's totals.

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
import math
from typing import Any

import pandas as pd

from graspcampaign.analysis.vocabulary import COATINGS, IMPULSE_LOADS_W, TEST2_GROUP_TRIALS, VERTICAL_LOADS_W

__all__ = [
    "BASELINES",
    "COATING_LEVELS",
    "DEFAULT_CLOSING_MM_PER_S",
    "DEFAULT_LIFT_MM_PER_S",
    "ENVELOPE_INDICES",
    "FRICTION_LEVELS",
    "HEAVY_INDICES",
    "HOLD_S",
    "LIFT_HEIGHT_MM",
    "MATCHED_OBJECTS",
    "OBJECT_MASSES_KG",
    "OBJECT_MATERIALS",
    "PAPER_COUNTS",
    "PLANNER_LABELS",
    "SESSION_SLOTS",
    "SHAPE_ORDER",
    "STUDY_TEST1",
    "STUDY_TEST2",
    "STUDY_TEST3",
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
    "all_objects",
    "envelope_objects",
    "object_row",
    "objects_table",
    "shape_equivalent_radius",
]


STUDY_TEST1 = "test1_bench"  # §7: its measured files are waveforms
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

FRICTION_LEVELS = ("natural", *COATINGS)
"""Contact surface: the object's own material, or a surface coating (§8.6 three friction levels of
Test 2: natural/medium/low; §9.2 coatings of Test 3: high/medium/low)."""
COATING_LEVELS = ("low", "medium", "high")
"""The coatings block A and C trials take in turn: the protocol's order, not the reports' display
order (:data:`~graspcampaign.analysis.vocabulary.COATINGS`, the same names)."""

MATCHED_OBJECTS = ("sphere-01", "sphere-05", "ellipsoid-03", "ellipsoid-07", "rounded_cube-02",
                   "rounded_cube-06", "pear-01", "pear-07", "handle-03", "handle-05")
"""The ten objects of the matched sets of Tests 2 and 3: two per shape, all four materials."""

PAPER_COUNTS = {
    STUDY_TEST2: {"commanded": 1785, "executed": 1755, "aborted": 30,
                  "planners": {"heuristic": 819, "centroid": 474, "no_pso": 90,
                               "force_balance": 90, "random": 282},
                  "groups": TEST2_GROUP_TRIALS,
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
TEST3_B_CELLS = tuple((way, w, n) for (way, w), n in zip(VERTICAL_LOADS_W, (40, 60, 40, 20, 20), strict=True))
"""Block B cells (direction, load [W], trials)."""
TEST3_B_RAMP_N_PER_S = 0.5
TEST3_C_RAMP_NM_PER_S = 0.01
TEST3_C_CAP_NM = 1.0
TEST3_D_CELLS = tuple(zip(IMPULSE_LOADS_W, (40, 40, 60, 10, 10), strict=True))
"""Block D cells (impulse peak [W], trials)."""
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

SCHEDULE_FRONT = ("trial_id", "slot_id", "attempt", "rig_fault", "study", "protocol_seed", "run_order",
                  "day", "session", "session_position")
"""The first columns of a Tests 2-3 schedule: ids and run order (``protocol_order``)."""

TEST2_COLUMNS = ("group", "object_id", "shape", "object_index", "material", "mass_kg", "planner",
                 "planner_label", "plan_key", "friction_level", "pose_err_mm",
                 "closing_speed_mm_per_s", "lift_speed_mm_per_s", "hold_s", "matched", "condition",
                 "repeat")
"""The design columns of the Test 2 schedule, after :data:`SCHEDULE_FRONT`."""

TEST3_COLUMNS = ("block", "disturbance", "disturbance_kind", "probe", "object_id", "shape",
                 "object_index", "material", "mass_kg", "planner", "planner_label", "plan_key",
                 "friction_level", "pose_err_mm", "closing_speed_mm_per_s", "lift_speed_mm_per_s",
                 "hold_s", "direction_deg", "load_frac_w", "load_n", "ramp_rate_n_per_s",
                 "ramp_cap_n", "torque_ramp_nm_per_s", "torque_cap_nm", "pulse_duration_ms",
                 "frequency_hz", "amplitude_n", "duration_s", "proof_force_n", "proof_torque_nm",
                 "matched", "condition", "repeat")
"""The design columns of the Test 3 schedule, after :data:`SCHEDULE_FRONT`."""

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


def object_row(object_id: str) -> dict[str, Any]:
    """Id, shape, index, material and mass of one object, e.g. ``object_row("sphere-03")``."""
    shape, k = object_id.rsplit("-", 1)
    k = int(k)
    return {"object_id": object_id, "shape": shape, "object_index": k,
            "material": OBJECT_MATERIALS[k - 1], "mass_kg": OBJECT_MASSES_KG[k - 1]}


def envelope_objects() -> list[str]:
    """Ids of the envelope objects (``ENVELOPE_INDICES`` of each shape)."""
    return [f"{s}-{k:02d}" for s in SHAPE_ORDER for k in ENVELOPE_INDICES]


def all_objects() -> list[str]:
    """Ids of all 40 objects, shape by shape."""
    return [f"{s}-{k:02d}" for s in SHAPE_ORDER for k in range(1, 9)]
