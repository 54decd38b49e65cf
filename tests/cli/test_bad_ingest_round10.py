"""Bad measured files, round 10: merged cells in a workbook, a title line above a CSV header, text
in a long file, a time column in milliseconds, an empty header cell. Each is refused in one sentence
naming the file, row and column, with exit 2 and nothing stored changed (``refused``; for Tests 2-3
on a run that already holds records, ``stored``)."""

from __future__ import annotations

from pathlib import Path

import numpy as np
import pandas as pd
import pytest
from cli_checks import EVENT, T1, T2, filled_records, invoke, refused


def _workbook(frame: pd.DataFrame, path: Path, merge: str) -> Path:
    from openpyxl import load_workbook

    frame.to_excel(path, index=False)
    book = load_workbook(path)
    book.active.merge_cells(merge)
    book.save(path)
    return path


@pytest.mark.parametrize(("merge", "where"), [
    ("J2:J3", "row 1, column 'peak_slip_mm'"),  # the old code stored row 2's slip as not measured
    ("M1:O1", "header, column 'normal_force_1_n'"),  # it said 'Unnamed: 13', 'Unnamed: 14'
])
def test_merged_cells_in_a_workbook_are_named(stored, tmp_path, merge, where):
    book = _workbook(filled_records(tmp_path, rows=slice(2, 4)), tmp_path / "day2.xlsx", merge)
    refused(stored, ["ingest", "test2_grasp", book, *T2, "--root", stored],
            f"day2.xlsx, {where}: the cell is merged with others ({merge}), which leaves all of "
            "them but the first empty; unmerge them and fill in each cell.")


def test_a_title_line_above_the_header_is_named_as_one(stored, tmp_path):
    # the old code took the title for the header: "row 1: 25 cells where the header has 1 columns"
    sheet = tmp_path / "day2.csv"
    sheet.write_text("# bench export 2026-03-01\n"
                     + filled_records(tmp_path, rows=slice(2, 4)).to_csv(index=False))
    refused(stored, ["ingest", "test2_grasp", sheet, *T2, "--root", stored],
            "day2.csv, header: the first line has 1 cell where the rows below it have 25 cells (a "
            "title or note line above the header?); the header must be the first line: delete the "
            "lines above it.")


def test_a_row_with_one_cell_is_counted_in_the_singular(stored, tmp_path):
    # the old code said "1 cells"; one data row alone is not taken for a title line's evidence
    sheet = tmp_path / "day2.csv"
    sheet.write_text(filled_records(tmp_path, rows=slice(2, 3)).to_csv(index=False) + "note\n")
    refused(stored, ["ingest", "test2_grasp", sheet, *T2, "--root", stored],
            "day2.csv, row 2: 1 cell where the header has 25 columns (a cell with a comma needs "
            "quotes; a truncated file loses its last row's cells).")


def _waves(n: int) -> pd.DataFrame:
    """``n`` samples at 1 kHz of the Test 1 event :data:`EVENT`, held at 0.5 mm (its commanded
    depth is 0.75 mm, within ``PEAK_FACTOR``)."""
    return pd.DataFrame({"event_id": EVENT, "time_s": np.arange(n) * 1e-3, "displacement_mm": 0.5,
                         "normal_force_n": 0.3, "tangential_force_n": 0.0,
                         "tangential_displacement_mm": 0.0})


def test_text_in_a_long_waveform_file_is_one_sentence_without_a_pandas_warning(results, tmp_path):
    # pandas reads a long file in pieces and warned of the column's "mixed types" first (the old
    # code printed "warning: Columns (1: time_s) have mixed types. Specify dtype option ...")
    waves = tmp_path / "waves.csv"
    waves.write_text(_waves(150_000).to_csv(index=False) + f"{EVENT},abc,0,0,0,0\n")
    refused(results, ["ingest", "test1_bench", waves, *T1, "--root", results],
            "waves.csv, row 150001, column 'time_s': value 'abc' is not a number of seconds.")


def test_a_waveform_time_column_in_milliseconds_is_named(results, tmp_path):
    # the old code stored the event's fits with time read as seconds: a damping 1000x too large,
    # accepted; the event is commanded at 100 Hz (schedule's daq_hz), its samples are 10 ms apart
    waves = _waves(300).assign(time_s=lambda d: d["time_s"] * 1e4)  # 10 ms, written as 10
    waves.to_csv(tmp_path / "waves.csv", index=False)
    refused(results, ["ingest", "test1_bench", tmp_path / "waves.csv", *T1, "--root", results],
            f"waves.csv, row 2, column 'time_s': event '{EVENT}' is sampled every 10 s (0.1 Hz) "
            "where the schedule commands 100 Hz (ratio 0.001, outside 1/30 to 30: time not in "
            "seconds?).")


def test_a_waveform_sampled_at_a_rate_the_bench_can_log_is_stored(results, tmp_path):
    # 1 kHz on an event commanded at 100 Hz: a logger faster than the sheet said, not a unit slip
    _waves(3000).to_csv(tmp_path / "waves.csv", index=False)
    done = invoke("ingest", "test1_bench", tmp_path / "waves.csv", *T1, "--root", results)
    assert done.exit_code == 0, done.output


def test_a_column_with_an_empty_header_cell_is_named_by_its_place(results, tmp_path):
    # a spreadsheet's export with a trailing comma on every line; the old code named pandas'
    # 'Unnamed: 6', which is in no file
    lines = _waves(300).to_csv(index=False).splitlines()
    (tmp_path / "waves.csv").write_text("".join(f"{line},\n" for line in lines))
    refused(results, ["ingest", "test1_bench", tmp_path / "waves.csv", *T1, "--root", results],
            "waves.csv, header: a column is not part of the sheet: column 7 (its header cell is "
            "empty); its columns are event_id, time_s, displacement_mm, normal_force_n, "
            "tangential_force_n, tangential_displacement_mm, attempt, anomaly, source "
            "(`graspcampaign schedule test1_bench --template` writes a sheet with every column).")
