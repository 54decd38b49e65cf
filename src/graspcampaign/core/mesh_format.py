"""What a mesh file's bytes say before trimesh reads it: its format by its first bytes (a binary
or ASCII STL, a PLY, an OBJ, a compressed file or an archive), an STL's layout, an OBJ's vertex
and face lines, a PLY header's elements against the bytes or lines that follow it.

:mod:`graspcampaign.core.mesh_file` calls these before and after ``trimesh.load``; every refusal
is a :class:`MeshError` naming the file and what is wrong, in one sentence.
"""

from __future__ import annotations

import codecs
import io
import os
import re

import numpy as np

from graspcampaign.core.words import counted, listed

__all__ = [
    "MeshError",
    "check_compressed",
    "check_obj_lines",
    "check_ply_faces",
    "check_stl_layout",
    "other_format",
    "ply_layout",
    "text_utf16",
    "text_with_bom",
]


class MeshError(ValueError):
    """A mesh or shape request that cannot be used; the message says what is wrong."""


#: The most triangles a binary STL cut short is recognised by (a 2.5 GB file): 50 times the
#: million faces beyond which `plan` warns of a mesh's size (decisions.md).
MAX_STL_TRIANGLES = 50_000_000


def check_stl_layout(name: str, base: str, n_bytes: int, head: bytes, skip: int = 0) -> None:
    """Tell an STL from other bytes before trimesh guesses (it would try text decodings); ``head``
    is the file's first bytes (84 or more, if it holds them), read once by the caller, from byte
    ``skip`` (past a byte-order mark; ``n_bytes`` counts from there too)."""
    head = head[:84]
    if _binary_stl_size(head, n_bytes):
        return  # binary STL: 80-byte header, triangle count, 50 bytes per triangle
    if head.lstrip()[:5].lower() == b"solid":
        last, at = "", 0  # its last line holding text, and that line's number
        try:
            with open(name, "rb") as raw:  # line by line: not the whole file at once
                raw.seek(skip)
                for n, line in enumerate(io.TextIOWrapper(raw, encoding="ascii"), 1):
                    if line.strip():
                        last, at = line.strip(), n
        except UnicodeDecodeError:
            pass
        else:  # an ASCII STL ends with 'endsolid': without it, trimesh reads no face at all
            if not last.lower().startswith("endsolid"):
                raise MeshError(f"mesh {base!r} is cut short: an ASCII STL ends with an "
                                f"'endsolid' line, and this one ends on line {at} "
                                f"({last[:40]!r}); copy or export it again.")
            return
    declared = int.from_bytes(head[80:84], "little") if len(head) == 84 else 0
    # a binary STL cut short (the copy stopped midway): a count no file of another kind holds by
    # chance (bytes 80-84 of other data read as a count are mostly far above it; of text, whose
    # byte 83 is 0x09 or more, always: 0x09000000 > MAX_STL_TRIANGLES) and one whole triangle at
    # least. Its header may begin 'solid' (free text; some CAD programs write 'solid <name>').
    if 0 < declared <= MAX_STL_TRIANGLES and 134 <= n_bytes < 84 + 50 * declared:
        raise MeshError(f"mesh {base!r} is truncated or its header is wrong: its header declares "
                        f"{declared:,} triangles, {84 + 50 * declared:,} bytes as a binary STL "
                        f"(84 plus 50 per triangle), but the file holds only {n_bytes:,} bytes.")
    raise MeshError(f"mesh {base!r} is not an STL file: {n_bytes} bytes are neither a binary STL "
                    "(84 bytes plus 50 per triangle) nor an ASCII STL (text starting with 'solid').")


def _binary_stl_size(head: bytes, n_bytes: int) -> bool:
    """Whether ``n_bytes`` is the size of a binary STL counting the triangles its header says."""
    return len(head) >= 84 and 84 + 50 * int.from_bytes(head[80:84], "little") == n_bytes


def text_with_bom(head: bytes, n_bytes: int) -> bool:
    """Whether a mesh file begins with a UTF-8 byte-order mark (as Windows Notepad saves text): a
    text mesh whose readers would take the mark for part of its first line (a binary STL of the
    size its header says may begin so, its 80-byte header being free text)."""
    return head.startswith(codecs.BOM_UTF8) and not _binary_stl_size(head, n_bytes)


def text_utf16(head: bytes, n_bytes: int) -> bool:
    """Whether a mesh file is UTF-16 text (:func:`core.text.utf16`: Windows PowerShell's
    redirection writes it), which no mesh reader takes: an OBJ was "binary data", an ASCII STL a
    binary STL of millions of triangles. A binary STL of the size its header says is not asked."""
    from graspcampaign.core.text import utf16

    return utf16(head) and not _binary_stl_size(head, n_bytes)


