"""Sphere-triangle contact geometry (paper §3.2-3.4, §3.6; SPEC §2.4).

The fingertip is a sphere of radius ``r`` (5 mm); the object is a triangulated surface. For every
(fingertip, face) pair this module decides whether they collide and which of the four collision
cases of §3.2 applies, places the reference points of the penetration depth (Eq. 11) with the three
subcases of §3.3, and provides the barycentric interpolation of vertex velocities (Eq. 12) and its
transpose, the force transfer to the vertices (Eq. 17-18).

Shape letters: ``p`` fingertips, ``f`` faces, ``k`` colliding (fingertip, face) pairs, ``m`` points.

This module holds the sphere-triangle query and re-exports the public names of its siblings, so
``from graspcampaign.core.geometry import ...`` keeps working: :mod:`~graspcampaign.core.geometry_faces`
(:class:`FaceGeometry`, :func:`face_frames`), :mod:`~graspcampaign.core.geometry_cases` (the cases,
subcases and :func:`closest_point_barycentric`) and :mod:`~graspcampaign.core.geometry_transfer`
(Eq. 12 and Eq. 17-18).

Local frame (§3.2). For a face (A, B, C) wound counter-clockwise seen from outside, take
``b = (A - B)/|A - B|``, ``c`` the *outward* unit normal and ``d = c x b``; ``R = [b, d, c]^T`` and
the origin B map world to local coordinates (:func:`face_frames`). The fingertip centre becomes
``(x0', y0', z0')`` and the sphere cuts the plane ``z' = 0`` in the disc of Eq. 10, of radius
``rho = sqrt(r^2 - z0'^2)`` when ``|z0'| < r``. The code evaluates the same local coordinates as dot
products with per-face unit vectors stored once (:class:`FaceGeometry`, no 4x4 matrix per pair):
``z0'`` is the signed height of the centre above the face plane and ``s_i`` the signed perpendicular
distances of the disc centre to the three edge lines, the "per-edge perpendicular distances" with
which §3.2 decides each case. The resulting partition of the plane is the Voronoi-region partition
of Ericson (2005); :func:`closest_point_barycentric` implements Ericson's own tests and the tests
check both against trimesh.

Collision cases (§3.2), :class:`CollisionCase`; the integer value is the paper's case number:

1. ``NONE``   the disc misses the triangle (closest distance from the centre to the face >= r);
2. ``EDGE``   the disc clips a triangle edge: the disc overlaps the face, is not contained in it, and
   its centre is not in a corner region;
3. ``CORNER`` the disc centre lies in a corner (vertex Voronoi) region: contact at that vertex;
4. ``FULL``   the disc lies entirely inside the triangle.

Penetration subcases (§3.3), :class:`PenetrationSubcase`: where the projection of the centre falls
(``INSIDE`` the triangle, in an ``EDGE`` region, in a ``CORNER`` region). The face reference point
``P_face`` is respectively the projection itself, its projection onto the nearest edge segment, or
the vertex: in every subcase the closest point of the triangle to the centre. The finger reference
point ``P_finger`` is on the sphere surface on the line through ``P_face`` along the face normal
(Fig. 4), so that

    delta_max = |P_face - P_finger| = sqrt(r^2 - e^2) - z0'          (Eq. 11)

with ``e`` the in-plane distance from the projection of the centre to ``P_face`` (zero in the INSIDE
subcase, where ``delta_max = r - z0'``). We also return the closest-point overlap
``r - |centre - P_face|`` (the minimum translation that separates sphere and triangle). Both are
positive exactly when the sphere and the triangle overlap.

References
----------
Ericson, C. (2005). Real-Time Collision Detection, §5.1.5 "Closest point on triangle to point".
Morgan Kaufmann. Symbols ``ab, ac, ap, d1..d6, va, vb, vc`` follow the book.
Paper Eq. 10-12, 17-18.
"""

from __future__ import annotations

from dataclasses import dataclass, fields

