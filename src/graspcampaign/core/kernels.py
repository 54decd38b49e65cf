"""Compiled (numba) kernel of the sphere-triangle contact query (paper §3.2-3.3).

The numpy implementation in :mod:`graspcampaign.core.geometry` is the reference; this kernel
computes the same quantities with the same formulas, one (fingertip, face) pair at a time, so
that a query costs tens of microseconds instead of the ~60 small numpy calls of the vectorised
path (each ~1 us on small batches, whatever the batch size). Tests check that both paths agree
pair for pair and that both agree with trimesh. Measurements and the decision to compile are in
docs/decisions.md (issue 3 and issue 6).

Symbols follow the module docstring of ``core.geometry``: for a face (V0, V1, V2) with edges
``e_i = V_{i+1} - V_i``, outward unit normal ``n``, in-plane inward edge normals
``m_i = n x e_i / |e_i|``, the fingertip centre P has height ``z0' = (P - V0) . n``, signed edge
distances ``s_i = (P - V_i) . m_i`` and clamped edge parameters ``t_i``.
"""

from __future__ import annotations

import math

import numpy as np
from numba import njit

_TINY = np.finfo(np.float64).tiny


@njit(cache=True)
def face_bounds(vertices, faces):
    """Return per-face bounding spheres: centroid (f, 3) and largest centroid-vertex distance (f,)."""
    n_faces = faces.shape[0]
    centers = np.empty((n_faces, 3))
    radii = np.empty(n_faces)
    for f in range(n_faces):
        a, b, c = faces[f, 0], faces[f, 1], faces[f, 2]
        for j in range(3):
            centers[f, j] = (vertices[a, j] + vertices[b, j] + vertices[c, j]) / 3.0
        largest = 0.0
        for v in (a, b, c):
            d_sq = 0.0
            for j in range(3):
                d = vertices[v, j] - centers[f, j]
                d_sq += d * d
            largest = max(largest, d_sq)
        radii[f] = math.sqrt(largest)
    return centers, radii


@njit(cache=True)
def sphere_faces(centers, radius, vertices, faces, bound_centers, bound_radii):
    """Collide spheres with the faces of an indexed mesh; return the colliding pairs.

    Parameters
    ----------
    centers : (p, 3) float
        Sphere centres [m].
    radius : float
        Sphere radius [m].
    vertices : (n, 3) float
        Mesh vertices [m].
    faces : (f, 3) int
        Vertex indices, counter-clockwise seen from outside.
    bound_centers, bound_radii : (f, 3), (f,) float
        Bounding spheres of the faces (broad phase; :func:`face_bounds`).

    Returns
    -------
    count : int
        Number k of colliding pairs; the arrays below hold them in their first k rows, ordered by
        sphere, then face.
    pairs : (m, 2) int64
        (sphere, face).
    keys : (m,) int8
        Region key: 0 outside the face in an edge region, 1 outside in a corner region, 2 inside
        with the disc crossing an edge line, 3 inside with the disc within all edge lines
        (``geometry._CASE_OF_KEY`` and ``_SUBCASE_OF_KEY`` map it to the case and subcase).
    scalars : (m, 4) float
        (depth delta_max of Eq. 11, distance ``|P - P_face|``, height z0', overlap
        ``r - |P - P_face|``) [m].
    vectors : (m, 4, 3) float
        (P_face, P_finger, outward face normal, barycentric weights of P_face).
    """
    n_spheres, n_faces = centers.shape[0], faces.shape[0]
    # Broad phase: the sphere overlaps the face's bounding sphere.
    candidates = np.empty(n_spheres * n_faces, dtype=np.int64)
    n_cand = 0
    for p in range(n_spheres):
        for f in range(n_faces):
            reach = radius + bound_radii[f]
            d_sq = 0.0
            for j in range(3):
                d = centers[p, j] - bound_centers[f, j]
                d_sq += d * d
            if d_sq < reach * reach:
                candidates[n_cand] = p * n_faces + f
                n_cand += 1

    pairs = np.empty((n_cand, 2), dtype=np.int64)
    keys = np.empty(n_cand, dtype=np.int8)
    scalars = np.empty((n_cand, 4))
    vectors = np.empty((n_cand, 4, 3))
    scratch = np.empty((9, 3))
    count = 0
    for i in range(n_cand):
        p, f = divmod(candidates[i], n_faces)
        key = narrow_pair(centers[p], radius, vertices, faces, f, scratch, scalars[count],
                          vectors[count])
        if key < 0:
            continue
        pairs[count, 0], pairs[count, 1] = p, f
        keys[count] = key
        count += 1
    return count, pairs, keys, scalars, vectors


