"""Ferrari-Canny epsilon: the L1 wrench-space quality of a three-contact grasp.

The classical rigid-body reference the paper names but never runs (§1): with unit normal force
per contact and a linearised friction cone of ``q`` edges, contact j contributes the primitive
forces ``f_jk = n_hat_j + mu (cos theta_k t1_j + sin theta_k t2_j)``, ``theta_k = 2 pi k / q``,
and the primitive wrenches ``w_jk = (f_jk, (p_j - c) x f_jk / L)`` about the centroid c, torque
divided by a characteristic length L. The L1 metric is the radius of the largest ball about the
origin inside ``conv{w_jk}`` (total normal force <= 1), and 0 when the origin is outside.

Exact facet enumeration (what :func:`epsilon_metric` computes)
--------------------------------------------------------------
The 3q points lie on three planar polygons ``P_j = c_j + mu span(T1_j, T2_j)`` in R^6, with
``c_j``, ``T1_j``, ``T2_j`` the wrenches of ``n_hat_j``, ``t1_j``, ``t2_j``. A hyperplane
``u . w = b`` meets polygon j along a vertex, an edge or the whole polygon, according to the
in-plane direction ``(alpha_j, beta_j) = (u . T1_j, u . T2_j)``. The six tangent wrenches form an
invertible 6x6 matrix P for any grasp with a non-degenerate tangent map, so
``u = P^-T (alpha_0, beta_0, ..., beta_2)``: the in-plane directions *are* coordinates of u. A facet
(5-dimensional face) touches the polygons in one of three generic patterns, each a 3x3 (or 2x2)
linear system for the scale-free unknowns:

* edge-edge-edge (q^3 choices): ``(alpha_j, beta_j) = r_j (cos phi_k, sin phi_k)``,
  ``phi_k = theta_k + pi/q`` the edge normal, ``r_j > 0``;
* whole-edge-vertex (6 q^2): one polygon flat (``alpha = beta = 0``), one at an edge, one at a
  vertex m with ``(alpha, beta)`` inside that vertex's normal cone;
* whole-whole (3 pairs): two polygons flat. All wrenches of two point contacts have zero moment
  about the line through them, so this hyperplane passes through the origin: it is a facet, and
  epsilon = 0, exactly when the third contact's moments about that line share one sign.

Requiring the three polygons' supports ``u . c_j + mu max_k (alpha_j cos theta_k + beta_j sin
theta_k)`` to be equal to b makes every solution a supporting hyperplane without testing the 3q
points; its offset ``b / |u|`` is a facet's distance from the origin (negative: origin outside).
epsilon = max(0, min over facets). Everything is vectorised over candidates; a grasp whose tangent
matrix is numerically singular falls back to the ConvexHull reference. The compiled kernel
(:func:`graspcampaign.core.kernels.epsilon_facets`) runs the same enumeration one candidate at a
time; the numpy path here is its reference.

Shape letters: ``b`` candidates, ``c = 3`` contacts, ``q`` cone edges, ``m`` facet patterns.

References
----------
Ferrari, C. & Canny, J. (1992), "Planning optimal grasps", Proc. IEEE ICRA, 2290-2295 (L1
epsilon metric). Miller, A. T. & Allen, P. K. (1999), "Examples of 3D grasp quality computations",
Proc. IEEE ICRA, 1240-1246 (linearised cones, torque over the object's maximum radius).
Mahler, J. et al. (2017), "Dex-Net 2.0", RSS (eight cone faces). Barber, Dobkin & Huhdanpaa
(1996), "The Quickhull algorithm for convex hulls", ACM TOMS 22(4) (scipy.spatial.ConvexHull, the
reference implementation). Paper §1 (the classical reference H(G) should be read against).
"""

from __future__ import annotations

import itertools
import logging

import numpy as np
from scipy.spatial import ConvexHull, QhullError

from graspcampaign.core.statics import tangent_bases

__all__ = ["DEFAULT_CONE_EDGES", "epsilon_metric", "epsilon_qhull", "primitive_wrenches"]

logger = logging.getLogger(__name__)

DEFAULT_CONE_EDGES = 8
"""Edges of the linearised friction cone (the eight-faced pyramid of GraspIt! and Dex-Net)."""

