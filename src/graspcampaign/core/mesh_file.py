"""User meshes: reading STL, OBJ and PLY files and validating closed surfaces (SPEC §2.1).

Every mesh leaving :func:`load_mesh` or :func:`check_mesh` is a closed, outward-wound
triangulated surface in metres whose solid's volume centroid (``mesh.center_mass``) sits at the
origin. Every refusal is a :class:`MeshError` whose message is one sentence naming the file and
what is wrong. A file's bytes are read first by :mod:`graspcampaign.core.mesh_format` (its format,
an STL's layout, OBJ lines, a PLY header), then by trimesh. :mod:`graspcampaign.core.mesh`
re-exports the public names.

Shape letters used in this module: ``n`` vertices (nodes), ``f`` faces, ``p`` query points.
"""

from __future__ import annotations

import codecs
import logging
import os

import numpy as np
import trimesh

from graspcampaign.core.mesh_format import (
    MeshError,
    check_compressed,
    check_obj_lines,
    check_ply_faces,
    check_stl_layout,
    other_format,
    ply_layout,
    text_utf16,
    text_with_bom,
)
from graspcampaign.core.plausible import OBJECT_SIZE_MM
from graspcampaign.core.winding import winding_numbers
from graspcampaign.core.words import PERMISSION_DENIED, as_given, counted, listed, meant, plural

logger = logging.getLogger(__name__)

__all__ = [
    "MAX_COORDINATE_M",
    "MESH_SUFFIXES",
    "UNITS",
    "MeshError",  # defined in core.mesh_format, which reads a file's bytes before trimesh
    "centre_mesh",
    "check_mesh",
    "check_one_body",
    "check_unit",
    "load_mesh",
    "winding_numbers",  # re-exported from core.winding
]

#: Length units accepted by :func:`load_mesh`, as metres per unit.
UNITS = {"m": 1.0, "cm": 1e-2, "mm": 1e-3}
#: File types read by :func:`load_mesh`.
MESH_SUFFIXES = (".stl", ".obj", ".ply")


def centre_mesh(mesh: trimesh.Trimesh) -> trimesh.Trimesh:
    """Centre a constructed mesh on its volume centroid."""
    # Assign rather than apply_translation: trimesh skips transforms within 1e-8 of identity,
    # and the second pass removes the ~1e-9 m left by the first.
    for _ in range(2):
        mesh.vertices = np.asarray(mesh.vertices) - np.asarray(mesh.center_mass)
    return mesh


def check_unit(unit: object, name: str = "unit") -> str:
    """Return ``unit``, one of the length units a mesh file is read in (:data:`UNITS`).

    Raises
    ------
    MeshError
        Another, naming it as ``name`` calls it (a command-line option, starting with ``-``, as
        typed: ``--unit 'inch'``; else ``unit = 'inch'``), a near miss as the user would type it,
        and the units.
    """
    if unit in UNITS:
        return unit  # type: ignore[return-value]
    shown = f"{name} {{}}" if name.startswith("-") else "{!r}"
    raise MeshError(f"{as_given(name, unit)} is not a length unit a mesh is read in; "
                    f"{meant(unit, UNITS, shown)}use one of {', '.join(UNITS)} (the unit of the mesh "
                    "file's coordinates).")


