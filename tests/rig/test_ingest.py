"""Ingest of measured Tests 2-3 records: round trip of the virtual rig's records, one test per
malformed-file kind with its message asserted."""

from __future__ import annotations

import re

import numpy as np
import pandas as pd
import pytest
from virtual_exports import virtual_run

from graspcampaign.analysis import hardware as analysis
from graspcampaign.rig import protocol
from graspcampaign.rig.ingest import IngestError, validate_records
from graspcampaign.rig.record_schema import record_columns


@pytest.fixture(scope="module")
def t2():
    schedule = protocol.test2_schedule(0)
    rows, preds, meas = virtual_run(schedule, 150)
    return schedule, rows, preds, meas


@pytest.fixture(scope="module")
def t3():
    schedule = protocol.test3_schedule(0)
    rows, preds, meas = virtual_run(schedule, 120)
    return schedule, rows, preds, meas


def _file(df: pd.DataFrame, path, kind: str):
    if kind == "csv":
        df.to_csv(path, index=False)
    elif kind == "parquet":
        df.to_parquet(path)
    else:
        df.to_excel(path, index=False)
    return path


STATISTICS = (lambda d: analysis.summary(d, ["planner"], ["is_stable", "is_slip"], cluster="object_id"),
              analysis.force_accuracy)


@pytest.fixture(scope="module")
def direct_statistics():
    """:data:`STATISTICS` of the rig's own records per fixture (``t2``, ``t3``), filled by the
    first file kind that needs them: they do not depend on the file kind."""
    return {}


@pytest.mark.parametrize("kind", ["csv", "parquet", "xlsx"])
@pytest.mark.parametrize("fixture", ["t2", "t3"])
def test_virtual_records_round_trip(fixture, kind, tmp_path, request, direct_statistics):
    schedule, rows, preds, meas = request.getfixturevalue(fixture)
    study = schedule["study"].iloc[0]
    rec = meas[record_columns(study)]
    back = validate_records(_file(rec, tmp_path / f"records.{kind}", kind), schedule)
    assert len(back) == len(rec) and (back["source"] == "virtual").all()
    for col in record_columns(study):
        a, b = rec[col], back[col]
        if b.dtype.kind == "f":
            np.testing.assert_allclose(pd.to_numeric(a).astype(float), b, equal_nan=True)
        else:
            assert a.where(a.notna(), None).tolist() == b.where(b.notna(), None).tolist(), col
    # the same statistics from the ingested file as from the rig's own records
    if fixture not in direct_statistics:
        direct = analysis.derive(_merge(rows, preds, meas).assign(status="ok"))
        direct_statistics[fixture] = [fn(direct) for fn in STATISTICS]
    ingested = analysis.derive(_merge(rows, preds, back).assign(status="ok"))
    for want, fn in zip(direct_statistics[fixture], STATISTICS, strict=True):
        pd.testing.assert_frame_equal(want, fn(ingested), check_dtype=False)


def _merge(schedule: pd.DataFrame, preds: pd.DataFrame, meas: pd.DataFrame) -> pd.DataFrame:
    """The records of a virtual run: schedule rows with their predictions, joined to the measured."""
    left = pd.concat([schedule.reset_index(drop=True), preds.reset_index(drop=True)], axis=1)
    return left.merge(meas.drop(columns=["slot_id", "attempt"], errors="ignore"), on="trial_id")


def test_source_defaults_to_measured_and_reruns_are_accepted(t2, tmp_path):
    schedule, _, _, meas = t2
    rec = meas[record_columns("test2_grasp")].drop(columns=["source"])
    executed = rec[~rec["aborted"].astype(bool)].iloc[:1].copy()
    slot = schedule.set_index("trial_id").loc[executed["trial_id"].iloc[0], "slot_id"]
    aborted = executed.copy()
    aborted["aborted"], aborted["outcome"] = True, "aborted"
    executed["trial_id"] = f"{slot}-a3"  # an unforeseen re-run of the same slot
    out = validate_records(pd.concat([aborted, executed]), schedule, "measured.csv")
    assert (out["source"] == "measured").all()
    assert out["attempt"].tolist() == [1, 3]


