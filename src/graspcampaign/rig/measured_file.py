"""Reading a measured file (CSV, XLSX, Parquet) and checking its header: the one reader of every
ingest path (Tests 2-3 trial records in :mod:`graspcampaign.rig.ingest`, Test 1 waveforms in
:mod:`graspcampaign.rig.test1_ingest`).

Problems raise :class:`IngestError` with one sentence naming the file, the 1-based data row (header
excluded) or line, and the column.
"""

from __future__ import annotations

import csv
import datetime
import re
import warnings
from collections import Counter
from collections.abc import Collection, Iterator, Mapping, Sequence
from pathlib import Path

import numpy as np
import pandas as pd

from graspcampaign.core.words import counted, meant, plural
from graspcampaign.errors import utf8_file
from graspcampaign.rig.sheet_xml import SheetMarks, first_sheet_marks

__all__ = ["IngestError", "cell_problem", "header_problems", "ingest_error", "read_table",
           "table_and_label"]


class IngestError(ValueError):
    """A measured file (trial records, Test 1 waveforms) failed validation; the message names the
    file, row and column."""


def ingest_error(label: str, row: int | None, column: str, problem: str) -> IngestError:
    """The error naming the file ``label``, its ``row`` (None: the header) and ``column``."""
    where = "header" if row is None else f"row {row}"
    return IngestError(f"{label}, {where}, column '{column}': {problem}.")


def empty_row(label: str, frame, row: int) -> IngestError | None:
    """The error naming data row ``row`` (1-based) of ``frame`` when its every cell is empty (a
    line of only commas, a spreadsheet row cleared but not deleted), else None: a row to delete,
    not a trial or an event without its id."""
    cells = frame.iloc[row - 1].tolist()
    if all(not v.strip() if isinstance(v, str) else pd.api.types.is_scalar(v) and pd.isna(v)
           for v in cells):
        return IngestError(f"{label}, row {row} is empty; delete it.")
    return None


def aside(word: str, known, cutoff: float = 0.6) -> str:
    """`` (did you mean 'x'?)`` after a cell value or column name ``word`` that is none of
    ``known`` (:func:`~graspcampaign.core.words.meant`), or ``""``."""
    near = meant(word, known, cutoff=cutoff)
    return f" ({near.strip()})" if near else ""


#: The error values a spreadsheet formula leaves in its cell: ECMA-376 Part 1 §18.18.21
#: (ST_CellErrorType) and those newer Excel writes (Microsoft's "#SPILL! error" etc. pages). A
#: workbook stores one as an error cell, which pandas reads as empty; a CSV export writes its text.
SPREADSHEET_ERRORS = ("#NULL!", "#DIV/0!", "#VALUE!", "#REF!", "#NAME?", "#NUM!", "#N/A",
                      "#SPILL!", "#CALC!", "#FIELD!", "#BLOCKED!", "#CONNECT!", "#BUSY!",
                      "#UNKNOWN!", "#GETTING_DATA")


def spreadsheet_error(error: str) -> str:
    """The problem of a cell holding the spreadsheet error ``error``."""
    return f"the cell holds the spreadsheet error {error}; fix the formula or clear the cell"


def cell_problem(value, expected: str = "a number") -> str:
    """The problem of a cell that is not ``expected``. A date/time or a list (Parquet keeps both)
    is named as one, not by its Python repr; a decimal comma ('1,5', a spreadsheet's regional
    export with quoted cells) is named as one, and a spreadsheet error ('#DIV/0!') as one."""
    if isinstance(value, str) and value.strip().upper() in SPREADSHEET_ERRORS:
        return spreadsheet_error(value.strip().upper())
    if isinstance(value, (datetime.date, np.datetime64)):  # pd.Timestamp is a datetime.date
        return f"value {value} is a date/time, not {expected}"
    if isinstance(value, (list, tuple, np.ndarray)):
        shown = ", ".join(str(item) for item in value[:3]) + (", ..." if len(value) > 3 else "")
        return f"value [{shown}] is a list of {counted(len(value), 'value')}, not {expected}"
    comma = isinstance(value, str) and re.fullmatch(r"\s*[+-]?[0-9]*,[0-9]+\s*", value)
    return f"value {value!r} is not {expected}" + (
        " (a decimal comma: save the sheet with a decimal point '.')" if comma else "")