# ------------------------------------------------------------------ Ferrari-Canny epsilon (L1)
# The facet enumeration of :mod:`graspcampaign.core.ferrari_canny` (module docstring there), one
# candidate at a time: the numpy path of that module is the reference and tests hold both to
# scipy.spatial.ConvexHull. Symbols: ``d[i] = P^-1 c_i`` (u . c_i = a . d[i]), ``basis = P^-T``
# (u = basis @ a), ``a = (alpha_0, beta_0, ..., beta_2)`` the in-plane directions.

@njit(cache=True)
def _cramer3(m, x):
    """Solve ``m x = 1`` (3x3) in place by Cramer's rule; return the determinant."""
    det = (m[0, 0] * (m[1, 1] * m[2, 2] - m[1, 2] * m[2, 1])
           - m[0, 1] * (m[1, 0] * m[2, 2] - m[1, 2] * m[2, 0])
           + m[0, 2] * (m[1, 0] * m[2, 1] - m[1, 1] * m[2, 0]))
    if det == 0.0 or not math.isfinite(det):
        return 0.0
    for col in range(3):
        value = 0.0
        # determinant with column ``col`` replaced by ones, expanded along that column
        for row in range(3):
            r1, r2 = (row + 1) % 3, (row + 2) % 3
            c1, c2 = (col + 1) % 3, (col + 2) % 3
            value += m[r1, c1] * m[r2, c2] - m[r1, c2] * m[r2, c1]
        x[col] = value / det
    return det


