"""Tests of graspcampaign.rig.test1's ingest: waveforms from a sheet give the in-process fits, and
a bad sheet is refused with a message that names the sheet, row and column.

The sheets are cut from the reduced virtual-bench run (``reduced`` in conftest.py).
"""

from __future__ import annotations

import math
import re

import numpy as np
import pandas as pd
import pytest

from graspcampaign.rig import test1 as T
from graspcampaign.rig.test1_ingest import PEAK_FACTOR


@pytest.fixture(scope="module")
def small(reduced):
    schedule, res = reduced
    ids = (res.fits.groupby("block").head(6)["event_id"].tolist()
           + res.fits.loc[res.fits["anomaly"] != "", "event_id"].head(3).tolist())
    wav = res.waveforms[res.waveforms["event_id"].isin(ids)].reset_index(drop=True)
    return schedule, res, wav


@pytest.mark.parametrize("suffix", ["csv", "parquet"])
def test_ingest_gives_the_in_process_fits(small, tmp_path, suffix):
    schedule, res, wav = small
    path = tmp_path / f"waves.{suffix}"
    if suffix == "csv":
        wav.to_csv(path, index=False)
    else:
        wav.to_parquet(path, index=False)
    valid = T.validate_waveforms(path, schedule["event_id"], schedule=schedule)
    fits = T.fit_waveforms(valid, schedule).set_index("event_id").sort_index()
    ref = res.fits.set_index("event_id").loc[fits.index]
    pd.testing.assert_frame_equal(fits, ref[fits.columns], check_dtype=False)


def test_the_bench_reaches_its_commanded_depth_and_stroke_within_the_peak_factor(small):
    """The virtual bench's own events, the rule's reference: peak over command per block, from
    the waveforms with pandas (an oblique press at 45 deg reaches 1/cos 45 of its depth)."""
    schedule, _, wav = small
    peaks = wav.assign(d=wav["displacement_mm"].abs(), t=wav["tangential_displacement_mm"].abs())
    peaks = peaks.groupby("event_id")[["d", "t"]].max().join(schedule.set_index("event_id"))
    ratios = pd.concat([peaks["d"] / peaks["depth_mm"], peaks["t"] / peaks["stroke_mm"]]).dropna()
    assert ratios.max() == pytest.approx(1.0 / math.cos(math.radians(45.0)), rel=0.01)
    assert 1.0 / PEAK_FACTOR < ratios.min() and ratios.max() < PEAK_FACTOR


@pytest.mark.parametrize(("column", "scale", "what"), [
    ("displacement_mm", 1e-3, "depth"),               # the tester's file: written in metres
    ("displacement_mm", 10.0, "depth"),               # in tenths of a millimetre
    ("tangential_displacement_mm", 0.1, "stroke"),    # in centimetres
], ids=["m", "tenths", "cm"])
def test_ingest_refuses_a_displacement_in_another_unit(small, tmp_path, column, scale, what):
    schedule, _, wav = small
    command = {"depth": "depth_mm", "stroke": "stroke_mm"}[what]
    events = schedule.set_index("event_id")[command].dropna()
    one = wav[wav["event_id"] == next(e for e in wav["event_id"] if e in events.index)]
    bad = one.assign(**{column: one[column] * scale}).reset_index(drop=True)
    path = tmp_path / "w.csv"
    bad.to_csv(path, index=False)
    row = int(bad[column].abs().idxmax())  # the peak sample
    event = bad["event_id"].iloc[0]
    peak, commanded = abs(bad[column].iloc[row]), events[event]
    with pytest.raises(T.IngestError) as info:
        T.validate_waveforms(path, schedule["event_id"], schedule=schedule)
    assert str(info.value) == (
        f"w.csv, row {row + 1}, column '{column}': event '{event}' peaks at {peak:g} mm where the "
        f"schedule commands a {what} of {commanded:g} mm (ratio {peak / commanded:.3g}, outside "
        "1/3 to 3: wrong units?).")


@pytest.fixture
def good(small):
    schedule, _, wav = small
    df = wav[wav["event_id"] == wav["event_id"].iloc[0]].iloc[:30].reset_index(drop=True)
    return schedule["event_id"], df


def _write(df, tmp_path):
    path = tmp_path / "bad.csv"
    df.to_csv(path, index=False)
    return path


def _set(df, row, column, value):
    """Return a copy of ``df`` with one cell replaced (the column widened to object for text)."""
    out = df.astype({column: object}) if isinstance(value, str) else df.copy()
    out.loc[row, column] = value
    return out


def _force_in_mn(df):
    """Normal force written in mN under the N header, after five zero samples."""
    out = df.assign(normal_force_n=df["normal_force_n"] * 1000.0)
    out.loc[:4, "normal_force_n"] = 0.0
    out.loc[5, "normal_force_n"] = 250.0
    return out