def read_table(path: str | Path, *, csv_options: dict | None = None,
               excel_options: dict | None = None) -> pd.DataFrame:
    """Read a measured table (``.csv``, ``.parquet``/``.pq``, ``.xlsx``) without checks.

    The one reader of the rig's ingest paths (trial records here, Test 1 waveforms in
    :mod:`graspcampaign.rig.test1`); ``csv_options`` and ``excel_options`` go to
    :func:`pandas.read_csv` and :func:`pandas.read_excel`.

    Raises
    ------
    IngestError
        Unsupported file type, missing, empty or unreadable file.
    """
    path = Path(path)
    suffix = path.suffix.lower()
    _check_lock(path)
    if suffix == ".xls" and path.is_file():  # the old binary format, which no reader here reads
        _check_compound(path)
    if suffix not in (".csv", ".parquet", ".pq", ".xlsx"):
        raise IngestError(f"{path.name}: unsupported file type "
                          f"'{suffix or '(none)'}' (expected .csv, .parquet or .xlsx).")
    if path.is_dir():
        raise IngestError(f"{path.name}: is a directory, not a file.")
    if not path.is_file():
        raise IngestError(f"{path.name}: the file does not exist.")
    if path.stat().st_size == 0:
        raise IngestError(f"{path.name}: the file is empty.")
    _check_content(path, ".parquet" if suffix == ".pq" else suffix)
    if suffix == ".csv":
        _checked_csv(path)
    try:
        if suffix == ".csv":  # from the file: its text held as a str was 5 times its size
            with warnings.catch_warnings():  # mixed types in a column: the validators name the cell
                warnings.simplefilter("ignore", pd.errors.DtypeWarning)
                return pd.read_csv(path, **(csv_options or {}))
        if suffix == ".xlsx":
            with pd.ExcelFile(path) as book:
                with warnings.catch_warnings(record=True) as caught:
                    warnings.simplefilter("always")
                    frame = pd.read_excel(book, book.sheet_names[0], **(excel_options or {}))
                _check_dates(path.name, frame, caught)
                # the headers of the other sheets, and those with a row below the header, for a
                # header check to say where records are
                other = {str(name): pd.read_excel(book, name, nrows=1)
                         for name in book.sheet_names[1:]}
                frame.attrs["other_sheets"] = {name: [str(c) for c in sheet.columns]
                                               for name, sheet in other.items()}
                frame.attrs["filled_sheets"] = [name for name, sheet in other.items() if len(sheet)]
            _check_sheet(path, book.sheet_names[0], frame)
            return frame
        return pd.read_parquet(path)
    except IngestError:
        raise
    except Exception as exc:  # the readers raise many types for corrupt files
        cut = type(exc).__name__ in ("BadZipFile", "ArrowInvalid")  # no zip directory, no footer
        raise IngestError(f"{path.name}: the file cannot be read as {suffix[1:]} "
                          f"({type(exc).__name__})" + ("; it is damaged or incomplete (a copy cut "
                                                        "short?): copy or save it again" if cut else "")
                          + ".") from exc


def _check_lock(path: Path) -> None:
    """Refuse a spreadsheet program's lock file (Excel's ``~$name.xlsx``, which a glob such as
    ``*.xlsx`` picks up beside the workbook), and a file beside which one is: the file is open, so
    what is saved may not be what the program shows. Excel names it ``~$`` and the file's name, or
    that name without its first two characters (a longer name; Microsoft's "Description of how
    Word creates temporary files"), LibreOffice ``.~lock.name#``."""
    name = path.name
    if name.startswith("~$"):
        raise IngestError(f"{name}: the file is the lock file Excel keeps beside a workbook open in "
                          "it, not records; ingest the workbook itself, saved and closed.")
    for lock in (f"~${name}", f"~${name[2:]}", f".~lock.{name}#"):
        if (path.parent / lock).is_file():
            raise IngestError(f"{name}: the file is open in a spreadsheet program (its lock file "
                              f"{lock} is beside it), so what is saved may not be what it shows; "
                              f"save and close it, then ingest again (delete {lock} if no program "
                              "has it open).")