_CHUNK = 256  # candidates per vectorised block (keeps the q^3 pattern arrays near 10 MB)
_SINGULAR = 1e-10  # reciprocal condition number below which P counts as singular
_REL_TOL = 1e-10  # sign tolerance on the scale-free unknowns (symmetric, non-simplicial facets)


def _check(points, normals, mu):
    points = np.asarray(points, dtype=float)
    normals = np.asarray(normals, dtype=float)
    if points.ndim == 2:
        points, normals = points[None], normals[None]
    if points.ndim != 3 or points.shape[1:] != (3, 3) or normals.shape != points.shape:
        raise ValueError(f"points and normals must have shape (b, 3, 3), got {points.shape} "
                         f"and {normals.shape}")
    normals = normals / np.linalg.norm(normals, axis=2, keepdims=True)
    mu = np.broadcast_to(np.asarray(mu, dtype=float), points.shape[:1]).copy()
    if np.any(~np.isfinite(mu) | (mu < 0.0)):
        raise ValueError("mu must be finite and >= 0")
    return points, normals, mu


def _cross(a, b):
    """``a x b`` over the last axis (np.cross costs ~0.2 ms per call in axis handling alone)."""
    return np.stack([a[..., 1] * b[..., 2] - a[..., 2] * b[..., 1],
                     a[..., 2] * b[..., 0] - a[..., 0] * b[..., 2],
                     a[..., 0] * b[..., 1] - a[..., 1] * b[..., 0]], axis=-1)


def _contact_wrenches(points, normals, center, torque_length):
    """Return the wrenches of n_hat, t1, t2 per contact: three (b, 3, 6) arrays."""
    if not torque_length > 0.0:
        raise ValueError(f"torque_length must be > 0 m, got {torque_length!r}")
    arms = points - np.asarray(center, dtype=float)
    t1, t2 = tangent_bases(normals.reshape(-1, 3))
    t1, t2 = t1.reshape(normals.shape), t2.reshape(normals.shape)

    def wrench(force):
        return np.concatenate([force, _cross(arms, force) / torque_length], axis=-1)

    return wrench(-normals), wrench(t1), wrench(t2)


def primitive_wrenches(points, normals, mu, center, torque_length: float,
                       n_edges: int = DEFAULT_CONE_EDGES) -> np.ndarray:
    """Return the primitive contact wrenches ``w_jk`` of the L1 metric.

    Parameters
    ----------
    points : (b, 3, 3) float
        Contact points in W [m] (a single (3, 3) triple is accepted as b = 1).
    normals : (b, 3, 3) float
        Outward unit normals; the fingers push along ``-normals``.
    mu : float or (b,) float
        Friction coefficient [-].
    center : (3,) float
        Torque reference, the object centroid [m].
    torque_length : float
        Characteristic length L dividing the torques [m].
    n_edges : int
        Cone edges q.

    Returns
    -------
    wrenches : (b, 3, q, 6) float
        ``(f_jk, (p_j - c) x f_jk / L)`` with unit normal component.
    """
    points, normals, mu = _check(points, normals, mu)
    center_w, t1_w, t2_w = _contact_wrenches(points, normals, center, torque_length)
    theta = 2.0 * np.pi * np.arange(n_edges) / n_edges
    spokes = (np.cos(theta)[:, None] * t1_w[:, :, None] + np.sin(theta)[:, None] * t2_w[:, :, None])
    return center_w[:, :, None] + mu[:, None, None, None] * spokes


def epsilon_qhull(wrenches) -> np.ndarray:
    """Return epsilon from ``scipy.spatial.ConvexHull`` of each candidate's wrenches (reference).

    Parameters
    ----------
    wrenches : (b, 3, q, 6) float
        From :func:`primitive_wrenches`.

    Returns
    -------
    epsilon : (b,) float
        ``max(0, min over facets of the origin's distance)``; 0 when the hull is flat.
    """
    wrenches = np.asarray(wrenches, dtype=float)
    out = np.zeros(wrenches.shape[0])
    for i, cloud in enumerate(wrenches.reshape(wrenches.shape[0], -1, 6)):
        try:
            hull = ConvexHull(cloud)
        except QhullError:  # lower-dimensional: the origin is not interior
            continue
        out[i] = max(0.0, float(np.min(-hull.equations[:, -1])))
    return out


