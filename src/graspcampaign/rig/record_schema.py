"""The measured-records schema of Tests 2-3: one :class:`FieldSpec` per column, and the sheet to
fill in (:func:`record_template`). The checks of a file against it are
:func:`graspcampaign.rig.ingest.validate_records`.

A measured-records file has one row per executed or aborted trial attempt, keyed by the
schedule's ``trial_id`` (a re-run of an aborted slot that the schedule did not foresee may use the
id ``<slot_id>-a<attempt>``). The columns are :data:`TEST2_SCHEMA` (Test 2) or
:data:`TEST3_SCHEMA` (Test 3, the Test 2 columns plus the disturbance measurements), each with its
unit in its name:

=========================  ======  =======================================================
column                     type    meaning, allowed values
=========================  ======  =======================================================
trial_id                   str     a schedule trial id (or a re-run ``<slot_id>-a<k>``)
aborted                    bool    rig fault before load; such rows need nothing else
outcome                    str     stable, success, partial, failure_slip, failure_drop,
                                   failure_damage, failure_contact_loss (``aborted``)
success, stable            bool    binary success (stable or success), stable hold
slip_flag ... contact_     bool    measured failure events (slip, drop, damage, contact
loss_flag                          loss); a failure class must carry its flag, and a drop,
                                   damage or contact loss makes the trial that failure (§8.1)
peak_slip_mm               float   [0, 1000] peak slip in the vision record
sf_actual                  float   [0, 100] post-hoc safety factor
g_geo_actual               float   [0, 1] achieved geometric efficiency
normal_force_{1,2,3}_n     float   [-1, 20] per-finger normal force (~20 N sensors)
normal_force_mean_n        float   [-1, 20]
deformation_{1,2,3}_mm     float   [0, 50] contact deformation (vision)
deformation_mean_mm        float   [0, 50]
max_indentation_mm         float   [0, 100]
contact_point_error_mm     float   [0, 200]
Test 3 only:
threshold_measured_n       float   [0, 50] sustained force at slip (load cell +-50 N)
threshold_measured_nm      float   [0, 1] sustained yaw torque (0-1 N m sensor)
threshold_censored         bool    the ramp ended (cap or commanded level) without slip
first_finger_measured      int     0 (no slip), 1, 2 or 3
rotation_at_limit_deg      float   [-180, 180]
optional: abort_reason (str), environment (str), source (measured | virtual)
=========================  ======  =======================================================

References
----------
SPEC §4 (ingest), paper §8.1 (outcome classes, flags, aborted attempts enter no statistic).
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import pandas as pd

from graspcampaign.rig.protocol import STUDY_TEST2, STUDY_TEST3

#: The words a boolean cell of measured records may hold, any case, true's and false's in pairs:
#: what ingest reads (``ingest._as_bool``, which also takes 1.0/0.0, a spreadsheet's number) and
#: what the template's columns sheet and ingest's refusals list (:data:`BOOLEAN_ALLOWED`).
BOOLEAN_WORDS = (("true", "false"), ("yes", "no"), ("y", "n"), ("t", "f"), ("1", "0"))
BOOLEAN_ALLOWED = ", ".join(f"{yes}/{no}" for yes, no in BOOLEAN_WORDS)
#: The words a cell of measured records may hold, any case, to say "not measured", as an empty
#: cell does: the words of pandas' default missing values (``read_csv``'s ``na_values``) but the
#: spreadsheet errors (``#N/A``: a formula's error is named as one) and the numeric oddities
#: (``-1.#IND``). What ingest reads (``ingest._blank``) and the template's columns sheet
#: lists (:data:`NOT_MEASURED_SAID`); any other text where a number belongs (``-``, ``?``) is
#: refused.
NOT_MEASURED_WORDS = ("NA", "N/A", "NaN", "null", "none")
NOT_MEASURED_SAID = f"empty or {', '.join(NOT_MEASURED_WORDS)} (any case)"

__all__ = [
    "ATTEMPT_TYPO_LIMIT",
    "BOOLEAN_ALLOWED",
    "BOOLEAN_WORDS",
    "DECISIVE",
    "FLAG_OF",
    "FieldSpec",
    "NOT_MEASURED_SAID",
    "NOT_MEASURED_WORDS",
    "OUTCOME_VALUES",
    "SOURCES",
    "TEST2_SCHEMA",
    "TEST3_SCHEMA",
    "UNIT_NAMES",
    "record_columns",
    "record_template",
    "schema_for",
]

OUTCOME_VALUES = ("stable", "success", "partial", "failure_slip", "failure_drop",
                  "failure_damage", "failure_contact_loss", "aborted")
SOURCES = ("measured", "virtual")
#: The failure flag each failure outcome must raise.
FLAG_OF = {"failure_slip": "slip_flag", "failure_drop": "drop_flag",
           "failure_damage": "damage_flag", "failure_contact_loss": "contact_loss_flag"}


ATTEMPT_TYPO_LIMIT = 99
"""The largest attempt number ingest accepts (``<slot_id>-a<k>``, Test 1's ``attempt``): a guard
against typing errors, not a protocol rule (the virtual bench's own retry budget is
``rig.test1_bench.MAX_ATTEMPTS``). The paper re-ran each aborted slot once (§7.1, §8.1, §9.1); a
number past two digits is a slip of the keyboard, which would otherwise be stored as that many
aborted attempts (``attempt = 1e6``: 999,999; docs/decisions.md)."""


@dataclass(frozen=True)
class FieldSpec:
    """One column of the measured-records schema.

    Attributes
    ----------
    name : str
        Column name (unit suffix included).
    kind : {"str", "bool", "float", "int"}
    low, high : float
        Inclusive range of numbers.
    unit : str
        Unit suffix for the wrong-unit check (``""`` for dimensionless or non-numeric).
    executed_required : bool
        Must be present (non-empty) in every non-aborted row.
    optional : bool
        May be missing from the header.
    choices : tuple of str
        Allowed strings (empty: any).
    """

    name: str
    kind: str
    low: float = -math.inf
    high: float = math.inf
    unit: str = ""
    executed_required: bool = False
    optional: bool = False
    choices: tuple[str, ...] = ()


_FLAGS = ("slip_flag", "drop_flag", "damage_flag", "contact_loss_flag")
DECISIVE = ("drop_flag", "damage_flag", "contact_loss_flag")
"""Failure events that class a trial as a failure whatever its hold (§8.1)."""
TEST2_SCHEMA: tuple[FieldSpec, ...] = (
    FieldSpec("trial_id", "str"),
    FieldSpec("aborted", "bool"),
    FieldSpec("outcome", "str", executed_required=True, choices=OUTCOME_VALUES),
    FieldSpec("success", "bool", executed_required=True),
    FieldSpec("stable", "bool", executed_required=True),
    *(FieldSpec(f, "bool", executed_required=True) for f in _FLAGS),
    FieldSpec("peak_slip_mm", "float", 0.0, 1000.0, "mm"),
    FieldSpec("sf_actual", "float", 0.0, 100.0, executed_required=True),
    FieldSpec("g_geo_actual", "float", 0.0, 1.0, executed_required=True),
    *(FieldSpec(f"normal_force_{j}_n", "float", -1.0, 20.0, "n") for j in (1, 2, 3)),
    FieldSpec("normal_force_mean_n", "float", -1.0, 20.0, "n"),
    *(FieldSpec(f"deformation_{j}_mm", "float", 0.0, 50.0, "mm") for j in (1, 2, 3)),
    FieldSpec("deformation_mean_mm", "float", 0.0, 50.0, "mm"),
    FieldSpec("max_indentation_mm", "float", 0.0, 100.0, "mm"),
    FieldSpec("contact_point_error_mm", "float", 0.0, 200.0, "mm"),
    FieldSpec("abort_reason", "str", optional=True),
    FieldSpec("environment", "str", optional=True),
    FieldSpec("source", "str", optional=True, choices=SOURCES),
)
"""Measured columns of a Test 2 record (module docstring)."""
TEST3_SCHEMA: tuple[FieldSpec, ...] = TEST2_SCHEMA + (
    FieldSpec("threshold_measured_n", "float", 0.0, 50.0, "n"),
    FieldSpec("threshold_measured_nm", "float", 0.0, 1.0, "nm"),
    FieldSpec("threshold_censored", "bool"),
    FieldSpec("first_finger_measured", "int", 0.0, 3.0),
    FieldSpec("rotation_at_limit_deg", "float", -180.0, 180.0, "deg"),
)
"""Measured columns of a Test 3 record: Test 2's plus the disturbance measurements."""

def schema_for(study: str) -> tuple[FieldSpec, ...]:
    """Return the schema of ``test2_grasp`` or ``test3_disturbance``."""
    if study == STUDY_TEST2:
        return TEST2_SCHEMA
    if study == STUDY_TEST3:
        return TEST3_SCHEMA
    raise ValueError(f"unknown study {study!r}: expected {STUDY_TEST2!r} or {STUDY_TEST3!r}")


def record_columns(study: str) -> list[str]:
    """Return the measured-record column names of a study, in schema order."""
    return [f.name for f in schema_for(study)]


#: How an ingest message and the record template name each unit suffix.
UNIT_NAMES = {"mm": "mm", "n": "N", "nm": "N m", "deg": "deg"}


def record_template(schedule: pd.DataFrame) -> tuple[pd.DataFrame, pd.DataFrame]:
    """Return the measured-records sheet to fill in, and the description of its columns.

    Returns
    -------
    sheet : pandas.DataFrame
        Every column of the study's schema (:func:`schema_for`), one row per commanded trial with
        its ``trial_id``; every measured cell empty.
    columns : pandas.DataFrame
        ``column, type, unit, allowed, required`` for each column of ``sheet`` (``unit`` ``1`` for
        dimensionless numbers, ``-`` for flags and text).
    """
    schema = schema_for(str(schedule["study"].iloc[0]))
    sheet = pd.DataFrame({spec.name: pd.Series([""] * len(schedule), dtype=object)
                          for spec in schema})
    sheet["trial_id"] = schedule["trial_id"].to_numpy()
    rows = []
    for spec in schema:
        if spec.kind in ("float", "int"):
            unit = UNIT_NAMES.get(spec.unit, spec.unit) or "1"
            allowed = f"{spec.kind} in [{spec.low:g}, {spec.high:g}]"
        else:
            unit = "-"
            allowed = (BOOLEAN_ALLOWED if spec.kind == "bool"
                       else ", ".join(spec.choices) if spec.choices else "text")
        required = ("every row" if spec.name in ("trial_id", "aborted")
                    else "optional column" if spec.optional
                    else "executed rows" if spec.executed_required else "column required, cells "
                    f"may be {NOT_MEASURED_SAID}: not measured")
        rows.append({"column": spec.name, "type": spec.kind, "unit": unit, "allowed": allowed,
                     "required": required})
    return sheet, pd.DataFrame(rows)