#: openpyxl's warning for a cell whose number format is a date's and whose value no date is (a
#: serial number past 9999-12-31, or before the epoch), which it reads as the error #VALUE!
_NO_DATE = re.compile(r"Cell ([A-Z]+[0-9]+) is marked as a date but the serial value (\S+) is outside")


def _check_dates(name: str, frame: pd.DataFrame, caught: list) -> None:
    """Refuse the first cell of the first sheet that is formatted as a date and holds a number no
    date is (openpyxl's warning, in ``caught``): read as the error #VALUE!, pandas leaves it empty,
    so a value would be stored as not measured. Row and column as :func:`_check_sheet` names them."""
    from openpyxl.utils.cell import column_index_from_string, coordinate_from_string

    for warning in caught:
        if match := _NO_DATE.match(str(warning.message)):
            letters, row = coordinate_from_string(match[1])
            j = column_index_from_string(letters) - 1
            column = str(frame.columns[j]) if j < len(frame.columns) else letters
            raise ingest_error(name, row - 1 or None, column,
                               f"the cell ({match[1]}) is formatted as a date, but its value "
                               f"{match[2]} is outside the dates a workbook holds (up to "
                               "9999-12-31), so it would be read as empty; give the cell a number "
                               "format, or fix its value")


#: what a file of each type is, and how it begins (an xlsx workbook is a zip archive)
_TYPES = {".csv": "CSV text", ".xlsx": "an Excel workbook (xlsx)", ".parquet": "a Parquet table"}
_MAGIC = {b"PK\x03\x04": ".xlsx", b"PAR1": ".parquet"}
#: how a Microsoft compound document begins: an old Excel workbook (.xls), or an xlsx workbook
#: saved with a password, which Excel encrypts into a stream 'EncryptedPackage' of such a document
#: ([MS-CFB] 2.2, header signature; [MS-OFFCRYPTO] 2.3.4.4, stream names)
_COMPOUND = b"\xd0\xcf\x11\xe0\xa1\xb1\x1a\xe1"
_ENCRYPTED = "EncryptedPackage".encode("utf-16-le")  # directory entries name streams in UTF-16


def _check_content(path: Path, named: str) -> None:
    """Refuse a file whose content is not the type its name says (a workbook saved as
    ``.csv`` was 'not UTF-8 text (byte 0xc7)'; a CSV named ``.xlsx`` 'cannot be read as xlsx
    (ValueError)')."""
    _check_compound(path)
    with path.open("rb") as handle:
        head = handle.read(4)
    holds = _MAGIC.get(head)
    if holds == ".xlsx" and not _workbook(path):  # a .docx, an .odt: zip archives too, any name
        raise IngestError(f"{path.name}: the file is a zip archive but not an Excel workbook (it "
                          "holds no xl/workbook.xml); save the sheet from the spreadsheet program "
                          "as .xlsx or as CSV UTF-8.")
    if holds not in (named, None):
        raise IngestError(f"{path.name}: the file is {_TYPES[holds]}, not {_TYPES[named]} as its "
                          f"name says; rename it to {path.stem}{holds}.")
    if holds is None and named != ".csv":
        raise IngestError(f"{path.name}: the file is not {_TYPES[named]}: it does not begin as "
                          f"one does; if it is CSV text, rename it to {path.stem}.csv.")


