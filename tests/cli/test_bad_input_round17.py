"""Bad input, round 17: Test 1 ingest as a new user, and what a file of another test says. A file
of one test (or a commanded sheet) given to another's ingest is named as what it is; a 'Total' row
below the records is named by its id; a waveform's event id in capitals or a specimen id in its
place, a load cell not zeroed before a press and an event of one sample are refused. Each refusal:
exit 2, one sentence naming the file, row and column, nothing stored changed (``refused``)."""

from __future__ import annotations

import numpy as np
import pandas as pd
import pytest
from cli_checks import EVENT, T1, T2, bench_press, filled_records, invoke, refused

TEMPLATE = "(`graspcampaign schedule <study> --template` writes a sheet with every column)."
TEMPLATE1 = "(`graspcampaign schedule test1_bench --template` writes a sheet with every column)."
NO_T1 = "no event_id, time_s, displacement_mm, normal_force_n, tangential_force_n, tangential_displacement_mm"
NO_T2 = "no trial_id, aborted, outcome, success, stable, slip_flag, drop_flag, damage_flag and more"


# -- a file of another test ----------------------------------------------------------------------
def test_a_test2_file_given_to_test3s_ingest_says_it_is_test2s(results, tmp_path):
    # the old code listed the five Test 3 columns it lacks, without a word of what it is
    filled_records(tmp_path).to_csv(tmp_path / "day1.csv", index=False)
    refused(results, ["ingest", "test3_disturbance", tmp_path / "day1.csv", *T2, "--root", results],
            "day1.csv, header: its columns are those of a Test 2 measured-records file (no "
            "threshold_measured_n, threshold_measured_nm, threshold_censored, first_finger_measured, "
            "rotation_at_limit_deg); ingest it with `graspcampaign ingest test2_grasp FILE` "
            f"{TEMPLATE}")


def test_a_test3_file_given_to_test2s_ingest_says_it_is_test3s(results, tmp_path):
    # the old code: "columns are not part of the sheet: 'threshold_measured_n', ..."
    filled_records(tmp_path, "test3_disturbance").to_csv(tmp_path / "day1.csv", index=False)
    refused(results, ["ingest", "test2_grasp", tmp_path / "day1.csv", *T2, "--root", results],
            "day1.csv, header: its columns are those of a Test 3 measured-records file; ingest it "
            f"with `graspcampaign ingest test3_disturbance FILE` {TEMPLATE}")


def test_test1_waveforms_given_to_test2s_ingest_say_they_are_test1s(results, tmp_path):
    bench_press().to_csv(tmp_path / "waves.csv", index=False)
    refused(results, ["ingest", "test2_grasp", tmp_path / "waves.csv", *T2, "--root", results],
            f"waves.csv, header: its columns are those of a Test 1 measured-records file ({NO_T2}); "
            f"ingest it with `graspcampaign ingest test1_bench FILE` {TEMPLATE}")


def test_a_test2_file_given_to_test1s_ingest_says_it_is_test2s(results, tmp_path):
    filled_records(tmp_path).to_csv(tmp_path / "day1.csv", index=False)
    refused(results, ["ingest", "test1_bench", tmp_path / "day1.csv", *T1, "--root", results],
            f"day1.csv, header: its columns are those of a Test 2 measured-records file ({NO_T1}); "
            f"ingest it with `graspcampaign ingest test2_grasp FILE` {TEMPLATE1}")


def test_the_commanded_sheet_given_as_waveforms_is_named(results, tmp_path):
    made = invoke("schedule", "test1_bench", *T1[1::2], "--out", tmp_path / "sheet")
    assert made.exit_code == 0, made.output
    refused(results, ["ingest", "test1_bench", tmp_path / "sheet.csv", *T1, "--root", results],
            "sheet.csv, header: its columns are those of the commanded sheet `graspcampaign "
            "schedule test1_bench` writes (no time_s, displacement_mm, normal_force_n, "
            "tangential_force_n, tangential_displacement_mm), not measured records; fill in the "
            f"template instead {TEMPLATE1}")


# -- a 'Total' row -------------------------------------------------------------------------------
@pytest.mark.parametrize("sums", [False, True])
def test_a_total_row_below_the_records_is_named_by_its_trial_id(results, tmp_path, sums):
    # the old code: "row 3, column 'aborted': the row is not filled in (only its trial_id)", and
    # with sums beside it "value '' is not a boolean"
    records = filled_records(tmp_path)
    total = {c: "" for c in records.columns} | {"trial_id": "Total"}
    if sums:
        total |= {"normal_force_1_n": 1.0, "peak_slip_mm": 0.2}
    pd.concat([records, pd.DataFrame([total])]).to_csv(tmp_path / "day1.csv", index=False)
    refused(results, ["ingest", "test2_grasp", tmp_path / "day1.csv", *T2, "--root", results],
            "day1.csv, row 3, column 'trial_id': trial id 'Total' is not in the schedule.")


