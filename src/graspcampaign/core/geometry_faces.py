"""Per-face geometry of a triangulated surface: packed face quantities and local face frames (§3.2).

Local frame (§3.2). For a face (A, B, C) wound counter-clockwise seen from outside, take
``b = (A - B)/|A - B|``, ``c`` the *outward* unit normal and ``d = c x b``; ``R = [b, d, c]^T`` and
the origin B map world to local coordinates (:func:`face_frames`). The sphere-triangle query of
:mod:`graspcampaign.core.geometry` evaluates the same local coordinates as dot products with the
per-face unit vectors stored once in :class:`FaceGeometry` (no 4x4 matrix per pair).

Shape letters: ``f`` faces.

References
----------
Paper §3.2.
"""

from __future__ import annotations

from dataclasses import dataclass
from functools import cached_property

import numpy as np

from graspcampaign.core import kernels

__all__ = [
    "COL_DOUBLE_AREA",
    "COL_EDGE",
    "COL_EDGE_NORMAL",
    "COL_EDGE_SQ",
    "COL_NORMAL",
    "COL_TRI",
    "NEXT_VERTEX",
    "FaceGeometry",
    "face_frames",
    "face_geometry",
    "pack_faces",
    "soup_faces",
    "vecdot",
]


NEXT_VERTEX = np.array([1, 2, 0])


def _einsum_dot(a: np.ndarray, b: np.ndarray, axis: int = -1) -> np.ndarray:
    return np.sum(a * b, axis=axis)


# Dot product over one axis with broadcasting: the numpy >= 2.0 gufunc is about twice as fast as
# einsum on the small batches of the narrow phase.
vecdot = getattr(np, "vecdot", _einsum_dot)


def _cross(a: np.ndarray, b: np.ndarray) -> np.ndarray:
    """Cross product over the last axis (broadcasting); cheaper than ``np.cross`` on our sizes."""
    a0, a1, a2 = a[..., 0], a[..., 1], a[..., 2]
    b0, b1, b2 = b[..., 0], b[..., 1], b[..., 2]
    out = np.empty(np.broadcast_shapes(a.shape, b.shape))
    out[..., 0] = a1 * b2 - a2 * b1
    out[..., 1] = a2 * b0 - a0 * b2
    out[..., 2] = a0 * b1 - a1 * b0
    return out


_TINY = np.finfo(float).tiny


# Column layout of FaceGeometry.packed: one gather brings every per-face quantity of a candidate.
COL_TRI = slice(0, 9)  # A, B, C
COL_EDGE = slice(9, 18)  # AB, BC, CA
COL_EDGE_NORMAL = slice(18, 27)  # unit in-plane normals of AB, BC, CA pointing into the face
COL_NORMAL = slice(27, 30)  # outward unit face normal
COL_EDGE_SQ = slice(30, 33)  # |AB|^2, |BC|^2, |CA|^2
COL_DOUBLE_AREA = 33  # |AB x AC|
_N_COLS = 34


@dataclass(frozen=True)
class FaceGeometry:
    """Per-face data of the collision test (§3.2) for one mesh state; build it with
    :func:`face_geometry` and reuse it while the mesh does not move.

    Attributes
    ----------
    triangles : (f, 3, 3) float
        Face vertices (A, B, C), C-contiguous [m].
    centers : (f, 3) float
        Face centroids, centres of the broad-phase bounding spheres [m].
    radii : (f,) float
        Largest centroid-to-vertex distance per face [m].
    """

    triangles: np.ndarray
    centers: np.ndarray
    radii: np.ndarray

    @property
    def vertices(self) -> np.ndarray:
        """(3 f, 3) the triangle soup as the vertex array of an indexed mesh (a view) [m]."""
        return self.triangles.reshape(-1, 3)

    @cached_property
    def faces(self) -> np.ndarray:
        """(f, 3) int64 indices into :attr:`vertices`, ``arange(3 f).reshape(f, 3)``."""
        return soup_faces(len(self.triangles))

    @cached_property
    def packed(self) -> np.ndarray:
        """(f, 34) rows of the numpy path, built on first use (layout ``COL_*``).

        Row-wise: vertices A, B, C; edges AB, BC, CA; the unit in-plane edge normals (pointing into
        the face, ``n x edge / |edge|``); the outward unit normal ``n``; squared edge lengths; twice
        the face area. Degenerate (zero-area) faces hold NaN in every derived column and never
        collide.
        """
        return pack_faces(self.triangles)


