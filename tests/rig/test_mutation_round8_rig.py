"""Mutation round 8: edges of the measured-file reader and the Test 1 waveform checks that no test
pinned, each against a workbook built cell by cell with openpyxl or a table counted by hand
(docs/decisions.md, mutation round 8)."""

from __future__ import annotations

import numpy as np
import openpyxl
import pandas as pd
import pytest

from graspcampaign.rig.measured_file import IngestError, cell_problem, empty_row, read_table
from graspcampaign.rig.record_schema import ATTEMPT_TYPO_LIMIT
from graspcampaign.rig.test1_ingest import RATE_FACTOR, _attempts, _check_rate

ROWS = 6  # data rows: sheet rows 2-7 under the header in row 1


def book(path, hidden=(), merged=()):
    """A sheet of ROWS trials; ``hidden`` and ``merged`` in the sheet's own row numbers."""
    wb = openpyxl.Workbook()
    ws = wb.active
    ws.append(["trial_id", "value"])
    for i in range(ROWS):
        ws.append([f"t{i}", i])
    for r in hidden:
        ws.row_dimensions[r].hidden = True
    for m in merged:
        ws.merge_cells(m)
    wb.save(path)
    return path


def test_the_last_data_row_hidden_is_refused_a_hidden_row_below_the_table_is_not(tmp_path):
    """Sheet row 7 is data row 6, the table's last; sheet row 8 holds nothing."""
    with pytest.raises(IngestError, match=r"t\.xlsx: row 6 is hidden in the sheet"):
        read_table(book(tmp_path / "t.xlsx", hidden=[ROWS + 1]))
    assert len(read_table(book(tmp_path / "u.xlsx", hidden=[ROWS + 2]))) == ROWS


def test_five_hidden_rows_are_all_named_a_sixth_is_counted(tmp_path):
    with pytest.raises(IngestError) as five:
        read_table(book(tmp_path / "t.xlsx", hidden=range(2, 7)))
    assert "row 1, row 2, row 3, row 4, row 5 are hidden" in str(five.value)
    assert "more" not in str(five.value)
    with pytest.raises(IngestError, match="row 1, row 2, row 3, row 4, row 5 and 1 more are hidden"):
        read_table(book(tmp_path / "u.xlsx", hidden=range(2, 8)))


def test_a_merge_starting_in_the_last_data_row_is_refused(tmp_path):
    said = r"t\.xlsx, row 6, column 'value': the cell is merged with others \(B7:B8\)"
    with pytest.raises(IngestError, match=said):
        read_table(book(tmp_path / "t.xlsx", merged=["B7:B8"]))


def test_a_list_of_three_values_is_shown_whole_four_are_cut():
    assert cell_problem([1, 2, 3]) == "value [1, 2, 3] is a list of 3 values, not a number"
    assert cell_problem([1, 2, 3, 4]) == "value [1, 2, 3, ...] is a list of 4 values, not a number"


def test_the_empty_row_is_the_one_named_by_its_1_based_number():
    frame = pd.DataFrame({"trial_id": ["t0", "", "t2"], "value": [1.0, np.nan, 2.0]})
    found = [empty_row("f.csv", frame, row) for row in (1, 2, 3)]
    assert found[0] is None and found[2] is None
    assert str(found[1]) == "f.csv, row 2 is empty; delete it."


def test_the_highest_attempt_number_is_accepted_the_next_is_refused():
    """The message says "an integer 1 to N": N is one."""
    assert _attempts(pd.Series([1, ATTEMPT_TYPO_LIMIT]), "f.csv").tolist() == [1, ATTEMPT_TYPO_LIMIT]
    said = f"is not an attempt number \\(an integer 1 to {ATTEMPT_TYPO_LIMIT} "
    with pytest.raises(IngestError, match=said):
        _attempts(pd.Series([ATTEMPT_TYPO_LIMIT + 1]), "f.csv")


@pytest.mark.parametrize("hz", [1.0, 1e5])
def test_an_event_sampled_far_slower_or_faster_than_commanded_is_refused(hz):
    """Commanded 1 kHz; sampled at 1 Hz (time in ms read as s?) or 100 kHz: more than RATE_FACTOR
    (30) either way."""
    assert max(hz / 1e3, 1e3 / hz) > RATE_FACTOR
    table = pd.DataFrame({"event_id": "e1", "time_s": np.arange(4) / hz})
    with pytest.raises(IngestError, match=r"f\.csv, row 2, column 'time_s': event 'e1' is sampled every "):
        _check_rate(table, pd.Series({"e1": 1e3}), "f.csv")
    _check_rate(table.assign(time_s=np.arange(4) / 1e3), pd.Series({"e1": 1e3}), "f.csv")


def test_a_displacement_of_zero_at_the_force_peak_is_not_below_zero():
    """The sign check refuses a displacement *below* zero where the normal force peaks; 0 mm there
    (the bench's zero at the peak) is not below it, -0.01 mm is."""
    from graspcampaign.rig.test1_ingest import _check_sign

    commands = pd.DataFrame({"depth_mm": [1.0]}, index=pd.Index(["e1"], name="event_id"))
    table = pd.DataFrame({"event_id": "e1", "normal_force_n": [0.1, 2.0, 0.5],
                          "displacement_mm": [0.5, 0.0, 0.2]})
    _check_sign(table, commands, "f.csv")
    with pytest.raises(IngestError, match=r"f\.csv, row 2, column 'displacement_mm': event 'e1' is at "
                                          r"-0\.01 mm where its normal force peaks \(2 N\), below zero"):
        _check_sign(table.assign(displacement_mm=[0.5, -0.01, 0.2]), commands, "f.csv")