# ------------------------------------------------------------------ malformed files
@pytest.fixture
def good(t2):
    schedule, _, _, meas = t2
    rec = meas[record_columns("test2_grasp")].copy()
    executed = np.flatnonzero(~rec["aborted"].astype(bool).to_numpy())
    return schedule, rec.reset_index(drop=True), int(executed[0])


def _check(schedule, df, tmp_path, match, kind="csv"):
    path = _file(df, tmp_path / f"bad.{kind}", kind)
    with pytest.raises(IngestError, match=match):
        validate_records(path, schedule)


TEMPLATE = (r" \(`graspcampaign schedule <study> --template` writes a sheet with every "
            r"column\)\.$")


def test_missing_column(good, tmp_path):
    schedule, rec, _ = good
    _check(schedule, rec.drop(columns=["sf_actual"]), tmp_path,
           r"^bad\.csv, header: a required column is missing: sf_actual" + TEMPLATE)


def test_every_missing_column_is_named_at_once(good, tmp_path):
    schedule, rec, _ = good
    bad = rec.drop(columns=["sf_actual", "aborted", "normal_force_mean_n"])
    bad = bad.rename(columns={"peak_slip_mm": "peak_slip_cm"})
    _check(schedule, bad, tmp_path, r"^bad\.csv, header: required columns are missing: aborted, "
           r"sf_actual, normal_force_mean_n; 'peak_slip_cm' has unit 'cm' where 'peak_slip_mm' "
           r"\(mm\) is expected" + TEMPLATE)


def test_wrong_unit(good, tmp_path):
    schedule, rec, _ = good
    bad = rec.rename(columns={"peak_slip_mm": "peak_slip_m"})
    bad["peak_slip_m"] = bad["peak_slip_m"] / 1000
    _check(schedule, bad, tmp_path, r"^bad\.csv, header: 'peak_slip_m' has unit 'm' where "
           r"'peak_slip_mm' \(mm\) is expected" + TEMPLATE)


KNOWN = r"; its columns are trial_id, aborted, outcome, .*, abort_reason, environment, source"


def test_an_unknown_column_is_refused_with_the_nearest_name(good, tmp_path):
    """A misspelt optional column would be dropped: ``Source = virtual`` stored as measured."""
    schedule, rec, _ = good
    bad = rec.assign(source="virtual").rename(columns={"source": "Source"})
    bad["operator_notes"] = "ok"
    _check(schedule, bad, tmp_path, r"^bad\.csv, header: columns are not part of the sheet: 'Source' "
           r"\(did you mean 'source'\?\), 'operator_notes'" + KNOWN + TEMPLATE)


def test_measurements_filled_in_beside_the_commanded_sheet_are_read_as_the_records_alone(good, tmp_path):
    """The sheet `schedule` writes, with the measured columns added: its own columns are not read."""
    schedule, rec, _ = good
    filled = schedule.merge(rec, on="trial_id", validate="one_to_one")
    assert len(filled) == len(rec) and len(filled.columns) == len(schedule.columns) + len(rec.columns) - 1
    alone, beside = (validate_records(_file(df, tmp_path / f"{name}.csv", "csv"), schedule)
                     for name, df in (("alone", rec), ("beside", filled)))
    pd.testing.assert_frame_equal(beside.set_index("trial_id").sort_index(),
                                  alone.set_index("trial_id").sort_index())


def test_a_long_list_of_unknown_columns_is_cut_short(good, tmp_path):
    schedule, rec, _ = good
    bad = rec.assign(**{f"x{i}": 0 for i in range(20)})
    _check(schedule, bad, tmp_path, r"^bad\.csv, header: columns are not part of the sheet: 'x0', 'x1', "
           r"'x2', 'x3', 'x4', 'x5', 'x6', 'x7' and 12 more" + KNOWN + TEMPLATE)