def load_mesh(path: str | os.PathLike, unit: str = "mm") -> trimesh.Trimesh:
    """Read a user mesh (STL, OBJ or PLY), convert it to metres and validate it.

    Parameters
    ----------
    path : str or path-like
        Mesh file.
    unit : str
        Length unit of the file's coordinates: ``"m"``, ``"cm"`` or ``"mm"``.

    Returns
    -------
    mesh : trimesh.Trimesh
        Validated by :func:`check_mesh`: watertight, consistently and outward wound, no degenerate
        faces, in metres, centred on its volume centroid.

    Raises
    ------
    MeshError
        Unknown unit (:func:`check_unit`), missing or unreadable file, or a mesh that fails
        :func:`check_mesh`.
    """
    check_unit(unit)
    name = os.fspath(path)
    base = os.path.basename(name)
    if not os.path.isfile(name):
        raise MeshError(f"mesh file {name!r} does not exist.")
    suffix = os.path.splitext(name)[1].lower()
    if suffix not in MESH_SUFFIXES:
        raise MeshError(
            f"mesh file {name!r} has unsupported type {suffix or '(none)'!r}: "
            f"use {', '.join(MESH_SUFFIXES)}."
        )
    n_bytes, skip = os.path.getsize(name), 0  # skip: the bytes of a byte-order mark read past
    try:
        with open(name, "rb") as fh:  # read once: the format and layout checks share it
            head = fh.read(4096)
            if text_with_bom(head, n_bytes):  # as a study file's or a CSV's, the mark is no content:
                skip = len(codecs.BOM_UTF8)  # every check and trimesh read it from the byte after it
                head, n_bytes = head[skip:] + fh.read(skip), n_bytes - skip
    except PermissionError:  # chmod 000, another user's: the file is there, and may be whole
        raise MeshError(f"mesh file {name!r} cannot be read by this user: {PERMISSION_DENIED}.") from None
    if n_bytes == 0:
        raise MeshError(f"mesh {base!r} is empty: the file "
                        f"{'holds only a byte-order mark' if skip else 'has 0 bytes'}.")
    if text_utf16(head, n_bytes):  # named as a study file's or a CSV's is
        raise MeshError(f"mesh {base!r} is UTF-16 text, not UTF-8; save it as UTF-8 (or ASCII) "
                        "text.")
    other = other_format(head, n_bytes)
    if other is None:  # a binary STL's 80-byte header is free text: its size tells it first
        check_compressed(head, base, suffix)
    if other and other[1] != suffix:
        raise MeshError(f"mesh {base!r} is not {'a' if suffix == '.ply' else 'an'} "
                        f"{suffix[1:].upper()} file: it looks like {other[0]}; rename it to {other[1]}.")
    if suffix == ".stl":
        check_stl_layout(name, base, n_bytes, head, skip=skip)
    face_word = "triangle" if suffix == ".stl" else None  # set when the faces keep the file's order
    if suffix == ".obj" and check_obj_lines(name, base, head):
        face_word = "face"
    ply = ply_layout(name, base) if suffix == ".ply" else None
    try:
        # validate=False, process=False: keep non-finite values, degenerate faces and bad winding
        # so that they are reported here and by check_mesh instead of silently dropped
        # (a file past its byte-order mark is given as a file object: trimesh reads from its
        # position, as it does from a name, and nothing is copied)
        with np.errstate(all="ignore"), open(name, "rb") as fh:  # non-finite values are reported
            fh.seek(skip)                                          # below, not warned about
            mesh = trimesh.load(fh, file_type=suffix[1:], force="mesh", process=False,
                                validate=False)
    except Exception as exc:  # trimesh raises many types for unreadable files
        text = str(exc).strip().splitlines()[0] if str(exc).strip() else type(exc).__name__
        raise MeshError(f"mesh {base!r} cannot be read as {suffix[1:].upper()} ({text}).") from exc
    if not isinstance(mesh, trimesh.Trimesh) or len(mesh.faces) == 0:
        raise MeshError(f"mesh {base!r} is empty: it has no faces.")
    if ply is not None:
        check_ply_faces(np.asarray(mesh.faces), len(mesh.vertices), base, ply)
        if dict(ply["elements"]).get("face") == len(mesh.faces):  # no polygon split in triangles
            face_word = "face"
    vertices = np.asarray(mesh.vertices)
    _check_coordinates(vertices, base, unit, per_triangle=suffix == ".stl")
    # merge the duplicated corners of STL triangle soups; trimesh's fixed 1e-8 (file units) would
    # also merge distinct corners of a mesh a few 1e-8 across, so the tolerance shrinks with it
    extent = float(np.ptp(vertices, axis=0).max())
    digits = trimesh.util.decimal_to_digits(trimesh.tol.merge * min(1.0, max(extent, 1e-290)))
    mesh.merge_vertices(digits_vertex=digits)
    if suffix == ".stl":
        mesh = _coordinate_order(mesh)
    size_mm = extent * UNITS[unit] * 1e3
    if size_mm < OBJECT_SIZE_MM.low and (n_degenerate := int(_degenerate(  # a unit slip, not a
            np.asarray(mesh.vertices), np.asarray(mesh.faces)).sum())):  # bad surface: scanned once
        raise MeshError(f"mesh {base!r} has {counted(n_degenerate, 'degenerate (zero-area) face')} "
                        f"and is only {size_mm:.3g} mm across read with --unit {unit}: check the "
                        "file and its unit (--unit).")
    mesh.apply_scale(UNITS[unit])
    # merging and renumbering the vertices keep the faces in the file's order
    return check_mesh(mesh, base, unit=unit, face_word=face_word)


