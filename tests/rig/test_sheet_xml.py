"""The first sheet's XML read in one pass (rig.sheet_xml): its error and formula cells are those
openpyxl's two read-only loads find (``data_only`` true: a cell of type ``e``; false: a cell with
a formula), on sheets written here cell by cell as ECMA-376 Part 1 §18.3.1.4 spells them, read in
pieces of every size; and ingest reads a workbook with empty cells in one openpyxl load, pandas'."""

from __future__ import annotations

import zipfile
from pathlib import Path

import pandas as pd
import pytest

from graspcampaign.rig import measured_file, sheet_xml
from graspcampaign.rig.measured_file import IngestError, read_table

MAIN = "http://schemas.openxmlformats.org/spreadsheetml/2006/main"
HEADER = ('<row r="1"><c r="A1" t="inlineStr"><is><t>a</t></is></c><c r="B1" t="inlineStr"><is><t>b'
          '</t></is></c><c r="C1" t="inlineStr"><is><t>c</t></is></c></row>')
LONG = "+".join(f"A{i % 9 + 2}" for i in range(200))  # 800 characters: cut by a piece of 64 bytes
SHEETS = {  # the data rows (2-4) of a sheet with columns a, b, c; what openpyxl reads in them
    "an error typed": '<row r="2"><c r="A2"><v>1</v></c><c r="B2" t="e"><v>#N/A</v></c></row>',
    "a formula's error first": ('<row r="2"><c r="A2"><f>1+1</f></c></row><row r="3"><c r="C3" t="e">'
                                '<f>1/0</f><v>#DIV/0!</v></c></row>'),
    "two errors": ('<row r="2"><c r="A2"><v>1</v></c><c r="C2" t="e"><v>#REF!</v></c></row><row r="3">'
                   '<c r="A3"><v>2</v></c><c r="B3" t="e"><v>#NUM!</v></c></row>'),
    "a shared formula": ('<row r="2"><c r="A2"><v>1</v></c><c r="B2"><f t="shared" ref="B2:B4" si="0">'
                         'A2*2</f><v>2</v></c></row><row r="3"><c r="B3"><f t="shared" si="0"/><v>4</v>'
                         '</c></row><row r="4"><c r="A4"><v>3</v></c><c r="B4"><f t="shared" si="0"/>'
                         '</c></row>'),
    "escaped text": '<row r="2"><c r="A2"><v>1</v></c><c r="C2"><f>IF(A2&gt;0,"x&amp;y",1)</f></c></row>',
    "a long formula": (f'<row r="2"><c r="A2"><v>1</v></c></row><row r="3"><c r="A3"><v>2</v></c>'
                       f'<c r="B3"><f>{LONG}</f></c></row>'),
    "with values": ('<row r="2"><c r="A2"><f>1+1</f><v>2</v></c><c r="B2" s="0"/><c r="C2" t="str">'
                    '<f>"t=""e"""</f><v>t="e"</v></c></row>'),
}
EXTENSION = ('<extLst><ext uri="{78C0D931-6437-407d-A8EE-F0AAD7539E65}"><x14:conditionalFormattings '
             'xmlns:x14="http://schemas.microsoft.com/office/spreadsheetml/2009/9/main" xmlns:xm="http:/'
             '/schemas.microsoft.com/office/excel/2006/main"><x14:conditionalFormatting><x14:cfRule '
             'type="expression" id="{1}"><xm:f>A2&gt;1</xm:f></x14:cfRule><xm:sqref>A2:C4</xm:sqref>'
             '</x14:conditionalFormatting></x14:conditionalFormattings></ext></extLst>')


def _book(path: Path, rows: str, prefix: str = "", tail: str = "") -> Path:
    """A workbook (written by openpyxl) whose first sheet's XML is ``rows`` under the header, its
    tags with the namespace ``prefix`` (``x:``) and ``tail`` after its data."""
    from openpyxl import Workbook

    Workbook().save(path)
    data = f"<sheetData>{HEADER}{rows}</sheetData>".replace("<", f"<{prefix}").replace(f"<{prefix}/",
                                                                                    f"</{prefix}")
    named = f' xmlns:{prefix[:-1]}="{MAIN}"' if prefix else ""  # the tail's tags stay unprefixed
    xml = f'<{prefix}worksheet xmlns="{MAIN}"{named}>{data}{tail}</{prefix}worksheet>'
    with zipfile.ZipFile(path) as old:
        parts = {name: old.read(name) for name in old.namelist()}
    parts["xl/worksheets/sheet1.xml"] = xml.encode()
    with zipfile.ZipFile(path, "w") as new:
        for name, data in parts.items():
            new.writestr(name, data)
    return path


