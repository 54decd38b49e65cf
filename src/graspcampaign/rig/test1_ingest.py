"""Test 1 ingest of waveform files (paper §7.1): reading, validation and the blank sheet a rig
fills in.

Validation raises :class:`graspcampaign.rig.ingest.IngestError` with one sentence naming the file,
the data row and the column; a validated table is fitted by
:func:`graspcampaign.rig.test1_fits.fit_waveforms`.

Waveform table columns: ``event_id, time_s, displacement_mm, normal_force_n,
tangential_force_n, tangential_displacement_mm`` plus optional metadata (``attempt``,
``anomaly``, ``source``).
"""

from __future__ import annotations

import math
import re
from collections.abc import Iterable
from pathlib import Path

import numpy as np
import pandas as pd

from graspcampaign.core.bench import MIN_FIT_SAMPLES
from graspcampaign.core.words import counted
from graspcampaign.rig.file_kinds import other_files
from graspcampaign.rig.ingest import case_hint, check_one_source, refuse_larger
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
from graspcampaign.rig.protocol_design import STUDY_TEST1
from graspcampaign.rig.record_schema import ATTEMPT_TYPO_LIMIT, SOURCES
from graspcampaign.rig.test1_summary import WAVEFORM_COLUMNS

__all__ = ["MAX_WAVEFORM_BYTES", "MIN_EVENT_SAMPLES", "PEAK_FACTOR", "RATE_FACTOR", "TARE_LIMIT_N",
           "read_waveforms", "validate_waveforms", "waveform_template"]


_UNIT_RE = re.compile(r"^(?P<stem>time|displacement|normal_force|tangential_force|"
                      r"tangential_displacement)_(?P<unit>[a-z]+)$")
_EXPECTED_UNIT = {"time": "s", "displacement": "mm", "normal_force": "n",
                  "tangential_force": "n", "tangential_displacement": "mm"}
_RANGES = {  # physical envelope of the rig (§7.1): values outside suggest wrong units
    "time_s": (0.0, 3600.0, "the 0-3600 s record window"),
    "displacement_mm": (-50.0, 50.0, "the +-50 mm actuator travel"),
    "normal_force_n": (-10.0, 10.0, "the 10 N load-cell range"),
    "tangential_force_n": (-10.0, 10.0, "the 10 N load-cell range"),
    "tangential_displacement_mm": (-50.0, 50.0, "the +-50 mm stage travel"),
}


MAX_WAVEFORM_BYTES = 8 * 2**30
"""The largest waveform file read: twice every event of the full Test 1 schedule in one CSV with
every float64 digit written (3.9 GiB; 1.7 GiB as the sensors resolve them, 1 um and 1 mN), which
leaves room for re-run attempts and a note on every sample (``benchmarks/test1_file_size.py``:
32.8 M samples at 50-500 Hz, §7.1). An ingest's memory grows by some 330 bytes a sample (the
whole schedule's file: about 10 GiB, ``benchmarks/test1_ingest_memory.py``), so a file beyond any
the protocol makes is refused unread (docs/decisions.md)."""


def read_waveforms(path: str | Path) -> pd.DataFrame:
    """Read a waveform file (``.csv``, ``.parquet``/``.pq`` or ``.xlsx``) without checks.

    Via :func:`graspcampaign.rig.ingest.read_table` (an unsupported, missing or unreadable
    file raises :class:`IngestError`); channels are parsed as numbers, only an empty cell is
    missing, in a CSV and a workbook alike (a sample is measured: no word stands for one). A file
    over :data:`MAX_WAVEFORM_BYTES` is refused unread.
    """
    refuse_larger(path, MAX_WAVEFORM_BYTES, "Test 1 waveforms", "all 19,168 events of the full schedule "
                  "in one CSV are 3.9 GiB with every float64 digit, 1.7 GiB as the sensors resolve them")
    missing = {"keep_default_na": False, "na_values": [""]}
    return read_table(path, csv_options={"dtype": {"event_id": str, "anomaly": str}, **missing},
                      excel_options={"dtype": {"event_id": str}, **missing})