def _workbook(path: Path) -> bool:
    """Whether the zip archive ``path`` holds an Excel workbook's main part (or cannot be listed:
    the reader then says why)."""
    import zipfile

    try:
        with zipfile.ZipFile(path) as archive:
            return "xl/workbook.xml" in archive.namelist()
    except (zipfile.BadZipFile, OSError):
        return True


def _check_compound(path: Path) -> None:
    """Refuse a compound document, whatever its name says: an old-format Excel workbook or an
    encrypted xlsx (it was "if it is CSV text, rename it to .csv", or "not UTF-8 text")."""
    with path.open("rb") as handle:
        if handle.read(len(_COMPOUND)) != _COMPOUND:
            return
    if _ENCRYPTED in path.read_bytes():
        raise IngestError(f"{path.name}: the file is an Excel workbook saved with a password "
                          "(encrypted), which cannot be read; open it in a spreadsheet program, "
                          "remove the password and save it again.")
    raise IngestError(f"{path.name}: the file is an old-format Excel workbook (.xls), which ingest "
                      "does not read; open it in a spreadsheet program and save it as .xlsx or as "
                      "CSV UTF-8.")


def _check_empty_cells(path: Path, sheet: str, frame: pd.DataFrame, marks: SheetMarks) -> None:
    """Refuse a cell pandas read as empty that holds an error (a formula's ``#DIV/0!``, a typed
    ``#N/A``: its stored value, a formula's last result) or a formula without a computed value (a
    file written by a program such as openpyxl and never opened in a spreadsheet program stores
    the formula only): either would be stored as not measured. The cells are those the sheet's
    XML names (``marks``), or openpyxl's (:func:`_first_empty`) where the XML leaves one unplaced."""
    if marks.unplaced:  # openpyxl counts the place of a cell without its reference
        error = _first_empty(path, sheet, frame, True, "e")
        formula = None if error else _first_empty(path, sheet, frame, False, "f")
    else:  # the sheet's row k + 2 is the frame's row k (header in row 1), its column j + 1 column j
        error, formula = ((cell[0] - 2, cell[1] - 1, cell[2]) if cell else None
                          for cell in (marks.error, marks.formula))
    if error is not None:
        k, j, value = error
        raise ingest_error(path.name, k + 1, str(frame.columns[j]), spreadsheet_error(str(value)))
    if formula is not None:
        k, j, value = formula
        raise ingest_error(path.name, k + 1, str(frame.columns[j]),
                           f"the cell holds a formula ({value}) with no computed value; open and "
                           "save the file in a spreadsheet program, which stores the values")


def _first_empty(path: Path, sheet: str, frame: pd.DataFrame, data_only: bool, data_type: str):
    """``(k, j, value)`` of the first cell of openpyxl's ``data_type`` (``"e"`` an error, ``"f"`` a
    formula) that the frame holds as empty, or None; the frame's row ``k`` is the sheet's row
    ``k + 2`` (header in row 1: pandas keeps leading empty rows and columns)."""
    from openpyxl import load_workbook

    book = load_workbook(path, read_only=True, data_only=data_only)
    try:
        rows = book[sheet].iter_rows(min_row=2, max_row=len(frame) + 1, min_col=1,
                                     max_col=len(frame.columns))
        for k, cells in enumerate(rows):
            for j, cell in enumerate(cells):
                if getattr(cell, "data_type", None) == data_type and pd.isna(frame.iat[k, j]):
                    return k, j, cell.value
    finally:
        book.close()
    return None


