"""The sphere-face collision cases (§3.2) and penetration subcases (§3.3), and the closest point of a
triangle to a point with its barycentric coordinates and subcase.

:func:`closest_point_barycentric` implements Ericson's Voronoi-region tests; the tests check it
against trimesh. The case and subcase definitions are in the docstring of
:mod:`graspcampaign.core.geometry`.

Shape letters: ``m`` points.

References
----------
Ericson, C. (2005). Real-Time Collision Detection, §5.1.5 "Closest point on triangle to point".
Morgan Kaufmann. Symbols ``ab, ac, ap, d1..d6, va, vb, vc`` follow the book.
Paper §3.2-3.3.
"""

from __future__ import annotations

from enum import IntEnum

import numpy as np

__all__ = [
    "CollisionCase",
    "PenetrationSubcase",
    "closest_point_barycentric",
]


class CollisionCase(IntEnum):
    """Sphere-face collision cases of §3.2 (value = the paper's case number)."""

    NONE = 1
    EDGE = 2
    CORNER = 3
    FULL = 4


class PenetrationSubcase(IntEnum):
    """Placement of the face reference point of Eq. 11 (§3.3 subcases i-iii)."""

    INSIDE = 1
    EDGE = 2
    CORNER = 3


def closest_point_barycentric(points: np.ndarray,
                              triangles: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """Return the closest point of each triangle to each point, as barycentric weights.

    Parameters
    ----------
    points : (m, 3) float
        Query points [m].
    triangles : (m, 3, 3) float
        One triangle (A, B, C) per query point [m].

    Returns
    -------
    weights : (m, 3) float
        Barycentric weights (u, v, w) of the closest point ``u A + v B + w C``; non-negative,
        summing to one.
    subcases : (m,) int8
        :class:`PenetrationSubcase` of the point's projection: face interior, edge or corner
        (vertex) Voronoi region.

    References
    ----------
    Ericson (2005), Real-Time Collision Detection, §5.1.5 (ClosestPtPointTriangle), vectorised:
    all region tests are evaluated for every point and the first matching region in Ericson's
    order (A, B, AB, C, AC, BC, face) is selected.
    """
    points = np.asarray(points, dtype=float)
    triangles = np.asarray(triangles, dtype=float)
    a = triangles[:, 0]
    edges = triangles[:, 1:] - a[:, None, :]  # rows ab, ac
    rel = points[:, None, :] - triangles  # rows ap, bp, cp
    d = np.einsum("mie,mje->mij", edges, rel)  # d[:, 0] = ab.(ap, bp, cp); d[:, 1] = ac.(...)
    d1, d3, d5 = d[:, 0, 0], d[:, 0, 1], d[:, 0, 2]
    d2, d4, d6 = d[:, 1, 0], d[:, 1, 1], d[:, 1, 2]
    va = d3 * d6 - d5 * d4
    vb = d5 * d2 - d1 * d6
    vc = d1 * d4 - d3 * d2

    in_a = (d1 <= 0.0) & (d2 <= 0.0)
    in_b = (d3 >= 0.0) & (d4 <= d3)
    on_ab = (vc <= 0.0) & (d1 >= 0.0) & (d3 <= 0.0)
    in_c = (d6 >= 0.0) & (d5 <= d6)
    on_ac = (vb <= 0.0) & (d2 >= 0.0) & (d6 <= 0.0)
    on_bc = (va <= 0.0) & (d4 - d3 >= 0.0) & (d5 - d6 >= 0.0)

    with np.errstate(divide="ignore", invalid="ignore"):
        t_ab = d1 / (d1 - d3)
        t_ac = d2 / (d2 - d6)
        t_bc = (d4 - d3) / ((d4 - d3) + (d5 - d6))
        denom = va + vb + vc
        v_face = vb / denom
        w_face = vc / denom
        u_face = va / denom
    conditions = [in_a, in_b, on_ab, in_c, on_ac, on_bc]
    u = np.select(conditions, [1.0, 0.0, 1.0 - t_ab, 0.0, 1.0 - t_ac, 0.0], u_face)
    v = np.select(conditions, [0.0, 1.0, t_ab, 0.0, 0.0, 1.0 - t_bc], v_face)
    w = np.select(conditions, [0.0, 0.0, 0.0, 1.0, t_ac, t_bc], w_face)
    weights = np.column_stack([u, v, w])
    subcases = np.select(
        [in_a | in_b | in_c, on_ab | on_ac | on_bc],
        [np.int8(PenetrationSubcase.CORNER), np.int8(PenetrationSubcase.EDGE)],
        np.int8(PenetrationSubcase.INSIDE),
    ).astype(np.int8)
    return weights, subcases