def pack_faces(triangles: np.ndarray) -> np.ndarray:
    """Per-face rows of the local-frame test, layout ``COL_*`` (see FaceGeometry.packed)."""
    n_faces = len(triangles)
    edges = triangles[:, NEXT_VERTEX] - triangles
    raw_normal = _cross(edges[:, 0], -edges[:, 2])
    double_area = np.sqrt(vecdot(raw_normal, raw_normal))
    edge_sq = vecdot(edges, edges)
    # Degenerate (zero-area) faces get NaN normals, edge normals and edge lengths: every distance
    # computed from them is NaN, and NaN < r^2 is false, so they never collide.
    degenerate = double_area <= 0.0
    if degenerate.any():
        double_area = np.where(degenerate, np.nan, double_area)
        edge_sq = np.where(degenerate[:, None], np.nan, edge_sq)
    edge_sq = np.maximum(edge_sq, _TINY)
    normals = raw_normal / double_area[:, None]
    packed = np.empty((n_faces, _N_COLS))
    packed[:, COL_TRI] = triangles.reshape(n_faces, 9)
    packed[:, COL_EDGE] = edges.reshape(n_faces, 9)
    # n x e_i / |e_i| is the in-plane normal of edge i pointing into a counter-clockwise face.
    edge_normals = _cross(normals[:, None, :], edges) / np.sqrt(edge_sq)[:, :, None]
    packed[:, COL_EDGE_NORMAL] = edge_normals.reshape(n_faces, 9)
    packed[:, COL_NORMAL] = normals
    packed[:, COL_EDGE_SQ] = edge_sq
    packed[:, COL_DOUBLE_AREA] = double_area
    return packed


def face_geometry(triangles: np.ndarray) -> FaceGeometry:
    """Precompute the per-face data used by :func:`sphere_triangle_contacts`.

    Parameters
    ----------
    triangles : (f, 3, 3) float
        Face vertices (A, B, C), counter-clockwise seen from outside [m].

    Returns
    -------
    geometry : FaceGeometry
        Reuse it for every query while the mesh does not move; recompute after it deforms.
    """
    triangles = np.ascontiguousarray(triangles, dtype=float)
    centers, radii = kernels.face_bounds(triangles.reshape(-1, 3), soup_faces(len(triangles)))
    return FaceGeometry(triangles=triangles, centers=centers, radii=radii)


def soup_faces(n_faces: int) -> np.ndarray:
    """Index array ``arange(3 f).reshape(f, 3)`` that makes a triangle soup an indexed mesh."""
    return np.arange(3 * n_faces, dtype=np.int64).reshape(n_faces, 3)


def face_frames(triangles: np.ndarray) -> np.ndarray:
    """Return the world-to-local homogeneous transforms of §3.2, one per face.

    Parameters
    ----------
    triangles : (f, 3, 3) float
        Vertices (A, B, C) of each face, counter-clockwise seen from outside [m].

    Returns
    -------
    transforms : (f, 4, 4) float
        ``DH`` with rotation ``R = [b, d, c]^T`` (``b`` along BA, ``c`` the outward unit normal,
        ``d = c x b``) and translation ``-R B``: local = DH @ [world, 1]. The face lies in
        ``z' = 0`` and outside the object ``z' > 0``.

    References
    ----------
    Paper §3.2 (we orient ``c`` outward so that a fingertip outside the object has ``z0' > 0``).
    """
    triangles = np.asarray(triangles, dtype=float)
    a, b, c = triangles[:, 0], triangles[:, 1], triangles[:, 2]
    b_hat = a - b
    b_hat /= np.linalg.norm(b_hat, axis=1)[:, None]
    c_hat = np.cross(b - a, c - a)
    c_hat /= np.linalg.norm(c_hat, axis=1)[:, None]
    d_hat = np.cross(c_hat, b_hat)
    rotation = np.stack([b_hat, d_hat, c_hat], axis=1)
    transforms = np.zeros((len(triangles), 4, 4))
    transforms[:, :3, :3] = rotation
    transforms[:, :3, 3] = -np.einsum("fij,fj->fi", rotation, b)
    transforms[:, 3, 3] = 1.0
    return transforms