PEAK_FACTOR = 3.0
"""An event's peak displacement lies within this factor of its commanded depth (tangential: of its
commanded stroke), both ways. A displacement-controlled actuator (1 um, §7.1) reaches what it is
commanded: along an oblique press at 45 deg that is up to 1/cos 45 = 1.41 of the depth, and a
cyclic event overshoots by some 20 % (the virtual bench: 1.00 to 1.42). A factor of 3 (about half
a decade) passes those with a margin of 2 and catches a unit slip (10x: cm, 1000x: m or um)."""


RATE_FACTOR = 30.0
"""An event's sampling rate (one over its median sample interval) lies within this factor of the
schedule's ``daq_hz``, both ways. The bench logs each event at one fixed rate of 50 Hz to 500 Hz
(§7.1); a factor of 30 passes a logger at any of those rates whatever the sheet commanded (10x),
and one up to 1.5 kHz on a 50 Hz event. A time column in milliseconds (a rate 1000x too slow) is
caught at any of them; one in minutes (a rate 60x too fast) is caught unless the logger ran well
below the commanded rate (a 50 Hz log of a 500 Hz event in minutes reads 3 kHz, 6x). Either would
put its fits off by that factor (a damping 1000x off)."""


MIN_EVENT_SAMPLES = MIN_FIT_SAMPLES
"""The fewest samples an event's waveform may have: the fewest any block's fit reads (core's
:data:`~graspcampaign.core.bench_fit_relaxation.MIN_FIT_SAMPLES`, of a slide or a hold; an oblique
press 5). The bench logs every event at 50 Hz to 500 Hz through its whole motion (§7.1: the virtual
bench's fewest is 235), so a few samples are a log cut short or filtered, whose fits would be stored
as failed."""


TARE_LIMIT_N = 0.01
"""Largest tension [N] an event commanded to a depth may read before contact (the median of its
samples before its displacement first exceeds 0): ten steps of the load cell's 1 mN resolution
(§7.1). Before the fingertip touches, the cell reads nothing but its noise (the virtual bench: within
3 mN); the only tension the bench measures, the adhesion pull-off of §7.2 (ii), comes at
separation, after contact. A steady tension before contact is a cell not zeroed (tared), whose
offset would shift every force, and so every fit (50 mN: a gel slide's mu_s 0.78 read as 0.98)."""