def other_format(head: bytes, n_bytes: int) -> tuple[str, str] | None:
    """Recognise an STL, PLY or OBJ file by its first bytes: (what it looks like, its suffix)."""
    if _binary_stl_size(head, n_bytes):
        return "a binary STL (84 bytes plus 50 per triangle)", ".stl"
    if head.lstrip()[:5].lower() == b"solid" and b"facet" in head:
        return "an ASCII STL (text starting with 'solid')", ".stl"
    if head[:4] in (b"ply\n", b"ply\r"):
        return "a PLY file (its first line is 'ply')", ".ply"
    if re.search(rb"(?m)^[ \t]*v[ \t]+[-+.\d]", head):  # an OBJ vertex line: 'v 1.0 2.0 3.0'
        return "an OBJ file (text with vertex lines 'v x y z')", ".obj"
    return None


def check_obj_lines(name: str, base: str, head: bytes) -> bool:
    """Refuse an OBJ with a vertex or face it cannot read, naming the line; return whether trimesh
    keeps its faces in the file's order (it splits polygons into triangles and regroups faces by
    object, group and material).

    Refused: binary data (OBJ is text), a 'v' line without three numbers, a face index that is
    not a whole number or refers to a missing vertex, vertices without faces. trimesh reports
    each as "could not be read to its end due to unmatched data". A face's vertex index is
    1-based, or negative counting back from the vertices read so far (the OBJ format); a
    positive index is checked against every vertex of the file, as readers do. ``head`` is the
    file's first 4096 bytes (or all of a shorter file), read once by the caller: a NUL among them
    is binary data.
    """
    n_vertices = n_faces = 0
    in_order = True
    largest = (0, 0)  # (positive vertex index, line)
    if b"\0" in head[:4096]:
        raise MeshError(f"mesh {base!r} is not an OBJ file: OBJ is text, but the file holds "
                        "binary data.")
    # utf-8-sig: a byte-order mark is no part of the first line (head is read past it)
    with open(name, encoding="utf-8-sig", errors="replace") as fh:
        for line_no, line in enumerate(fh, 1):
            words = line.split()
            if words[:1] == ["v"]:
                n_vertices += 1
                if len(words) < 4:
                    raise MeshError(f"mesh {base!r} has a vertex (line {line_no}) with "
                                    f"{counted(len(words) - 1, 'coordinate')}: an OBJ 'v' line "
                                    "gives x, y and z.")
                for token in words[1:]:
                    try:
                        float(token)
                    except ValueError:
                        raise MeshError(f"mesh {base!r} has a vertex (line {line_no}) whose "
                                        f"coordinate {token!r} is not a number.") from None
            elif words[:1] in (["o"], ["g"], ["usemtl"]):
                in_order = False
            elif words[:1] == ["f"]:
                n_faces += 1
                in_order &= len(words) == 4
                for token in words[1:]:
                    try:
                        index = int(token.split("/", 1)[0])  # v, v/vt, v//vn or v/vt/vn
                    except ValueError:
                        raise MeshError(f"mesh {base!r} has a face (line {line_no}) whose vertex "
                                        f"{token!r} is not a whole number.") from None
                    if index > largest[0]:
                        largest = (index, line_no)
                    elif index == 0 or index < -n_vertices:  # a positive index passes both
                        raise MeshError(f"mesh {base!r} has a face (line {line_no}) that refers to "
                                        f"vertex {index}, but {counted(n_vertices, 'vertex', 'vertices')} "
                                        "precede it: OBJ "
                                        "indices count from 1, or back from -1.")
    if largest[0] > n_vertices:
        raise MeshError(f"mesh {base!r} has a face (line {largest[1]}) that refers to vertex "
                        f"{largest[0]}, but the file has only {counted(n_vertices, 'vertex', 'vertices')}.")
    if n_vertices and not n_faces:
        raise MeshError(f"mesh {base!r} has {counted(n_vertices, 'vertex', 'vertices')} but no "
                        "faces: a point cloud is no surface; export the mesh with its faces (OBJ 'f' lines).")
    return in_order