TEMPLATE = r" \(`graspcampaign schedule test1_bench --template` writes a sheet with every column\)\."
# Each case: how the bad table is made from the good 30-sample event, and the message after
# "bad.csv, " ({event} is the good event's id).
BAD_WAVEFORMS = {
    "missing_column": (lambda d: d.drop(columns="normal_force_n"),
                       r"header: a required column is missing: normal_force_n" + TEMPLATE),
    "missing_columns_all_named": (lambda d: d.drop(columns=["normal_force_n", "time_s"]),
                                  r"header: required columns are missing: time_s, normal_force_n"
                                  + TEMPLATE),
    "wrong_unit_column": (lambda d: d.rename(columns={"displacement_mm": "displacement_m"}),
                          r"header: 'displacement_m' has unit 'm' where 'displacement_mm' "
                          r"\(mm\) is expected" + TEMPLATE),
    "attempt_not_an_integer": (lambda d: _set(d, 3, "attempt", "two"),
                               r"row 4, column 'attempt': value 'two' is not an attempt number "
                               r"\(an integer 1 to 99 counting the tries of the event\)\."),
    "attempt_fractional": (lambda d: d.astype({"attempt": float}).assign(attempt=1.5),
                           r"row 1, column 'attempt': value 1\.5 is not an attempt number \(an "
                           r"integer 1 to 99 counting the tries of the event\)\."),
    "attempt_beyond_the_limit": (lambda d: d.assign(attempt=1000000),  # stored as 999999 aborts
                                 r"row 1, column 'attempt': value 1000000 is not an attempt number "
                                 r"\(an integer 1 to 99 counting the tries of the event\)\."),
    "two_sources": (lambda d: _set(d.assign(source="measured"), 6, "source", "virtual"),
                    r"row 7, column 'source': value 'virtual' differs from 'measured' in bad\.csv, "
                    r"row 1; a run holds the records of one source \(measured or virtual\): ingest "
                    r"the others into another run with --run\."),
    "a_misspelt_optional_column": (lambda d: d.rename(columns={"source": "Source"}),
                                   r"header: a column is not part of the sheet: 'Source' \(did you "
                                   r"mean 'source'\?\); its columns are event_id, time_s, "
                                   r"displacement_mm, normal_force_n, tangential_force_n, "
                                   r"tangential_displacement_mm, attempt, anomaly, source" + TEMPLATE),
    "attempt_negative": (lambda d: d.assign(attempt=-4),
                         r"row 1, column 'attempt': value -4 is not an attempt number \(an "
                         r"integer 1 to 99 counting the tries of the event\)\."),
    "attempt_changes_within_event": (lambda d: _set(d, 6, "attempt", 2),
                                     r"row 7, column 'attempt': value 2 differs from 1 earlier in "
                                     r"event '{event}' \(one value per event\)\."),
    "unknown_source": (lambda d: _set(d, 2, "source", "bogus"),
                       r"row 3, column 'source': value 'bogus' is not one of measured, "
                       r"virtual\."),
    "empty_source": (lambda d: _set(d, 5, "source", ""),
                     r"row 6, column 'source': value is empty; expected one of measured, "
                     r"virtual\."),
    "no_rows": (lambda d: d.iloc[:0], r"header, column 'event_id': the file has no data rows\."),
    "values_in_wrong_units": (_force_in_mn, r"row 6, column 'normal_force_n': value 250 lies "
                                            r"outside the 10 N load-cell range \(wrong units\?\)\."),
    "non_numeric": (lambda d: _set(d, 3, "time_s", "0.3s"),
                    r"row 4, column 'time_s': value '0\.3s' is not a number of seconds\."),
    "non_finite": (lambda d: _set(d, 7, "tangential_force_n", np.nan),
                   r"row 8, column 'tangential_force_n': value nan \(an empty cell or NaN\) is "
                   r"not finite\."),
    "non_monotonic_time": (lambda d: _set(d, 10, "time_s", d.loc[8, "time_s"] - 1e-4),
                           r"row 11, column 'time_s': time .* s does not increase within event "
                           r"'{event}' \(previous sample .* s\)\."),
    "unknown_event": (lambda d: _set(d, 12, "event_id", "t1-000000000000"),
                      r"row 13, column 'event_id': event id 't1-000000000000' is not in the "
                      r"schedule\."),
    "empty_event_id": (lambda d: _set(d, 2, "event_id", ""),
                       r"row 3, column 'event_id': event id is empty\."),
    "duplicate_rows": (lambda d: pd.concat([d, d.iloc[[4]]], ignore_index=True),
                       r"row 31, column 'time_s': duplicate sample of event '{event}' at .* s "
                       r"\(first seen in row 5\)\."),
}


