"""A mesh refused for a hole or a zero-area face is refused in one sentence that says where: the
hole's corners (or its bounding box) in the file's unit, the face's number in the file when trimesh
keeps the file's face order. Each file is written by hand, so the place named is checked against
the coordinates and faces written."""

from __future__ import annotations

import numpy as np
import pytest
from cli_checks import refused

#: a tetrahedron 40 x 30 x 20 mm; its faces, outward wound, as 1-based vertex numbers
CORNERS = [(0, 0, 0), (40, 0, 0), (0, 30, 0), (0, 0, 20)]
FACES = [(1, 3, 2), (1, 2, 4), (1, 4, 3), (2, 3, 4)]


def _stl(faces, corners) -> str:
    """An ASCII STL of ``faces`` (1-based numbers into ``corners``)."""
    facets = "".join("facet normal 0 0 0\nouter loop\n"
                     + "".join(f"vertex {x} {y} {z}\n" for x, y, z in (corners[i - 1] for i in face))
                     + "endloop\nendfacet\n" for face in faces)
    return f"solid hand\n{facets}endsolid hand\n"


def _obj(faces, corners, head: str = "") -> str:
    """An OBJ of ``faces`` (1-based numbers into ``corners``) after the lines ``head``."""
    return (head + "".join(f"v {x} {y} {z}\n" for x, y, z in corners)
            + "".join(f"f {a} {b} {c}\n" for a, b, c in faces))


def _refused(path, message: str, *unit: str) -> None:
    """``plan`` of the mesh file exits 2 with ``message`` and writes nothing beside it."""
    refused(path.parent, ["plan", path, "--mass-kg", "0.1", *unit], message)


def test_a_hole_is_named_by_its_corners_in_the_file_unit(tmp_path):
    # the old message, "mesh 'open.stl' is not watertight: 3 boundary edges", said not where
    path = tmp_path / "open.stl"
    path.write_text(_stl(FACES[:3], CORNERS))  # the face (40,0,0)-(0,30,0)-(0,0,20) left out
    _refused(path, "mesh 'open.stl' is not watertight: 3 boundary edges (on one face only) between "
                   "the vertices at (0, 0, 20), (0, 30, 0) and (40, 0, 0) mm.")
    path.write_text(_stl(FACES[:3], [np.multiply(c, 0.1) for c in CORNERS]))  # the same in cm
    _refused(path, "mesh 'open.stl' is not watertight: 3 boundary edges (on one face only) between "
                   "the vertices at (0, 0, 2), (0, 3, 0) and (4, 0, 0) cm.", "--unit", "cm")


def test_a_wide_hole_is_named_by_its_bounding_box(tmp_path):
    # a 40 x 30 x 20 mm box without its top (z = 20): a scan's open face
    box = [(x, y, z) for x in (0, 40) for y in (0, 30) for z in (0, 20)]
    sides = [(1, 2, 4), (1, 4, 3), (1, 5, 6), (1, 6, 2), (1, 3, 7), (1, 7, 5),
             (5, 7, 8), (5, 8, 6), (3, 4, 8), (3, 8, 7), (2, 6, 8), (2, 8, 4)]
    top = [face for face in sides if all(box[i - 1][2] == 20 for i in face)]
    assert len(top) == 2
    path = tmp_path / "open_top.obj"
    path.write_text(_obj([face for face in sides if face not in top], box))
    _refused(path, "mesh 'open_top.obj' is not watertight: 4 boundary edges (on one face only) "
                   "between 4 vertices within x 0 to 40, y 0 to 30 and z 20 mm.")


#: the tetrahedron with its first face split at the midpoint (20, 0, 0) of an edge, and the
#: zero-area sliver (0,0,0)-(20,0,0)-(40,0,0) closing the split: still one closed surface
SLIVER_CORNERS = [*CORNERS, (20, 0, 0)]
SLIVER_FACES = [(1, 5, 3), (5, 2, 3), (1, 2, 4), (1, 4, 3), (2, 3, 4), (1, 2, 5)]


@pytest.mark.parametrize(("name", "text", "where"), [
    ("sliver.stl", _stl(SLIVER_FACES, SLIVER_CORNERS), ": triangle 6 of the file"),
    ("sliver.obj", _obj(SLIVER_FACES, SLIVER_CORNERS), ": face 6 of the file"),
    # trimesh regroups an OBJ's faces by object: their numbers are not the file's, so none is given
    ("parts.obj", _obj(SLIVER_FACES, SLIVER_CORNERS, head="o part\n"), ""),
])
def test_a_zero_area_face_is_named_by_its_number_in_the_file(tmp_path, name, text, where):
    # the old message, "has 1 degenerate (zero-area) faces", said neither one face nor which
    corners = np.array(SLIVER_CORNERS, dtype=float)
    areas = [np.linalg.norm(np.cross(corners[b - 1] - corners[a - 1], corners[c - 1] - corners[a - 1]))
             for a, b, c in SLIVER_FACES]
    assert np.flatnonzero(np.isclose(areas, 0.0)).tolist() == [5]  # the sixth face, alone
    path = tmp_path / name
    path.write_text(text)
    _refused(path, f"mesh '{name}' has 1 degenerate (zero-area) face{where}.")
