"""Winding numbers of closed triangulated surfaces: which points a surface encloses.

:func:`graspcampaign.core.mesh_file.check_one_body` tells a second body from a cavity with them.
Shape letters: ``p`` query points, ``f`` faces.
"""

from __future__ import annotations

import numpy as np

__all__ = ["winding_numbers"]


def winding_numbers(points: np.ndarray, triangles: np.ndarray) -> np.ndarray:
    """Return the winding number of a closed triangulated surface about each point.

    Parameters
    ----------
    points : (p, 3) float
        Query points [m].
    triangles : (f, 3, 3) float
        Corners of the surface's faces [m], in their winding order.

    Returns
    -------
    (p,) float
        The signed solid angle the surface subtends at each point over ``4 pi``: +1 inside an
        outward-wound closed surface, -1 inside an inward-wound one, 0 outside (up to rounding).

    References
    ----------
    Van Oosterom, A. & Strackee, J. (1983). The solid angle of a plane triangle. IEEE Trans.
    Biomed. Eng. 30(2), 125-126 (``tan(Omega / 2) = a.(b x c) / (|a||b||c| + (a.b)|c| +
    (b.c)|a| + (c.a)|b|)``). Jacobson, A., Kavan, L. & Sorkine-Hornung, O. (2013). Robust
    inside-outside segmentation using generalized winding numbers. ACM TOG 32(4), 33.
    """
    points = np.asarray(points, dtype=float).reshape(-1, 3)
    triangles = np.asarray(triangles, dtype=float).reshape(-1, 3, 3)
    out = np.empty(len(points))
    block = max(1, 2**20 // max(len(triangles), 1))  # about 2**20 point-face pairs at a time
    for start in range(0, len(points), block):
        rel = triangles[None, :, :, :] - points[start:start + block, None, None, :]
        a, b, c = rel[:, :, 0], rel[:, :, 1], rel[:, :, 2]
        la, lb, lc = (np.linalg.norm(v, axis=-1) for v in (a, b, c))
        det = np.einsum("pfi,pfi->pf", a, np.cross(b, c))
        dots = (np.einsum("pfi,pfi->pf", a, b) * lc + np.einsum("pfi,pfi->pf", b, c) * la
                + np.einsum("pfi,pfi->pf", c, a) * lb)
        out[start:start + block] = (2.0 * np.arctan2(det, la * lb * lc + dots)).sum(axis=1)
    return out / (4.0 * np.pi)
