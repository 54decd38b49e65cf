"""A measured CSV is checked and read from the file, block by block and row by row, never held
whole: a Test 1 waveform file of the full schedule is 1.7 GiB (3.9 GiB with every float64 digit),
and its bytes, its text and the UCS-4 buffer of a StringIO over that text took some six times its
size before pandas read it (docs/decisions.md, "A Test 1 waveform file is read from the file")."""

from __future__ import annotations

from pathlib import Path

import pandas as pd
import pytest

from graspcampaign.rig.measured_file import IngestError, read_table


def _no_whole_file(monkeypatch):
    """Make reading a file whole at once fail (``Path.read_bytes``, ``Path.read_text``)."""
    def whole(self, *args, **kwargs):
        raise AssertionError(f"{self.name} was read whole")
    monkeypatch.setattr(Path, "read_bytes", whole)
    monkeypatch.setattr(Path, "read_text", whole)


def test_a_csv_is_read_without_holding_its_bytes_or_text(tmp_path, monkeypatch):
    # the check read the file's bytes and decoded them to one str, and pandas read a StringIO of it
    sheet = tmp_path / "waves.csv"
    sheet.write_text("event_id,time_s,note\nt1-a,0.0,\nt1-a,0.002,é\r\nt1-b,1e-3,x\n")
    expected = pd.read_csv(sheet, dtype={"event_id": str}, keep_default_na=False, na_values=[""])
    _no_whole_file(monkeypatch)
    frame = read_table(sheet, csv_options={"dtype": {"event_id": str}, "keep_default_na": False,
                                           "na_values": [""]})
    pd.testing.assert_frame_equal(frame, expected)
    assert frame["note"].tolist()[1:] == ["é", "x"]


def test_a_byte_order_mark_is_no_part_of_the_first_column_name(tmp_path, monkeypatch):
    sheet = tmp_path / "waves.csv"
    sheet.write_bytes(b"\xef\xbb\xbf" + b'"event_id",time_s\nt1-a,0.5\n')
    _no_whole_file(monkeypatch)
    assert read_table(sheet).columns.tolist() == ["event_id", "time_s"]


def test_a_character_across_the_first_block_read_is_utf8(tmp_path):
    # the first 202 bytes are read apart (the UTF-16 check's): an 'é' (0xc3 0xa9) on bytes 201-202
    # was no character when each block was decoded alone
    sheet = tmp_path / "waves.csv"
    head = b"a,b\n" + b"x" * 197
    sheet.write_bytes(head + "é,1\n".encode())
    assert len(head) == 201 and sheet.read_bytes()[201:203] == b"\xc3\xa9"
    assert read_table(sheet)["a"].tolist() == ["x" * 197 + "é"]


def test_a_csv_not_utf8_is_named_so_before_an_earlier_row_of_too_many_cells(tmp_path):
    # the bytes are checked first, whole, as before: the bad byte on line 5, 0xff (bytes.decode's
    # own answer), though row 2 has four cells
    sheet = tmp_path / "day1.csv"
    data = b"a,b,c\n1,2,3\n1,2,3,4\n7,8,9\n" + b"x" * 70_000 + b",\xff,3\n"
    sheet.write_bytes(data)
    with pytest.raises(UnicodeDecodeError) as decoded:
        data.decode("utf-8")
    assert data[:decoded.value.start].count(b"\n") + 1 == 5
    with pytest.raises(IngestError) as caught:
        read_table(sheet)
    assert str(caught.value) == ("day1.csv, line 5: the file is not UTF-8 text (byte 0xff); save it "
                                 "as CSV UTF-8.")


def test_a_csv_not_utf8_after_a_byte_order_mark_is_named_by_its_own_byte_and_line(tmp_path):
    # 'utf-8-sig' counts the error's position from after the mark: the sentence named the byte three
    # before the bad one, a newline on line 2 ("line 2 ... (byte 0x0a)"), which is UTF-8
    sheet = tmp_path / "day1.csv"
    sheet.write_bytes(b"\xef\xbb\xbfa,b\n1,2\n3,\xff\n")
    with pytest.raises(IngestError) as caught:
        read_table(sheet)
    assert str(caught.value) == ("day1.csv, line 3: the file is not UTF-8 text (byte 0xff); save it "
                                 "as CSV UTF-8.")


@pytest.mark.parametrize("block", [5, 7, 64])
@pytest.mark.parametrize("bom", [b"", b"\xef\xbb\xbf"])
def test_a_csv_not_utf8_is_named_without_reading_it_whole(tmp_path, monkeypatch, block, bom):
    # the refusal read the whole file to name the line (a waveform file may be 8 GiB): now the
    # newlines of the blocks before the bad one are counted; small blocks cut 'é' (0xc3 0xa9) and
    # the CRLF line ends, and put the bad byte (after more 'é') in a later block than the first
    import graspcampaign.errors as errors

    sheet = tmp_path / "day1.csv"
    rows = "".join(f"{i},é{'x' * (i % 9)}\r\n" for i in range(40))
    data = bom + f"a,b\r\n{rows}".encode() + b"7,\xc3\xa9\xc3\x28\r\n" + b"8,9\r\n"
    sheet.write_bytes(data)
    with pytest.raises(UnicodeDecodeError) as decoded:  # bytes.decode's own answer
        data.decode("utf-8")
    line, byte = data[:decoded.value.start].count(b"\n") + 1, data[decoded.value.start]
    assert (line, byte) == (42, 0xc3)
    monkeypatch.setattr(errors, "UTF8_BLOCK", block)
    _no_whole_file(monkeypatch)
    with pytest.raises(IngestError) as caught:
        read_table(sheet)
    assert str(caught.value) == (f"day1.csv, line {line}: the file is not UTF-8 text (byte 0x{byte:02x}); "
                                 "save it as CSV UTF-8.")


def test_a_csv_cut_inside_its_last_character_is_named_at_that_character(tmp_path, monkeypatch):
    # the last block decoded whole but for its cut character, which only the final decode refuses
    import graspcampaign.errors as errors

    sheet = tmp_path / "day1.csv"
    data = b"a,b\n" + b"1,x\n" * 40 + b"2,\xc3"  # 'é' cut after its first byte, at the end
    sheet.write_bytes(data)
    with pytest.raises(UnicodeDecodeError) as decoded:
        data.decode("utf-8")
    assert (data[:decoded.value.start].count(b"\n") + 1, decoded.value.start) == (42, len(data) - 1)
    monkeypatch.setattr(errors, "UTF8_BLOCK", 10)
    _no_whole_file(monkeypatch)
    with pytest.raises(IngestError) as caught:
        read_table(sheet)
    assert str(caught.value) == ("day1.csv, line 42: the file is not UTF-8 text (byte 0xc3); save it as "
                                 "CSV UTF-8.")