@pytest.mark.parametrize("kind", ["csv", "xlsx"])
def test_a_column_given_twice_is_refused(good, tmp_path, kind):
    schedule, rec, _ = good
    bad = pd.concat([rec, rec[["sf_actual"]] * 0 + 42], axis=1)  # pandas keeps the first one
    _check(schedule, bad, tmp_path, rf"^bad\.{kind}, header: a column appears more than once: "
           r"sf_actual" + TEMPLATE, kind)


@pytest.mark.parametrize("text, message", [
    (b"trial_id;aborted\nx;false\n", r"header: the cells are separated by ';', not commas; "
     r"save the sheet as comma-separated CSV \(decimal point '\.'\)\."),
    (b"trial_id\taborted\nx\tfalse\n", r"header: the cells are separated by tabs, not commas; "
     r"save the sheet as comma-separated CSV \(decimal point '\.'\)\."),
    ("trial_id,aborted\nt\u00e4,false\n".encode("latin-1"), r"line 2: the file is not UTF-8 text "
     r"\(byte 0xe4\); save it as CSV UTF-8\."),
    (b"trial_id,aborted\nx,false\ny,false,3,4\n", r"row 2: 4 cells where the header has 2 columns "
     r"\(a cell with a comma needs quotes; a truncated file loses its last row's cells\)\."),
    (b"trial_id,aborted,outcome\nx,false,stable\ny,fal\n", r"row 2: 2 cells where the header has 3 "
     r"columns \(a cell with a comma needs quotes; a truncated file loses its last row's cells\)\."),
])
def test_a_csv_pandas_would_misread_is_refused_with_the_reason(good, tmp_path, text, message):
    schedule, _, _ = good
    path = tmp_path / "bad.csv"
    path.write_bytes(text)
    with pytest.raises(IngestError, match=rf"^bad\.csv, {message}$"):
        validate_records(path, schedule)


@pytest.mark.parametrize("name, data", [("blank.csv", b"  \n\n"), ("empty.csv", b""),
                                        ("empty.parquet", b""), ("empty.xlsx", b"")])
def test_an_empty_file_is_named_and_called_empty(good, tmp_path, name, data):
    """No header to point at: the file and what is wrong with it, not a column '-'."""
    schedule, _, _ = good
    (tmp_path / name).write_bytes(data)
    with pytest.raises(IngestError, match=rf"^{re.escape(name)}: the file is empty\.$"):
        validate_records(tmp_path / name, schedule)


def test_a_cell_holding_a_line_separator_is_one_cell(good, tmp_path):
    """U+2028 inside a quoted cell ends no CSV row (str.splitlines would break there)."""
    schedule, rec, i = good
    bad = rec.astype({"abort_reason": object})
    bad.loc[i, "abort_reason"] = "gripper\u2028note"
    path = _file(bad, tmp_path / "notes.csv", "csv")
    assert validate_records(path, schedule).loc[i, "abort_reason"] == "gripper\u2028note"


def test_a_directory_is_not_a_file(good, tmp_path):
    schedule, _, _ = good
    (tmp_path / "day1.csv").mkdir()
    with pytest.raises(IngestError, match=r"^day1\.csv: is a directory, not a file\.$"):
        validate_records(tmp_path / "day1.csv", schedule)


def test_a_file_of_two_sources_is_refused(good, tmp_path):
    """A run is measured or virtual, never both: its report labels the whole run by its source."""
    schedule, rec, i = good
    bad = rec.assign(source="measured")
    bad.loc[i + 1, "source"] = "virtual"
    _check(schedule, bad, tmp_path, rf"^bad\.csv, row {i + 2}, column 'source': value 'virtual' "
           r"differs from 'measured' in bad\.csv, row 1; a run holds the records of one source "
           r"\(measured or virtual\): ingest the others into another run with --run\.$")


