"""What text a file's first bytes hold, asked by every reader of a text file (a study or group
file, a CSV of measured records, an OBJ, PLY or ASCII STL mesh), so that each names a file saved
in another text form alike."""

from __future__ import annotations

#: UTF-16's byte-order marks, little- and big-endian (RFC 2781)
UTF16_MARKS = (b"\xff\xfe", b"\xfe\xff")

#: The bytes of a file's start :func:`utf16` reads: a mark and the 200 after it
UTF16_HEAD = 202


def utf16(data: bytes) -> bool:
    """Whether ``data`` (a file's first bytes, at least 200 of them where the file has them) is
    UTF-16 text, with or without its byte-order mark: its first 100 characters ASCII or Latin-1,
    so that every other byte is a NUL. Without a mark such text decodes as UTF-8 (each character
    beside a NUL byte), which the readers would take for content (docs/decisions.md, "A text
    file saved as UTF-16 is named as one")."""
    head = data[2:UTF16_HEAD] if data[:2] in UTF16_MARKS else data[:UTF16_HEAD - 2]
    return len(head) >= 2 and any(head[1::2]) != any(head[0::2])
