"""Contact-level slip statics of a held three-finger grasp (paper §9.1, §9.3; Eq. 15-16).

Given the contacts, their normal forces and an external wrench, the tangential (friction) forces
of three point contacts are determinate (six unknowns, six balance equations). This module solves
them, finds the disturbance scale at which each contact reaches its friction capacity -- the
*first finger to slip* the planner predicts (§9.3: "identifies which finger slips first") -- and
gives the Mindlin partial-slip displacement of a pad below gross slip. The grasp-level budget
(safety factor, G_geo, grip sizing, predicted limits) is :mod:`graspcampaign.core.disturbance`.

Shape letters: ``c = 3`` contacts.

References
----------
Murray, Li & Sastry (1994), A Mathematical Introduction to Robotic Manipulation, §5.2 (contact
wrenches, grasp statics). Johnson, K. L. (1985), Contact Mechanics, §7.2 (Mindlin partial slip,
Eq. 7.42). Paper §9.1, §9.3, Eq. 15-16.
"""

from __future__ import annotations

import logging

import numpy as np

from graspcampaign.core.disturbance import DISTURBANCE_KINDS, KAPPA, unit_normals
from graspcampaign.core.statics import GRAVITY

__all__ = [
    "contact_tangential_forces",
    "disturbance_wrench",
    "first_slip_finger",
    "microslip",
    "slip_load_factors",
]

logger = logging.getLogger(__name__)


def _cross(a: np.ndarray, b: np.ndarray) -> np.ndarray:
    """Cross products of (..., 3) arrays, written out: np.cross costs ~0.1 ms per call here."""
    return np.stack([a[..., 1] * b[..., 2] - a[..., 2] * b[..., 1],
                     a[..., 2] * b[..., 0] - a[..., 0] * b[..., 2],
                     a[..., 0] * b[..., 1] - a[..., 1] * b[..., 0]], axis=-1)


def _tangent_bases(normals: np.ndarray) -> np.ndarray:
    """Return (3, 3, 2) orthonormal tangent bases; the first tangent points as far up as possible."""
    n = np.asarray(normals, dtype=float)
    up = np.array([0.0, 0.0, 1.0]) - n[:, 2:3] * n
    flat = np.linalg.norm(up, axis=1) < 1e-9  # vertical normal: any horizontal pair
    up[flat] = np.array([1.0, 0.0, 0.0]) - n[flat, 0:1] * n[flat]
    t1 = up / np.linalg.norm(up, axis=1, keepdims=True)
    return np.stack([t1, _cross(n, t1)], axis=2)


def _tangential_solve(points, normals, normal_forces, centroid, forces, moments) -> np.ndarray:
    """Tangential forces (w, 3, 3) for w external wrenches ``forces``, ``moments`` (w, 3)."""
    p = np.asarray(points, dtype=float) - np.asarray(centroid, dtype=float)
    n = unit_normals(normals)
    fn = np.asarray(normal_forces, dtype=float).reshape(3)
    bases = _tangent_bases(n)
    t = np.transpose(bases, (0, 2, 1)).reshape(6, 3)  # row 2j+k: tangent k of contact j
    a = np.vstack([t.T, _cross(np.repeat(p, 2, axis=0), t).T])  # (6, 6)
    normal_vectors = -fn[:, None] * n
    own = np.concatenate([normal_vectors.sum(axis=0), _cross(p, normal_vectors).sum(axis=0)])
    rhs = -(own[None, :] + np.hstack([np.atleast_2d(forces), np.atleast_2d(moments)]))
    x = np.linalg.lstsq(a, rhs.T, rcond=None)[0].T  # (w, 6)
    return np.einsum("jik,wjk->wji", bases, x.reshape(-1, 3, 2))


def contact_tangential_forces(points, normals, normal_forces, centroid, force, moment):
    """Solve the determinate statics of three contacts with given normal forces.

    Parameters
    ----------
    points : (3, 3) float
        Contact points [m].
    normals : (3, 3) float
        Outward unit normals.
    normal_forces : (3,) float
        Normal force of each finger [N] (applied along ``-n``).
    centroid : (3,) float
        Reference point of the moments (object centre of mass) [m].
    force : (3,) float
        External force on the object other than the contacts, incl. weight [N].
    moment : (3,) float
        External moment about ``centroid`` [N m].

    Returns
    -------
    tangential : (3, 3) float
        Tangential (friction) force of each contact [N]: the unique in-plane forces (6 unknowns)
        that satisfy force and moment balance (6 equations); least-norm when the 6 x 6 system is
        singular.

    References
    ----------
    Murray, Li & Sastry (1994) §5.2.
    """
    return _tangential_solve(points, normals, normal_forces, centroid,
                             np.asarray(force, dtype=float), np.asarray(moment, dtype=float))[0]