@pytest.mark.parametrize("attempt", ["100", "1000000000000000000000"])
def test_a_rerun_beyond_the_attempt_limit_is_refused(good, tmp_path, attempt):
    schedule, rec, i = good
    slot = schedule.set_index("trial_id").loc[rec.loc[i, "trial_id"], "slot_id"]
    bad = pd.concat([rec, rec.iloc[[i]].assign(trial_id=f"{slot}-a{attempt}", aborted=True)],
                    ignore_index=True)
    _check(schedule, bad, tmp_path, rf"^bad\.csv, row {len(rec) + 1}, column 'trial_id': trial id "
           rf"'{slot}-a{attempt}' names attempt {attempt} of slot '{slot}'; a re-run is attempt 2 to "
           r"99\.$")


# One bad row: the first executed trial, row i + 1 of the file. Each case: the cells changed in
# that row, the file type, the column the message names and the message after that column.
BAD_ROW = {
    "not_a_number": ({"normal_force_1_n": "1,2"}, "csv", "normal_force_1_n",
                     r"value '1,2' is not a number \(a decimal comma: save the sheet with a "
                     r"decimal point '\.'\)\.$"),
    "out_of_range": ({"deformation_2_mm": 4200.0},  # micrometres written into a mm column
                     "csv", "deformation_2_mm",
                     r"value 4200 lies outside \[0, 50\] mm \(wrong units\?\)\.$"),
    "out_of_range_in_newtons": ({"normal_force_1_n": 1e6}, "csv", "normal_force_1_n",
                                r"value 1e\+06 lies outside \[-1, 20\] N \(wrong units\?\)\.$"),
    "not_finite": ({"sf_actual": np.inf}, "parquet", "sf_actual", r"value inf is not finite\.$"),
    "bad_aborted_flag": ({"aborted": "maybe"}, "csv", "aborted",
                         r"value 'maybe' is not a boolean \(true/false, yes/no, y/n, t/f, 1/0\)\.$"),
    "empty_required_cell_of_an_executed_trial": (
        {"g_geo_actual": np.nan}, "xlsx", "g_geo_actual",
        r"value is empty but the trial was executed \(aborted is false\)\.$"),
    "unknown_outcome": ({"outcome": "wobbly"}, "csv", "outcome",
                        r"value 'wobbly' is not one of stable, success, partial, "
                        r"failure_slip, failure_drop, failure_damage, failure_contact_loss, "
                        r"aborted\.$"),
    "unknown_trial_id": ({"trial_id": "t2Z-nowhere"}, "csv", "trial_id",
                         r"trial id 't2Z-nowhere' is not in the schedule\.$"),
    "empty_trial_id": ({"trial_id": ""}, "csv", "trial_id", r"trial id is empty\.$"),
    "bad_source": ({"source": "simulated"}, "csv", "source",
                   r"value 'simulated' is not one of measured, virtual\.$"),
    "misspelt_outcome": ({"outcome": "failure_slp"}, "csv", "outcome", r"value 'failure_slp' \(did "
                         r"you mean 'failure_slip'\?\) is not one of stable, success, partial, "
                         r"failure_slip, failure_drop, failure_damage, failure_contact_loss, aborted\.$"),
    "success_inconsistent_with_outcome": (
        {"outcome": "failure_slip", "success": True, "stable": False, "slip_flag": True}, "csv",
        "success", r"success is True but outcome is 'failure_slip' \(success means outcome "
        r"stable or success, §8\.1\)\.$"),
    "failure_event_under_a_non_failure_outcome": (
        {"outcome": "stable", "success": True, "stable": True, "drop_flag": True}, "csv", "drop_flag",
        r"drop_flag is true but outcome is 'stable' \(a measured drop, damage or contact loss classes "
        r"the trial as that failure, §8\.1\)\.$"),
    "an_outcome_on_an_aborted_row": (
        {"aborted": True, "outcome": "stable"}, "csv", "outcome", r"outcome is 'stable' on a row "
        r"whose aborted flag is true \(an aborted attempt has no outcome: leave it empty or write "
        r"aborted\)\.$"),
    "failure_class_without_its_flag": (
        {"outcome": "failure_drop", "success": False, "stable": False, "drop_flag": False}, "csv",
        "drop_flag", r"outcome is 'failure_drop' but drop_flag is false \(every failure class "
        r"carries its flag, §8\.1\)\.$"),
}


