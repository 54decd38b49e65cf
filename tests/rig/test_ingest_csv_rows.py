"""The CSV check of ingest numbers data rows as pandas reads them: a line of only commas is a row,
a blank or all-space line is not (each refusal names the row ``pd.read_csv`` gives it)."""

from __future__ import annotations

import pandas as pd
import pytest

from graspcampaign.rig.ingest import IngestError


def test_a_csv_row_after_a_row_of_only_commas_is_numbered_as_pandas_reads_it(tmp_path):
    # pandas keeps a line of only commas as a row (a blank line it skips): the header repeated
    # below one is data row 3 of read_csv, which the check called row 2; a longer such line was
    # "the file cannot be read as csv (ParserError)"
    from graspcampaign.rig.measured_file import read_table

    sheet = tmp_path / "day1.csv"
    sheet.write_text("a,b,c\n1,2,3\n,,\n\n   \na,b,c\n")
    assert pd.read_csv(sheet).iloc[2].tolist() == ["a", "b", "c"]  # pandas' data row 3
    with pytest.raises(IngestError) as caught:
        read_table(sheet)
    assert str(caught.value) == ("day1.csv, row 3: the row repeats the header (two sheets pasted one "
                                 "after the other?); delete it.")
    sheet.write_text("a,b,c\n1,2,3\n,,,,\n")
    with pytest.raises(IngestError) as caught:
        read_table(sheet)
    assert str(caught.value) == ("day1.csv, row 2: 5 cells where the header has 3 columns (a cell "
                                 "with a comma needs quotes; a truncated file loses its last row's "
                                 "cells).")