def _solve3(matrix):
    """Solve ``matrix x = 1`` for stacked 3x3 systems by Cramer's rule; returns (x, det)."""
    a, b, c = matrix[..., 0, :], matrix[..., 1, :], matrix[..., 2, :]
    det = np.einsum("...i,...i->...", a, np.cross(b, c))
    ones = np.ones(3)
    # x_i = det(matrix with column i replaced by ones) / det = (ones . (col_j x col_k)) / det
    cols = np.swapaxes(matrix, -1, -2)
    numer = np.stack([np.einsum("i,...i->...", ones, np.cross(cols[..., 1, :], cols[..., 2, :])),
                      np.einsum("i,...i->...", ones, np.cross(cols[..., 2, :], cols[..., 0, :])),
                      np.einsum("i,...i->...", ones, np.cross(cols[..., 0, :], cols[..., 1, :]))],
                     axis=-1)
    with np.errstate(divide="ignore", invalid="ignore"):
        return numer / det[..., None], det


def _patterns(n_edges: int):
    """Index arrays of the edge-edge-edge and whole-edge-vertex patterns."""
    edges3 = np.array(list(itertools.product(range(n_edges), repeat=3)))
    mixed = np.array([(a, b, c, k, m) for a, b, c in itertools.permutations(range(3))
                      for k in range(n_edges) for m in range(n_edges)])
    return edges3, mixed


def _pair_axis_supports(points, center_w, t1_w, t2_w, mu, center, torque_length, n_edges):
    """Whether some contact pair's axis leaves the third contact's wrenches on one side, (b,).

    Every wrench of two point contacts a, b has zero moment about the line through p_a and p_b,
    so the whole-whole facets lie in that hyperplane through the origin (``u = (e x (c - p_a),
    L e)``, e along the axis). It is a facet, and the origin is on the hull's boundary (epsilon =
    0: no grip resists a torque about that axis in one sense), exactly when the third contact's
    moments about the axis, ``u . c_c + mu (cos theta_k u . T1_c + sin theta_k u . T2_c)``, all
    share one sign.
    """
    supported = np.zeros(points.shape[0], dtype=bool)
    center = np.asarray(center, dtype=float)
    theta = 2.0 * np.pi * np.arange(n_edges) / n_edges
    for a, b, c in ((0, 1, 2), (0, 2, 1), (1, 2, 0)):
        axis = points[:, b] - points[:, a]
        axis /= np.linalg.norm(axis, axis=1, keepdims=True)
        u = np.concatenate([_cross(axis, center - points[:, a]), torque_length * axis], axis=1)
        at_c, along_1, along_2 = (np.einsum("bx,bx->b", w[:, c], u) for w in (center_w, t1_w, t2_w))
        moments = at_c[:, None] + mu[:, None] * (np.cos(theta) * along_1[:, None]
                                                 + np.sin(theta) * along_2[:, None])
        scale = np.abs(at_c) + mu * np.hypot(along_1, along_2)
        tol = 1e-12 * np.maximum(scale, 1e-300)[:, None]
        supported |= np.all(moments >= -tol, axis=1) | np.all(moments <= tol, axis=1)
    return supported


def _tangent_inverse(tangent):
    """Return ``P^-T`` (inverse of the stacked tangent wrenches) and an inf-norm rcond, per row."""
    try:
        basis = np.linalg.inv(tangent)
    except np.linalg.LinAlgError:  # an exactly singular row: invert row by row
        basis = np.full_like(tangent, np.nan)
        for i, m in enumerate(tangent):
            try:
                basis[i] = np.linalg.inv(m)
            except np.linalg.LinAlgError:
                pass
    norm = np.abs(tangent).sum(axis=2).max(axis=1) * np.abs(basis).sum(axis=2).max(axis=1)
    with np.errstate(divide="ignore", invalid="ignore"):
        rcond = np.where(np.isfinite(norm), 1.0 / norm, 0.0)
    return basis, rcond


