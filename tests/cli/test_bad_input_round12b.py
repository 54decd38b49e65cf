"""Bad input, round 12 (a fresh adversary): what stored wrong data, lost records or printed a
traceback. Each refusal: exit 2, one sentence naming what is wrong and where, nothing stored
changed (``refused``; for Tests 2-3 on a run that already holds records, ``stored``)."""

from __future__ import annotations

import pandas as pd
import test_bad_ingest_round10 as round10
from cli_checks import invoke, refused

T2, _records = round10.T2, round10._records
stored = round10.stored  # the fixture: a measured Test 2 run holding two trials


def test_a_number_with_an_underscore_in_a_measured_cell_is_refused(stored, tmp_path):
    # the old code stored sf_actual '1_4' as 14.0 (Python's float reads '_' as digit grouping)
    frame = _records(tmp_path, slice(2, 4)).astype({"sf_actual": object})
    frame.loc[1, "sf_actual"] = "1_4"
    frame.to_csv(tmp_path / "day2.csv", index=False)
    refused(stored, ["ingest", "test2_grasp", tmp_path / "day2.csv", *T2, "--root", stored],
            "day2.csv, row 2, column 'sf_actual': value '1_4' is not a number.")


def test_records_on_a_second_sheet_of_a_workbook_are_named_not_left_unread(stored, tmp_path):
    # the old code stored the first sheet's two trials and said nothing of the second sheet's
    book = tmp_path / "days.xlsx"
    with pd.ExcelWriter(book) as writer:
        _records(tmp_path, slice(2, 4)).to_excel(writer, sheet_name="day2", index=False)
        _records(tmp_path, slice(4, 6)).to_excel(writer, sheet_name="day3", index=False)
    refused(stored, ["ingest", "test2_grasp", book, *T2, "--root", stored],
            "days.xlsx, header: sheet 'day3' holds records too (every required column, rows "
            "below it), but ingest reads only the workbook's first sheet, so they would not be "
            "stored: save each sheet as a CSV file and ingest the files together, or move the "
            "rows to the first sheet (`graspcampaign schedule <study> --template` writes a sheet "
            "with every column).")
    with pd.ExcelWriter(book) as writer:  # a blank template kept behind the records holds none
        _records(tmp_path, slice(2, 4)).to_excel(writer, sheet_name="day2", index=False)
        _records(tmp_path, slice(0, 0)).to_excel(writer, sheet_name="blank", index=False)
    done = invoke("ingest", "test2_grasp", book, *T2, "--root", stored)
    assert done.exit_code == 0, done.output


def test_negative_zero_is_the_level_zero_so_listing_both_is_refused(tmp_path):
    # the old code took 0.0 and -0.0 for two levels (their reprs differ): two trials of one scene
    for command in ("show", "run"):
        refused(tmp_path, [command, "wrench_balance", "factors.mu=[0.0,-0.0]", "--root", tmp_path],
                "factors.mu lists the level 0.0 twice (factors.mu[0] and factors.mu[1]); give each "
                "level once.")