def disturbance_wrench(kind: str, level: float, direction_deg: float = 0.0):
    """Return the external (force [N], moment [N m]) of a unit-described disturbance at the COM.

    ``lateral``: horizontal force ``level`` at azimuth ``direction_deg``; ``down`` / ``up``:
    vertical force; ``yaw``: moment ``level`` about +z; ``none``: zero.
    """
    force = np.zeros(3)
    moment = np.zeros(3)
    if kind == "lateral":
        a = np.radians(direction_deg)
        force[:2] = level * np.array([np.cos(a), np.sin(a)])
    elif kind == "down":
        force[2] = -level
    elif kind == "up":
        force[2] = level
    elif kind == "yaw":
        moment[2] = level
    elif kind != "none":
        raise ValueError(f"kind must be one of {DISTURBANCE_KINDS}, got {kind!r}")
    return force, moment


def slip_load_factors(points, normals, normal_forces, centroid, capacities, base_force,
                      base_moment, unit_force, unit_moment) -> np.ndarray:
    """Return, per contact, the disturbance scale at which its friction reaches its capacity.

    The tangential forces are affine in the disturbance scale ``s``:
    ``f_t,j(s) = a_j + s b_j`` (base wrench plus ``s`` times the unit wrench); contact j saturates
    at the smallest ``s >= 0`` beyond which ``|a_j + s b_j| > capacity_j``. A contact exactly on its
    cone sticks (Eq. 16, ``<=``): it saturates at 0 if the disturbance loads it, else where it
    meets the cone again.

    Returns
    -------
    scales : (3,) float
        0 when the contact already slips under the base wrench; inf when it never saturates.
    """
    base_f, base_m = np.asarray(base_force, dtype=float), np.asarray(base_moment, dtype=float)
    a, ab = _tangential_solve(points, normals, normal_forces, centroid,
                              np.stack([base_f, base_f + unit_force]),
                              np.stack([base_m, base_m + unit_moment]))
    b = ab - a
    cap = np.asarray(capacities, dtype=float).reshape(3)
    qa = np.einsum("ij,ij->i", b, b)
    qb = 2.0 * np.einsum("ij,ij->i", a, b)
    qc = np.einsum("ij,ij->i", a, a) - cap**2
    out = np.full(3, np.inf)
    for j in range(3):
        if qc[j] > 0.0:  # beyond the cone; on it (0) the root below is 0 or the next meeting
            out[j] = 0.0
        elif qa[j] > 1e-18:
            out[j] = (-qb[j] + np.sqrt(qb[j] ** 2 - 4.0 * qa[j] * qc[j])) / (2.0 * qa[j])
    return out


def first_slip_finger(points, normals, normal_forces, centroid, mass, mu_s, kind, direction_deg=0.0,
                      kappa=KAPPA, g=GRAVITY) -> int:
    """Return the finger (1-3) whose contact saturates first as a disturbance grows; 0 if none.

    Parameters
    ----------
    points, normals : (3, 3) float
        Contacts and outward normals.
    normal_forces : (3,) float
        Per-finger normal forces [N].
    centroid : (3,) float
        Object centre of mass [m].
    mass : float
        [kg]; the weight is the base load.
    mu_s : float
        Friction coefficient; each contact's capacity is ``kappa mu_s f_n,j``.
    kind : {"none", "lateral", "down", "up", "yaw"}
        Disturbance family (``none``: the weight itself is scaled).
    direction_deg : float
        Azimuth of a lateral disturbance.

    Returns
    -------
    finger : int
        1-based index, ties broken by the lower index.
    """
    weight = np.array([0.0, 0.0, -mass * g])
    caps = kappa * mu_s * np.asarray(normal_forces, dtype=float)
    if kind == "none":
        base_f, base_m = np.zeros(3), np.zeros(3)
        unit_f, unit_m = weight, np.zeros(3)
    else:
        base_f, base_m = weight, np.zeros(3)
        unit_f, unit_m = disturbance_wrench(kind, 1.0, direction_deg)
    scales = slip_load_factors(points, normals, normal_forces, centroid, caps, base_f, base_m,
                               unit_f, unit_m)
    if not np.any(np.isfinite(scales)):
        return 0
    return int(np.argmin(scales)) + 1


def microslip(utilisation, capacity, k_t):
    """Return the Mindlin partial-slip tangential displacement of a contact [m].

    Parameters
    ----------
    utilisation : float or (...) float
        ``Q / Q_cap`` in [0, 1] (clipped).
    capacity : float or (...) float
        Tangential capacity ``Q_cap`` of the contact [N].
    k_t : float or (...) float
        Initial tangential (stick) stiffness [N/m] (Table 4).

    Returns
    -------
    displacement : float or (...) float
        ``(3 Q_cap / (2 k_t)) (1 - (1 - u)^(2/3))``: ``Q / k_t`` for small u, ``1.5 Q_cap / k_t``
        at the onset of gross slip.

    References
    ----------
    Johnson (1985) Eq. 7.42 with the initial stiffness ``k_t = 8 a G*``.
    """
    u = np.clip(np.asarray(utilisation, dtype=float), 0.0, 1.0)
    return 1.5 * np.asarray(capacity) / np.asarray(k_t) * (1.0 - (1.0 - u) ** (2.0 / 3.0))
