"""The simulated hand: planned fingertip contacts and the straight approach lines of the fingers.

SynGrasp is not available in Python and is not imitated (SPEC §2.6): each fingertip is a sphere
whose centre moves on the straight line through its planned contact point along the outward normal
there. Planned contacts come either from the hand-reachable family of §5.2 (rays from the centroid
along :func:`hand_contact_directions`, hitting the mesh: :func:`planned_contacts`) or from any
planner (points and outward normals given directly, e.g. the vertex triples of the quasi-static
studies). :func:`finger_contacts` collides the fingertip spheres with the deformed mesh and keeps
one contact per finger, its deepest face.

Shape letters: ``c`` contacts (fingers), ``f`` faces.

References
----------
§5.1 (three fingers, two coplanar, the third 120 deg behind), §5.2 and Fig. 8 (the reachable
optimum 45/45/-90), §6.1. Moller, T. & Trumbore, B. (1997), "Fast, minimum storage ray-triangle
intersection", Journal of Graphics Tools 2(1):21-28.
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import TYPE_CHECKING

import numpy as np
import trimesh

from graspcampaign.core import geometry

if TYPE_CHECKING:
    from graspcampaign.core.msd import MsdBody

__all__ = ["FingerContacts", "finger_contacts", "hand_contact_directions", "planned_contacts"]


def hand_contact_directions(
    elevation_deg: float = 45.0,
    third_elevation_deg: float = -90.0,
    azimuth_deg: float = 0.0,
    third_azimuth_deg: float = 90.0,
) -> np.ndarray:
    """Return the three contact directions (from the centroid) of the hand-reachable family.

    Parameters
    ----------
    elevation_deg : float
        Elevation of the two coplanar fingers above the equatorial plane [deg].
    third_elevation_deg : float
        Elevation of the third finger [deg] (-90: the bottom pole).
    azimuth_deg : float
        Azimuth of the plane of fingers 1-2 [deg]; finger 1 at ``azimuth``, finger 2 opposite.
    third_azimuth_deg : float
        Azimuth of the third finger [deg], relative to ``azimuth_deg`` (irrelevant at +-90 deg).

    Returns
    -------
    directions : (3, 3) float
        Unit vectors; the defaults give the paper's reachable optimum 45/45/-90 (§5.2, Fig. 8,
        §6.1: two contacts 45 deg above the equator, diametrically opposite, the third at the pole).
    """
    def unit(elev, azim):
        e, a = np.radians(elev), np.radians(azim)
        return np.array([np.cos(e) * np.cos(a), np.cos(e) * np.sin(a), np.sin(e)])

    return np.stack(
        [
            unit(elevation_deg, azimuth_deg),
            unit(elevation_deg, azimuth_deg + 180.0),
            unit(third_elevation_deg, azimuth_deg + third_azimuth_deg),
        ]
    )


def planned_contacts(mesh: trimesh.Trimesh, directions) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """Return the surface points hit by rays from the centroid, their faces and outward normals.

    Parameters
    ----------
    mesh : trimesh.Trimesh
        Watertight object mesh [m].
    directions : (c, 3) float
        Ray directions from ``mesh.centroid``.

    Returns
    -------
    points : (c, 3) float
        Outermost hit of each ray [m].
    faces : (c,) int
        Hit faces.
    normals : (c, 3) float
        Outward unit normals of those faces.

    Raises
    ------
    ValueError
        If a ray misses the mesh.
    """
    directions = np.asarray(directions, dtype=np.float64)
    directions = directions / np.linalg.norm(directions, axis=1)[:, None]
    origin = np.asarray(mesh.centroid, dtype=np.float64)
    triangles = np.asarray(mesh.triangles, dtype=np.float64)
    distances = _ray_triangle_distances(origin, directions, triangles)  # (c, f), inf = miss
    points = np.empty_like(directions)
    faces = np.empty(len(directions), dtype=np.int64)
    for j in range(len(directions)):  # a handful of rays
        hit = np.isfinite(distances[j])
        if not np.any(hit):
            raise ValueError(f"ray {j} along {directions[j]} misses the mesh")
        faces[j] = int(np.argmax(np.where(hit, distances[j], -np.inf)))  # outermost surface
        points[j] = origin + distances[j, faces[j]] * directions[j]
    return points, faces, np.asarray(mesh.face_normals)[faces]


def _ray_triangle_distances(origin, directions, triangles) -> np.ndarray:
    """Return (r, f) distances along each ray to each triangle it crosses (inf if it misses).

    References
    ----------
    Moller & Trumbore (1997) (symbols e1, e2, p, q, s, u, v, t as in the paper).
    """
    v0 = triangles[:, 0]
    e1 = triangles[:, 1] - v0
    e2 = triangles[:, 2] - v0
    p = np.cross(directions[:, None, :], e2[None, :, :])  # (r, f, 3)
    det = np.einsum("rfk,fk->rf", p, e1)
    ok = np.abs(det) > 1e-300
    inv = np.where(ok, 1.0 / np.where(ok, det, 1.0), 0.0)
    s = origin - v0  # (f, 3)
    u = np.einsum("rfk,fk->rf", p, s) * inv
    q = np.cross(s, e1)  # (f, 3)
    v = np.einsum("rk,fk->rf", directions, q) * inv
    t = np.einsum("fk,fk->f", e2, q)[None, :] * inv
    hit = ok & (u >= 0.0) & (v >= 0.0) & (u + v <= 1.0) & (t > 0.0)
    return np.where(hit, t, np.inf)


@dataclass(frozen=True)
class FingerContacts:
    """One contact per fingertip on the current mesh (deepest colliding face).

    Attributes
    ----------
    active : (c,) bool
        Fingertip touches the mesh.
    depths : (c,) float
        Penetration delta_max of Eq. 11 [m] (0 when inactive).
    faces : (c,) int
        Host face (-1 when inactive).
    points : (c, 3) float
        Contact point P_face [m] (the fingertip's nearest surface point direction when inactive).
    normals : (c, 3) float
        Outward face normal n_f (the approach normal when inactive).
    weights : (c, 3) float
        Barycentric weights of the points in their faces (Eq. 12).
    """

    active: np.ndarray
    depths: np.ndarray
    faces: np.ndarray
    points: np.ndarray
    normals: np.ndarray
    weights: np.ndarray


def finger_contacts(
    positions: np.ndarray,
    body: MsdBody,
    centers: np.ndarray,
    radius: float,
    approach_normals: np.ndarray,
) -> FingerContacts:
    """Collide the fingertip spheres with the deformed mesh; keep the deepest face per finger.

    Parameters
    ----------
    positions : (n, 3) float
        Current node positions [m].
    body : MsdBody
        With ``faces``.
    centers : (c, 3) float
        Fingertip centres [m].
    radius : float
        Fingertip radius [m].
    approach_normals : (c, 3) float
        Outward normals of the approach lines (placeholders for inactive fingers).

    Returns
    -------
    contacts : FingerContacts

    Notes
    -----
    ``geometry.sphere_mesh_contacts`` (compiled) collides the spheres with every face of the
    current mesh: its broad phase builds the faces' bounding spheres from the current positions,
    so no state is carried between calls.
    """
    n_fingers = len(centers)
    hits = geometry.sphere_mesh_contacts(centers, radius, positions, body.faces)
    best = geometry.deepest_per_finger(hits)  # -1 for every finger when nothing touches
    active = best >= 0
    rows = best[active]
    depths = np.zeros(n_fingers)
    depths[active] = hits.depths[rows]
    hosts = np.full(n_fingers, -1, dtype=np.int64)
    hosts[active] = hits.faces[rows]
    points = centers - radius * approach_normals
    points[active] = hits.points[rows]
    normals = np.array(approach_normals, dtype=np.float64)
    normals[active] = hits.normals[rows]
    weights = np.full((n_fingers, 3), 1.0 / 3.0)
    weights[active] = hits.weights[rows]
    return FingerContacts(
        active=active, depths=depths, faces=hosts, points=points, normals=normals, weights=weights
    )
