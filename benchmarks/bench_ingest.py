"""Ingest benchmark: what reading a Test 2 workbook with empty cells costs, step by step.

The full commanded sheet of Test 2 (1785 rows; every trial run by the virtual rig, its records'
columns, the optional cells of the aborted trials empty) written as an ``.xlsx`` by openpyxl, then
timed in this same run, on one core:
- the whole ingest (``validate_records``: reading, every check), the reference;
- pandas' reading of the first sheet alone (``read_records``' options);
- the one pass over the sheet's XML (``sheet_xml.first_sheet_marks``): hidden sheet and rows,
  merged ranges, and the error and formula cells among those pandas read as empty;
- openpyxl's two read-only loads that pass stands for (``measured_file._first_empty``, kept for a
  sheet whose cells lack their reference): ``data_only`` true for the error cells, false for the
  formulas without a value; ingest made both on every workbook with an empty cell;
- the XML pass over the same sheet with one more column computed in the spreadsheet (one shared
  formula over its data rows, each cell holding its value, as a derived column is stored): a
  shared formula is moved to a cell (openpyxl's ``Translator``) only where the cell is asked for.
Ratios are to the whole ingest.

Run: ``python benchmarks/bench_ingest.py``.
"""

from __future__ import annotations

import re
import tempfile
import zipfile
from pathlib import Path

import numpy as np
import pandas as pd
from _common import best_of, print_table

from graspcampaign.rig import measured_file, protocol
from graspcampaign.rig.ingest import read_records, validate_records
from graspcampaign.rig.plan import predict_trial
from graspcampaign.rig.record_schema import record_columns
from graspcampaign.rig.sheet_xml import first_sheet_marks
from graspcampaign.rig.virtual import virtual_trial


def records(schedule: pd.DataFrame) -> pd.DataFrame:
    """The virtual rig's records of every trial of ``schedule`` (the retries of its rig faults too)."""
    rows = schedule.to_dict("records")
    out = pd.DataFrame([virtual_trial(r, predict_trial(r), np.random.default_rng(i))
                        for i, r in enumerate(rows)])
    out.insert(0, "trial_id", schedule["trial_id"].to_numpy())
    return out[record_columns("test2_grasp")]


def with_shared_formula(path: Path, out: Path, column: str) -> Path:
    """``path`` written as ``out`` with a column ``column`` (its letters) computed in the sheet: a
    header ``computed``, then one shared formula (``=B2*1000``, ECMA-376 Part 1 §18.3.1.40) over
    every data row, each cell holding a value as a spreadsheet stores one it computed."""
    with zipfile.ZipFile(path) as book:
        parts = {name: book.read(name) for name in book.namelist()}
    xml = parts["xl/worksheets/sheet1.xml"].decode()
    last = max(int(r) for r in re.findall(r'<row r="([0-9]+)"', xml))

    def cell(row: re.Match) -> str:
        r = int(row[1])
        text = (f'<c r="{column}1" t="inlineStr"><is><t>computed</t></is></c>' if r == 1 else
                f'<c r="{column}{r}"><f t="shared" si="0"'
                + (f' ref="{column}2:{column}{last}">B2*1000</f>' if r == 2 else "/>") + f"<v>{r}</v></c>")
        return row[0].replace("</row>", f"{text}</row>")

    parts["xl/worksheets/sheet1.xml"] = re.sub(r'<row r="([0-9]+)".*?</row>', cell, xml,
                                               flags=re.S).encode()
    with zipfile.ZipFile(out, "w", zipfile.ZIP_DEFLATED) as book:
        for name, data in parts.items():
            book.writestr(name, data)
    return out


def main() -> None:
    schedule = protocol.test2_schedule(801)  # campaigns/test2_grasp.yaml's seed
    sheet = records(schedule)
    with tempfile.TemporaryDirectory() as tmp:
        path = Path(tmp) / "day.xlsx"
        sheet.to_excel(path, index=False, engine="openpyxl")
        frame = read_records(path)
        empty = frame.isna().to_numpy()

        def wanted(row: int, column: int) -> bool:
            return 2 <= row <= len(frame) + 1 and bool(empty[row - 2, column - 1])

        from openpyxl.utils import get_column_letter

        computed = with_shared_formula(path, Path(tmp) / "computed.xlsx",
                                       get_column_letter(len(frame.columns) + 1))
        empty_too = pd.read_excel(computed, dtype=object, keep_default_na=False,
                                  na_values=[""]).isna().to_numpy()

        def wanted_too(row: int, column: int) -> bool:
            return 2 <= row <= len(frame) + 1 and bool(empty_too[row - 2, column - 1])

        steps = [
            ("whole ingest (validate_records)", lambda: validate_records(path, schedule)),
            ("pandas read_excel", lambda: pd.read_excel(path, dtype=object, keep_default_na=False,
                                                        na_values=[""])),
            ("one XML pass (first_sheet_marks)", lambda: first_sheet_marks(path, wanted)),
            ("openpyxl load, data_only=True (errors)",
             lambda: measured_file._first_empty(path, "Sheet1", frame, True, "e")),
            ("openpyxl load, data_only=False (formulas)",
             lambda: measured_file._first_empty(path, "Sheet1", frame, False, "f")),
            ("one XML pass, a column of one shared formula more",
             lambda: first_sheet_marks(computed, wanted_too)),
        ]
        times = [best_of(fn, 3) for _, fn in steps]
        print(f"## Ingest of a Test 2 workbook ({len(frame)} rows x {len(frame.columns)} columns, "
              f"{int(empty.sum())} empty cells, {path.stat().st_size / 2**10:.0f} KiB; one core)\n")
        print_table(["step", "wall time (s)", "share of the whole ingest"],
                    [[name, f"{t:.3f}", f"{t / times[0]:.2f}"] for (name, _), t in zip(steps, times,
                                                                                      strict=True)],
                    ["---", "---:", "---:"])
        print(f"\nThe two openpyxl loads the XML pass stands for: {times[3] + times[4]:.3f} s, "
              f"{(times[3] + times[4]) / times[2]:.0f}x the pass.")


if __name__ == "__main__":
    main()
