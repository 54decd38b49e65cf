"""Ingest reads a spreadsheet's typed cells by their column's kind: a boolean is no number (TRUE is
not a force of 1 N) and only 0 and 1 of the numbers are booleans (2 is no flag)."""

from __future__ import annotations

import pandas as pd
import pytest
from virtual_exports import virtual_run

from graspcampaign.rig import protocol
from graspcampaign.rig.ingest import IngestError, validate_records
from graspcampaign.rig.record_schema import record_columns

CASES = {  # column, typed cell, the problem the message names
    "true_as_a_force": ("normal_force_1_n", True, r"value True is not a number"),
    "false_as_a_force": ("normal_force_1_n", False, r"value False is not a number"),
    "two_as_a_flag": ("aborted", 2, r"value 2 is not a boolean \(true/false, yes/no, y/n, t/f, 1/0\)"),
    "minus_one_as_a_flag": ("aborted", -1,
                            r"value -1 is not a boolean \(true/false, yes/no, y/n, t/f, 1/0\)"),
}


@pytest.fixture(scope="module")
def records():
    schedule = protocol.test2_schedule(0)
    _, _, meas = virtual_run(schedule, 3)
    rec = meas[record_columns("test2_grasp")].reset_index(drop=True)
    return schedule, rec, int((~rec["aborted"].astype(bool)).to_numpy().nonzero()[0][0])


@pytest.mark.parametrize("case", list(CASES))
def test_a_typed_cell_of_the_wrong_kind_is_refused(records, tmp_path, case):
    schedule, rec, row = records
    column, value, problem = CASES[case]
    bad = rec.astype({column: object})
    bad.loc[row, column] = value  # an Excel TRUE/FALSE or number cell keeps its type when read
    path = tmp_path / "bad.xlsx"
    bad.to_excel(path, index=False)
    assert type(pd.read_excel(path, dtype=object).loc[row, column]) is type(value)
    with pytest.raises(IngestError, match=rf"^bad\.xlsx, row {row + 1}, column '{column}': {problem}\.$"):
        validate_records(path, schedule)