@pytest.mark.parametrize("case", list(BAD_ROW))
def test_bad_row(good, tmp_path, case):
    schedule, rec, i = good
    cells, kind, column, problem = BAD_ROW[case]
    bad = rec.astype({c: object for c, value in cells.items() if isinstance(value, str)})
    for c, value in cells.items():
        bad.loc[i, c] = value
    _check(schedule, bad, tmp_path, rf"^bad\.{kind}, row {i + 1}, column '{column}': {problem}",
           kind)


def test_duplicate_trial_id(good, tmp_path):
    schedule, rec, i = good
    bad = pd.concat([rec, rec.iloc[[i]]], ignore_index=True)
    _check(schedule, bad, tmp_path, rf"^bad\.csv, row {len(rec) + 1}, column 'trial_id': "
           rf"duplicate trial id '.+' \(first seen in row {i + 1}\)\.$")


def test_two_executed_attempts_of_one_slot(good, tmp_path):
    schedule, rec, i = good
    slot = schedule.set_index("trial_id").loc[rec.loc[i, "trial_id"], "slot_id"]
    extra = rec.iloc[[i]].copy()
    extra["trial_id"] = f"{slot}-a2"
    bad = pd.concat([rec, extra], ignore_index=True)
    _check(schedule, bad, tmp_path, rf"^bad\.csv, row {len(rec) + 1}, column 'aborted': slot "
           rf"'{slot}' already has an executed record in row {i + 1}; only one attempt per slot "
           r"may be executed\.$")


def test_unsupported_file_type(good, tmp_path):
    schedule, rec, _ = good
    path = tmp_path / "records.json"
    rec.to_json(path)
    with pytest.raises(IngestError, match=r"^records\.json: unsupported file "
                       r"type '\.json' \(expected \.csv, \.parquet or \.xlsx\)\.$"):
        validate_records(path, schedule)


def test_records_behind_a_cover_sheet_name_their_sheet(good, tmp_path):
    """A workbook whose first sheet is not the records (a cover page) is refused naming the
    sheet that has them; with the records sheet first, the same workbook reads."""
    schedule, rec, _ = good
    path = tmp_path / "book.xlsx"
    with pd.ExcelWriter(path) as book:
        cover = pd.DataFrame({"operator": ["A. B."], "date": ["2026-11-29"]})
        cover.to_excel(book, sheet_name="cover", index=False)
        rec.to_excel(book, sheet_name="trials", index=False)
    with pytest.raises(IngestError, match=r"^book\.xlsx, header: ingest reads the workbook's first "
                       r"sheet, which lacks the required columns; sheet 'trials' has them all: move "
                       r"it to the front or save it as CSV \(`graspcampaign schedule"):
        validate_records(path, schedule)
    with pd.ExcelWriter(path) as book:
        rec.to_excel(book, sheet_name="trials", index=False)
        pd.DataFrame({"operator": ["A. B."]}).to_excel(book, sheet_name="cover", index=False)
    assert len(validate_records(path, schedule)) == len(rec)


