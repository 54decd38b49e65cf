"""Ingest of measured Tests 2-3 per-trial records (CSV, XLSX, Parquet) against a documented schema.

A measured-records file has one row per executed or aborted trial attempt, keyed by the
schedule's ``trial_id``; its columns, with their types, units and ranges, are the schema of
:mod:`graspcampaign.rig.record_schema` (:data:`TEST2_SCHEMA`, :data:`TEST3_SCHEMA`).

Float cells may be empty (not measured) except ``sf_actual``, ``g_geo_actual`` and the flags of
an executed row. ``normal_force_mean_n`` and ``deformation_mean_mm`` are the means of the fingers'
values recorded beside them, within :data:`MEAN_REL_TOL` plus :data:`MEAN_ABS_TOL`. Validation
stops at the first problem and raises :class:`IngestError` with one sentence naming the file, the
1-based data row (header excluded) and the column; nothing is returned, so a caller that stores
only after validation changes nothing on bad input.

References
----------
SPEC §4 (ingest), paper §8.1 (outcome classes, flags, aborted attempts enter no statistic).
"""

from __future__ import annotations

import logging
import math
import re
from collections.abc import Collection, Sequence
from pathlib import Path

import numpy as np
import pandas as pd

from graspcampaign.rig.file_kinds import other_files
from graspcampaign.rig.measured_file import (
    IngestError,
    aside,
    cell_problem,
    empty_row,
    header_problems,
    ingest_error,
    read_table,
    table_and_label,
)
from graspcampaign.rig.record_schema import (
    ATTEMPT_TYPO_LIMIT,
    BOOLEAN_ALLOWED,
    BOOLEAN_WORDS,
    DECISIVE,
    FLAG_OF,
    NOT_MEASURED_SAID,
    NOT_MEASURED_WORDS,
    UNIT_NAMES,
    FieldSpec,
    schema_for,
)

__all__ = [
    "IngestError",
    "case_hint",
    "check_one_source",
    "header_problems",
    "read_records",
    "read_table",
    "refuse_larger",
    "validate_records",
]

logger = logging.getLogger(__name__)

_UNIT_RE = re.compile(r"^(?P<stem>.+)_(?P<unit>mm|m|cm|um|n|kn|mn|nm|nmm|deg|rad|s|ms|kg|g)$")
_TRUE = {yes for yes, _ in BOOLEAN_WORDS} | {"1.0"}
_FALSE = {no for _, no in BOOLEAN_WORDS} | {"0.0"}
_BOOLEAN = f"a boolean ({BOOLEAN_ALLOWED})"  # what a boolean cell must hold
_NOT_MEASURED = {word.lower() for word in NOT_MEASURED_WORDS}


MAX_RECORDS_BYTES = 32 * 2**20
"""The largest records file read: 16x the full Test 2 sheet with every commanded column beside the
records (2 MiB); a 200 MiB file took a minute and 3 GiB to refuse (docs/decisions.md)."""


def refuse_larger(path: str | Path, limit: int, files: str, largest: str) -> None:
    """Refuse the file ``path`` unread when it is over ``limit`` bytes: "a file of ``files`` is at most
    ..." with ``largest``, what the limit is drawn from (the largest file the protocol makes)."""
    def size(n: int) -> str:  # MiB below 1 GiB, else GiB; rounded up to 0.1 (just over is not "at" it)
        unit, scale = ("MiB", 2**20) if n < 2**30 else ("GiB", 2**30)
        return f"{math.ceil(n / scale * 10) / 10:g} {unit}"
    path = Path(path)
    if path.is_file() and (n := path.stat().st_size) > limit:
        raise IngestError(f"{path.name}: the file is {size(n)}, and a file of {files} is at most "
                          f"{size(limit)} ({largest}); check it is the right file.")


def read_records(path: str | Path) -> pd.DataFrame:
    """Read a records file (``.csv``, ``.parquet``/``.pq``, ``.xlsx``) without checks.

    Every CSV cell stays a string (the checks parse them), and no cell's word is read as missing
    (a CSV's or a workbook's: `_blank` reads NOT_MEASURED_WORDS); see :func:`read_table`. A file over
    :data:`MAX_RECORDS_BYTES` is refused unread.
    """
    refuse_larger(path, MAX_RECORDS_BYTES, "trial records",
                  "the whole Test 2 sheet with its commanded columns is 2 MiB")
    return read_table(path, csv_options={"dtype": str, "keep_default_na": False},
                      excel_options={"dtype": object, "keep_default_na": False,
                                     "na_values": [""]})