def validate_waveforms(data: pd.DataFrame | str | Path, known_event_ids: Iterable[str],
                       file_label: str | None = None, schedule: pd.DataFrame | None = None
                       ) -> pd.DataFrame:
    """Validate a waveform table and return it with clean dtypes.

    Checks, in order: required columns (a column with the right quantity but another unit
    suffix is reported as wrong units), numbers, finite values, the rig's physical ranges
    (values outside them usually mean wrong units), known event ids, duplicate samples
    (same ``event_id`` and ``time_s``), strictly increasing time within each event, and, given
    the ``schedule``, each event's peak displacement against its commanded depth and stroke
    (within :data:`PEAK_FACTOR`) and its sampling rate against its commanded ``daq_hz`` (within
    :data:`RATE_FACTOR`).

    Parameters
    ----------
    data : DataFrame or path
        The table, or a CSV/Parquet/XLSX file to read with :func:`read_waveforms`.
    known_event_ids : iterable of str
        Event ids of the study's schedule.
    file_label : str, optional
        Name used in messages; default the file name (or ``"<dataframe>"``).
    schedule : pandas.DataFrame, optional
        The study's schedule (``event_id``, ``depth_mm``, ``stroke_mm``).

    Returns
    -------
    pandas.DataFrame
        The validated table (``event_id`` str, channels float64), in file order.

    Raises
    ------
    IngestError
        One sentence naming the file, the 1-based data row (header excluded) and the column.
    """
    df, label = table_and_label(data, file_label, read_waveforms)
    df = df.reset_index(drop=True)
    df.columns = [str(c).strip() for c in df.columns]
    units = {c: _EXPECTED_UNIT[c.rsplit("_", 1)[0]] for c in WAVEFORM_COLUMNS[1:]}
    problems = header_problems(list(df.columns), list(WAVEFORM_COLUMNS), units, _UNIT_RE,
                               ("attempt", "anomaly", "source"),
                               other_sheets=df.attrs.get("other_sheets"),
                               first_rows=df.head(5).to_numpy().tolist(),
                               filled_sheets=df.attrs.get("filled_sheets", ()),
                               others=other_files(STUDY_TEST1))
    if problems:
        raise IngestError(f"{label}, header: {'; '.join(problems)} (`graspcampaign schedule "
                          "test1_bench --template` writes a sheet with every column).")
    if len(df) == 0:
        raise ingest_error(label, None, "event_id", "the file has no data rows")
    out = pd.DataFrame({"event_id": df["event_id"]})
    ids = df["event_id"]
    bad = ids.isna() | (ids.astype(str).str.strip() == "")
    if bad.any():
        row = int(np.flatnonzero(bad.to_numpy())[0]) + 1
        raise empty_row(label, df, row) or ingest_error(label, row, "event_id", "event id is empty")
    out["event_id"] = ids.astype(str).str.strip()
    known = set(known_event_ids)
    unknown = ~out["event_id"].isin(known)

    def refuse(i: int, column: str, problem: str) -> IngestError:
        """The error of row ``i + 1``'s cell, or of its event id when that is not the schedule's
        (a 'Total' row below the samples is named as one, not by its empty time)."""
        if unknown.iloc[i]:
            return _unknown_event(label, i, out["event_id"].iloc[i], known, schedule)
        return ingest_error(label, i + 1, column, problem)
    for c in WAVEFORM_COLUMNS[1:]:
        raw = df[c]
        if pd.api.types.is_datetime64_any_dtype(raw):  # else read as microseconds since 1970
            raw = raw.astype(object)
        num = pd.to_numeric(raw, errors="coerce")
        # the cells read as no number, told from nan/inf spellings: those cells alone, not every
        # cell as text (3 s of a million rows)
        nonnum = num.isna() & raw.notna()
        nonnum[nonnum] = ~raw[nonnum].astype(str).str.strip().str.lower().isin(
            ["nan", "inf", "-inf", "+inf", "infinity", "-infinity"])
        if nonnum.any():
            i = int(np.flatnonzero(nonnum.to_numpy())[0])
            expected = "a number of seconds" if c == "time_s" else "a number"
            raise refuse(i, c, cell_problem(raw.iloc[i], expected))
        vals = num.to_numpy(dtype=float)
        notfinite = ~np.isfinite(vals)
        if notfinite.any():
            i = int(np.flatnonzero(notfinite)[0])
            problem = ("value nan (an empty cell or NaN) is not finite" if np.isnan(vals[i])
                       else f"value {vals[i]:g} is not finite")  # not np.float64(inf)
            raise refuse(i, c, problem)
        lo, hi, what = _RANGES[c]
        outside = (vals < lo) | (vals > hi)
        if outside.any():
            i = int(np.flatnonzero(outside)[0])
            raise refuse(i, c, f"value {vals[i]:g} lies outside {what} (wrong units?)")
        out[c] = vals
    if unknown.any():
        i = int(np.flatnonzero(unknown.to_numpy())[0])
        raise _unknown_event(label, i, out["event_id"].iloc[i], known, schedule)
    dup = out.duplicated(["event_id", "time_s"], keep="first")
    if dup.any():
        i = int(np.flatnonzero(dup.to_numpy())[0])
        key = out.iloc[i]
        first = out.index[(out["event_id"] == key["event_id"])
                          & (out["time_s"] == key["time_s"])][0]
        raise ingest_error(label, i + 1, "time_s", f"duplicate sample of event '{key['event_id']}' "
                           f"at {key['time_s']:g} s (first seen in row {first + 1})")
    prev = out.groupby("event_id", sort=False)["time_s"].shift()
    back = (out["time_s"] <= prev).to_numpy()
    if back.any():
        i = int(np.flatnonzero(back)[0])
        raise ingest_error(label, i + 1, "time_s", f"time {out['time_s'].iloc[i]:g} s does not "
                           f"increase within event '{out['event_id'].iloc[i]}' (previous sample "
                           f"{prev.iloc[i]:g} s)")
    _check_samples(out, label)
    if schedule is not None:
        _check_commanded(out, schedule, label)
    if "attempt" in df.columns:
        out["attempt"] = _attempts(df["attempt"], label)
    if "anomaly" in df.columns:
        anomaly = df["anomaly"].astype(object)
        out["anomaly"] = anomaly.where(anomaly.notna(), "").astype(str).str.strip()
    if "source" in df.columns:
        out["source"] = _sources(df["source"], label)
        # row 1 and the first row of another source: the rows check_one_source tells apart (a list
        # of every row took 0.35 GB for 3.4 M samples)
        other = np.flatnonzero((out["source"] != out["source"].iloc[0]).to_numpy())[:1]
        check_one_source([(label, i + 1, out["source"].iloc[i]) for i in (0, *other)])
    for extra in ("attempt", "anomaly"):
        if extra in out:
            _check_constant(out, extra, label)
    return out