def _check_sheet(path: Path, sheet: str, frame: pd.DataFrame) -> None:
    """Refuse a hidden first sheet, hidden rows and merged cells in the first sheet's table (its
    header and data rows), and a cell pandas read as empty that holds an error or a formula
    (:func:`_check_empty_cells`), all read from the sheet's XML in one pass
    (:func:`~graspcampaign.rig.sheet_xml.first_sheet_marks`).

    A merged range keeps its value in its first (top-left) cell and leaves the others empty
    (ECMA-376 Part 1 §18.3.1.55), so pandas reads every cell but the first as not measured: a value
    merged over two trials would be stored for the first alone. A hidden sheet or row (hidden, or
    filtered out, §18.3.1.73 ``hidden``) is one someone left out, usually: pandas reads it as any
    other, so it would be stored without a word. The sheet's row ``k + 2`` is the frame's row
    ``k`` (header in row 1), as in :func:`_first_empty`.
    """
    from openpyxl.utils.cell import range_boundaries

    empty = frame.isna().to_numpy()  # where an error or an uncomputed formula may be
    n_rows, n_columns = empty.shape

    def wanted(row: int, column: int) -> bool:  # a cell of the table that pandas read as empty
        return 2 <= row <= n_rows + 1 and column <= n_columns and bool(empty[row - 2, column - 1])

    marks = first_sheet_marks(path, wanted if empty.any() else None)
    name, merged, hidden = marks.hidden_sheet, marks.merged, marks.hidden_rows
    if name is not None:
        raise IngestError(f"{path.name}: ingest reads the workbook's first sheet, and it, "
                          f"'{name}', is hidden (a sheet someone set aside?); unhide it if it "
                          "holds the records, or move the sheet that does to the front.")
    if rows := [r for r in hidden if r <= len(frame) + 1]:
        said = ", ".join("the header" if r == 1 else f"row {r - 1}" for r in rows[:5])
        more = f" and {len(rows) - 5} more" if len(rows) > 5 else ""
        raise IngestError(f"{path.name}: {said}{more} {plural('is', len(rows), 'are')} hidden in "
                          "the sheet (hidden or filtered out: left out of the records?); delete "
                          "the hidden rows to leave them out, or unhide them to ingest them.")
    for ref in merged:
        col, row = range_boundaries(ref)[:2]
        if col <= len(frame.columns) and row <= len(frame) + 1:
            raise ingest_error(path.name, row - 1 or None, str(frame.columns[col - 1]),
                               f"the cell is merged with others ({ref}), which leaves all of them "
                               "but the first empty; unmerge them and fill in each cell")
    if empty.any():
        _check_empty_cells(path, sheet, frame, marks)


def _checked_csv(path: Path) -> None:
    """Refuse a CSV that pandas would misread or describe only by an exception's name: not UTF-8,
    empty, cells separated by ';' or tabs (a spreadsheet's regional export), or a data row with
    more or fewer cells than the header (pandas shifts a longer first row into an index and pads
    a shorter row, a truncated file's last row, with empty cells). The file is read block by block
    and row by row, never held whole (docs/decisions.md, "A Test 1 waveform file is read ...")."""
    if (why := utf8_file(path)) is not None:
        raise IngestError(f"{path.name}{why}; save it as CSV UTF-8.")
    # lines as the csv module (and pandas) end them: not str.splitlines, which also breaks at
    # U+2028 and other separators a cell may hold; row by row, not a list of a million rows (a
    # waveform file's), which took 0.8 GB to check a 45 MB file; the rows pandas reads: it skips a
    # blank or all-space line, not a line of only commas, so such a line counts in the row numbers
    with path.open(encoding="utf-8-sig", newline="") as handle:
        rows = (r for r in csv.reader(handle) if r and (len(r) > 1 or r[0].strip()))
        try:
            header = next((r for r in rows if r[0].strip() or any(c.strip() for c in r)), None)
            if header is None:
                raise IngestError(f"{path.name}: the file is empty.")  # blank lines only
            for sep, name in ((";", "';'"), ("\t", "tabs")):
                if len(header) == 1 and sep in header[0]:
                    raise IngestError(f"{path.name}, header: the cells are separated by {name}, not "
                                      "commas; save the sheet as comma-separated CSV (decimal point "
                                      "'.').")
            for i, row in enumerate(rows, start=1):
                if not row[0].strip() and len(row) <= len(header) and not any(c.strip() for c in row):
                    continue  # only commas: pandas pads it, and ingest names it an empty row to delete
                if row == header:  # it was "value 'aborted' is not a boolean"
                    raise IngestError(f"{path.name}, row {i}: the row repeats the header (two "
                                      "sheets pasted one after the other?); delete it.")
                if len(row) != len(header):
                    _wrong_cells(path.name, header, i, row, rows)
        except csv.Error as exc:  # a cell over the csv module's field limit, a stray NUL byte
            raise IngestError(f"{path.name}: the file cannot be read as CSV ({exc}).") from None