@njit(cache=True)
def epsilon_facets(d, basis, mu, n_edges, rel_tol):
    """Return the L1 epsilon of each candidate from its facet patterns (edge-edge-edge and
    whole-edge-vertex; the whole-whole pattern is handled by the caller).

    Parameters
    ----------
    d : (b, 3, 6) float
        ``P^-1 c_i`` per contact.
    basis : (b, 6, 6) float
        ``P^-T``.
    mu : (b,) float
        Friction coefficients (> 0).
    n_edges : int
        Cone edges q.
    rel_tol : float
        Sign tolerance on the scale-free unknowns.

    Returns
    -------
    epsilon : (b,) float
        0 when a facet has the origin on its outer side (or none is found).
    """
    n_batch = d.shape[0]
    q = n_edges
    out = np.zeros(n_batch)
    cos_t = np.empty(q)
    sin_t = np.empty(q)
    cos_p = np.empty(q)
    sin_p = np.empty(q)
    for k in range(q):
        t = 2.0 * math.pi * k / q
        cos_t[k], sin_t[k] = math.cos(t), math.sin(t)
        cos_p[k], sin_p[k] = math.cos(t + math.pi / q), math.sin(t + math.pi / q)
    cos_half = math.cos(math.pi / q)
    e0 = np.empty((3, 3, q))
    edge = np.empty((3, q, 6))
    m = np.empty((3, 3))
    x = np.empty(3)
    u = np.empty(6)
    for b in range(n_batch):
        mu_c = mu[b] * cos_half
        for j in range(3):
            for k in range(q):
                for i in range(3):
                    e0[i, j, k] = cos_p[k] * d[b, i, 2 * j] + sin_p[k] * d[b, i, 2 * j + 1]
                for r in range(6):
                    edge[j, k, r] = cos_p[k] * basis[b, r, 2 * j] + sin_p[k] * basis[b, r, 2 * j + 1]
        best = math.inf
        outside = False
        # edge-edge-edge: E r = 1 with E[i, j] = e0[i, j, k_j] + mu cos(pi/q) delta_ij
        for k0 in range(q):
            for k1 in range(q):
                for k2 in range(q):
                    for i in range(3):
                        m[i, 0] = e0[i, 0, k0]
                        m[i, 1] = e0[i, 1, k1]
                        m[i, 2] = e0[i, 2, k2]
                        m[i, i] += mu_c
                    if _cramer3(m, x) == 0.0:
                        continue
                    scale = max(abs(x[0]), abs(x[1]), abs(x[2]))
                    tol = rel_tol * scale
                    if x[0] > -tol and x[1] > -tol and x[2] > -tol:
                        sign = 1.0
                    elif x[0] < tol and x[1] < tol and x[2] < tol:
                        sign = -1.0
                    else:
                        continue
                    norm_sq = 0.0
                    for r in range(6):
                        u[r] = sign * (x[0] * edge[0, k0, r] + x[1] * edge[1, k1, r]
                                       + x[2] * edge[2, k2, r])
                        norm_sq += u[r] * u[r]
                    offset = sign / math.sqrt(norm_sq)
                    if offset < 0.0:
                        outside = True
                        break
                    best = min(best, offset)
                if outside:
                    break
            if outside:
                break
        # whole-edge-vertex: unknowns (r_b, alpha_c, beta_c)
        if not outside:
            for p in range(6):  # (edge polygon, vertex polygon); the third is whole
                bb, c = p // 2, (p // 2 + 1 + p % 2) % 3
                for k in range(q):
                    for v in range(q):
                        for i in range(3):
                            m[i, 0] = e0[i, bb, k]
                            m[i, 1] = d[b, i, 2 * c]
                            m[i, 2] = d[b, i, 2 * c + 1]
                        m[bb, 0] += mu_c
                        m[c, 1] += mu[b] * cos_t[v]
                        m[c, 2] += mu[b] * sin_t[v]
                        if _cramer3(m, x) == 0.0 or x[0] == 0.0:
                            continue
                        sign = 1.0 if x[0] > 0.0 else -1.0
                        r_b, alpha, beta = sign * x[0], sign * x[1], sign * x[2]
                        tol = rel_tol * max(math.sqrt(alpha * alpha + beta * beta), r_b)
                        vp, vn = (v - 1) % q, (v + 1) % q
                        if (alpha * (cos_t[v] - cos_t[vp]) + beta * (sin_t[v] - sin_t[vp]) < -tol
                                or alpha * (cos_t[v] - cos_t[vn]) + beta * (sin_t[v] - sin_t[vn])
                                < -tol):
                            continue
                        norm_sq = 0.0
                        for r in range(6):
                            u[r] = (r_b * edge[bb, k, r] + alpha * basis[b, r, 2 * c]
                                    + beta * basis[b, r, 2 * c + 1])
                            norm_sq += u[r] * u[r]
                        offset = sign / math.sqrt(norm_sq)
                        if offset < 0.0:
                            outside = True
                            break
                        best = min(best, offset)
                    if outside:
                        break
                if outside:
                    break
        out[b] = 0.0 if (outside or best == math.inf) else best
    return out
