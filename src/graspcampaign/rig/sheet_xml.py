"""A workbook's first sheet read from its XML in pieces, for what pandas does not say of it: whether
it is hidden, its merged ranges and hidden rows, and the cells holding a spreadsheet error or a
formula, which pandas reads as empty.

openpyxl names merged ranges and hidden rows only when it loads the whole workbook into memory,
not in its read-only mode, and tells an error cell and a formula apart in two read-only loads
(``data_only`` true and false), each parsing every cell: on a Test 2 sheet with empty cells the
two took half of ingest (``benchmarks/bench_ingest.py``), where one pass of regular expressions
over the XML the marks are read from takes a few per cent.
"""

from __future__ import annotations

import html
import re
from collections.abc import Callable
from pathlib import Path
from typing import NamedTuple

PIECE = 2**20  #: the bytes of a sheet's XML read at a time


class SheetMarks(NamedTuple):
    """What :func:`first_sheet_marks` read of a workbook's first sheet."""

    hidden_sheet: str | None = None  #: its name when it is hidden, else None
    merged: tuple[str, ...] = ()  #: its merged ranges (``'J2:J3'``)
    hidden_rows: tuple[int, ...] = ()  #: its hidden rows (1-based, the sheet's numbers)
    #: the first cell asked for (row, column, 1-based) holding an error, and its stored value
    #: (``'#DIV/0!'``; None if it has none), or None
    error: tuple[int, int, str | None] | None = None
    #: the first cell asked for holding a formula, and the formula (``'=A2*2'``), or None
    formula: tuple[int, int, str] | None = None
    #: whether a cell holding either has no reference (``r``, optional in the XML): not placed
    unplaced: bool = False


def first_sheet_marks(path: Path, wanted: Callable[[int, int], bool] | None = None) -> SheetMarks:
    """Read the :class:`SheetMarks` of the workbook ``path``'s first sheet; its error and formula
    cells only among those ``wanted(row, column)`` (1-based) says (None: none).

    The first sheet is the first ``<sheet>`` of ``xl/workbook.xml`` (the one pandas reads), its
    ``state`` ``hidden`` or ``veryHidden`` when hidden; its part is named by the workbook's
    relationships (ECMA-376 Part 1 §18.2.19, Part 2 §9.3). A part that cannot be found leaves the
    checks to the reader, which said the workbook is readable. A cell holds an error when its type
    is ``e`` (``<c r="B7" t="e"><v>#DIV/0!</v></c>``, §18.18.11), a formula when it has an ``f``
    (§18.3.1.40), whose text a shared formula's other cells leave to its first (``<f t="shared"
    si="0"/>``), read as openpyxl reads it, moved to the cell (its ``Translator``).
    """
    import xml.etree.ElementTree as ET
    import zipfile

    with zipfile.ZipFile(path) as archive:
        try:
            sheet = ET.fromstring(archive.read("xl/workbook.xml")).find("{*}sheets/{*}sheet")
            rid = next(v for k, v in sheet.attrib.items() if k.endswith("}id"))
            rels = ET.fromstring(archive.read("xl/_rels/workbook.xml.rels"))
            target = next(r.get("Target") for r in rels if r.get("Id") == rid)
        except (KeyError, AttributeError, StopIteration, ET.ParseError):
            return SheetMarks()
        name = sheet.get("name") if sheet.get("state") in ("hidden", "veryHidden") else None
        part = target.lstrip("/") if target.startswith("/") else f"xl/{target}"
        if part not in archive.namelist():
            return SheetMarks(name)
        cells = _Cells(wanted)
        found, rows, tail = [], [], b""
        with archive.open(part) as xml:  # in pieces: a sheet of a million rows is ~100 MB of XML
            while chunk := xml.read(PIECE):
                text = tail + chunk
                found += _MERGE.findall(text)
                rows += [int(r) for r in _HIDDEN_ROW.findall(text)]
                # a tag cut in two is found whole in the next piece, and so is a cell
                tail = text[max(0, min(cells.read(text), len(text) - 512)):]
    return SheetMarks(name, tuple(dict.fromkeys(r.decode() for r in found)), tuple(sorted(set(rows))),
                      cells.error, cells.formula, cells.unplaced)