import numpy as np
from scipy.spatial.distance import cdist

from graspcampaign.core import kernels
from graspcampaign.core.geometry_cases import (
    CollisionCase,
    PenetrationSubcase,
    closest_point_barycentric,
)
from graspcampaign.core.geometry_faces import (
    COL_DOUBLE_AREA,
    COL_EDGE,
    COL_EDGE_NORMAL,
    COL_EDGE_SQ,
    COL_NORMAL,
    COL_TRI,
    NEXT_VERTEX,
    FaceGeometry,
    face_frames,
    face_geometry,
    pack_faces,
    soup_faces,
    vecdot,
)
from graspcampaign.core.geometry_transfer import (
    barycentric_weights,
    point_velocity,
    transfer_force,
)

__all__ = [
    # sphere-triangle collision (this module)
    "SphereTriangleResult",
    "sphere_triangle_contacts",
    "sphere_mesh_contacts",
    "deepest_per_finger",
    # re-exported: they live in graspcampaign.core.geometry_faces
    "FaceGeometry",
    "face_geometry",
    "face_frames",
    # re-exported: they live in graspcampaign.core.geometry_cases
    "CollisionCase",
    "PenetrationSubcase",
    "closest_point_barycentric",
    # re-exported: they live in graspcampaign.core.geometry_transfer
    "barycentric_weights",
    "point_velocity",
    "transfer_force",
]


# Region key of a colliding pair, shared by both backends: 0 outside the face in an edge region,
# 1 outside in a corner region, 2 inside with the disc crossing an edge line, 3 inside with the
# disc within all edge lines. The tables give its penetration subcase and collision case.
_SUBCASE_OF_KEY = np.array([PenetrationSubcase.EDGE, PenetrationSubcase.CORNER,
                            PenetrationSubcase.INSIDE, PenetrationSubcase.INSIDE], dtype=np.int8)
_CASE_OF_KEY = np.array([CollisionCase.EDGE, CollisionCase.CORNER, CollisionCase.EDGE,
                         CollisionCase.FULL], dtype=np.int8)


@dataclass(frozen=True)
class SphereTriangleResult:
    """Colliding (fingertip, face) pairs, one row per pair (cases 2-4 of §3.2).

    Attributes
    ----------
    fingers : (k,) int
        Fingertip index into ``centers``.
    faces : (k,) int
        Face index into ``triangles``.
    cases : (k,) int8
        :class:`CollisionCase` (2 EDGE, 3 CORNER, 4 FULL; NONE pairs are not listed).
    subcases : (k,) int8
        :class:`PenetrationSubcase` of the face reference point (§3.3).
    depths : (k,) float
        Penetration depth ``delta_max`` of Eq. 11, measured along the face normal [m].
    overlaps : (k,) float
        Closest-point overlap ``r - |centre - P_face|`` [m].
    distances : (k,) float
        Distance from the fingertip centre to the face, ``|centre - P_face|`` [m].
    heights : (k,) float
        Signed height ``z0'`` of the centre above the face plane, positive outside [m].
    points : (k, 3) float
        Contact point on the face, ``P_face`` of Eq. 11 [m].
    finger_points : (k, 3) float
        ``P_finger`` of Eq. 11: on the sphere surface, ``P_face - depths * normals`` [m].
    normals : (k, 3) float
        Contact normal: the outward unit face normal ``n_f`` (force on the object is along
        ``-n_f``).
    weights : (k, 3) float
        Barycentric weights of ``points`` in the face (Eq. 12); rows sum to one.
    n_fingers : int
        Number of fingertips queried (``p``).
    radius : float
        Fingertip radius [m].
    """

    fingers: np.ndarray
    faces: np.ndarray
    cases: np.ndarray
    subcases: np.ndarray
    depths: np.ndarray
    overlaps: np.ndarray
    distances: np.ndarray
    heights: np.ndarray
    points: np.ndarray
    finger_points: np.ndarray
    normals: np.ndarray
    weights: np.ndarray
    n_fingers: int
    radius: float

    def __len__(self) -> int:
        return len(self.fingers)

    @property
    def face_points(self) -> np.ndarray:
        """``P_face`` of Eq. 11, the same array as ``points``."""
        return self.points

    def take(self, indices: np.ndarray) -> SphereTriangleResult:
        """Return the pairs at ``indices`` (an int or bool index over the k pairs)."""
        arrays = {
            f.name: getattr(self, f.name)[indices]
            for f in fields(self)
            if f.name not in ("n_fingers", "radius")
        }
        return SphereTriangleResult(**arrays, n_fingers=self.n_fingers, radius=self.radius)


