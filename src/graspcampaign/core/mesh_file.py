"""User meshes: reading STL, OBJ and PLY files and validating closed surfaces (SPEC §2.1).

Every mesh leaving :func:`load_mesh` or :func:`check_mesh` is a closed, outward-wound
triangulated surface in metres whose solid's volume centroid (``mesh.center_mass``) sits at the
origin. Every refusal is a :class:`MeshError` whose message is one sentence naming the file and
what is wrong. :mod:`graspcampaign.core.mesh` re-exports the public names.

Shape letters used in this module: ``n`` vertices (nodes), ``f`` faces.
"""

from __future__ import annotations

import logging
import os

import numpy as np
import trimesh

logger = logging.getLogger(__name__)

__all__ = [
    "MeshError",
    "UNITS",
    "MESH_SUFFIXES",
    "MAX_COORDINATE_M",
    "load_mesh",
    "check_mesh",
]

#: Length units accepted by :func:`load_mesh`, as metres per unit.
UNITS = {"m": 1.0, "cm": 1e-2, "mm": 1e-3}
#: File types read by :func:`load_mesh`.
MESH_SUFFIXES = (".stl", ".obj", ".ply")


class MeshError(ValueError):
    """A mesh or shape request that cannot be used; the message says what is wrong."""


def _finish(mesh: trimesh.Trimesh) -> trimesh.Trimesh:
    """Centre a constructed mesh on its volume centroid."""
    # Assign rather than apply_translation: trimesh skips transforms within 1e-8 of identity,
    # and the second pass removes the ~1e-9 m left by the first.
    for _ in range(2):
        mesh.vertices = np.asarray(mesh.vertices) - np.asarray(mesh.center_mass)
    return mesh


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
        Unknown unit, missing or unreadable file, or a mesh that fails :func:`check_mesh`.
    """
    if unit not in UNITS:
        raise MeshError(f"unknown unit {unit!r}: use one of {', '.join(repr(u) for u in UNITS)}")
    name = os.fspath(path)
    base = os.path.basename(name)
    if not os.path.isfile(name):
        raise MeshError(f"mesh file {name!r} does not exist")
    suffix = os.path.splitext(name)[1].lower()
    if suffix not in MESH_SUFFIXES:
        raise MeshError(
            f"mesh file {name!r} has unsupported type {suffix or '(none)'!r}: "
            f"use {', '.join(MESH_SUFFIXES)}"
        )
    n_bytes = os.path.getsize(name)
    if n_bytes == 0:
        raise MeshError(f"mesh {base!r} is empty: the file has 0 bytes")
    if suffix == ".stl":
        _check_stl_layout(name, base, n_bytes)
    try:
        # validate=False, process=False: keep non-finite values, degenerate faces and bad winding
        # so that they are reported here and by check_mesh instead of silently dropped
        with np.errstate(all="ignore"):  # non-finite values are reported below, not warned about
            mesh = trimesh.load(name, force="mesh", process=False, validate=False)
    except Exception as exc:  # trimesh raises many types for unreadable files
        text = str(exc).strip().splitlines()[0] if str(exc).strip() else type(exc).__name__
        raise MeshError(f"mesh {base!r} cannot be read as {suffix[1:].upper()} ({text})") from exc
    if not isinstance(mesh, trimesh.Trimesh) or len(mesh.faces) == 0:
        raise MeshError(f"mesh {base!r} is empty: it has no faces")
    _check_coordinates(np.asarray(mesh.vertices), base, unit, per_triangle=suffix == ".stl")
    mesh.process(validate=False)  # merge the duplicated corners of STL triangle soups
    mesh.apply_scale(UNITS[unit])
    return check_mesh(mesh, base)


#: Largest coordinate accepted from a mesh file [m]: a kilometre is no graspable object, and
#: bounding coordinates keeps areas and volumes (cubes of lengths) far from float overflow.
MAX_COORDINATE_M = 1e3


def _check_stl_layout(name: str, base: str, n_bytes: int) -> None:
    """Tell an STL from other bytes before trimesh guesses (it would try text decodings)."""
    with open(name, "rb") as fh:
        head = fh.read(84)
    if len(head) == 84 and 84 + 50 * int.from_bytes(head[80:84], "little") == n_bytes:
        return  # binary STL: 80-byte header, triangle count, 50 bytes per triangle
    if head.lstrip()[:5].lower() == b"solid":
        try:
            with open(name, encoding="ascii") as fh:
                fh.read()
            return
        except UnicodeDecodeError:
            pass
    raise MeshError(f"mesh {base!r} is not an STL file: {n_bytes} bytes are neither a binary STL "
                    "(84 bytes plus 50 per triangle) nor an ASCII STL (text starting with 'solid')")


def _check_coordinates(vertices: np.ndarray, base: str, unit: str, per_triangle: bool) -> None:
    """Refuse non-finite or absurdly large coordinates, naming the first vertex (or triangle)."""
    def where(i: int) -> str:
        return f"triangle {i // 3 + 1}" if per_triangle else f"vertex {i + 1}"

    finite = np.isfinite(vertices).all(axis=1)
    if not finite.all():
        i = int(np.flatnonzero(~finite)[0])
        raise MeshError(f"mesh {base!r} has a non-finite coordinate at {where(i)} "
                        f"({', '.join(f'{x:g}' for x in vertices[i])}): every coordinate must be a "
                        "finite number")
    limit = MAX_COORDINATE_M / UNITS[unit]
    far = np.abs(vertices).max(axis=1) > limit
    if far.any():
        i = int(np.flatnonzero(far)[0])
        raise MeshError(f"mesh {base!r} has a coordinate of {np.abs(vertices[i]).max():.3g} {unit} "
                        f"at {where(i)}, beyond the {limit:g} {unit} ({MAX_COORDINATE_M:g} m) any "
                        "graspable object fits in; check the file and its unit (--unit)")


def check_mesh(mesh: trimesh.Trimesh, name: str = "mesh", centre: bool = True) -> trimesh.Trimesh:
    """Validate a closed surface mesh and return an outward-wound, centred copy.

    Parameters
    ----------
    mesh : trimesh.Trimesh
        Candidate mesh in metres.
    name : str
        Name used in error messages (e.g. the file name).
    centre : bool
        Translate the result so its volume centroid is at the origin.

    Returns
    -------
    mesh : trimesh.Trimesh
        A copy; winding flipped if it was consistently inward.

    Raises
    ------
    MeshError
        Empty mesh, non-finite coordinates, degenerate (zero-area) faces, open or non-manifold
        edges, inconsistent winding, or zero enclosed volume.
    """
    if len(mesh.faces) == 0 or len(mesh.vertices) == 0:
        raise MeshError(f"mesh {name!r} is empty: it has no faces")
    vertices = np.asarray(mesh.vertices, dtype=float)
    faces = np.asarray(mesh.faces, dtype=np.int64)
    bad_coords = ~np.isfinite(vertices).all(axis=1)
    if bad_coords.any():
        raise MeshError(
            f"mesh {name!r} has non-finite coordinates at {int(bad_coords.sum())} vertices"
        )
    scale = float(np.ptp(vertices, axis=0).max())
    tri = vertices[faces]
    double_area = np.linalg.norm(np.cross(tri[:, 1] - tri[:, 0], tri[:, 2] - tri[:, 0]), axis=1)
    degenerate = double_area <= 1e-12 * max(scale, 1e-300) ** 2
    if degenerate.any():
        raise MeshError(
            f"mesh {name!r} has {int(degenerate.sum())} degenerate (zero-area) faces"
        )
    edges = np.sort(mesh.edges, axis=1)
    _, counts = np.unique(edges, axis=0, return_counts=True)
    n_boundary = int((counts == 1).sum())
    n_nonmanifold = int((counts > 2).sum())
    if n_boundary:
        raise MeshError(f"mesh {name!r} is not watertight: {n_boundary} boundary edges")
    if n_nonmanifold:
        raise MeshError(
            f"mesh {name!r} is not watertight: {n_nonmanifold} non-manifold edges "
            "(shared by more than two faces)"
        )
    # On a closed manifold every undirected edge is used twice; consistent winding traverses it
    # once in each direction, so a repeated *directed* edge marks a flipped neighbour.
    n_directed = len(np.unique(mesh.edges, axis=0))
    n_inconsistent = len(mesh.edges) - n_directed
    if n_inconsistent:
        raise MeshError(
            f"mesh {name!r} is inconsistently wound: {n_inconsistent} edges are traversed in the "
            "same direction by both of their faces"
        )
    out = mesh.copy()
    volume = out.volume
    if abs(volume) <= 1e-12 * scale**3:
        raise MeshError(f"mesh {name!r} encloses no volume")
    if volume < 0.0:
        logger.info("mesh %r was wound inward; inverted to outward winding", name)
        out.invert()
    if centre:
        out = _finish(out)
    return out
