"""core/mesh_format.py on hand-built files: the edges of its length checks and of its sniffing.

Each file is made here byte by byte (``struct``, the ``bz2`` module), so the sizes below are the
formats' own: a binary STL is 80 header bytes, a 4-byte count and 50 bytes per triangle; a binary
PLY body holds each element's properties at their type's size (a list property: its count first).
"""

from __future__ import annotations

import bz2
import struct

import pytest

from graspcampaign.core.mesh_format import MeshError, check_compressed, check_stl_layout, ply_layout


def _stl(path, declared: int, n_triangles: int, extra: bytes = b""):
    """A binary STL whose count says ``declared`` triangles, holding ``n_triangles`` whole ones."""
    triangle = struct.pack("<12fH", *range(12), 0)
    assert len(triangle) == 50
    path.write_bytes(b"\0" * 80 + struct.pack("<I", declared) + triangle * n_triangles + extra)
    return path.stat().st_size


def _head(path) -> bytes:
    """A file's first bytes, as load_mesh reads them once for every check."""
    return path.read_bytes()[:4096]


def test_a_binary_stl_cut_within_its_first_triangle_is_no_stl_named_truncated(tmp_path):
    """A truncated STL is named so once one whole triangle is there (84 + 50 bytes); 20 bytes of a
    first triangle are not enough to say the file is an STL at all."""
    n_bytes = _stl(tmp_path / "short.stl", declared=2, n_triangles=0, extra=b"\1" * 20)
    assert n_bytes == 104
    with pytest.raises(MeshError, match=r"^mesh 'short\.stl' is not an STL file: 104 bytes"):
        check_stl_layout(str(tmp_path / "short.stl"), "short.stl", n_bytes, _head(tmp_path / "short.stl"))
    n_bytes = _stl(tmp_path / "cut.stl", declared=2, n_triangles=1)
    assert n_bytes == 134
    with pytest.raises(MeshError, match=r"^mesh 'cut\.stl' is truncated or its header is wrong: its "
                                        r"header declares 2 triangles, 184 bytes"):
        check_stl_layout(str(tmp_path / "cut.stl"), "cut.stl", n_bytes, _head(tmp_path / "cut.stl"))


def _binary_ply(path, properties: list[str], n_vertices: int, body: bytes, faces: int | None = None):
    header = ["ply", "format binary_little_endian 1.0", f"element vertex {n_vertices}",
              *[f"property {p}" for p in properties]]
    if faces is not None:
        header += [f"element face {faces}", "property list uchar int vertex_indices"]
    path.write_bytes(("\n".join([*header, "end_header"]) + "\n").encode() + body)
    return str(path)


def test_a_binary_ply_body_of_exactly_its_declared_size_is_read(tmp_path):
    body = struct.pack("<9f", *range(9))  # 3 vertices of 3 floats: 36 bytes, no more
    name = _binary_ply(tmp_path / "exact.ply", ["float x", "float y", "float z"], 3, body)
    assert ply_layout(name, "exact.ply") == {"ascii": False, "elements": [["vertex", 3]]}
    with pytest.raises(MeshError, match=r"declares 3 vertex elements, at least 36 bytes of binary "
                                        r"data, but the file holds only 35 bytes after its header\.$"):
        ply_layout(_binary_ply(tmp_path / "short.ply", ["float x", "float y", "float z"], 3,
                               body[:-1]), "short.ply")


def test_a_binary_ply_with_a_type_the_format_does_not_name_is_left_to_the_reader(tmp_path):
    """A property of an unknown type has no known size: no length is claimed for that element or
    any after it (1000 faces after it would need 1000 bytes at least), and trimesh's reader names
    the type."""
    name = _binary_ply(tmp_path / "odd.ply", ["float128 x", "float y", "float z"], 3, b"\0" * 40,
                       faces=1000)
    assert ply_layout(name, "odd.ply") == {"ascii": False, "elements": [["vertex", 3], ["face", 1000]]}


def test_bzip2_is_told_by_its_block_magic_not_by_its_first_three_bytes():
    """'BZh' begins a bzip2 file and some text too: a bzip2 stream goes on with a block size digit
    and the first block's magic (the ``bz2`` module's output is the reference)."""
    check_compressed(b"BZh ello: a text mesh file\n", "words.obj", ".obj")
    with pytest.raises(MeshError, match=r"^mesh 'sphere\.obj' is a bzip2-compressed file, not an OBJ"):
        check_compressed(bz2.compress(b"v 0 0 0\n" * 10)[:64], "sphere.obj", ".obj")


@pytest.mark.parametrize("property_line", ["list", "list uchar", ""])
def test_a_binary_ply_property_without_its_types_is_left_to_the_reader(tmp_path, property_line):
    """A header line 'property list' (or 'property' alone) names no type: it was an IndexError
    (a traceback) while the header was read; now no length is claimed and the reader says why."""
    name = _binary_ply(tmp_path / "bare.ply", [property_line], 3, b"\0" * 40)
    assert ply_layout(name, "bare.ply") == {"ascii": False, "elements": [["vertex", 3]]}


def test_a_binary_stl_cut_short_whose_header_begins_solid_is_named_truncated(tmp_path):
    """A binary STL's 80-byte header is free text, and CAD programs write 'solid <name>' there; cut
    short, such a file is no ASCII STL (its triangles are not ASCII text): it was "not an STL file"."""
    triangle = struct.pack("<12fH", *[0.5 + i for i in range(12)], 0)
    assert any(byte >= 0x80 for byte in triangle)  # binary data: no ASCII STL
    path = tmp_path / "part.stl"
    path.write_bytes(b"solid part".ljust(80, b" ") + struct.pack("<I", 3) + triangle * 2)
    with pytest.raises(MeshError, match=r"^mesh 'part\.stl' is truncated or its header is wrong: its "
                                        r"header declares 3 triangles, 234 bytes as a binary STL \(84 "
                                        r"plus 50 per triangle\), but the file holds only 184 bytes\.$"):
        check_stl_layout(str(path), "part.stl", path.stat().st_size, _head(path))


def test_an_ascii_stl_with_a_byte_beyond_ascii_is_no_truncated_binary_stl(tmp_path):
    """Text's bytes 80-84 read as a count exceed MAX_STL_TRIANGLES: an ASCII STL holding one UTF-8
    letter stays "not an STL file", never "truncated"."""
    text = "solid Größe\n" + "facet normal 0 0 1\n outer loop\n  vertex 0 0 0\n" * 4
    path = tmp_path / "text.stl"
    path.write_bytes(text.encode())
    with pytest.raises(MeshError, match=r"^mesh 'text\.stl' is not an STL file: "):
        check_stl_layout(str(path), "text.stl", path.stat().st_size, _head(path))