def test_records_behind_an_empty_first_sheet_name_their_sheet(good, tmp_path):
    """The tester's workbook: an empty first sheet (a spreadsheet's default 'Sheet1'), the records
    on sheet 'data'; was "the file has no data rows"."""
    schedule, rec, _ = good
    path = tmp_path / "book.xlsx"
    with pd.ExcelWriter(path) as book:
        pd.DataFrame().to_excel(book, sheet_name="Sheet1", index=False)
        rec.to_excel(book, sheet_name="data", index=False)
    with pytest.raises(IngestError) as info:
        validate_records(path, schedule)
    assert str(info.value) == (
        "book.xlsx, header: ingest reads the workbook's first sheet, which is empty; sheet 'data' "
        "has every required column: move it to the front or save it as CSV (`graspcampaign "
        "schedule <study> --template` writes a sheet with every column).")


@pytest.mark.parametrize("column", ["peak_slip_mm", "sf_actual"])  # optional cell, required cell
def test_a_formula_without_its_computed_value_is_refused(good, tmp_path, column):
    """openpyxl writes a formula without a value; pandas reads the cell as empty (not measured)."""
    from openpyxl import load_workbook

    schedule, rec, i = good
    path = _file(rec, tmp_path / "book.xlsx", "xlsx")
    book = load_workbook(path)
    book.active.cell(row=i + 2, column=list(rec.columns).index(column) + 1).value = "=12.5*2"
    book.save(path)
    assert pd.isna(pd.read_excel(path)[column].iloc[i])  # what pandas alone reads: an empty cell
    with pytest.raises(IngestError) as info:
        validate_records(path, schedule)
    assert str(info.value) == (
        f"book.xlsx, row {i + 1}, column '{column}': the cell holds a formula (=12.5*2) with no "
        "computed value; open and save the file in a spreadsheet program, which stores the values.")


def test_missing_file(good, tmp_path):
    schedule, _, _ = good
    with pytest.raises(IngestError, match=r"^nope\.csv: the file does not "
                       r"exist\.$"):
        validate_records(tmp_path / "nope.csv", schedule)


def test_corrupt_file(good, tmp_path):
    schedule, _, _ = good
    path = tmp_path / "records.parquet"
    path.write_bytes(b"not parquet at all")
    with pytest.raises(IngestError, match=r"^records\.parquet: the file is not a Parquet table: "
                       r"it does not begin as one does; if it is CSV text, rename it to "
                       r"records\.csv\.$"):
        validate_records(path, schedule)


def test_no_data_rows(good, tmp_path):
    schedule, rec, _ = good
    _check(schedule, rec.iloc[:0], tmp_path, r"^bad\.csv, header, column 'trial_id': the file has "
           r"no data rows\.$")


def test_test3_specific_columns(t3, tmp_path):
    schedule, _, _, meas = t3
    rec = meas[record_columns("test3_disturbance")].copy().reset_index(drop=True)
    i = int(np.flatnonzero(~rec["aborted"].astype(bool).to_numpy())[0])
    bad = rec.astype({"first_finger_measured": object})
    bad.loc[i, "first_finger_measured"] = 1.5
    _check(schedule, bad, tmp_path, rf"^bad\.csv, row {i + 1}, column 'first_finger_measured': "
           r"value '1\.5' is not an integer\.$")
    _check(schedule, rec.rename(columns={"threshold_measured_nm": "threshold_measured_nmm"}),
           tmp_path, r"^bad\.csv, header: 'threshold_measured_nmm' has unit 'nmm' where "
           r"'threshold_measured_nm' \(nm\) is expected" + TEMPLATE)
    bad = rec.astype({"first_finger_measured": object})
    bad.loc[i, "first_finger_measured"] = 4
    _check(schedule, bad, tmp_path, rf"^bad\.csv, row {i + 1}, column 'first_finger_measured': "
           r"value 4 lies outside \[0, 3\] \(wrong units\?\)\.$")
    bad = rec.copy()
    bad.loc[i, ["threshold_censored", "first_finger_measured"]] = [True, 2]
    _check(schedule, bad, tmp_path, rf"^bad\.csv, row {i + 1}, column 'first_finger_measured': finger "
           r"2 slipped first but threshold_censored is true \(a censored ramp ended without slip: "
           r"0\)\.$")


