"""Ingest of measured Tests 2-3 records: round trip of the virtual rig's records, one test per
malformed-file kind with its message asserted."""

from __future__ import annotations

import numpy as np
import pandas as pd
import pytest

from graspcampaign.rig import analysis, protocol
from graspcampaign.rig.ingest import IngestError, record_columns, validate_records
from graspcampaign.rig.plan import predict_trial
from graspcampaign.rig.virtual import virtual_trial


def _virtual(schedule: pd.DataFrame, n_executed: int) -> tuple[pd.DataFrame, pd.DataFrame]:
    rows = pd.concat([schedule[schedule["rig_fault"] | (schedule["attempt"] == 2)],
                      schedule[~schedule["rig_fault"] & (schedule["attempt"] == 1)]
                      .head(n_executed)])
    rows = rows.sort_values("run_order")
    preds = pd.DataFrame([predict_trial(r) for r in rows.to_dict("records")])
    meas = pd.DataFrame([virtual_trial(r, p, np.random.default_rng(i)) for i, (r, p) in
                         enumerate(zip(rows.to_dict("records"), preds.to_dict("records"),
                                       strict=True))])
    meas.insert(0, "trial_id", rows["trial_id"].to_numpy())
    return rows.reset_index(drop=True), preds, meas


@pytest.fixture(scope="module")
def t2():
    schedule = protocol.test2_schedule(0)
    rows, preds, meas = _virtual(schedule, 150)
    return schedule, rows, preds, meas


@pytest.fixture(scope="module")
def t3():
    schedule = protocol.test3_schedule(0)
    rows, preds, meas = _virtual(schedule, 120)
    return schedule, rows, preds, meas


def _file(df: pd.DataFrame, path, kind: str):
    if kind == "csv":
        df.to_csv(path, index=False)
    elif kind == "parquet":
        df.to_parquet(path)
    else:
        df.to_excel(path, index=False)
    return path


@pytest.mark.parametrize("kind", ["csv", "parquet", "xlsx"])
@pytest.mark.parametrize("fixture", ["t2", "t3"])
def test_virtual_records_round_trip(fixture, kind, tmp_path, request):
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
    direct = analysis.merge_records(rows, preds, meas)
    ingested = analysis.merge_records(rows, preds, back)
    for fn in (analysis.planner_summary, analysis.outcome_breakdown, analysis.force_accuracy):
        pd.testing.assert_frame_equal(fn(direct), fn(ingested), check_dtype=False)


def test_source_defaults_to_measured_and_reruns_are_accepted(t2, tmp_path):
    schedule, _, _, meas = t2
    rec = meas[record_columns("test2_grasp")].drop(columns=["source"])
    executed = rec[~rec["aborted"].astype(bool)].iloc[:1].copy()
    slot = schedule.set_index("trial_id").loc[executed["trial_id"].iloc[0], "slot_id"]
    aborted = executed.copy()
    aborted["aborted"] = True
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


def test_missing_column(good, tmp_path):
    schedule, rec, _ = good
    _check(schedule, rec.drop(columns=["sf_actual"]), tmp_path,
           r"^bad\.csv, header, column 'sf_actual': required column is missing\.$")


def test_wrong_unit(good, tmp_path):
    schedule, rec, _ = good
    bad = rec.rename(columns={"peak_slip_mm": "peak_slip_m"})
    bad["peak_slip_m"] = bad["peak_slip_m"] / 1000
    _check(schedule, bad, tmp_path, r"^bad\.csv, header, column 'peak_slip_m': unit 'm' where "
           r"'peak_slip_mm' \(mm\) is expected\.$")


def test_not_a_number(good, tmp_path):
    schedule, rec, i = good
    bad = rec.astype({"normal_force_1_n": object})
    bad.loc[i, "normal_force_1_n"] = "1,2"
    _check(schedule, bad, tmp_path,
           rf"^bad\.csv, row {i + 1}, column 'normal_force_1_n': value '1,2' is not a number\.$")


def test_out_of_range(good, tmp_path):
    schedule, rec, i = good
    bad = rec.copy()
    bad.loc[i, "deformation_2_mm"] = 4200.0  # micrometres written into a mm column
    _check(schedule, bad, tmp_path, rf"^bad\.csv, row {i + 1}, column 'deformation_2_mm': value "
           r"4200 lies outside \[0, 50\] mm \(wrong units\?\)\.$")


def test_not_finite(good, tmp_path):
    schedule, rec, i = good
    bad = rec.copy()
    bad.loc[i, "sf_actual"] = np.inf
    _check(schedule, bad, tmp_path, rf"^bad\.parquet, row {i + 1}, column 'sf_actual': value "
           r"inf is not finite\.$", kind="parquet")


def test_bad_aborted_flag(good, tmp_path):
    schedule, rec, i = good
    bad = rec.astype({"aborted": object})
    bad.loc[i, "aborted"] = "maybe"
    _check(schedule, bad, tmp_path, rf"^bad\.csv, row {i + 1}, column 'aborted': value 'maybe' "
           r"is not a boolean")