def _wrong_cells(name: str, header: list[str], i: int, row: list[str], rest: Iterator[list[str]]) -> None:
    """Refuse data row ``i`` of a CSV, the first whose cells are not the header's. When it is wider
    than the lines above it and every row after it (one at least) is as wide, the lines above are
    the odd ones: a title or note above the header, which pandas would take for it."""
    below = next(rest, None)
    if (below is not None and len(row) > len(header) and len(below) == len(row)
            and all(len(r) == len(row) for r in rest)):
        one = i == 1
        raise IngestError(f"{name}, header: the first {'line has' if one else f'{i} lines have'} "
                          f"{counted(len(header), 'cell')}{'' if one else ' each'} where the rows "
                          f"below {'it' if one else 'them'} have {counted(len(row), 'cell')} "
                          f"({'a title or note line' if one else 'title or note lines'} above the "
                          "header?); the header must be the first line: delete the lines above it.")
    raise IngestError(f"{name}, row {i}: {counted(len(row), 'cell')} where the header has "
                      f"{counted(len(header), 'column')} (a cell with a comma needs quotes; a "
                      "truncated file loses its last row's cells).")


def table_and_label(data: pd.DataFrame | str | Path, file_label: str | None,
                    reader) -> tuple[pd.DataFrame, str]:
    """Return the table to validate and the file name its messages use.

    ``data`` is a table (label ``file_label`` or ``"<dataframe>"``) or a path read with
    ``reader`` (label ``file_label`` or the file name).
    """
    if isinstance(data, (str, Path)):
        return reader(data), file_label or Path(data).name
    return data, file_label or "<dataframe>"