def test_a_total_row_below_the_samples_is_named_by_its_event_id(results, tmp_path):
    # the old code: "row 302, column 'time_s': value nan (an empty cell or NaN) is not finite"
    waves = bench_press()
    total = pd.DataFrame([{"event_id": "Total", "normal_force_n": waves["normal_force_n"].sum()}])
    pd.concat([waves, total]).to_csv(tmp_path / "waves.csv", index=False)
    refused(results, ["ingest", "test1_bench", tmp_path / "waves.csv", *T1, "--root", results],
            "waves.csv, row 302, column 'event_id': event id 'Total' is not in the schedule.")


# -- Test 1 waveforms ----------------------------------------------------------------------------
@pytest.mark.parametrize(("event", "hint"), [
    (EVENT.upper(), f" (event ids are case-sensitive: '{EVENT}'?)"),
    ("gel-S01", " (it is a specimen_id; the column holds the event_id of the schedule's row of "
     "each event)"),
])
def test_an_event_id_in_capitals_or_a_specimen_id_is_named_as_such(results, tmp_path, event, hint):
    # the old code: "event id '...' is not in the schedule", nothing more
    bench_press().assign(event_id=event).to_csv(tmp_path / "waves.csv", index=False)
    refused(results, ["ingest", "test1_bench", tmp_path / "waves.csv", *T1, "--root", results],
            f"waves.csv, row 1, column 'event_id': event id '{event}' is not in the schedule{hint}.")


def test_a_load_cell_not_zeroed_before_a_press_is_refused(results, tmp_path):
    # the old code stored it, every force 50 mN low (a slide's mu_s 0.78 read as 0.98), accepted
    waves = bench_press().assign(normal_force_n=lambda d: d["normal_force_n"] - 0.05)
    waves.to_csv(tmp_path / "waves.csv", index=False)
    refused(results, ["ingest", "test1_bench", tmp_path / "waves.csv", *T1, "--root", results],
            f"waves.csv, row 1, column 'normal_force_n': event '{EVENT}' reads -0.05 N before "
            "contact (the median of its samples before its displacement exceeds 0), a tension "
            "beyond 0.01 N, as from a load cell not zeroed (tared): zero the channel (subtract "
            "its reading before contact).")


def test_a_press_with_noise_before_contact_is_stored(results, tmp_path):
    # the neighbouring case: a cell reading its noise (a few mN either way) before contact
    noise = np.random.default_rng(1).normal(0.0, 0.003, 301)
    bench_press().assign(normal_force_n=lambda d: d["normal_force_n"] + noise).to_csv(
        tmp_path / "waves.csv", index=False)
    done = invoke("ingest", "test1_bench", tmp_path / "waves.csv", *T1, "--root", results)
    assert done.exit_code == 0, done.output


def test_an_event_of_one_sample_is_refused(results, tmp_path):
    # the old code stored it, its fits failed (a waveform of one sample has no rate to check)
    bench_press().iloc[150:151].to_csv(tmp_path / "waves.csv", index=False)
    refused(results, ["ingest", "test1_bench", tmp_path / "waves.csv", *T1, "--root", results],
            f"waves.csv, row 1, column 'event_id': event '{EVENT}' has 1 sample, fewer than the 10 "
            "its fits need (a log cut short?); give its whole waveform, or leave the event out.")


def test_a_report_of_waveforms_without_a_cyclic_event_names_the_missing_column(results, tmp_path):
    # pandas' groupby says "Columns not found: 'onset_mm'", which the report printed inside its
    # sentence: "the records have no `Columns not found: 'onset_mm'` column"
    bench_press().to_csv(tmp_path / "waves.csv", index=False)
    done = invoke("ingest", "test1_bench", tmp_path / "waves.csv", *T1, "--root", results)
    assert done.exit_code == 0, done.output
    done = invoke("report", "test1_bench", "--run", "measured", "--root", results)
    assert done.exit_code == 0, done.output
    claims = pd.read_csv(results / "test1_bench" / "measured" / "report" / "tables" / "test1_claims.csv")
    said = claims.loc[claims["quantity"].str.startswith("permanent set"), "verdict"]
    assert list(said.unique()) == ["not computed: the records have no `onset_mm` column"]