@pytest.mark.parametrize("case", list(BAD_WAVEFORMS))
def test_ingest_rejects(good, tmp_path, case):
    ids, df = good
    make, message = BAD_WAVEFORMS[case]
    path = _write(make(df), tmp_path)
    message = message.format(event=re.escape(df["event_id"].iloc[0]))
    with pytest.raises(T.IngestError, match=rf"^bad\.csv, {message}$"):
        T.validate_waveforms(path, ids)


def test_ingest_names_the_sheet_behind_an_empty_first_sheet(good, tmp_path):
    ids, df = good
    path = tmp_path / "waves.xlsx"
    with pd.ExcelWriter(path) as book:
        pd.DataFrame().to_excel(book, sheet_name="Sheet1", index=False)
        df.to_excel(book, sheet_name="data", index=False)
    with pytest.raises(T.IngestError) as info:
        T.validate_waveforms(path, ids)
    assert str(info.value) == (
        "waves.xlsx, header: ingest reads the workbook's first sheet, which is empty; sheet 'data' "
        "has every required column: move it to the front or save it as CSV (`graspcampaign "
        "schedule test1_bench --template` writes a sheet with every column).")


def test_ingest_refuses_a_formula_without_its_computed_value(good, tmp_path):
    from openpyxl import load_workbook

    ids, df = good
    path = tmp_path / "waves.xlsx"
    df.to_excel(path, index=False)
    book = load_workbook(path)
    book.active.cell(row=5, column=list(df.columns).index("displacement_mm") + 1).value = "=0.1*2"
    book.save(path)
    with pytest.raises(T.IngestError) as info:
        T.validate_waveforms(path, ids)
    assert str(info.value) == (
        "waves.xlsx, row 4, column 'displacement_mm': the cell holds a formula (=0.1*2) with no "
        "computed value; open and save the file in a spreadsheet program, which stores the values.")


def test_ingest_rejects_unknown_file_type(good, tmp_path):
    ids, df = good
    path = tmp_path / "waves.txt"
    path.write_text("x")
    with pytest.raises(T.IngestError, match=r"^waves\.txt: unsupported file "
                                            r"type '\.txt' \(expected \.csv, \.parquet or "
                                            r"\.xlsx\)\.$"):
        T.validate_waveforms(path, ids)


def test_ingest_error_is_a_value_error_and_labels_dataframes(good):
    ids, df = good
    with pytest.raises(ValueError, match=r"^<dataframe>, header: a required column is missing: "
                                         r"event_id" + TEMPLATE + "$"):
        T.validate_waveforms(df.drop(columns="event_id"), ids)


def test_ingest_refuses_below_the_fits_own_minimum_named_once_in_core():
    """Test 1 ingest refuses an event of fewer samples than the fits read, core's ``MIN_FIT_SAMPLES``;
    rig's ``MIN_EVENT_SAMPLES = 10`` repeated the bare 10 of ``fit_sliding`` and ``fit_relaxation``, so a
    change to one would not move the other. Read from the source (no size check there is a bare number)
    and from a fit: a hold of ``MIN_FIT_SAMPLES`` samples fits, one of a sample fewer does not."""
    import ast
    import inspect

    from graspcampaign.core import bench, bench_fit_friction, bench_fit_relaxation
    from graspcampaign.rig import test1_ingest

    for module in (bench_fit_friction, bench_fit_relaxation):
        bare = [node.lineno for node in ast.walk(ast.parse(inspect.getsource(module)))
                if isinstance(node, ast.Compare) and isinstance(node.left, ast.Attribute)
                and node.left.attr == "size" and isinstance(node.comparators[0], ast.Constant)
                and node.comparators[0].value == bench.MIN_FIT_SAMPLES]
        assert not bare, f"{module.__name__}: a bare sample count at line {bare[0]}"
    rig = next(node for node in ast.parse(inspect.getsource(test1_ingest)).body
               if isinstance(node, ast.Assign) and node.targets[0].id == "MIN_EVENT_SAMPLES")
    assert isinstance(rig.value, ast.Name) and rig.value.id == "MIN_FIT_SAMPLES"  # core's, not retyped
    assert test1_ingest.MIN_EVENT_SAMPLES == bench.MIN_FIT_SAMPLES
    t = np.arange(bench.MIN_FIT_SAMPLES) * 0.5
    f = 0.4 * (0.7 + 0.3 * np.exp(-t / 3.0))
    assert bench.fit_relaxation(t, np.full(t.size, 1e-3), f).success
    assert not bench.fit_relaxation(t[1:], np.full(t.size - 1, 1e-3), f[1:]).success