def sphere_triangle_contacts(centers: np.ndarray, radius: float, triangles: np.ndarray,
                             geometry: FaceGeometry | None = None, *,
                             backend: str = "numba") -> SphereTriangleResult:
    """Find every colliding (fingertip, face) pair and its contact geometry (§3.2-3.3).

    Parameters
    ----------
    centers : (p, 3) float
        Fingertip sphere centres [m].
    radius : float
        Fingertip radius [m].
    triangles : (f, 3, 3) float
        Face vertices, counter-clockwise seen from outside (trimesh's ``mesh.triangles``) [m].
        Ignored when ``geometry`` is given.
    geometry : FaceGeometry, optional
        Precomputed :func:`face_geometry` of ``triangles``; reuse it while the mesh is undeformed.
    backend : {"numba", "numpy"}
        ``"numba"`` (default) runs the compiled kernel of :mod:`graspcampaign.core.kernels`, one
        pair at a time; ``"numpy"`` the vectorised reference described below. Both return the
        same pairs with the same values (to rounding); tests hold them to each other and to
        trimesh.

    Returns
    -------
    result : SphereTriangleResult
        Colliding pairs ordered by fingertip, then face.

    Notes
    -----
    Broad phase: a face is a candidate for a fingertip when the fingertip overlaps the face's
    bounding sphere (precomputed ``geometry``; on raw ``triangles`` the compiled path computes the
    centroid spheres on the fly, the numpy path the spheres of the axis-aligned boxes). Only
    candidates reach the narrow phase, so its cost depends on the number of nearby faces, not on
    the face count.

    Narrow phase, on the k candidates (all at once in the numpy path), in the face's local frame
    (§3.2): the signed height ``z0' = (P - A) . n`` and the signed perpendicular distances ``s_i =
    (P - V_i) . m_i`` of the disc centre to the three edge lines (``m_i`` the in-plane inward edge
    normals). The projection is inside the triangle iff all ``s_i >= 0`` (subcase i, ``P_face`` the
    projection); the disc of Eq. 10 lies inside iff additionally ``rho = sqrt(r^2 - z0'^2) <= min
    s_i`` (case iv). Otherwise ``P_face`` is the nearest of the three projections of the centre onto
    the edge segments, a vertex when the projection is clamped to a segment end (corner region,
    subcase iii, case iii) and an edge point otherwise (subcase ii, case ii). This is the
    Voronoi-region partition of Ericson (2005), checked against :func:`closest_point_barycentric`
    and trimesh.

    References
    ----------
    Paper §3.2 (four cases), §3.3 and Eq. 11 (depth), Eq. 10 (the disc); Ericson (2005) §5.1.5.
    """
    centers = np.ascontiguousarray(centers, dtype=float).reshape(-1, 3)
    if backend == "numpy":
        return _contacts_numpy(centers, float(radius), triangles, geometry)
    if backend != "numba":
        raise ValueError(f"backend must be 'numba' or 'numpy', got {backend!r}")
    if geometry is None:
        triangles = np.ascontiguousarray(triangles, dtype=float)
        return sphere_mesh_contacts(centers, radius, triangles.reshape(-1, 3),
                                    soup_faces(len(triangles)))
    found = kernels.sphere_faces(centers, float(radius), geometry.vertices, geometry.faces,
                                 geometry.centers, geometry.radii)
    return _from_kernel(found, len(centers), float(radius))