def _empty(value) -> bool:
    """Whether a cell is empty: nothing, blank text, or a reader's missing value (NaN, NA)."""
    if value is None:
        return True
    if isinstance(value, float) and math.isnan(value):
        return True
    if value is pd.NA or value is pd.NaT:
        return True
    return isinstance(value, str) and not value.strip()


def _blank(value) -> bool:
    """Whether a cell says not measured: empty, or one of ``NOT_MEASURED_WORDS`` (any case)."""
    return _empty(value) or isinstance(value, str) and value.strip().lower() in _NOT_MEASURED


def _as_bool(value) -> bool | None:
    if isinstance(value, (bool, np.bool_)):
        return bool(value)
    if isinstance(value, (int, np.integer)) and value in (0, 1):
        return bool(value)
    if isinstance(value, (float, np.floating)) and value in (0.0, 1.0):
        return bool(value)
    text = str(value).strip().lower()
    if text in _TRUE:
        return True
    if text in _FALSE:
        return False
    return None


def _as_float(value) -> float | None:
    """A cell's number, or None. Text with an underscore is none: Python's float reads '1_4' as
    14 (digit grouping), which no spreadsheet writes, so it is a typo, not fourteen."""
    if isinstance(value, (bool, np.bool_)) or (isinstance(value, str) and "_" in value):
        return None
    try:
        return float(value)
    except (TypeError, ValueError):
        return None


def _check_header(df: pd.DataFrame, schema, label: str, commanded: Collection[str],
                  study: str) -> None:
    columns = [str(c) for c in df.columns]
    problems = header_problems(columns, [s.name for s in schema if not s.optional],
                               {s.name: s.unit for s in schema}, _UNIT_RE,
                               [s.name for s in schema if s.optional], commanded,
                               df.attrs.get("other_sheets"), df.head(5).to_numpy().tolist(),
                               df.attrs.get("filled_sheets", ()), other_files(study))
    if problems:
        raise IngestError(f"{label}, header: {'; '.join(problems)} (`graspcampaign schedule "
                          "<study> --template` writes a sheet with every column).")


