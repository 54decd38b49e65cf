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
  formulas without a value; ingest made both on every workbook with an empty cell.
Ratios are to the whole ingest.

Run: ``python benchmarks/bench_ingest.py``.
"""

from __future__ import annotations

import tempfile
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

        steps = [
            ("whole ingest (validate_records)", lambda: validate_records(path, schedule)),
            ("pandas read_excel", lambda: pd.read_excel(path, dtype=object, keep_default_na=False,
                                                        na_values=[""])),
            ("one XML pass (first_sheet_marks)", lambda: first_sheet_marks(path, wanted)),
            ("openpyxl load, data_only=True (errors)",
             lambda: measured_file._first_empty(path, "Sheet1", frame, True, "e")),
            ("openpyxl load, data_only=False (formulas)",
             lambda: measured_file._first_empty(path, "Sheet1", frame, False, "f")),
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