@njit(cache=True)
def narrow_pair(center, radius, vertices, faces, f, scratch, scalars, vectors):
    """Collide one sphere with one face of an indexed mesh (the narrow phase of §3.2-3.3).

    Parameters
    ----------
    center : (3,) float
        Sphere centre P [m].
    radius : float
        Sphere radius r [m].
    vertices : (n, 3) float
        Mesh vertices [m] (an (n, 6) state works too: only the first three columns are read).
    faces : (f, 3) int
        Vertex indices, counter-clockwise seen from outside.
    f : int
        Face index.
    scratch : (9, 3) float
        Work array.
    scalars : (4,) float
        Output on a hit: (depth delta_max of Eq. 11, distance ``|P - P_face|``, height z0',
        overlap ``r - |P - P_face|``) [m].
    vectors : (4, 3) float
        Output on a hit: (P_face, P_finger, outward face normal, barycentric weights of P_face).

    Returns
    -------
    key : int
        -1 when the sphere does not reach the face (degenerate faces never collide), else the
        region key of :func:`sphere_faces`.
    """
    r_sq = radius * radius
    tri, edges, rel = scratch[0:3], scratch[3:6], scratch[6:9]
    for v in range(3):
        for j in range(3):
            tri[v, j] = vertices[faces[f, v], j]
    for v in range(3):
        for j in range(3):
            edges[v, j] = tri[(v + 1) % 3, j] - tri[v, j]
            rel[v, j] = center[j] - tri[v, j]
    # raw normal = AB x AC = e0 x (-e2)
    nx = -(edges[0, 1] * edges[2, 2] - edges[0, 2] * edges[2, 1])
    ny = -(edges[0, 2] * edges[2, 0] - edges[0, 0] * edges[2, 2])
    nz = -(edges[0, 0] * edges[2, 1] - edges[0, 1] * edges[2, 0])
    double_area = math.sqrt(nx * nx + ny * ny + nz * nz)
    if not double_area > 0.0:
        return -1
    n0, n1, n2 = nx / double_area, ny / double_area, nz / double_area
    height = rel[0, 0] * n0 + rel[0, 1] * n1 + rel[0, 2] * n2
    nearest = 0
    min_perp = np.inf
    perp0 = perp1 = perp2 = 0.0
    t0 = t1 = t2 = 0.0
    off0 = off1 = off2 = 0.0
    esq0 = esq1 = esq2 = 0.0
    for v in range(3):
        ex, ey, ez = edges[v, 0], edges[v, 1], edges[v, 2]
        edge_sq = max(ex * ex + ey * ey + ez * ez, _TINY)
        inv_len = 1.0 / math.sqrt(edge_sq)
        # m_v = n x e_v / |e_v|
        mx = (n1 * ez - n2 * ey) * inv_len
        my = (n2 * ex - n0 * ez) * inv_len
        mz = (n0 * ey - n1 * ex) * inv_len
        rx, ry, rz = rel[v, 0], rel[v, 1], rel[v, 2]
        perp = rx * mx + ry * my + rz * mz
        min_perp = min(min_perp, perp)
        t = min(max((rx * ex + ry * ey + rz * ez) / edge_sq, 0.0), 1.0)
        ox, oy, oz = rx - t * ex, ry - t * ey, rz - t * ez
        offset_sq = ox * ox + oy * oy + oz * oz
        if v == 0:
            perp0, t0, off0, esq0 = perp, t, offset_sq, edge_sq
        elif v == 1:
            perp1, t1, off1, esq1 = perp, t, offset_sq, edge_sq
            if off1 < off0:
                nearest = 1
        else:
            perp2, t2, off2, esq2 = perp, t, offset_sq, edge_sq
            if off2 < (off0 if nearest == 0 else off1):
                nearest = 2
    inside = min_perp >= 0.0
    near_off = off0 if nearest == 0 else (off1 if nearest == 1 else off2)
    dist_sq = height * height if inside else near_off
    if not dist_sq < r_sq:
        return -1
    if inside:
        # weight of vertex v: s_{v+1} |e_{v+1}| / (2 area)
        w0 = perp1 * math.sqrt(esq1) / double_area
        w1 = perp2 * math.sqrt(esq2) / double_area
        w2 = perp0 * math.sqrt(esq0) / double_area
        key = 2 + (1 if r_sq - height * height <= min_perp * min_perp else 0)
    else:
        t_edge = t0 if nearest == 0 else (t1 if nearest == 1 else t2)
        w0 = w1 = w2 = 0.0
        if nearest == 0:
            w0, w1 = 1.0 - t_edge, t_edge
        elif nearest == 1:
            w1, w2 = 1.0 - t_edge, t_edge
        else:
            w2, w0 = 1.0 - t_edge, t_edge
        key = 1 if (t_edge <= 0.0 or t_edge >= 1.0) else 0
    depth = math.sqrt(r_sq - max(dist_sq - height * height, 0.0)) - height
    normal = (n0, n1, n2)
    for j in range(3):
        point = w0 * tri[0, j] + w1 * tri[1, j] + w2 * tri[2, j]
        vectors[0, j] = point
        vectors[1, j] = point - depth * normal[j]
        vectors[2, j] = normal[j]
    vectors[3, 0], vectors[3, 1], vectors[3, 2] = w0, w1, w2
    distance = math.sqrt(dist_sq)
    scalars[0] = depth
    scalars[1] = distance
    scalars[2] = height
    scalars[3] = radius - distance
    return key