def validate_records(data: pd.DataFrame | str | Path, schedule: pd.DataFrame,
                     file_label: str | None = None) -> pd.DataFrame:
    """Validate measured per-trial records against the schedule and the study's schema.

    Checks, in order: file type and readability, at least one row, the header (every schema
    column present; a known quantity with another unit suffix is reported as wrong units; no
    column outside the schema but the commanded sheet's own, which are accepted and not read),
    ``trial_id`` present, ``aborted`` a boolean, then per executed row every column's type and
    range (booleans, numbers, allowed strings, required cells non-empty), known trial ids (the
    schedule's, or a re-run ``<slot_id>-a<k>`` of a known slot), no duplicate ``trial_id``, at
    most one executed record per slot, and the §8.1 consistency of ``outcome`` with
    ``success``/``stable`` and with its failure flag.

    Parameters
    ----------
    data : DataFrame or path
        The records, or a CSV/XLSX/Parquet file.
    schedule : pandas.DataFrame
        The study's schedule (its ``study`` column selects the schema).
    file_label : str, optional
        Name used in messages; default the file name (``"<dataframe>"`` for a frame).

    Returns
    -------
    pandas.DataFrame
        The schema columns with clean dtypes (bool columns are object arrays holding True/False
        or None on aborted rows), plus ``slot_id`` and ``attempt`` from the schedule and
        ``source`` (``"measured"`` unless the file says ``"virtual"``), in file order.

    Raises
    ------
    IngestError
        One sentence naming the file, the 1-based data row (header excluded) and the column.
    """
    df, label = table_and_label(data, file_label, read_records)
    if not isinstance(df, pd.DataFrame):
        raise IngestError(f"{label}: expected a table, got "
                          f"{type(df).__name__}.")
    studies = schedule["study"].unique().tolist() if "study" in schedule else []
    if len(studies) != 1:
        raise ValueError(f"the schedule must hold exactly one study, got {studies}")
    schema = schema_for(str(studies[0]))
    df = df.reset_index(drop=True)
    df.columns = [str(c).strip() for c in df.columns]
    # first: it names a sheet holding records
    _check_header(df, schema, label, schedule.columns, str(studies[0]))
    if len(df) == 0:
        raise ingest_error(label, None, "trial_id", "the file has no data rows")

    n = len(df)
    ids = []
    for i, value in enumerate(df["trial_id"].tolist()):
        if _empty(value):  # 'NA' is an id the schedule does not have, not an empty cell
            raise empty_row(label, df, i + 1) or ingest_error(label, i + 1, "trial_id",
                                                              "trial id is empty")
        ids.append(str(value).strip())
    aborted = []
    for i, value in enumerate(df["aborted"].tolist()):
        flag = _as_bool(value)
        if flag is None and _not_scheduled(ids[i], schedule):  # a 'Total' row below the trials
            raise ingest_error(label, i + 1, "trial_id", f"trial id '{ids[i]}' is not in the schedule")
        if flag is None and all(_blank(v) for v in df.iloc[i].drop("trial_id")):  # the template's
            raise ingest_error(label, i + 1, "aborted", "the row is not filled in (only its "
                               "trial_id); a file holds the trials run: delete the rows not run yet")
        if flag is None:
            raise ingest_error(label, i + 1, "aborted", cell_problem(value, _BOOLEAN))
        aborted.append(flag)

    out: dict[str, list] = {"trial_id": ids, "aborted": aborted}
    for spec in schema:
        if spec.name in ("trial_id", "aborted"):
            continue
        if spec.name not in df.columns:
            out[spec.name] = [None] * n
            continue
        values = df[spec.name].tolist()
        clean: list = []
        for i, value in enumerate(values):
            executed = not aborted[i]
            if _blank(value):
                if executed and spec.executed_required:
                    said = ("value is empty" if _empty(value) else
                            f"value {value.strip()!r} means not measured,")
                    raise ingest_error(label, i + 1, spec.name, f"{said} but the trial was "
                                       "executed (aborted is false)")
                if spec.kind in ("float", "int"):
                    clean.append(math.nan)
                else:
                    clean.append("" if spec.kind == "str" and spec.optional else None)
                continue
            clean.append(_parse(spec, value, label, i + 1))
        out[spec.name] = clean
    clean_df = pd.DataFrame(out)

    _check_ids(clean_df, schedule, label)
    _check_consistency(clean_df, label)
    _check_means(clean_df, label)
    sources = clean_df["source"].where(clean_df["source"].fillna("") != "", "measured")
    clean_df["source"] = sources.astype(object)
    check_one_source([(label, i + 1, v) for i, v in enumerate(clean_df["source"])])
    for spec in schema:
        if spec.kind in ("float", "int"):  # int columns stay float: empty cells are NaN
            clean_df[spec.name] = clean_df[spec.name].astype(float)
    return clean_df


def case_hint(what: str, given: str, known: Collection[str]) -> str:
    """`` (trial ids are case-sensitive: 'T2A-…'?)``: the id of ``known`` that ``given`` (an id
    of ``what``, "trial" or "event", not among them) spells in another case, or ``""``."""
    same = next((k for k in known if k.lower() == str(given).lower()), None)
    return f" ({what} ids are case-sensitive: '{same}'?)" if same else ""


def check_one_source(rows: Sequence[tuple[str, int, str]], stored: pd.DataFrame | None = None) -> None:
    """Refuse records of more than one source in a run: ``rows`` are (file, 1-based row,
    source) of the files being ingested, ``stored`` the run's stored records (None: a new run).

    A run is measured on a rig or exported from a virtual rig or bench, never both: its report
    labels the whole run by its source, and pooling the two would mix hardware and model data.
    """
    first = None if stored is None or "source" not in stored else next(iter(stored["source"].dropna()), None)
    where = "the run's stored records"
    for label, row, source in rows:
        if first is None:
            first, where = source, f"{label}, row {row}"
        elif source != first:
            raise ingest_error(label, row, "source", f"value '{source}' differs from '{first}' in {where}; "
                               "a run holds the records of one source (measured or virtual): ingest the "
                               "others into another run with --run")