def _block(center_w, t1_w, t2_w, mu, n_edges):
    """Epsilon of one block of candidates with an invertible tangent matrix (module docstring)."""
    n = center_w.shape[0]
    rows = np.arange(n)
    tangent = np.stack([t1_w, t2_w], axis=2).reshape(n, 6, 6)  # rows T1_0, T2_0, T1_1, ...
    inv = np.linalg.inv(np.swapaxes(tangent, 1, 2))  # P^-1 with P's columns the tangent wrenches
    d = np.einsum("bij,bcj->bci", inv, center_w)  # d[b, c] = P^-1 c_c; u . c_c = a . d[b, c]
    basis = np.swapaxes(inv, 1, 2)  # P^-T: u = basis @ a
    theta = 2.0 * np.pi * np.arange(n_edges) / n_edges
    phi = theta + np.pi / n_edges
    cos_half = np.cos(np.pi / n_edges)
    # e0[b, i, j, k]: u . c_i per unit r_j when polygon j sits at edge k
    e0 = (np.cos(phi) * d[:, :, 0::2, None] + np.sin(phi) * d[:, :, 1::2, None])
    # edge[b, j, k, :]: u per unit r_j at edge k;  flat columns of P^-T per polygon
    edge = (np.cos(phi)[None, None, :, None] * basis[:, None, :, 0::2].transpose(0, 3, 1, 2)
            + np.sin(phi)[None, None, :, None] * basis[:, None, :, 1::2].transpose(0, 3, 1, 2))
    free_a, free_b = basis[:, :, 0::2], basis[:, :, 1::2]  # (b, 6, 3): u per unit alpha_j, beta_j
    mu_c = (mu * cos_half)[:, None]
    edges3, mixed = _patterns(n_edges)
    best = np.full(n, np.inf)
    outside = np.zeros(n, dtype=bool)

    def keep(sign, u, valid):
        offset = sign / np.linalg.norm(u, axis=-1)
        outside[:] |= np.any(valid & (offset < 0.0), axis=1)
        best[:] = np.minimum(best, np.min(np.where(valid & (offset > 0.0), offset, np.inf), axis=1))

    # edge-edge-edge: E[b, m, i, j] = e0[b, i, j, k_j] + mu cos(pi/q) delta_ij; E r = b 1
    matrix = np.stack([e0[:, :, j, edges3[:, j]] for j in range(3)], axis=-1)  # (b, i, m, j)
    matrix = np.moveaxis(matrix, 1, 2) + mu_c[:, :, None, None] * np.eye(3)
    r, det = _solve3(matrix)
    scale = np.max(np.abs(r), axis=-1, keepdims=True)
    pos = np.all(r > -_REL_TOL * scale, axis=-1) & (np.abs(det) > 0) & np.isfinite(scale[..., 0])
    neg = np.all(r < _REL_TOL * scale, axis=-1) & (np.abs(det) > 0) & np.isfinite(scale[..., 0])
    sign = np.where(pos, 1.0, -1.0)
    u = sum((sign[..., None] * r)[..., j, None] * edge[:, j][:, edges3[:, j]] for j in range(3))
    keep(sign, u, pos | neg)

    # whole-edge-vertex: unknowns (r_b, alpha_c, beta_c)
    a_i, b_i, c_i, k_i, m_i = mixed.T
    eye = np.eye(3)
    col0 = e0[:, :, b_i, k_i] + mu[:, None, None] * cos_half * eye[:, b_i]  # (b, i, m)
    col1 = d[:, :, 2 * c_i] + mu[:, None, None] * np.cos(theta[m_i]) * eye[:, c_i]
    col2 = d[:, :, 2 * c_i + 1] + mu[:, None, None] * np.sin(theta[m_i]) * eye[:, c_i]
    x, det = _solve3(np.moveaxis(np.stack([col0, col1, col2], axis=-1), 1, 2))
    sign = np.sign(x[..., 0])
    x = sign[..., None] * x
    ab = x[..., 1:]
    here = np.stack([np.cos(theta[m_i]), np.sin(theta[m_i])], axis=-1)
    prev = np.stack([np.cos(theta[m_i] - 2 * np.pi / n_edges),
                     np.sin(theta[m_i] - 2 * np.pi / n_edges)], axis=-1)
    nxt = np.stack([np.cos(theta[m_i] + 2 * np.pi / n_edges),
                    np.sin(theta[m_i] + 2 * np.pi / n_edges)], axis=-1)
    size = np.linalg.norm(ab, axis=-1)
    tol = _REL_TOL * np.maximum(size, np.abs(x[..., 0]))
    valid = ((sign != 0) & (np.abs(det) > 0) & np.all(np.isfinite(x), axis=-1)
             & (np.einsum("bmi,mi->bm", ab, here - prev) >= -tol)
             & (np.einsum("bmi,mi->bm", ab, here - nxt) >= -tol))
    u = (x[..., 0, None] * edge[rows[:, None], b_i[None], k_i[None]]
         + ab[..., 0, None] * np.moveaxis(free_a[:, :, c_i], 1, 2)
         + ab[..., 1, None] * np.moveaxis(free_b[:, :, c_i], 1, 2))
    keep(sign, u, valid)

    return np.where(outside | ~np.isfinite(best), 0.0, best)


