"""Heuristic grasp metric H(G) for batches of vertex triples (paper Eq. 6-9, §3.1, §5.2, §8.1).

``H(G) = w1 S1 + w2 S2 + w3 S3 + n_c P_c + n_e P_e`` (Eq. 6), lower is better, where for contacts at
mesh vertices ``i, j, k``:

- ``S1`` (Eq. 7): force-direction balance. The force a finger applies pushes along ``-n_out``; with
  ``theta_12, theta_23, theta_31`` the angles between the three force directions [deg],
  ``S1 = (|120 - theta_12| + |120 - theta_23| + |120 - theta_31|) / 240``.
- ``S2`` (Eq. 8): contact-triangle regularity, ``S2 = (s21 + s22 + s23) / 3``. The paper does not
  publish ``s2i``; ours (decision, ``docs/decisions.md``) is
  ``s2i = (min(1, |alpha_i - 60 deg| / 60 deg) + min(1, |l_i - d_opt| / d_opt)) / 2`` with
  ``alpha_i`` the interior angle at contact i and ``l_i`` the side from contact i to contact i+1
  (cyclic). Each ``s2i`` lies in [0, 1] and ``S2 = 0`` exactly for an equilateral triangle of side
  ``d_opt``.
- ``S3`` (Eq. 9): centroid proximity, ``d_c / d_max``, ``d_c`` the distance from the contact
  triangle's centroid to the object's centroid and ``d_max`` the largest centroid-to-vertex
  distance.
- ``n_c``, ``n_e``: number of contacts on a sharp vertex / near a sharp edge (§3.1).

Hardware form (§8.1): weights (0.45, 0.30, 0.25), penalties as continuous magnitudes, and the
maximised score ``H~ = sum_i w_i (1 - S_i) - P_c - P_e``. Our continuous magnitudes (decision) are
soft counts: per contact a ramp ``c = clip((defect - tau_v) / tau_v, 0, 1)`` (0 at the sharpness
threshold, 1 at twice it) and ``e = clip(1 - dist / (f * l_local), 0, 1)`` (1 on a sharp edge, 0 at
the proximity band's edge); ``pc_mag``, ``pe_mag`` are their sums over the three contacts, so they
are non-zero exactly where the counts are and never exceed them.

Shape letters: ``n`` vertices, ``m`` candidate triples.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np
import trimesh
from trimesh import intersections

from .feature import SharpFeatures

_THIRD_TURN = 2.0 * np.pi / 3.0  # 120 deg
_SIXTH_TURN = np.pi / 3.0  # 60 deg

__all__ = [
    "HeuristicWeights",
    "HARDWARE_WEIGHTS",
    "HeuristicContext",
    "HeuristicTerms",
    "heuristic_context",
    "heuristic_terms",
    "default_d_opt",
]


@dataclass(frozen=True)
class HeuristicWeights:
    """Weights of Eq. 6: term weights ``w1..w3`` and penalty weights ``P_c``, ``P_e``.

    Defaults are the simulation form (all unity, §3.1, §5.2).
    """

    w1: float = 1.0
    w2: float = 1.0
    w3: float = 1.0
    p_c: float = 1.0
    p_e: float = 1.0

    @classmethod
    def hardware(cls) -> HeuristicWeights:
        """Return the hardware-campaign weighting (0.45, 0.30, 0.25), unit penalties (§8.1)."""
        return cls(w1=0.45, w2=0.30, w3=0.25, p_c=1.0, p_e=1.0)

    def scaled(self, factor: float) -> HeuristicWeights:
        """Return all five weights multiplied by ``factor`` (the §5.2 uniform-scaling sweep)."""
        return HeuristicWeights(self.w1 * factor, self.w2 * factor, self.w3 * factor,
                                self.p_c * factor, self.p_e * factor)


#: Hardware weighting of §8.1.
HARDWARE_WEIGHTS = HeuristicWeights.hardware()


@dataclass(frozen=True)
class HeuristicContext:
    """Per-mesh data of the heuristic, built once by :func:`heuristic_context`.

    Attributes
    ----------
    vertices : (n, 3) float
        Candidate contact positions [m].
    normals : (n, 3) float
        Outward unit vertex normals ``n_out``.
    centroid : (3,) float
        Object centroid (volume centroid for a closed mesh) [m].
    d_max : float
        Largest centroid-to-vertex distance [m] (Eq. 9).
    d_opt : float
        Target side of the contact triangle [m] (Eq. 8).
    sharp_vertex : (n,) bool
        Vertex is sharp (counts into ``n_c``).
    near_sharp_edge : (n,) bool
        Vertex is within the proximity band of a sharp edge (counts into ``n_e``).
    pc_magnitude : (n,) float
        Continuous sharp-vertex magnitude in [0, 1], zero where ``sharp_vertex`` is false.
    pe_magnitude : (n,) float
        Continuous sharp-edge-proximity magnitude in [0, 1], zero where ``near_sharp_edge`` is
        false.
    """

    vertices: np.ndarray
    normals: np.ndarray
    centroid: np.ndarray
    d_max: float
    d_opt: float
    sharp_vertex: np.ndarray
    near_sharp_edge: np.ndarray
    pc_magnitude: np.ndarray
    pe_magnitude: np.ndarray

    @property
    def n_vertices(self) -> int:
        """Number of candidate vertices."""
        return len(self.vertices)


def default_d_opt(mesh: trimesh.Trimesh) -> float:
    """Return the default target side ``d_opt``: equilateral triangle in the equatorial section.

    The equatorial section is the cut of the solid by the horizontal plane (world z up) through
    its volume centroid. Its mean radius is taken as the area-equivalent radius
    ``R_eq = sqrt(A / pi)`` and ``d_opt = sqrt(3) R_eq``, the side of the equilateral triangle
    inscribed in a circle of that radius (``sqrt(3) * 50 mm = 86.6 mm`` on the sphere).

    Parameters
    ----------
    mesh : trimesh.Trimesh
        Closed, outward-wound mesh [m].

    Returns
    -------
    d_opt : float
        [m]. Falls back to ``sqrt(3)`` times the mean centroid-to-vertex distance when the plane
        misses the solid.

    Notes
    -----
    The section area comes from the cut segments by the shoelace formula: each segment is oriented
    along ``z x n_face`` so that the solid lies on its left, which makes holes count negative.
    """
    centroid = np.asarray(mesh.center_mass, dtype=float)
    lines, face_index = intersections.mesh_plane(
        mesh, plane_normal=[0.0, 0.0, 1.0], plane_origin=centroid, return_faces=True)
    area = 0.0
    if len(lines):
        start, end = lines[:, 0, :2] - centroid[:2], lines[:, 1, :2] - centroid[:2]
        normals = np.asarray(mesh.face_normals)[face_index]
        tangent = np.column_stack([-normals[:, 1], normals[:, 0]])  # z x n, in the plane
        flip = np.einsum("ij,ij->i", end - start, tangent) < 0.0
        start, end = np.where(flip[:, None], end, start), np.where(flip[:, None], start, end)
        area = 0.5 * float(np.sum(start[:, 0] * end[:, 1] - start[:, 1] * end[:, 0]))
    if area > 0.0:
        return float(np.sqrt(3.0) * np.sqrt(area / np.pi))
    radii = np.linalg.norm(np.asarray(mesh.vertices) - centroid, axis=1)
    return float(np.sqrt(3.0) * radii.mean())


def heuristic_context(mesh: trimesh.Trimesh, features: SharpFeatures,
                      d_opt: float | None = None) -> HeuristicContext:
    """Build the per-mesh data of H(G).

    Parameters
    ----------
    mesh : trimesh.Trimesh
        Closed, outward-wound mesh [m].
    features : SharpFeatures
        Output of :func:`graspcampaign.core.feature.sharp_features` for ``mesh``.
    d_opt : float, optional
        Target contact-triangle side [m]; default :func:`default_d_opt`.

    Returns
    -------
    context : HeuristicContext
    """
    vertices = np.asarray(mesh.vertices, dtype=float)
    centroid = np.asarray(mesh.center_mass, dtype=float)
    d_max = float(np.linalg.norm(vertices - centroid, axis=1).max())
    d_opt = default_d_opt(mesh) if d_opt is None else float(d_opt)
    if not d_opt > 0.0:
        raise ValueError(f"d_opt must be positive, got {d_opt}")

    tau_v = features.vertex_threshold_rad
    pc_mag = np.clip((features.vertex_defects - tau_v) / tau_v, 0.0, 1.0)
    pc_mag = np.where(features.sharp_vertices, pc_mag, 0.0)
    band = features.thresholds.edge_proximity_factor * features.vertex_mean_edge_length
    with np.errstate(invalid="ignore"):  # inf distance / finite band -> 1 - inf, clipped to 0
        pe_mag = np.clip(1.0 - features.vertex_sharp_edge_distance / band, 0.0, 1.0)
    pe_mag = np.where(features.vertex_near_sharp_edge, pe_mag, 0.0)

    return HeuristicContext(
        vertices=vertices,
        normals=np.asarray(mesh.vertex_normals, dtype=float),
        centroid=centroid,
        d_max=d_max,
        d_opt=d_opt,
        sharp_vertex=np.asarray(features.sharp_vertices, dtype=bool),
        near_sharp_edge=np.asarray(features.vertex_near_sharp_edge, dtype=bool),
        pc_magnitude=pc_mag,
        pe_magnitude=pe_mag,
    )


@dataclass(frozen=True)
class HeuristicTerms:
    """Components of H(G) for m candidate triples; every array has shape (m,).

    Attributes
    ----------
    s1, s2, s3 : (m,) float
        Eq. 7, 8, 9.
    s2_angle, s2_side : (m,) float
        The two halves of S2 (mean angle part and mean side part), ``S2 = (s2_angle + s2_side)/2``.
    n_c, n_e : (m,) int
        Contacts on a sharp vertex / near a sharp edge (0-3).
    pc_mag, pe_mag : (m,) float
        Continuous penalty magnitudes of the hardware form (0-3).
    """

    s1: np.ndarray
    s2: np.ndarray
    s3: np.ndarray
    s2_angle: np.ndarray
    s2_side: np.ndarray
    n_c: np.ndarray
    n_e: np.ndarray
    pc_mag: np.ndarray
    pe_mag: np.ndarray

    def __len__(self) -> int:
        return len(self.s1)

    def total(self, weights: HeuristicWeights | None = None) -> np.ndarray:
        """Return the simulation form ``H = w1 S1 + w2 S2 + w3 S3 + n_c P_c + n_e P_e`` (Eq. 6).

        Parameters
        ----------
        weights : HeuristicWeights, optional
            Default: all unity (§5.2).

        Returns
        -------
        h : (m,) float
            Lower is better.
        """
        w = HeuristicWeights() if weights is None else weights
        return (w.w1 * self.s1 + w.w2 * self.s2 + w.w3 * self.s3
                + w.p_c * self.n_c + w.p_e * self.n_e)

    def score_hardware(self, weights: HeuristicWeights | None = None) -> np.ndarray:
        """Return the hardware score ``H~ = sum_i w_i (1 - S_i) - P_c - P_e`` (§8.1).

        Parameters
        ----------
        weights : HeuristicWeights, optional
            Default: :data:`HARDWARE_WEIGHTS`. ``P_c = p_c * pc_mag`` and ``P_e = p_e * pe_mag``.

        Returns
        -------
        score : (m,) float
            Higher is better.
        """
        w = HARDWARE_WEIGHTS if weights is None else weights
        return (w.w1 * (1.0 - self.s1) + w.w2 * (1.0 - self.s2) + w.w3 * (1.0 - self.s3)
                - w.p_c * self.pc_mag - w.p_e * self.pe_mag)


def _sum3(values: np.ndarray, i: np.ndarray, j: np.ndarray, k: np.ndarray) -> np.ndarray:
    return np.take(values, i) + np.take(values, j) + np.take(values, k)


def heuristic_terms(ctx: HeuristicContext, triples: np.ndarray) -> HeuristicTerms:
    """Evaluate every component of H(G) for a batch of vertex triples.

    Parameters
    ----------
    ctx : HeuristicContext
        Per-mesh data.
    triples : (m, 3) int
        Vertex indices of the three contacts of each candidate.

    Returns
    -------
    terms : HeuristicTerms
        All components, each (m,).

    Notes
    -----
    A triple that repeats a vertex has a zero-length side: its interior angles are undefined and
    its angle part of S2 is set to the maximum, 1.

    References
    ----------
    Paper Eq. 6-9, §3.1, §5.2, §8.1.
    """
    triples = np.asarray(triples)
    if triples.ndim != 2 or triples.shape[1] != 3:
        raise ValueError(f"triples must have shape (m, 3), got {triples.shape}")
    # Row gathers with np.take and column-wise sums: both much faster than fancy indexing and
    # axis-1 reductions on (m, 3) arrays.
    i, j, k = triples[:, 0], triples[:, 1], triples[:, 2]
    p0, p1, p2 = (np.take(ctx.vertices, v, axis=0) for v in (i, j, k))
    n0, n1, n2 = (np.take(ctx.normals, v, axis=0) for v in (i, j, k))
    n_triples = len(triples)

    # Sides e_i from contact i to contact i+1 and their lengths l_i.
    e0, e1, e2 = p1 - p0, p2 - p1, p0 - p2
    side_len = np.sqrt(np.column_stack([np.einsum("ij,ij->i", e0, e0),
                                        np.einsum("ij,ij->i", e1, e1),
                                        np.einsum("ij,ij->i", e2, e2)]))
    # Six cosines, one arccos: columns 0-2 are the angles 12, 23, 31 between the force directions
    # -n_out (the signs cancel in the dot product); columns 3-5 the interior angles at contacts
    # 1, 2, 3, between the sides to the next and to the previous contact.
    cosines = np.empty((n_triples, 6))
    cosines[:, 0] = np.einsum("ij,ij->i", n0, n1)
    cosines[:, 1] = np.einsum("ij,ij->i", n1, n2)
    cosines[:, 2] = np.einsum("ij,ij->i", n2, n0)
    with np.errstate(divide="ignore", invalid="ignore"):
        cosines[:, 3] = -np.einsum("ij,ij->i", e0, e2) / (side_len[:, 0] * side_len[:, 2])
        cosines[:, 4] = -np.einsum("ij,ij->i", e1, e0) / (side_len[:, 1] * side_len[:, 0])
        cosines[:, 5] = -np.einsum("ij,ij->i", e2, e1) / (side_len[:, 2] * side_len[:, 1])
    angles = np.arccos(np.clip(cosines, -1.0, 1.0))  # [rad]; NaN for a zero-length side

    # S1 (Eq. 7) in radians: sum |120 deg - theta| / 240 deg.
    dev = np.abs(_THIRD_TURN - angles[:, :3])
    s1 = (dev[:, 0] + dev[:, 1] + dev[:, 2]) / (2.0 * _THIRD_TURN)
    # S2 (Eq. 8): our bounded s2i (module docstring).
    angle_dev = np.minimum(1.0, np.abs(angles[:, 3:] - _SIXTH_TURN) / _SIXTH_TURN)
    angle_dev[np.isnan(angle_dev)] = 1.0
    side_dev = np.minimum(1.0, np.abs(side_len - ctx.d_opt) / ctx.d_opt)
    s2_angle = (angle_dev[:, 0] + angle_dev[:, 1] + angle_dev[:, 2]) / 3.0
    s2_side = (side_dev[:, 0] + side_dev[:, 1] + side_dev[:, 2]) / 3.0
    s2 = 0.5 * (s2_angle + s2_side)
    # S3 (Eq. 9).
    offset = (p0 + p1 + p2) / 3.0 - ctx.centroid
    s3 = np.sqrt(np.einsum("ij,ij->i", offset, offset)) / ctx.d_max

    return HeuristicTerms(
        s1=s1,
        s2=s2,
        s3=s3,
        s2_angle=s2_angle,
        s2_side=s2_side,
        n_c=_sum3(ctx.sharp_vertex.astype(np.int64), i, j, k),
        n_e=_sum3(ctx.near_sharp_edge.astype(np.int64), i, j, k),
        pc_mag=_sum3(ctx.pc_magnitude, i, j, k),
        pe_mag=_sum3(ctx.pe_magnitude, i, j, k),
    )