def test_record_template_has_every_column_with_its_unit(t3):
    from graspcampaign.rig.record_schema import record_template

    schedule = t3[0]
    sheet, columns = record_template(schedule)
    assert list(sheet.columns) == record_columns("test3_disturbance") == list(columns["column"])
    assert sheet["trial_id"].tolist() == schedule["trial_id"].tolist()
    assert (sheet.drop(columns="trial_id") == "").all().all()
    unit = dict(zip(columns["column"], columns["unit"], strict=True))
    assert (unit["peak_slip_mm"], unit["normal_force_1_n"], unit["threshold_measured_nm"],
            unit["rotation_at_limit_deg"], unit["sf_actual"], unit["outcome"]) == (
        "mm", "N", "N m", "deg", "1", "-")
    # the template read back, every measured cell still empty: its rows are not filled in
    with pytest.raises(IngestError, match=r"^template.csv, row 1, column 'aborted': the row is not "
                                          r"filled in \(only its trial_id\); a file holds the trials "
                                          r"run: delete the rows not run yet\.$"):
        validate_records(sheet, schedule, "template.csv")


# ------------------------------------------------------------------ self-contradicting records
@pytest.mark.parametrize(("stem", "fingers", "mean", "message"), [
    # the tester's record: fingers 1, 1, 1 N beside a 15 N mean was stored
    ("normal_force", (1.0, 1.0, 1.0), 15.0, "value 15 N is not the mean of normal_force_1_n, "
     "normal_force_2_n, normal_force_3_n (1, 1, 1: mean 1 N) within 5% + 0.01 N."),
    # the mean written in tenths of a millimetre
    ("deformation", (0.5, 0.6, 0.7), 6.0, "value 6 mm is not the mean of deformation_1_mm, "
     "deformation_2_mm, deformation_3_mm (0.5, 0.6, 0.7: mean 0.6 mm) within 5% + 0.2 mm."),
], ids=["force", "deformation"])
def test_a_mean_that_is_not_the_fingers_mean_is_refused(good, tmp_path, stem, fingers, mean, message):
    schedule, rec, i = good
    unit = "n" if stem == "normal_force" else "mm"
    bad = rec.copy()
    bad.loc[i, [f"{stem}_{k}_{unit}" for k in (1, 2, 3)]] = fingers
    bad.loc[i, f"{stem}_mean_{unit}"] = mean
    path = _file(bad, tmp_path / "bad.csv", "csv")
    with pytest.raises(IngestError) as info:
        validate_records(path, schedule)
    assert str(info.value) == f"bad.csv, row {i + 1}, column '{stem}_mean_{unit}': {message}"


@pytest.mark.parametrize(("fingers", "mean", "accepted"), [
    ((1.000, 1.005, 1.010), 1.000, True),    # each rounded to the 5 mN step: 5 mN off
    ((4.0, 4.0, 4.1), 4.24, True),           # 4.033 N: 0.207 N off, inside 5 % + 0.01 N = 0.212 N
    ((4.0, 4.0, 4.1), 4.30, False),          # 0.267 N off
    ((2.0, float("nan"), 4.0), 3.0, True),   # a finger not recorded: the mean of the others
], ids=["rounding", "edge", "beyond", "two_fingers"])
def test_the_mean_force_tolerance(good, tmp_path, fingers, mean, accepted):
    schedule, rec, i = good
    bad = rec.copy()
    bad.loc[i, ["normal_force_1_n", "normal_force_2_n", "normal_force_3_n"]] = fingers
    bad.loc[i, "normal_force_mean_n"] = mean
    path = _file(bad, tmp_path / "bad.csv", "csv")
    if accepted:
        assert validate_records(path, schedule)["normal_force_mean_n"].iloc[i] == mean
    else:
        with pytest.raises(IngestError, match=rf"^bad\.csv, row {i + 1}, column "
                                              r"'normal_force_mean_n': value 4\.3 N is not the mean"):
            validate_records(path, schedule)