def _both(path: Path, frame: pd.DataFrame) -> tuple:
    """The error and formula cells (frame row, column, value) of the XML pass, then openpyxl's."""
    empty = frame.isna().to_numpy()
    marks = sheet_xml.first_sheet_marks(path, lambda row, column: 2 <= row <= len(frame) + 1 and
                                        column <= len(frame.columns) and empty[row - 2, column - 1])
    ours = tuple((c[0] - 2, c[1] - 1, c[2]) if c else None for c in (marks.error, marks.formula))
    return ours, (measured_file._first_empty(path, "Sheet", frame, True, "e"),
                  measured_file._first_empty(path, "Sheet", frame, False, "f"))


@pytest.mark.parametrize("piece", [64, 1000, 2**20])
@pytest.mark.parametrize("prefix", ["", "x:"])
@pytest.mark.parametrize("sheet", list(SHEETS))
def test_the_error_and_formula_cells_are_those_openpyxl_reads(tmp_path, monkeypatch, sheet, prefix, piece):
    monkeypatch.setattr(sheet_xml, "PIECE", piece)
    path = _book(tmp_path / "book.xlsx", SHEETS[sheet], prefix, EXTENSION)
    frame = pd.read_excel(path, dtype=object, keep_default_na=False, na_values=[""])
    ours, openpyxl = _both(path, frame)
    assert ours == openpyxl


def test_what_openpyxl_reads_is_what_the_cells_hold(tmp_path):
    """The expected cells, written out: an error before a formula of the same sheet, a shared
    formula moved to its cell (B4: A4*2), the text of entities, an empty value as none."""
    cases = {"an error typed": ((0, 1, "#N/A"), None),
             "a formula's error first": ((1, 2, "#DIV/0!"), (0, 0, "=1+1")),
             "two errors": ((0, 2, "#REF!"), None),
             "a shared formula": (None, (2, 1, "=A4*2")),
             "escaped text": (None, (0, 2, '=IF(A2>0,"x&y",1)')),
             "a long formula": (None, (1, 1, f"={LONG}")),
             "with values": (None, None)}
    for name, expected in cases.items():
        path = _book(tmp_path / f"{name}.xlsx", SHEETS[name])
        frame = pd.read_excel(path, dtype=object, keep_default_na=False, na_values=[""])
        assert _both(path, frame)[0] == expected, name


def test_cells_without_their_reference_are_read_by_openpyxl(tmp_path):
    """A writer may leave out a cell's ``r`` (its place is then counted): the XML pass says it
    cannot place the cell, and ingest reads the sheet with openpyxl, as before, alike."""
    rows = '<row r="2"><c><v>1</v></c><c t="e"><v>#REF!</v></c></row>'
    path = _book(tmp_path / "book.xlsx", rows)
    assert sheet_xml.first_sheet_marks(path, lambda row, column: True).unplaced
    with pytest.raises(IngestError) as info:
        read_table(path, excel_options={"dtype": object, "keep_default_na": False, "na_values": [""]})
    assert str(info.value) == ("book.xlsx, row 1, column 'b': the cell holds the spreadsheet error "
                               "#REF!; fix the formula or clear the cell.")


def test_a_workbook_with_empty_cells_is_loaded_once(tmp_path, monkeypatch):
    """pandas loads the workbook (openpyxl, read-only); the checks read the sheet's XML, where
    ingest loaded it once more to find an error cell, and again to find a formula, when a cell
    was empty."""
    import openpyxl

    loads, load = [], openpyxl.load_workbook
    monkeypatch.setattr(openpyxl, "load_workbook", lambda *a, **k: loads.append(k) or load(*a, **k))
    path = _book(tmp_path / "book.xlsx", SHEETS["a formula's error first"])
    with pytest.raises(IngestError, match=r"^book\.xlsx, row 2, column 'c': the cell holds the "
                                          r"spreadsheet error #DIV/0!; fix the formula or clear"):
        read_table(path, excel_options={"dtype": object, "keep_default_na": False, "na_values": [""]})
    assert len(loads) == 1


def test_a_shared_formula_is_moved_to_a_cell_asked_for_only(tmp_path, monkeypatch):
    """A shared formula's text is moved (openpyxl's Translator, which parses it) to the cells the
    check asks about: those pandas read as empty. The cells of one holding values were each
    translated and then passed over; its first cell is still read for the text of the others."""
    from openpyxl.formula import translate

    moved, translator = [], translate.Translator
    monkeypatch.setattr(translate, "Translator",
                        lambda *a, **k: moved.append(a) or translator(*a, **k))
    rows = "".join(f'<row r="{r}"><c r="A{r}"><v>{r}</v></c><c r="B{r}"><f t="shared" si="0"'
                   + (' ref="B2:B9">A2*2</f>' if r == 2 else "/>") + f"<v>{2 * r}</v></c></row>"
                   for r in range(2, 10))
    path = _book(tmp_path / "book.xlsx", rows)
    assert sheet_xml.first_sheet_marks(path, lambda row, column: column == 1) == sheet_xml.SheetMarks()
    assert moved == []
    marks = sheet_xml.first_sheet_marks(path, lambda row, column: (row, column) == (7, 2))
    assert (marks.formula, moved) == ((7, 2, "=A7*2"), [("=A2*2", "B2")])