def _coordinate_order(mesh: trimesh.Trimesh) -> trimesh.Trimesh:
    """Number an STL's merged vertices in coordinate order (x, then y, then z).

    An STL stores triangles, not a vertex list; trimesh numbers the corners in the order they
    first appear, which depends on each triangle's corner order, so an inward-wound copy of a
    file (corners reversed) would number them differently and the planner, which samples
    vertices, would plan differently. The coordinate order depends on the surface alone.
    """
    vertices = np.asarray(mesh.vertices)
    order = np.lexsort(vertices.T[::-1])
    rank = np.empty_like(order)
    rank[order] = np.arange(len(order))
    return trimesh.Trimesh(vertices[order], rank[np.asarray(mesh.faces)], process=False)


#: Largest coordinate accepted from a mesh file [m]: a kilometre is no graspable object, and
#: bounding coordinates keeps areas and volumes (cubes of lengths) far from float overflow.
MAX_COORDINATE_M = 1e3


def _check_coordinates(vertices: np.ndarray, base: str, unit: str, per_triangle: bool) -> None:
    """Refuse non-finite or absurdly large coordinates, naming the first vertex (or triangle)."""
    def where(i: int) -> str:
        return f"triangle {i // 3 + 1}" if per_triangle else f"vertex {i + 1}"

    finite = np.isfinite(vertices).all(axis=1)
    if not finite.all():
        i = int(np.flatnonzero(~finite)[0])
        raise MeshError(f"mesh {base!r} has a non-finite coordinate at {where(i)} "
                        f"({', '.join(f'{x:g}' for x in vertices[i])}): every coordinate must be a "
                        "finite number.")
    limit = MAX_COORDINATE_M / UNITS[unit]
    far = np.abs(vertices).max(axis=1) > limit
    if far.any():
        i = int(np.flatnonzero(far)[0])
        raise MeshError(f"mesh {base!r} has a coordinate of {np.abs(vertices[i]).max():.3g} {unit} "
                        f"at {where(i)}, beyond the {limit:g} {unit} ({MAX_COORDINATE_M:g} m) any "
                        "graspable object fits in; check the file and its unit (--unit).")


def _degenerate(vertices: np.ndarray, faces: np.ndarray) -> np.ndarray:
    """(f,) bool: faces of (nearly) zero area, relative to the mesh's extent squared."""
    scale = float(np.ptp(vertices, axis=0).max())
    tri = vertices[faces]
    double_area = np.linalg.norm(np.cross(tri[:, 1] - tri[:, 0], tri[:, 2] - tri[:, 0]), axis=1)
    return double_area <= 1e-12 * max(scale, 1e-300) ** 2