def test_empty_required_cell_of_an_executed_trial(good, tmp_path):
    schedule, rec, i = good
    bad = rec.copy()
    bad.loc[i, "g_geo_actual"] = np.nan
    _check(schedule, bad, tmp_path, rf"^bad\.xlsx, row {i + 1}, column 'g_geo_actual': value is "
           r"empty but the trial was executed", kind="xlsx")


def test_unknown_outcome(good, tmp_path):
    schedule, rec, i = good
    bad = rec.copy()
    bad.loc[i, "outcome"] = "wobbly"
    _check(schedule, bad, tmp_path, rf"^bad\.csv, row {i + 1}, column 'outcome': value 'wobbly' "
           r"is not one of")


def test_unknown_trial_id(good, tmp_path):
    schedule, rec, i = good
    bad = rec.copy()
    bad.loc[i, "trial_id"] = "t2Z-nowhere"
    _check(schedule, bad, tmp_path, rf"^bad\.csv, row {i + 1}, column 'trial_id': trial id "
           r"'t2Z-nowhere' is not in the schedule\.$")


def test_empty_trial_id(good, tmp_path):
    schedule, rec, i = good
    bad = rec.copy()
    bad.loc[i, "trial_id"] = ""
    _check(schedule, bad, tmp_path, rf"^bad\.csv, row {i + 1}, column 'trial_id': trial id is "
           r"empty\.$")


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
           rf"'{slot}' already has an executed record in row {i + 1}")


def test_success_inconsistent_with_outcome(good, tmp_path):
    schedule, rec, i = good
    bad = rec.copy()
    bad.loc[i, "outcome"] = "failure_slip"
    bad.loc[i, "success"] = True
    bad.loc[i, "stable"] = False
    bad.loc[i, "slip_flag"] = True
    _check(schedule, bad, tmp_path, rf"^bad\.csv, row {i + 1}, column 'success': success is True "
           r"but outcome is 'failure_slip'")


def test_failure_class_without_its_flag(good, tmp_path):
    schedule, rec, i = good
    bad = rec.copy()
    bad.loc[i, ["outcome", "success", "stable", "drop_flag"]] = ["failure_drop", False, False,
                                                                  False]
    _check(schedule, bad, tmp_path, rf"^bad\.csv, row {i + 1}, column 'drop_flag': outcome is "
           r"'failure_drop' but drop_flag is false")


def test_unsupported_file_type(good, tmp_path):
    schedule, rec, _ = good
    path = tmp_path / "records.json"
    rec.to_json(path)
    with pytest.raises(IngestError, match=r"^records\.json, header, column '-': unsupported file "
                       r"type '\.json' \(expected \.csv, \.parquet or \.xlsx\)\.$"):
        validate_records(path, schedule)


def test_missing_file(good, tmp_path):
    schedule, _, _ = good
    with pytest.raises(IngestError, match=r"^nope\.csv, header, column '-': the file does not "
                       r"exist\.$"):
        validate_records(tmp_path / "nope.csv", schedule)


def test_corrupt_file(good, tmp_path):
    schedule, _, _ = good
    path = tmp_path / "records.parquet"
    path.write_bytes(b"not parquet at all")
    with pytest.raises(IngestError, match=r"^records\.parquet, header, column '-': the file cannot "
                       r"be read as parquet"):
        validate_records(path, schedule)


def test_no_data_rows(good, tmp_path):
    schedule, rec, _ = good
    _check(schedule, rec.iloc[:0], tmp_path, r"^bad\.csv, header, column 'trial_id': the file has "
           r"no data rows\.$")


def test_bad_source(good, tmp_path):
    schedule, rec, i = good
    bad = rec.copy()
    bad.loc[i, "source"] = "simulated"
    _check(schedule, bad, tmp_path, rf"^bad\.csv, row {i + 1}, column 'source': value 'simulated' "
           r"is not one of measured, virtual\.$")


def test_test3_specific_columns(t3, tmp_path):
    schedule, _, _, meas = t3
    rec = meas[record_columns("test3_disturbance")].copy().reset_index(drop=True)
    i = int(np.flatnonzero(~rec["aborted"].astype(bool).to_numpy())[0])
    bad = rec.astype({"first_finger_measured": object})
    bad.loc[i, "first_finger_measured"] = 1.5
    _check(schedule, bad, tmp_path, rf"^bad\.csv, row {i + 1}, column 'first_finger_measured': "
           r"value '1\.5' is not an integer\.$")
    _check(schedule, rec.rename(columns={"threshold_measured_nm": "threshold_measured_nmm"}),
           tmp_path, r"^bad\.csv, header, column 'threshold_measured_nmm': unit 'nmm' where "
           r"'threshold_measured_nm' \(nm\) is expected\.$")