#: a merged range in a worksheet's XML, ``<mergeCell ref="J2:J3"/>`` (any namespace prefix)
_MERGE = re.compile(rb'<(?:\w+:)?mergeCell\s[^>]*?ref="([A-Z]+[0-9]+:[A-Z]+[0-9]+)"')
#: a hidden row's number in a worksheet's XML, ``<row r="3" hidden="1" ...>`` (attributes in any
#: order; ``hidden`` is an xsd:boolean, "1" or "true")
_HIDDEN_ROW = re.compile(rb'<(?:\w+:)?row\s(?=[^>]*?\bhidden="(?:1|true)")[^>]*?\br="([0-9]+)"')
#: where a cell may hold a formula or an error: an ``f`` in it, or the type ``t="e"`` in its tag
#: (an ``f`` is a cell's first child, so the ``<`` before either is the cell's); searched apart,
#: as one pattern of both took six times as long
_FORMULA_TAG, _ERROR_TYPE = re.compile(rb'<(?:\w+:)?f[\s/>]'), re.compile(rb't="e"')
#: a cell from its start: its attributes and content (none when it closes itself)
_CELL = re.compile(rb'<((?:\w+:)?)c\s([^>]*?)(?:/>|>(.*?)</\1c>)', re.S)
_CELL_START = re.compile(rb'<(?:\w+:)?c\s')
_ATTRIBUTE = re.compile(rb'\b(\w+)="([^"]*)"')
_FORMULA = re.compile(rb'<(?:\w+:)?f(\s[^>]*?)?(?:/>|>(.*?)</(?:\w+:)?f>)', re.S)
_VALUE = re.compile(rb'<(?:\w+:)?v>(.*?)</(?:\w+:)?v>', re.S)
_REFERENCE = re.compile(rb'([A-Z]{1,3})([0-9]+)')


class _Cells:
    """The first error cell and the first formula cell :func:`first_sheet_marks` is asked for,
    read piece by piece (a cell read twice, where two pieces overlap, is read alike)."""

    def __init__(self, wanted: Callable[[int, int], bool] | None):
        self.wanted, self.shared = wanted, {}  # a shared formula's si: its first cell and text
        self.error = self.formula = None
        self.unplaced = False

    def read(self, text: bytes) -> int:
        """Read the cells of ``text`` that may hold an error or a formula; return where a cell cut
        at its end begins (to be read whole with the next piece), else ``len(text)``."""
        if self.wanted is None:
            return len(text)
        hits = [m.start() for pattern in (_FORMULA_TAG, _ERROR_TYPE) for m in pattern.finditer(text)]
        for hit in sorted(hits):
            start = text.rfind(b"<", 0, hit)
            cell = _CELL.match(text, start)
            if cell is None:
                if _CELL_START.match(text, start):
                    return start  # cut: its end is in the next piece
                continue  # an f of no cell (a condition's formula in the sheet's extensions)
            self._cell(dict(_ATTRIBUTE.findall(cell[2])), cell[3] or b"")
        return len(text)

    def _cell(self, attributes: dict[bytes, bytes], content: bytes) -> None:
        formula = _FORMULA.search(content)
        error = attributes.get(b"t") == b"e"
        if not (formula or error):
            return
        if not (place := _REFERENCE.fullmatch(attributes.get(b"r", b""))):
            self.unplaced = True
            return
        from openpyxl.utils.cell import column_index_from_string

        ref = place[0].decode()
        at = (int(place[2]), column_index_from_string(place[1].decode()))
        written = "=" + (_text(formula[2]) or "") if formula else ""
        first = None  # a shared formula's first cell and text, for a cell that reads them
        if formula:  # a shared formula's text is read from its first cell, as openpyxl reads it
            given = dict(_ATTRIBUTE.findall(formula[1] or b""))
            if given.get(b"t") == b"shared" and (si := given.get(b"si")) is not None:
                if si not in self.shared and written != "=":
                    self.shared[si] = (written, ref)  # kept whether or not its cell is asked for
                elif si in self.shared and self.shared[si][1] != ref:
                    first = self.shared[si]
        if not self.wanted(*at):
            return
        if first is not None:  # moved to a cell asked for only (a translation parses the formula)
            from openpyxl.formula.translate import Translator

            written = Translator(*first).translate_formula(ref)
        if error and (self.error is None or at < self.error[:2]):
            value = _VALUE.search(content)
            self.error = (*at, _text(value[1]) if value else None)
        if formula and (self.formula is None or at < self.formula[:2]):
            self.formula = (*at, written)


def _text(xml: bytes | None) -> str | None:
    """The text of an element's XML content (entities read), or None when it has none."""
    return (html.unescape(xml.decode("utf-8")) or None) if xml else None