def _listed(noun: str, numbers: np.ndarray, few: int = 3) -> str:
    """``triangle 5``, ``triangles 5 and 9``, ``triangles 5, 9, 12 and 4 more``: the first few."""
    shown = [str(n) for n in numbers[:few]]
    if len(numbers) > few:
        shown.append(f"{len(numbers) - few} more")
    return f"{plural(noun, len(numbers))} {listed(shown)}"


def _located(points: np.ndarray, unit: str) -> str:
    """Where (p, 3) points lie: each point up to three, else their bounding box (a flat one, such
    as a scan's open base, by the one value of its flat axis)."""
    if len(points) <= 3:
        return f"the vertices at {listed([f'({x:g}, {y:g}, {z:g})' for x, y, z in points])} {unit}"
    spans = [f"{axis} {low:g}" if low == high else f"{axis} {low:g} to {high:g}"
             for axis, low, high in zip("xyz", points.min(0), points.max(0), strict=True)]
    return f"{len(points)} vertices within {listed(spans)} {unit}"


def check_mesh(mesh: trimesh.Trimesh, name: str = "mesh", centre: bool = True, unit: str = "m",
               face_word: str | None = None) -> trimesh.Trimesh:
    """Validate a closed surface mesh and return an outward-wound, centred copy.

    Parameters
    ----------
    mesh : trimesh.Trimesh
        Candidate mesh in metres.
    name : str
        Name used in error messages (e.g. the file name).
    centre : bool
        Translate the result so its volume centroid is at the origin.
    unit : str
        Unit the messages give coordinates in (a key of :data:`UNITS`; the mesh is in metres).
    face_word : str or None
        What the file calls a face (``"triangle"``, ``"face"``) when the mesh's faces are the
        file's, in its order: degenerate faces are then named by their number in the file.

    Returns
    -------
    mesh : trimesh.Trimesh
        A copy; winding flipped if it was consistently inward.

    Raises
    ------
    MeshError
        Empty mesh, non-finite coordinates, degenerate (zero-area) faces, open or non-manifold
        edges, inconsistent winding, more than one closed surface (:func:`check_one_body`), or
        zero enclosed volume.
    """
    if len(mesh.faces) == 0 or len(mesh.vertices) == 0:
        raise MeshError(f"mesh {name!r} is empty: it has no faces.")
    vertices = np.asarray(mesh.vertices, dtype=float)
    faces = np.asarray(mesh.faces, dtype=np.int64)
    bad_coords = ~np.isfinite(vertices).all(axis=1)
    if bad_coords.any():
        raise MeshError(f"mesh {name!r} has non-finite coordinates at "
                        f"{counted(int(bad_coords.sum()), 'vertex', 'vertices')}.")
    scale = float(np.ptp(vertices, axis=0).max())
    degenerate = np.flatnonzero(_degenerate(vertices, faces))
    if len(degenerate):
        where = f": {_listed(face_word, degenerate + 1)} of the file" if face_word else ""
        raise MeshError(f"mesh {name!r} has {counted(len(degenerate), 'degenerate (zero-area) face')}"
                        f"{where}.")
    # every undirected edge of a closed manifold surface is shared by exactly two faces
    faces_per_edge = np.bincount(mesh.edges_unique_inverse)
    for bad, what in ((faces_per_edge == 1, "boundary"), (faces_per_edge > 2, "non-manifold")):
        if bad.any():
            shared = "on one face only" if what == "boundary" else "shared by more than two faces"
            corners = vertices[np.unique(mesh.edges_unique[bad])] / UNITS[unit]
            raise MeshError(f"mesh {name!r} is not watertight: "
                            f"{counted(int(bad.sum()), what + ' edge')} ({shared}) between "
                            f"{_located(corners, unit)}.")
    # On a closed manifold every undirected edge is used twice; consistent winding traverses it
    # once in each direction, so a repeated *directed* edge marks a flipped neighbour.
    n_directed = len(np.unique(mesh.edges, axis=0))
    n_inconsistent = len(mesh.edges) - n_directed
    if n_inconsistent:
        raise MeshError(
            f"mesh {name!r} is inconsistently wound: {counted(n_inconsistent, 'edge')} "
            f"{'is' if n_inconsistent == 1 else 'are'} traversed in the same direction "
            "by both of their faces."
        )
    check_one_body(mesh, name)
    out = mesh.copy()
    volume = out.volume
    if abs(volume) <= 1e-12 * scale**3:
        raise MeshError(f"mesh {name!r} encloses no volume.")
    if volume < 0.0:
        logger.info("mesh %r was wound inward; inverted to outward winding", name)
        out.invert()
    if centre:
        out = centre_mesh(out)
    return out