def sphere_mesh_contacts(centers: np.ndarray, radius: float, vertices: np.ndarray,
                         faces: np.ndarray) -> SphereTriangleResult:
    """Collide spheres with an indexed (possibly deforming) mesh; compiled path.

    The same as ``sphere_triangle_contacts(centers, radius, vertices[faces])`` without forming the
    triangle soup: face bounding spheres (centroid, farthest vertex) are computed from the current
    vertices, then the kernel runs the broad and narrow phases. ``faces`` in the result index the
    rows of ``faces``.

    Parameters
    ----------
    centers : (p, 3) float
        Sphere centres [m].
    radius : float
        Sphere radius [m].
    vertices : (n, 3) float
        Current vertex positions [m].
    faces : (f, 3) int
        Vertex indices, counter-clockwise seen from outside.

    Returns
    -------
    result : SphereTriangleResult
    """
    centers = np.ascontiguousarray(centers, dtype=float).reshape(-1, 3)
    vertices = np.ascontiguousarray(vertices, dtype=float)
    faces = np.ascontiguousarray(faces, dtype=np.int64)
    bound_centers, bound_radii = kernels.face_bounds(vertices, faces)
    found = kernels.sphere_faces(centers, float(radius), vertices, faces, bound_centers, bound_radii)
    return _from_kernel(found, len(centers), float(radius))


def _from_kernel(found, n_fingers: int, radius: float) -> SphereTriangleResult:
    """Wrap the arrays of ``kernels.sphere_faces`` (first ``count`` rows) as a result."""
    count, pairs, keys, scalars, vectors = found
    keys = keys[:count]
    return SphereTriangleResult(
        fingers=pairs[:count, 0],
        faces=pairs[:count, 1],
        cases=_CASE_OF_KEY[keys],
        subcases=_SUBCASE_OF_KEY[keys],
        depths=scalars[:count, 0],
        overlaps=scalars[:count, 3],
        distances=scalars[:count, 1],
        heights=scalars[:count, 2],
        points=vectors[:count, 0],
        finger_points=vectors[:count, 1],
        normals=vectors[:count, 2],
        weights=vectors[:count, 3],
        n_fingers=n_fingers,
        radius=radius,
    )