def _parse(spec: FieldSpec, value, label: str, row: int):
    if spec.kind == "bool":
        flag = _as_bool(value)
        if flag is None:
            raise ingest_error(label, row, spec.name, cell_problem(value, _BOOLEAN))
        return flag
    if spec.kind == "str":
        text = str(value).strip()
        if spec.choices and text not in spec.choices:
            raise ingest_error(label, row, spec.name, f"value {text!r}{aside(text, spec.choices)} is "
                               f"not one of {', '.join(spec.choices)}")
        return text
    number = _as_float(value)
    if number is None:  # a dash or a question mark: a mark for not measured, not its word
        mark = isinstance(value, str) and not any(c.isalnum() for c in value)
        raise ingest_error(label, row, spec.name, cell_problem(value) + (
            f"; a cell not measured is {NOT_MEASURED_SAID}" if mark else ""))
    if not math.isfinite(number):
        raise ingest_error(label, row, spec.name, f"value {value!r} is not finite")
    if spec.kind == "int" and number != int(number):
        raise ingest_error(label, row, spec.name, f"value {value!r} is not an integer")
    if not spec.low <= number <= spec.high:
        unit = f" {UNIT_NAMES.get(spec.unit, spec.unit)}" if spec.unit else ""
        raise ingest_error(label, row, spec.name, f"value {number:g} lies outside "
                           f"[{spec.low:g}, {spec.high:g}]{unit} (wrong units?)")
    return number


#: a re-run's trial id, ``<slot_id>-a<k>`` (``protocol_order`` writes it)
_RERUN_ID = re.compile(r"(?P<slot>.+)-a(?P<k>[0-9]+)")


def _not_scheduled(tid: str, schedule: pd.DataFrame) -> bool:
    """Whether trial id ``tid`` is neither the schedule's nor a re-run ``<slot_id>-a<k>`` of one of
    its slots (whatever ``k``: :func:`_check_ids` names a wrong attempt number)."""
    m = _RERUN_ID.fullmatch(tid)
    return not ((schedule["trial_id"] == tid).any() or m and (schedule["slot_id"] == m["slot"]).any())


def _check_ids(df: pd.DataFrame, schedule: pd.DataFrame, label: str) -> None:
    known = dict(zip(schedule["trial_id"], schedule["slot_id"], strict=True))
    attempts = dict(zip(schedule["trial_id"], schedule["attempt"], strict=True))
    slots = set(schedule["slot_id"])
    slot_col, attempt_col = [], []
    for i, tid in enumerate(df["trial_id"]):
        if tid in known:
            slot_col.append(known[tid])
            attempt_col.append(int(attempts[tid]))
            continue
        m = _RERUN_ID.fullmatch(tid)
        if m and m["slot"] in slots and 2 <= int(m["k"]) <= ATTEMPT_TYPO_LIMIT:
            slot_col.append(m["slot"])
            attempt_col.append(int(m["k"]))
            continue
        if m and m["slot"] in slots:
            raise ingest_error(label, i + 1, "trial_id", f"trial id '{tid}' names attempt {m['k']} of slot "
                               f"'{m['slot']}'; a re-run is attempt 2 to {ATTEMPT_TYPO_LIMIT}")
        raise ingest_error(label, i + 1, "trial_id", f"trial id '{tid}' is not in the schedule"
                           f"{case_hint('trial', tid, known)}")
    dup = df["trial_id"].duplicated(keep="first")
    if dup.any():
        i = int(np.flatnonzero(dup.to_numpy())[0])
        first = int(np.flatnonzero((df["trial_id"] == df["trial_id"].iloc[i]).to_numpy())[0])
        raise ingest_error(label, i + 1, "trial_id", f"duplicate trial id '{df['trial_id'].iloc[i]}' "
                           f"(first seen in row {first + 1})")
    df["slot_id"] = slot_col
    df["attempt"] = attempt_col
    executed = ~df["aborted"].astype(bool)
    twice = df["slot_id"].where(executed).duplicated(keep="first") & executed
    if twice.any():
        i = int(np.flatnonzero(twice.to_numpy())[0])
        slot = df["slot_id"].iloc[i]
        first = int(np.flatnonzero(((df["slot_id"] == slot) & executed).to_numpy())[0])
        raise ingest_error(label, i + 1, "aborted", f"slot '{slot}' already has an executed record in "
                           f"row {first + 1}; only one attempt per slot may be executed")