#: Vertices of each surface tested against the others by :func:`check_one_body` (evenly spaced).
NESTING_SAMPLES = 64


def check_one_body(mesh: trimesh.Trimesh, name: str = "mesh") -> None:
    """Refuse a closed mesh made of more than one surface, saying what the surfaces are.

    The surfaces are the face-connected components (``trimesh.Trimesh.split``). A surface lies
    inside another when its sampled vertices have winding number ``|w| > 1/2`` about it
    (:func:`winding_numbers`); a surface inside an odd number of others bounds a cavity, one
    inside an even number (none: the outside) is a body of its own.

    Parameters
    ----------
    mesh : trimesh.Trimesh
        A closed mesh (every edge shared by two faces).
    name : str
        Name used in error messages (e.g. the file name).

    Raises
    ------
    MeshError
        Surfaces passing through each other; more than one separate body (side by side, or one
        inside another's cavity); or one body with an internal cavity.
    """
    labels = trimesh.graph.connected_component_labels(mesh.face_adjacency,
                                                      node_count=len(mesh.faces))
    n_surfaces = int(labels.max()) + 1 if len(labels) else 0
    if n_surfaces <= 1:
        return
    triangles = np.asarray(mesh.triangles)
    faces = np.asarray(mesh.faces)
    vertices = np.asarray(mesh.vertices)
    inside = np.zeros((n_surfaces, n_surfaces), dtype=bool)  # [i, j]: surface i inside surface j
    for i in range(n_surfaces):
        ids = np.unique(faces[labels == i])
        samples = vertices[ids[np.linspace(0, len(ids) - 1, min(len(ids), NESTING_SAMPLES))
                               .astype(np.int64)]]
        for j in range(n_surfaces):
            if i == j:
                continue
            other = triangles[labels == j]
            # a point outside the surface's bounding box is outside it: no solid angles needed
            boxed = ((samples >= other.min(axis=(0, 1))) & (samples <= other.max(axis=(0, 1)))).all(1)
            enclosed = np.zeros(len(samples), dtype=bool)
            if boxed.any():
                enclosed[boxed] = np.abs(winding_numbers(samples[boxed], other)) > 0.5
            if enclosed.any() and not enclosed.all():
                raise MeshError(f"mesh {name!r} has {n_surfaces} closed surfaces that pass through "
                                "each other: merge them into one closed surface (a boolean union) "
                                "before planning.")
            inside[i, j] = enclosed.all()
    depth = inside.sum(axis=1)
    n_bodies = int((depth % 2 == 0).sum())
    if n_bodies > 1:
        raise MeshError(f"mesh {name!r} has {n_bodies} separate bodies: the planner grasps one "
                        "object, so put each body in a file of its own and plan it alone.")
    n_cavities = n_surfaces - n_bodies
    lies = "lies" if n_cavities == 1 else "lie"
    raise MeshError(f"mesh {name!r} has an internal cavity ({n_cavities} of its {n_surfaces} closed "
                    f"surfaces {lies} inside the outer one), whose surface no finger reaches: keep "
                    "only the outer surface in the file (the plan then takes the object as solid).")