def _contacts_numpy(centers: np.ndarray, radius: float, triangles: np.ndarray,
                    geometry: FaceGeometry | None) -> SphereTriangleResult:
    """The vectorised reference path of :func:`sphere_triangle_contacts` (see its Notes)."""
    r_sq = radius * radius
    if geometry is None:
        # Broad phase on the raw soup: bounding spheres of the faces' axis-aligned boxes (cheap to
        # form for a deforming mesh); then pack the local-frame data of the candidates only.
        triangles = np.asarray(triangles, dtype=float)
        a, b, c = triangles[:, 0], triangles[:, 1], triangles[:, 2]
        lo = np.minimum(np.minimum(a, b), c)
        hi = np.maximum(np.maximum(a, b), c)
        half = 0.5 * (hi - lo)
        reach = radius + np.sqrt(vecdot(half, half))
        flat = np.flatnonzero(cdist(centers, lo + half) < reach)
        fingers, faces = np.divmod(flat, len(triangles))
        data = pack_faces(triangles[faces])
    else:
        # Broad phase on precomputed bounding spheres, then one gather of the packed rows.
        flat = np.flatnonzero(cdist(centers, geometry.centers) < radius + geometry.radii)
        fingers, faces = np.divmod(flat, len(geometry.radii))
        data = geometry.packed[faces]

    # Narrow phase on the k candidates, in each face's local frame.
    k = len(faces)
    tri = data[:, COL_TRI].reshape(k, 3, 3)
    edges = data[:, COL_EDGE].reshape(k, 3, 3)
    p = centers[fingers]
    rel = p[:, None, :] - tri  # P - A, P - B, P - C
    heights = vecdot(rel[:, 0], data[:, COL_NORMAL])  # z0'
    perp = vecdot(rel, data[:, COL_EDGE_NORMAL].reshape(k, 3, 3))  # s_i
    along = vecdot(rel, edges)  # (P - V_i) . e_i
    t = np.minimum(np.maximum(along / data[:, COL_EDGE_SQ], 0.0), 1.0)
    offsets = rel - t[:, :, None] * edges  # P minus its clamped projection on edge i
    offset_sq = vecdot(offsets, offsets)
    inside = perp.min(axis=1) >= 0.0
    dist_sq = np.where(inside, heights * heights, offset_sq.min(axis=1))
    hit = np.flatnonzero(dist_sq < r_sq)  # NaN rows of degenerate faces never hit

    data, fingers, faces, tri = data[hit], fingers[hit], faces[hit], tri[hit]
    heights, perp, dist_sq, inside = heights[hit], perp[hit], dist_sq[hit], inside[hit]
    nearest_edge = offset_sq[hit].argmin(axis=1)
    rows = np.arange(len(hit))
    t_edge = t[hit, nearest_edge]

    # Barycentric weights of P_face: inside, the weight of the vertex opposite edge i is
    # s_i |e_i| / (2 area); on edge i = (V_i, V_i+1) at parameter t, (1 - t, t).
    double_area = data[:, COL_DOUBLE_AREA]
    weights = np.zeros((len(hit), 3))
    weights[rows, nearest_edge] = 1.0 - t_edge
    weights[rows, NEXT_VERTEX[nearest_edge]] = t_edge
    inside_weights = perp * np.sqrt(data[:, COL_EDGE_SQ]) / double_area[:, None]
    weights = np.where(inside[:, None], inside_weights[:, NEXT_VERTEX], weights)
    # Key 0: outside, edge region; 1: outside, corner region; 2: inside, disc crosses an edge
    # line; 3: inside, disc within all edge lines. Look-up tables give the subcase and case.
    corner = (t_edge <= 0.0) | (t_edge >= 1.0)
    full = r_sq - heights * heights <= np.square(perp.min(axis=1))
    key = 2 * inside + np.where(inside, full, corner)
    subcases = _SUBCASE_OF_KEY[key]
    cases = _CASE_OF_KEY[key]

    q = vecdot(weights[:, :, None], tri, axis=1)
    normals = data[:, COL_NORMAL]
    depths = np.sqrt(r_sq - np.maximum(dist_sq - heights * heights, 0.0)) - heights
    distances = np.sqrt(dist_sq)
    return SphereTriangleResult(
        fingers=fingers,
        faces=faces,
        cases=cases,
        subcases=subcases,
        depths=depths,
        overlaps=radius - distances,
        distances=distances,
        heights=heights,
        points=q,
        finger_points=q - depths[:, None] * normals,
        normals=normals,
        weights=weights,
        n_fingers=len(centers),
        radius=radius,
    )


def deepest_per_finger(result: SphereTriangleResult) -> np.ndarray:
    """Return, per fingertip, the index of its deepest colliding pair.

    Parameters
    ----------
    result : SphereTriangleResult

    Returns
    -------
    indices : (p,) int
        Index into the k pairs of ``result`` (largest ``depths``; ties to the lower face index),
        or -1 for a fingertip with no contact. ``result.take(indices[indices >= 0])`` gives one
        contact per touching fingertip, as the simulator uses.
    """
    indices = np.full(result.n_fingers, -1, dtype=np.int64)
    if len(result) == 0:
        return indices
    order = np.lexsort((result.faces, -result.depths, result.fingers))
    sorted_fingers = result.fingers[order]
    first = np.r_[True, sorted_fingers[1:] != sorted_fingers[:-1]]
    indices[sorted_fingers[first]] = order[first]
    return indices


