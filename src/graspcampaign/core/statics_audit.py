"""Audits of a grasp's statics built on :mod:`graspcampaign.core.statics`: the §12 horizontal
residual with fixed normal magnitudes (the audit of Fig. 13) and the §6.1 diagnosis of why normal
forces alone can or cannot hold an object (force or torque balance).

Conventions as :mod:`graspcampaign.core.statics`: world z up, outward unit normals ``n_out``,
the normal force a finger applies is ``f_n (-n_out)``.

References
----------
§6.1 (closed-form static feasibility of the 45/45/-90 set as mu -> 0), §12 (the horizontal audit
of Fig. 13). Murray, Li & Sastry (1994), A Mathematical Introduction to Robotic Manipulation,
§5.2-5.3.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np
from scipy.optimize import linprog

from graspcampaign.core.statics import (
    GRAVITY,
    check_contacts,
    friction_cone_feasibility,
    tangent_bases,
    wrench_residual,
)

__all__ = ["FrictionlessDiagnosis", "frictionless_diagnosis", "min_horizontal_residual"]


def min_horizontal_residual(
    normals,
    normal_forces,
    mu: float,
    n_facets: int = 64,
) -> float:
    """Return the smallest |horizontal net force| reachable with fixed normal forces.

    Parameters
    ----------
    normals : (c, 3) float
        Outward unit normals.
    normal_forces : (c,) float
        Prescribed normal force magnitudes f_n >= 0 [N] (any consistent unit).
    mu : float
        Friction coefficient; each tangential force is free within ``|f_t| <= mu f_n`` [-].
    n_facets : int
        Facets q of both the friction cones (inscribed q-gons) and of the Euclidean norm of the
        residual (``max_k e_k . r``). With r* the exact minimum the returned value lies in
        ``[cos(pi/q) r*, r* + (1 - cos(pi/q)) mu sum f_n]`` (0.12 % at q = 64).

    Returns
    -------
    residual : float
        ``min || (sum_j f_j)_xy ||`` over admissible tangential forces [same unit as the forces].
        Scale-free in the sense of §12: scaling all f_n scales the result.

    References
    ----------
    §12 (the horizontal audit of the Fig. 13 magnitudes: >= 1.6 at mu = 0.1 in the paper's units).
    """
    normals = np.asarray(normals, dtype=np.float64)
    normals = normals / np.linalg.norm(normals, axis=1)[:, None]
    f_n = np.asarray(normal_forces, dtype=np.float64)
    n_contacts = len(normals)
    t1, t2 = tangent_bases(normals)
    angles = 2.0 * np.pi * np.arange(n_facets) / n_facets
    dirs = np.column_stack([np.cos(angles), np.sin(angles)])
    fixed = -(f_n[:, None] * normals).sum(axis=0)[:2]
    # Unknowns: (a_j, b_j) per contact, then s. Residual_xy = fixed + sum a t1_xy + b t2_xy.
    tang = np.stack([t1[:, :2], t2[:, :2]], axis=1).reshape(2 * n_contacts, 2)  # rows a_j, b_j
    a_norm = np.hstack([dirs @ tang.T, -np.ones((n_facets, 1))])
    b_norm = -dirs @ fixed
    rho = np.cos(np.pi / n_facets)
    a_cone = np.zeros((n_contacts * n_facets, 2 * n_contacts + 1))
    b_cone = np.repeat(rho * mu * f_n, n_facets)
    for j in range(n_contacts):  # LP assembly over a handful of contacts
        a_cone[j * n_facets : (j + 1) * n_facets, 2 * j : 2 * j + 2] = dirs
    cost = np.zeros(2 * n_contacts + 1)
    cost[-1] = 1.0
    result = linprog(
        cost,
        A_ub=np.vstack([a_norm, a_cone]),
        b_ub=np.concatenate([b_norm, b_cone]),
        bounds=[(None, None)] * (2 * n_contacts) + [(0.0, None)],
        method="highs",
    )
    if result.status != 0:
        raise RuntimeError(f"horizontal-residual LP failed: {result.message}")
    return float(result.x[-1])


@dataclass(frozen=True)
class FrictionlessDiagnosis:
    """Why normal forces alone can or cannot hold an object (the ``mu -> 0`` limit of §6.1).

    Attributes
    ----------
    status : str
        :func:`friction_cone_feasibility` at ``mu = 0`` (force and torque balance; exact: the cones
        are rays).
    reason : str
        ``"feasible"``; ``"force_balance"``: no non-negative normal forces balance the weight even
        in force alone; ``"torque_balance"``: some do, but none of them balances the torque too
        (the normals' lines of action miss the centre of mass).
    force_only_status : str
        The same LP with the torque rows trivially satisfied (every point moved to ``center``).
    torque_residual : float or None
        Norm of the torque about ``center`` of the force-only solution (the unique one for three
        independent normals) [N*m]; None when force balance alone fails.
    off_radial_deg : (c,) float
        Angle between each normal and the direction from ``center`` to its point [deg]: the
        facet-normal error of a meshed sphere (0 for an ideal sphere).
    """

    status: str
    reason: str
    force_only_status: str
    torque_residual: float | None
    off_radial_deg: np.ndarray


def frictionless_diagnosis(
    points,
    normals,
    mass: float,
    center=(0.0, 0.0, 0.0),
    g: float = GRAVITY,
) -> FrictionlessDiagnosis:
    """Decide whether normal forces alone hold the object and, if not, which balance fails.

    Parameters
    ----------
    points : (c, 3) float
        Contact points in W [m].
    normals : (c, 3) float
        Outward unit normals.
    mass : float
        Object mass [kg].
    center : (3,) float
        Centre of mass [m].
    g : float
        Gravity [m/s^2].

    Returns
    -------
    diagnosis : FrictionlessDiagnosis

    Notes
    -----
    §6.1 argues that on the ideal sphere the 45/45/-90 normals alone carry the weight (all lines
    of action pass through the centre, so torque balance is automatic). On a meshed sphere the
    contact normals are facet normals a few degrees off radial: the force-only problem tells
    whether the failure is already in the force balance (e.g. every normal leaning to the same
    side out of the plane of the fingers) or only in the torque balance.

    References
    ----------
    §6.1 (the mu -> 0 feasibility of the 45/45/-90 set), Murray, Li & Sastry (1994) §5.3.
    """
    points, normals = check_contacts(points, normals)
    center = np.asarray(center, dtype=np.float64)
    full = friction_cone_feasibility(points, normals, 0.0, mass, center, g=g)
    at_center = np.broadcast_to(center, points.shape)
    force_only = friction_cone_feasibility(at_center, normals, 0.0, mass, center, g=g)
    torque = None
    if force_only.forces is not None:
        torque = float(np.linalg.norm(wrench_residual(points, force_only.forces, mass, center, g)[3:]))
    if full.status == "feasible":
        reason = "feasible"
    elif force_only.status != "feasible":
        reason = "force_balance"
    else:
        reason = "torque_balance"
    radial = points - center
    radial /= np.linalg.norm(radial, axis=1)[:, None]
    cosines = np.clip(np.einsum("ij,ij->i", radial, normals), -1.0, 1.0)
    return FrictionlessDiagnosis(
        status=full.status,
        reason=reason,
        force_only_status=force_only.status,
        torque_residual=torque,
        off_radial_deg=np.degrees(np.arccos(cosines)),
    )