def epsilon_metric(points, normals, mu, center, torque_length: float,
                   n_edges: int = DEFAULT_CONE_EDGES, backend: str = "numba") -> np.ndarray:
    """Return the Ferrari-Canny L1 epsilon of contact triples (exact facet enumeration).

    Parameters
    ----------
    points : (b, 3, 3) float
        Contact points in W [m] (a single (3, 3) triple is accepted as b = 1).
    normals : (b, 3, 3) float
        Outward unit normals; the fingers push along ``-normals``.
    mu : float or (b,) float
        Friction coefficient [-]; mu = 0 gives 0 (three points span no 6-D volume).
    center : (3,) float
        Torque reference, the object centroid [m].
    torque_length : float
        Characteristic length L dividing the torques [m] (the campaign uses the object's largest
        centroid-to-vertex distance).
    n_edges : int
        Cone edges q (>= 3).
    backend : {"numba", "numpy"}
        The compiled kernel (default) or the vectorised numpy reference.

    Returns
    -------
    epsilon : (b,) float
        Radius of the largest origin-centred ball inside the hull of the primitive wrenches
        [force units per unit total normal force]; 0 when the origin is not interior (no force
        closure). Agrees with :func:`epsilon_qhull` to round-off (tests: 1e-9 relative).

    Notes
    -----
    See the module docstring. Cost per candidate: one 6x6 inverse and ``q^3 + 6 q^2`` 3x3
    solves, plus the three pair-axis tests.

    References
    ----------
    Ferrari & Canny (1992); Miller & Allen (1999).
    """
    if int(n_edges) != n_edges or n_edges < 3:
        raise ValueError(f"n_edges must be an int >= 3, got {n_edges!r}")
    if backend not in ("numba", "numpy"):
        raise ValueError(f"backend must be 'numba' or 'numpy', got {backend!r}")
    n_edges = int(n_edges)
    points, normals, mu = _check(points, normals, mu)
    center_w, t1_w, t2_w = _contact_wrenches(points, normals, center, torque_length)
    n_batch = points.shape[0]
    out = np.zeros(n_batch)
    tangent = np.stack([t1_w, t2_w], axis=2).reshape(n_batch, 6, 6)  # rows: P^T
    basis, rcond = _tangent_inverse(tangent)
    open_ = (mu > 0.0) & ~_pair_axis_supports(points, center_w, t1_w, t2_w, mu, center,
                                               torque_length, n_edges)
    regular = open_ & (rcond > _SINGULAR)
    index = np.flatnonzero(regular)
    if backend == "numba" and len(index):
        from graspcampaign.core import kernels

        d = np.einsum("bjr,bij->bir", basis[index], center_w[index])  # P^-1 c_i
        out[index] = kernels.epsilon_facets(np.ascontiguousarray(d),
                                            np.ascontiguousarray(basis[index]), mu[index],
                                            n_edges, _REL_TOL)
    else:
        for start in range(0, len(index), _CHUNK):
            block = index[start:start + _CHUNK]
            out[block] = _block(center_w[block], t1_w[block], t2_w[block], mu[block], n_edges)
    singular = np.flatnonzero(open_ & ~regular)
    if len(singular):
        logger.debug("epsilon: %d candidate(s) with a singular tangent map use ConvexHull",
                     len(singular))
        out[singular] = epsilon_qhull(primitive_wrenches(points[singular], normals[singular],
                                                         mu[singular], center, torque_length,
                                                         n_edges))
    return out
