"""Barycentric interpolation of vertex velocities to a contact point (Eq. 12) and its transpose, the
transfer of a contact force to the face's vertices (Eq. 17-18).

Shape letters: ``m`` points.

References
----------
Paper Eq. 12, 17-18 (§3.4, §3.6).
"""

from __future__ import annotations

import numpy as np

__all__ = [
    "barycentric_weights",
    "point_velocity",
    "transfer_force",
]


def barycentric_weights(points: np.ndarray, triangles: np.ndarray) -> np.ndarray:
    """Return the area weights of Eq. 12 of points in their triangles.

    Parameters
    ----------
    points : (m, 3) float
        Points in (or projected onto) the plane of their triangle [m].
    triangles : (m, 3, 3) float
        Vertices N1, N2, N3 of each host triangle [m].

    Returns
    -------
    weights : (m, 3) float
        ``A_i / A_G`` with ``A_i`` the area of the sub-triangle formed by the point and the two
        vertices other than ``N_i`` (Fig. 5). Areas are signed (measured along the face normal), so
        the rows sum to one exactly and a point outside the triangle gets a negative weight.

    References
    ----------
    Paper Eq. 12, Fig. 5.
    """
    points = np.asarray(points, dtype=float)
    triangles = np.asarray(triangles, dtype=float)
    normal = np.cross(triangles[:, 1] - triangles[:, 0], triangles[:, 2] - triangles[:, 0])
    rel = triangles - points[:, None, :]  # N_i - P
    # Twice the signed area opposite N_i: ((N_j - P) x (N_k - P)) . n for (i, j, k) cyclic.
    sub = np.cross(rel[:, [1, 2, 0]], rel[:, [2, 0, 1]])
    areas = np.einsum("mij,mj->mi", sub, normal)
    return areas / np.einsum("ij,ij->i", normal, normal)[:, None]


def point_velocity(weights: np.ndarray, vertex_velocities: np.ndarray) -> np.ndarray:
    """Interpolate the velocity of the face contact point from its vertices (Eq. 12).

    Parameters
    ----------
    weights : (m, 3) float
        Barycentric weights of the contact points.
    vertex_velocities : (m, 3, 3) float
        Velocities of N1, N2, N3 of each host face [m/s].

    Returns
    -------
    velocities : (m, 3) float
        ``sum_i (A_i / A_G) V_Ni`` [m/s].
    """
    return np.einsum("mi,mij->mj", weights, vertex_velocities)


def transfer_force(weights: np.ndarray, forces: np.ndarray) -> np.ndarray:
    """Distribute contact forces to the three face vertices, ``f_l = Phi^T f_p`` (Eq. 17-18).

    Parameters
    ----------
    weights : (m, 3) float
        Barycentric weights of the contact points (the blocks of ``Phi``).
    forces : (m, 3) float
        Contact force at each point [N].

    Returns
    -------
    nodal_forces : (m, 3, 3) float
        Force on N1, N2, N3 of each face [N]. They sum to the contact force, and their moment
        about the contact point is zero (the contact force's own moment there), because the
        weights sum to one and reproduce the point.

    References
    ----------
    Paper Eq. 17-18.
    """
    return np.asarray(weights, dtype=float)[:, :, None] * np.asarray(forces, dtype=float)[:, None, :]
