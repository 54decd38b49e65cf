"""The contact-modelling stage of the dynamic grasp (Fig. 3) and the kinematic support.

:func:`grasp_forces` runs once per state: collision of each fingertip with the deformed mesh
(``core.hand``, ``core.geometry``), normal force by the contact law with its rate term (Eq. 13),
tangential force by Coulomb stick-slip (Eq. 15-16), transfer to the face vertices by Phi^T
(Eq. 17-18), the Eq. 19 residual and the support force. :func:`rigid_body_part` is the
rigid-body part of the nodal accelerations the support removes a share of (see
:mod:`graspcampaign.core.dynamics`).

Shape letters: ``n`` nodes, ``c`` fingers (contacts).

References
----------
§3 (Fig. 3), §3.2-3.7 (Eq. 10-19). Hunt & Crossley (1975). Goldstein, H., Poole, C. & Safko, J.
(2002), Classical Mechanics, 3rd ed., §5.1-5.3 (rigid body: momentum, angular momentum, inertia
tensor).
"""

from __future__ import annotations

import numpy as np

from graspcampaign.core import geometry
from graspcampaign.core.contact import normal_force, tangential_force
from graspcampaign.core.grasp_state import GraspForces, GraspSetup, GraspState
from graspcampaign.core.hand import finger_contacts

__all__ = [
    "finger_centers",
    "grasp_forces",
    "rigid_body_part",
]


def finger_centers(setup: GraspSetup, grip) -> np.ndarray:
    """Return the (c, 3) fingertip centres ``p_j + n_j (r - s_j)`` for finger advances ``grip`` [m]."""
    radius = setup.contact.fingertip_radius
    return setup.targets + setup.approach * (radius - np.asarray(grip))[:, None]


def rigid_body_part(positions: np.ndarray, accelerations: np.ndarray) -> np.ndarray:
    """Return the rigid-body part ``A + alpha x r_i`` of equal-mass nodal accelerations.

    Parameters
    ----------
    positions : (n, 3) float
        Node positions [m].
    accelerations : (n, 3) float
        Node accelerations [m/s^2] (equal node masses).

    Returns
    -------
    rigid : (n, 3) float
        ``A + alpha x r_i`` with ``A`` the mean acceleration (net force / m), ``r_i`` the position
        about the centroid and ``alpha = I^-1 tau`` (``tau = sum_i r_i x a_i``, ``I = sum_i
        (|r_i|^2 1 - r_i r_i^T)``, both per unit node mass) [m/s^2]. Subtracting it leaves
        accelerations with zero net force and zero net torque about the centroid: the reaction
        of a support that holds the body's translation and rotation (at rest) but not its shape.

    References
    ----------
    Goldstein, Poole & Safko (2002) §5.1-5.3.
    """
    share = np.full(len(positions), 1.0 / len(positions))
    r = positions - share @ positions  # (a mat-vec mean: several times faster than .mean(axis=0))
    mean = share @ accelerations
    # 3x3 products only (np.cross on (n, 3) arrays costs several times more): with
    # M = sum_i r_i a_i^T, tau = (M_yz - M_zy, M_zx - M_xz, M_xy - M_yx); with G = sum_i r_i r_i^T,
    # I = tr(G) 1 - G; and alpha x r_i = S r_i, S the cross-product matrix of alpha.
    moment = r.T @ accelerations
    torque = np.array([moment[1, 2] - moment[2, 1], moment[2, 0] - moment[0, 2],
                       moment[0, 1] - moment[1, 0]])
    gram = r.T @ r
    alpha = np.linalg.solve(np.trace(gram) * np.eye(3) - gram, torque)
    skew = np.array([[0.0, -alpha[2], alpha[1]], [alpha[2], 0.0, -alpha[0]],
                     [-alpha[1], alpha[0], 0.0]])
    return mean + r @ skew.T


def grasp_forces(setup: GraspSetup, gs: GraspState) -> GraspForces:
    """Run the contact-modelling stage of Fig. 3 once on a state (``gs.contact`` is not read).

    Returns
    -------
    forces : GraspForces
        Contacts, Eq. 13 normal and Eq. 15-16 tangential forces, their Phi^T transfer (Eq. 17-18),
        the Eq. 19 residual and the support force.
    """
    body, contact = setup.body, setup.contact
    nodes = gs.state.reshape(-1, 6)
    positions, velocities = nodes[:, :3], nodes[:, 3:]
    hits = finger_contacts(
        positions, body, finger_centers(setup, gs.grip), contact.fingertip_radius, setup.approach
    )
    host_nodes = body.faces[np.maximum(hits.faces, 0)]  # (c, 3)
    v_face = geometry.point_velocity(hits.weights, np.take(velocities, host_nodes, axis=0))
    v_rel = v_face + gs.grip_rate[:, None] * setup.approach  # minus the fingertip velocity
    depth_rate = np.einsum("ij,ij->i", v_rel, hits.normals)
    f_n = np.where(
        hits.active,
        normal_force(hits.depths, depth_rate, contact.k_n_per_mm_n, contact.n, contact.c_n_s_per_m,
                     contact.damping_law, contact.alpha_hc_s_per_m),
        0.0,
    )
    # Stick deflection: xi_dot = V_t (§3.5) with V_t of the *material* point of the face (Eq. 12)
    # relative to the fingertip. The "points" handed to the stick-slip law are the integrated
    # relative displacements, so a contact point that jumps between faces of the deforming mesh
    # does not jerk the stick spring.
    slip_coords = np.where(hits.active[:, None], gs.slip_coords, 0.0)
    f_t, stick = tangential_force(gs.stick, setup.stick, slip_coords, f_n, v_rel, hits.normals)
    forces = np.where(hits.active[:, None], -f_n[:, None] * hits.normals + f_t, 0.0)
    nodal = np.zeros((body.n_nodes, 3))
    on = np.flatnonzero(hits.active)
    if on.size:
        np.add.at(nodal, host_nodes[on], geometry.transfer_force(hits.weights[on], forces[on]))
    residual = forces.sum(axis=0) + setup.weight
    damping = setup.msd_params.b * velocities.sum(axis=0)
    return GraspForces(
        contacts=hits,
        normal_forces=f_n,
        tangential=np.where(hits.active[:, None], f_t, 0.0),
        forces=forces,
        residual=residual,
        support_force=-(1.0 - gs.load_fraction) * (residual - damping),
        nodal_forces=nodal,
        relative_velocity=v_rel,
        stick=stick,
    )