def _unknown_event(label: str, i: int, event: str, known: set[str],
                   schedule: pd.DataFrame | None) -> IngestError:
    """The error of row ``i + 1``, whose event id ``event`` is not among ``known``: named as the
    schedule's event id in another case, or as a specimen id (a column the sheet also has)."""
    hint = case_hint("event", event, known)
    if (not hint and schedule is not None and "specimen_id" in schedule
            and (schedule["specimen_id"] == event).any()):
        hint = (" (it is a specimen_id; the column holds the event_id of the schedule's row of "
                "each event)")
    return ingest_error(label, i + 1, "event_id", f"event id '{event}' is not in the schedule{hint}")


def _check_samples(table: pd.DataFrame, label: str) -> None:
    """Refuse an event of fewer than :data:`MIN_EVENT_SAMPLES` samples, naming its first."""
    events = table["event_id"]
    size = events.groupby(events, sort=False).size()
    if (size < MIN_EVENT_SAMPLES).any():
        event = size.index[int(np.flatnonzero((size < MIN_EVENT_SAMPLES).to_numpy())[0])]
        i = int(np.flatnonzero((events == event).to_numpy())[0])
        n = int(size[event])
        raise ingest_error(label, i + 1, "event_id", f"event '{event}' has {counted(n, 'sample')}, "
                           f"fewer than the {MIN_EVENT_SAMPLES} its fits need (a log cut short?); "
                           "give its whole waveform, or leave the event out")


def _check_tare(table: pd.DataFrame, commands: pd.DataFrame, label: str) -> None:
    """Refuse an event commanded to a depth whose normal force before contact (its samples before
    its displacement first exceeds 0) has a median below ``-TARE_LIMIT_N`` (a load cell not
    zeroed), naming the first such event's first sample."""
    if "depth_mm" not in commands:
        return
    events = table["event_id"].reset_index(drop=True)
    touched = (table["displacement_mm"].reset_index(drop=True) > 0).groupby(events, sort=False).cummax()
    free = ~touched.astype(bool)  # the samples before the event's displacement first exceeds 0
    before = table["normal_force_n"].reset_index(drop=True)[free].groupby(events[free], sort=False).median()
    pressed = commands["depth_mm"].reindex(before.index).fillna(0.0).to_numpy(dtype=float) > 0
    tense = pressed & (before.to_numpy() < -TARE_LIMIT_N)
    if tense.any():
        event = before.index[int(np.flatnonzero(tense)[0])]
        i = int(np.flatnonzero((events == event).to_numpy())[0])
        raise ingest_error(label, i + 1, "normal_force_n", f"event '{event}' reads {before[event]:.4g} "
                           f"N before contact (the median of its samples before its displacement "
                           f"exceeds 0), a tension beyond {TARE_LIMIT_N:g} N, as from a load cell not "
                           "zeroed (tared): zero the channel (subtract its reading before contact)")