def _check_consistency(df: pd.DataFrame, label: str) -> None:
    for i, row in enumerate(df.itertuples(index=False)):
        if row.aborted:
            if row.outcome not in (None, "aborted"):
                raise ingest_error(label, i + 1, "outcome", f"outcome is '{row.outcome}' on a row whose "
                                   "aborted flag is true (an aborted attempt has no outcome: leave it empty "
                                   "or write aborted)")
            continue
        outcome = row.outcome
        if outcome == "aborted":
            raise ingest_error(label, i + 1, "outcome", "outcome 'aborted' on a row whose aborted flag "
                               "is false")
        if bool(row.success) != (outcome in ("stable", "success")):
            raise ingest_error(label, i + 1, "success", f"success is {row.success} but outcome is "
                               f"'{outcome}' (success means outcome stable or success, §8.1)")
        if bool(row.stable) != (outcome == "stable"):
            raise ingest_error(label, i + 1, "stable", f"stable is {row.stable} but outcome is "
                               f"'{outcome}'")
        flag = FLAG_OF.get(outcome)
        if flag and not getattr(row, flag):
            raise ingest_error(label, i + 1, flag, f"outcome is '{outcome}' but {flag} is false "
                               "(every failure class carries its flag, §8.1)")
        finger = getattr(row, "first_finger_measured", math.nan)
        if getattr(row, "threshold_censored", None) and finger == finger and finger != 0:
            raise ingest_error(label, i + 1, "first_finger_measured", f"finger {finger:g} slipped first but "
                               "threshold_censored is true (a censored ramp ended without slip: 0)")
        # a drop, damage or contact loss classes the trial as a failure whatever its hold (§8.1);
        # several may co-occur under one failure class; slip is graded by its amount (a partial
        # hold may carry a slip flag)
        if not flag and (raised := next((f for f in DECISIVE if getattr(row, f)), None)):
            raise ingest_error(label, i + 1, raised, f"{raised} is true but outcome is '{outcome}' (a "
                               "measured drop, damage or contact loss classes the trial as that failure, "
                               "§8.1)")


MEAN_REL_TOL = 0.05
"""Relative tolerance of a recorded mean against the mean of its per-finger values: a judgement,
a third of the 13.8 % median normal-force prediction error the mean is judged by (§8, Fig. 29b),
so a tolerated difference moves no reported statistic; a unit or column slip is far outside it
(docs/decisions.md)."""
MEAN_ABS_TOL = {"normal_force": 2 * 5e-3, "deformation": 2 * 0.1}
"""Absolute tolerance of a recorded mean [N, mm]: two resolution steps of its sensor (finger force
5 mN, vision 0.1 mm; §8.1, Fig. 27), what rounding the four values separately can leave."""


def _check_means(df: pd.DataFrame, label: str) -> None:
    """Refuse a recorded mean that is not the mean of its per-finger values (those recorded)."""
    for stem, unit in (("normal_force", "n"), ("deformation", "mm")):
        fingers = [f"{stem}_{j}_{unit}" for j in (1, 2, 3)]
        column = f"{stem}_mean_{unit}"
        values = df[fingers].to_numpy(dtype=float)
        given = df[column].to_numpy(dtype=float)
        mean = df[fingers].astype(float).mean(axis=1).to_numpy()  # NaN: no finger recorded
        recorded = ~np.isnan(given) & ~np.isnan(mean) & ~df["aborted"].to_numpy(bool)
        tol = MEAN_REL_TOL * np.abs(mean) + MEAN_ABS_TOL[stem]
        off = recorded & (np.abs(given - mean) > tol)
        if off.any():
            i = int(np.flatnonzero(off)[0])
            name = UNIT_NAMES[unit]
            shown = ", ".join("empty" if np.isnan(v) else f"{v:g}" for v in values[i])
            raise ingest_error(label, i + 1, column, f"value {given[i]:g} {name} is not the mean of "
                               f"{', '.join(fingers)} ({shown}: mean {mean[i]:.4g} {name}) within "
                               f"{MEAN_REL_TOL:.0%} + {MEAN_ABS_TOL[stem]:g} {name}")