def header_problems(columns: list[str], required: list[str], units: dict[str, str],
                    unit_re: re.Pattern, optional: Sequence[str] = (),
                    ignored: Collection[str] = (),
                    other_sheets: Mapping[str, Sequence[str]] | None = None,
                    first_rows: Sequence[Sequence] = (),
                    filled_sheets: Collection[str] = (),
                    others: Sequence[tuple[str, str, Collection[str]]] = ()) -> list[str]:
    """Describe every problem of a header, all at once.

    Missing required columns; a missing column whose quantity is present under another unit suffix
    (``peak_slip_cm`` for ``peak_slip_mm``, ``units`` maps a column to its suffix) as wrong units;
    a column given twice (pandas reads the second ``x`` of a CSV or XLSX header as ``x.1``); any
    other column the sheet does not have (a misspelt optional column such as ``Source`` would
    otherwise be dropped and its rows stored as measured), with the closest known name (the column
    spelt as the sheet spells its names, so ``Time (s)`` and ``time [s]`` are near ``time_s``).
    ``ignored`` columns are accepted and not read (the commanded sheet's own columns, when a rig
    fills in its measurements beside its commands). ``other_sheets`` (a workbook's other sheets'
    headers, ``read_table``'s ``attrs["other_sheets"]``): when the first sheet, the one read,
    misses required columns that another sheet has, the problem names that sheet; when it has them
    and another sheet of ``filled_sheets`` (those with a data row) has them too, that sheet's
    records would be left unread, and the problem names it. ``first_rows``
    (the table's first data rows): when one of them holds every required column's name, the
    header is below a title or a note, and the problem says which row holds it. ``others``
    (``(what, advice, columns)`` of the files this one may be mistaken for,
    :func:`graspcampaign.rig.file_kinds.other_files`): a header with a problem that holds every
    column of one of them, and none of the required columns but its, is named as that file (the
    first that fits), with what it lacks and the advice.

    Returns
    -------
    list of str
        One phrase per kind of problem; empty when the header is complete.
    """
    known = list(dict.fromkeys([*required, *units, *optional]))
    counts = Counter(m[1] if (m := re.fullmatch(r"(.+)\.[0-9]+", c)) and m[1] in columns else c
                     for c in columns)
    twice = [c for c, k in counts.items() if k > 1]
    unknown = [c for c in counts if c not in known and c not in ignored and c not in twice]
    wrong, missing, explained = [], [], set()
    for name in required:
        if name in counts:
            continue
        want = unit_re.match(name) if units.get(name) else None
        other = next((c for c in unknown if want and (m := unit_re.match(c))
                      and m["stem"] == want["stem"] and m["unit"] != want["unit"]), None)
        if other:
            explained.add(other)
            wrong.append(f"'{other}' has unit '{unit_re.match(other)['unit']}' where '{name}' "
                         f"({units[name]}) is expected")
        else:
            missing.append(name)
    out = []
    if missing:
        out.append(f"{'a required column is' if len(missing) == 1 else 'required columns are'} "
                   f"missing: {', '.join(missing)}")
        if holder := next((n for n, cols in (other_sheets or {}).items()
                           if set(required) <= set(cols)), None):
            first = ("is empty; sheet '{}' has every required column" if not columns else
                     "lacks the required columns; sheet '{}' has them all").format(holder)
            return [f"ingest reads the workbook's first sheet, which {first}: move it to the front "
                    "or save it as CSV"]
        below = next((k for k, row in enumerate(first_rows)
                      if set(required) <= {str(cell).strip() for cell in row}), None)
        if below is not None:  # a title above the header: its names are a data row's cells
            return [f"row {below + 1} holds the column names, so what is above it (a title or a "
                    "note?) was read as the header; the header must be the first row, so delete "
                    "the rows above it"]
    elif also := [n for n in filled_sheets if set(required) <= set((other_sheets or {})[n])]:
        return [f"{plural('sheet', len(also))} {', '.join(map(repr, also))} "
                f"{plural('holds', len(also), 'hold')} records too (every required column, "
                "rows below it), but ingest reads only the workbook's first sheet, so they would "
                "not be stored: save each sheet as a CSV file and ingest the files together, or "
                "move the rows to the first sheet"]
    held = set(required) & set(counts)  # the other file must hold these too: not a typo in ours
    if (missing or unknown) and (mistaken := next((o for o in others if set(o[2]) <= set(counts)
                                                   and held <= set(o[2])), None)):
        lacks = (f" (no {', '.join(missing[:8])}{' and more' if len(missing) > 8 else ''})"
                 if missing else "")
        return [f"its columns are those of {mistaken[0]}{lacks}{mistaken[1]}"]
    out += wrong
    if twice:
        out.append(f"{'a column appears' if len(twice) == 1 else 'columns appear'} more than once: "
                   f"{', '.join(twice)}")
    if unknown := [c for c in unknown if c not in explained]:
        def hint(c: str) -> str:
            if empty := re.fullmatch(r"Unnamed: ([0-9]+)", c):  # pandas' name of an empty cell
                return f"column {int(empty[1]) + 1} (its header cell is empty)"
            # compared as the sheet writes a name (lower case, '_' between words): 'Time (s)' as time_s;
            # a character that does not print (a NUL, a zero-width space) shown escaped: 'sta\x00ble'
            shown = f"'{c}'" if c.isprintable() else repr(c)
            return f"{shown}{aside(re.sub(r'[^0-9a-z]+', '_', c.lower()).strip('_'), known, cutoff=0.75)}"
        more = f" and {len(unknown) - 8} more" if len(unknown) > 8 else ""
        out.append(f"{'a column is' if len(unknown) == 1 else 'columns are'} not part of the sheet: "
                   f"{', '.join(map(hint, unknown[:8]))}{more}; its columns are {', '.join(known)}")
    return out