def _check_sign(table: pd.DataFrame, commands: pd.DataFrame, label: str) -> None:
    """Refuse an event commanded into contact (a depth, or a sliding preload) recorded with the
    other sign convention (§7.1, Eq. 13: indentation and the force it makes are positive into the
    specimen), which was stored with its fits flagged ``fit_failed``: its normal force of largest
    size is tensile (the only tension, the adhesion pull-off at separation, is small beside the
    press), or its displacement is negative at that sample, where the fingertip presses hardest.
    The displacement's own largest sample says nothing: a bench may log its approach from further
    off the specimen than the commanded depth. The first such sample in the file is named. An
    event not commanded into contact is not asked."""
    contact = pd.Series(False, index=commands.index)
    for target in ("depth_mm", "normal_load_n"):
        if target in commands:
            contact |= commands[target].fillna(0.0).to_numpy(dtype=float) > 0
    events = table["event_id"]
    force = table["normal_force_n"].to_numpy(dtype=float)
    at = pd.Series(np.abs(force)).groupby(events.reset_index(drop=True), sort=False).idxmax()  # by place
    rows = at.to_numpy()[contact.reindex(at.index, fill_value=False).to_numpy(dtype=bool)]
    depth = table["displacement_mm"].to_numpy(dtype=float)[rows]
    bad = [(int(i), "normal_force_n", f"peaks at {force[i]:g} N", "compression (the fingertip "
            "pressing)") for i in rows[force[rows] < 0]]
    pressed = (force[rows] > 0) & (depth < 0)  # a tensile peak is named above, its depth moot
    bad += [(int(i), "displacement_mm", f"is at {d:g} mm where its normal force peaks "
             f"({force[i]:g} N)", "indentation (into the specimen)")
            for i, d in zip(rows[pressed], depth[pressed], strict=True)]
    if bad:
        i, column, said, positive = min(bad)
        raise ingest_error(label, i + 1, column, f"event '{events.iloc[i]}' {said}, below zero: "
                           f"{positive} is positive here; flip the column's sign")


def _check_commanded(table: pd.DataFrame, schedule: pd.DataFrame, label: str) -> None:
    """Refuse an event whose peak displacement is not within :data:`PEAK_FACTOR` of what the
    schedule commands (a depth for the pressing blocks, a stroke for the tangential slide)."""
    commands = schedule.drop_duplicates("event_id").set_index("event_id")
    for column, target, what in (("displacement_mm", "depth_mm", "depth"),
                                 ("tangential_displacement_mm", "stroke_mm", "stroke")):
        if target not in commands:
            continue
        size = table[column].abs()
        at = size.groupby(table["event_id"], sort=False).idxmax()  # each event's peak sample
        commanded = commands[target].reindex(at.index).to_numpy(dtype=float)
        peak = size.to_numpy()[at.to_numpy()]
        with np.errstate(divide="ignore", invalid="ignore"):
            ratio = peak / commanded
        off = (commanded > 0) & ((ratio > PEAK_FACTOR) | (ratio < 1.0 / PEAK_FACTOR))
        if off.any():
            i = int(at.to_numpy()[off].min())
            k = int(np.flatnonzero(at.to_numpy() == i)[0])
            raise ingest_error(label, i + 1, column, f"event '{at.index[k]}' peaks at {peak[k]:g} mm where "
                               f"the schedule commands a {what} of {commanded[k]:g} mm (ratio "
                               f"{ratio[k]:.3g}, outside 1/{PEAK_FACTOR:g} to {PEAK_FACTOR:g}: wrong units?)")
    _check_sign(table, commands, label)  # first: a force negative throughout is a flipped sign
    _check_tare(table, commands, label)
    if "daq_hz" in commands:
        _check_rate(table, commands["daq_hz"], label)


def _check_rate(table: pd.DataFrame, daq_hz: pd.Series, label: str) -> None:
    """Refuse an event sampled at a rate not within :data:`RATE_FACTOR` of its commanded
    ``daq_hz`` (each event has a rate: :func:`_check_samples` refused one of fewer than
    :data:`MIN_EVENT_SAMPLES` samples before)."""
    events = table["event_id"]
    step = table["time_s"].groupby(events, sort=False).diff().groupby(events, sort=False).median()
    commanded = daq_hz.reindex(step.index).to_numpy(dtype=float)
    with np.errstate(divide="ignore", invalid="ignore"):  # time increases within an event: step > 0
        ratio = 1.0 / step.to_numpy() / commanded  # a daq_hz of 0 is no command (masked below)
    off = (commanded > 0) & ((ratio > RATE_FACTOR) | (ratio < 1.0 / RATE_FACTOR))
    if off.any():
        k = int(np.flatnonzero(off)[0])
        event = step.index[k]
        i = int(np.flatnonzero((events == event).to_numpy())[1])  # its first interval ends here
        raise ingest_error(label, i + 1, "time_s", f"event '{event}' is sampled every "
                           f"{step.iloc[k]:g} s ({1.0 / step.iloc[k]:.4g} Hz) where the schedule "
                           f"commands {commanded[k]:g} Hz (ratio {ratio[k]:.3g}, outside "
                           f"1/{RATE_FACTOR:g} to {RATE_FACTOR:g}: time not in seconds?)")


