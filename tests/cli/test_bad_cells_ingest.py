"""A parquet cell that holds no number where one is expected, a date/time or a list (Parquet keeps
both types, a CSV cannot), is refused by what it holds, never by a Python repr such as
``Timestamp('2026-...')`` or ``array([0.94])``. Each refusal is one sentence with exit 2 and nothing
stored changed (``refused``)."""

from __future__ import annotations

import numpy as np
import pandas as pd
import pytest
from cli_checks import invoke, refused

WHEN = pd.Timestamp("2026-03-01 12:00:00")


def _sheet(tmp_path, study: str, *overrides: str) -> pd.DataFrame:
    """The first row of ``study``'s fill-in template, as ``schedule --template`` writes it (Test 1's
    template has the header alone: the row is the first scheduled event's)."""
    made = invoke("schedule", study, *overrides, "--template", "--out", tmp_path / "sheet")
    assert made.exit_code == 0, made.output
    template = pd.read_csv(tmp_path / "sheet-template.csv", keep_default_na=False)
    if template.empty:
        first = pd.read_csv(tmp_path / "sheet.csv")["event_id"].iloc[0]
        return pd.DataFrame([{**dict.fromkeys(template.columns, ""), "event_id": first}])
    return template.iloc[[0]]


@pytest.mark.parametrize(("study", "fraction"), [("test2_grasp", "0.06"), ("test3_disturbance", "0.05")])
@pytest.mark.parametrize(("cell", "what"), [
    (WHEN, "value 2026-03-01 12:00:00 is a date/time, not a number"),
    (np.array([0.94]), "value [0.94] is a list of 1 value, not a number"),
    (np.array([0.5, 0.6]), "value [0.5, 0.6] is a list of 2 values, not a number"),
])
def test_a_date_or_list_where_a_number_belongs_is_named(results, tmp_path, study, fraction, cell, what):
    row = _sheet(tmp_path, study, f"params.fraction={fraction}")
    # an aborted trial: its cells are checked all the same, and no measured column is required
    row = row.assign(aborted=True, peak_slip_mm=pd.Series([cell], index=row.index, dtype=object))
    row.to_parquet(tmp_path / "rig.parquet", index=False)
    assert isinstance(pd.read_parquet(tmp_path / "rig.parquet")["peak_slip_mm"].iloc[0],
                      type(cell))  # the cell reads back as what was written
    refused(results, ["ingest", study, tmp_path / "rig.parquet", "--set",
                      f"params.fraction={fraction}", "--root", results],
            f"rig.parquet, row 1, column 'peak_slip_mm': {what}.")


def test_a_date_where_a_boolean_belongs_is_named(results, tmp_path):
    row = _sheet(tmp_path, "test2_grasp", "params.fraction=0.06").assign(aborted=WHEN)
    row.to_parquet(tmp_path / "rig.parquet", index=False)
    refused(results, ["ingest", "test2_grasp", tmp_path / "rig.parquet", "--set",
                      "params.fraction=0.06", "--root", results],
            "rig.parquet, row 1, column 'aborted': value 2026-03-01 12:00:00 is a date/time, not a "
            "boolean (true/false, yes/no, y/n, t/f, 1/0).")


def test_a_date_in_a_waveform_time_column_is_named(results, tmp_path):
    # the old code read the date as microseconds since 1970 and said it lay outside 0-3600 s
    row = _sheet(tmp_path, "test1_bench", "params.materials=[gel]", "params.specimens=[1]",
                 "params.environments=[normal_lab]").assign(time_s=WHEN)
    row.to_parquet(tmp_path / "waves.parquet", index=False)
    refused(results, ["ingest", "test1_bench", tmp_path / "waves.parquet", "--set",
                      "params.materials=[gel]", "--set", "params.specimens=[1]", "--set",
                      "params.environments=[normal_lab]", "--root", results],
            "waves.parquet, row 1, column 'time_s': value 2026-03-01 12:00:00 is a date/time, not "
            "a number of seconds.")