def ply_layout(name: str, base: str) -> dict | None:
    """Read a PLY header (``None`` if there is none: trimesh's reader says why) and refuse an
    ASCII PLY that ends before the elements its header declares (one element a line)."""
    elements: list[list] = []
    sizes: list[int | None] = []  # each element's least size in bytes (None: a type unknown)
    ascii_format, declared = False, ""
    n_header = 0  # header lines, end_header included
    with open(name, "rb") as fh:
        for raw in fh:
            n_header += 1
            words = raw.decode("ascii", errors="replace").split()
            if words[:1] == ["format"]:
                ascii_format, declared = words[1:2] == ["ascii"], " ".join(words)
            elif words[:1] == ["element"] and len(words) == 3 and words[2].isdigit():
                elements.append([words[1], int(words[2])])
                sizes.append(0)
            elif words[:1] == ["property"] and sizes and sizes[-1] is not None:
                # a list property holds at least its count (its items may be none)
                kind = words[2:3] if words[1:2] == ["list"] else words[1:2]  # [] if it has none
                size = PLY_TYPE_BYTES.get(kind[0]) if kind else None
                sizes[-1] = None if size is None else sizes[-1] + size
            elif words == ["end_header"]:
                break
        else:
            return None
        if not ascii_format:
            body = fh.read(4096)
            if len(body) >= 16 and not body.strip(_PLY_TEXT) and b"\n" in body:  # only numbers
                raise MeshError(f"mesh {base!r} says '{declared}' in its header, but what follows "
                                "the header is text (lines of numbers), which an ASCII PLY holds "
                                "(format ascii 1.0); correct that line or export the mesh again.")
            fh.seek(-len(body), os.SEEK_CUR)
            _check_ply_length(base, elements, sizes, os.fstat(fh.fileno()).st_size - fh.tell())
            return {"ascii": False, "elements": elements}
        n_lines = sum(1 for raw in fh if raw.strip())
    line = n_header
    for element, count in elements:
        if n_lines < count:
            raise MeshError(f"mesh {base!r} is truncated: its header declares {count} "
                            f"{element} elements, but the file ends after {n_lines} of them "
                            f"(line {line + n_lines}).")
        n_lines -= count
        line += count
    return {"ascii": True, "elements": elements, "header_lines": n_header}


def check_ply_faces(faces: np.ndarray, n_vertices: int, base: str, ply: dict | None) -> None:
    """Refuse a PLY face that refers to a missing vertex, naming the face (and its line)."""
    bad = (faces < 0) | (faces >= n_vertices)
    if not bad.any():
        return
    row = int(np.flatnonzero(bad.any(axis=1))[0])
    index = int(faces[row][bad[row]][0])
    counts = dict(ply["elements"]) if ply else {}
    where = ""
    if counts.get("face") == len(faces):  # no polygon was split into triangles: rows are faces
        where = f" (face {row + 1})"
        if ply["ascii"]:
            before = 0
            for element, count in ply["elements"]:
                if element == "face":
                    break
                before += count
            where = f" (face {row + 1}, line {ply['header_lines'] + before + row + 1})"
    raise MeshError(f"mesh {base!r} has a face{where} that refers to vertex {index}, but the file "
                    f"has only {counted(n_vertices, 'vertex', 'vertices')}: PLY indices count from 0.")


#: The bytes of an ASCII PLY's body (numbers, spaces, line ends): binary data of 16 bytes or more
#: made of them alone is all but impossible (a float's exponent byte would be a digit or a space).
_PLY_TEXT = b"0123456789+-.eE \t\r\n"
#: Bytes of each PLY property type (the PLY format's scalar types, old and sized names).
PLY_TYPE_BYTES = {**dict.fromkeys(("char", "uchar", "int8", "uint8"), 1),
                  **dict.fromkeys(("short", "ushort", "int16", "uint16"), 2),
                  **dict.fromkeys(("int", "uint", "float", "int32", "uint32", "float32"), 4),
                  **dict.fromkeys(("double", "float64"), 8)}


def _check_ply_length(base: str, elements: list[list], sizes: list[int | None], n_body: int) -> None:
    """Refuse a binary PLY whose header declares more elements than the bytes after it can hold
    (each element at least the sum of its properties' sizes, a list property's count alone)."""
    least = 0
    for i, ((_, count), size) in enumerate(zip(elements, sizes, strict=True)):
        if size is None:  # a type the format does not name: trimesh's reader says so
            return
        least += count * size
        if least > n_body:
            declared = listed([f"{n:,} {element}" for element, n in elements[:i + 1]])
            raise MeshError(f"mesh {base!r} is truncated or its header is wrong: its header declares "
                            f"{declared} elements, at least {least:,} bytes of binary data, but "
                            f"the file holds only {n_body:,} bytes after its header.")


#: How a compressed file or an archive begins (its magic number), what it is and what to do.
COMPRESSED = (
    (b"\x1f\x8b", "a gzip-compressed file", "decompress it first (gunzip)"),
    (b"BZh", "a bzip2-compressed file", "decompress it first (bunzip2)"),
    (b"\xfd7zXZ\x00", "an xz-compressed file", "decompress it first (unxz)"),
    (b"\x28\xb5\x2f\xfd", "a zstd-compressed file", "decompress it first (unzstd)"),
    (b"PK\x03\x04", "a zip archive", "extract the mesh from it first (unzip)"),
)


def check_compressed(head: bytes, base: str, suffix: str) -> None:
    """Refuse a mesh file that is a compressed file or an archive, saying what to do with it (a
    binary STL of that size is checked first by the caller: its 80-byte header is free text)."""
    for magic, what, todo in COMPRESSED:
        # bzip2: "BZh", the block size (1-9), then the first block's magic "1AY&SY" (pi's digits)
        if head.startswith(magic) and (magic != b"BZh" or head[4:10] == b"1AY&SY"):
            raise MeshError(f"mesh {base!r} is {what}, not {'a' if suffix == '.ply' else 'an'} "
                            f"{suffix[1:].upper()} file itself: {todo} and give the mesh it holds.")