def _attempts(raw: pd.Series, label: str) -> np.ndarray:
    """Parse the optional ``attempt`` column: an integer from 1 (the first try) on."""
    values = []
    for i, value in enumerate(raw.tolist()):
        text = str(value).strip()
        try:
            number = float(text)
        except ValueError:
            number = math.nan
        if not (math.isfinite(number) and number == int(number) and 1 <= number <= ATTEMPT_TYPO_LIMIT):
            shown = value.item() if isinstance(value, np.generic) else value  # no np reprs
            raise ingest_error(label, i + 1, "attempt", f"value {shown!r} is not an attempt number (an "
                               f"integer 1 to {ATTEMPT_TYPO_LIMIT} counting the tries of the event)")
        values.append(int(number))
    return np.asarray(values, dtype=np.int64)


def _sources(raw: pd.Series, label: str) -> np.ndarray:
    """Parse the optional ``source`` column: ``measured`` (a rig) or ``virtual`` (a virtual bench).
    Each distinct value is read once, and the first row of one that is neither is named (a list
    of every row's value took 0.25 GB for 3.4 M samples)."""
    codes, values = pd.factorize(raw)  # code -1: a missing value, which no source is
    texts = [str(value).strip() for value in values]
    known = np.array([text in SOURCES for text in texts] + [False])[codes]
    if not known.all():
        i = int(np.flatnonzero(~known)[0])
        value = raw.iloc[[i]].tolist()[0]  # as a Python value: no np reprs
        text = "" if value is None or (isinstance(value, float) and math.isnan(value)) \
            else str(value).strip()
        if not text:
            raise ingest_error(label, i + 1, "source", f"value is empty; expected one of "
                               f"{', '.join(SOURCES)}")
        raise ingest_error(label, i + 1, "source", f"value {text!r}{aside(text, SOURCES)} is not "
                           f"one of {', '.join(SOURCES)}")
    return np.asarray([*texts, ""], dtype=object)[codes]


def _check_constant(table: pd.DataFrame, column: str, label: str) -> None:
    """A per-event column (attempt, anomaly, source) must not change within an event."""
    first = table.groupby("event_id", sort=False)[column].transform("first")
    changed = (table[column] != first).to_numpy()
    if changed.any():
        i = int(np.flatnonzero(changed)[0])
        value, before = (v.item() if isinstance(v, np.generic) else v  # no np reprs
                         for v in (table[column].iloc[i], first.iloc[i]))
        raise ingest_error(label, i + 1, column, f"value {value!r} differs from {before!r} earlier in "
                           f"event '{table['event_id'].iloc[i]}' (one value per event)")


def waveform_template() -> tuple[pd.DataFrame, pd.DataFrame]:
    """Return the (empty) waveform sheet a rig fills in, and the description of its columns.

    Returns
    -------
    sheet : pandas.DataFrame
        No rows; the columns :data:`WAVEFORM_COLUMNS` then the optional ``attempt``, ``anomaly``,
        ``source``.
    columns : pandas.DataFrame
        ``column, type, unit, allowed, required`` per column (ranges: the rig envelope of §7.1).
    """
    rows = [{"column": "event_id", "type": "str", "unit": "-",
             "allowed": "an event_id of the schedule", "required": "every row"}]
    for name in WAVEFORM_COLUMNS[1:]:
        lo, hi, what = _RANGES[name]
        unit = {"s": "s", "mm": "mm", "n": "N"}[name.rsplit("_", 1)[1]]
        rows.append({"column": name, "type": "float", "unit": unit,
                     "allowed": f"float in [{lo:g}, {hi:g}] ({what})", "required": "every row"})
    rows += [
        {"column": "attempt", "type": "int", "unit": "1",
         "allowed": f"integer 1 to {ATTEMPT_TYPO_LIMIT}, one value per event",
         "required": "optional column (1)"},
        {"column": "anomaly", "type": "str", "unit": "-", "allowed": "rig-log note, one per event",
         "required": "optional column"},
        {"column": "source", "type": "str", "unit": "-", "allowed": ", ".join(SOURCES),
         "required": "optional column (measured)"},
    ]
    columns = pd.DataFrame(rows)
    return pd.DataFrame({c: pd.Series(dtype=object) for c in columns["column"]}), columns
