"""One step of the dynamic three-finger grasp of a deforming MSD body (paper §3, Fig. 3; SPEC §2.6).

Every time step the pipeline of Fig. 3 runs once: collision of each fingertip with the *deformed*
mesh (``core.geometry``), normal force by the contact law with its rate term (Eq. 13), tangential
force by Coulomb stick-slip with per-finger state (Eq. 15-16), transfer to the face vertices by
Phi^T (Eq. 17-18), one RK4 step of the MSD body under gravity (Eq. 5, ``core.msd``). The phases of
Fig. 11 (closure with the object supported, lift-off, hold) and the Eq. 19 verdict are driven by
``core.grasp_phases``, which only sets the command of each step (finger advance rates and the
support's share of the load) and calls :func:`grasp_step`.

Shape letters: ``n`` nodes, ``c`` fingers (contacts).

This module prepares the grasp (:func:`prepare_grasp`) and steps it (:func:`grasp_step`); the
parameter, setup and state types live in :mod:`graspcampaign.core.grasp_state`, the
contact-modelling stage and the support's rigid-body part in :mod:`graspcampaign.core.grasp_contact`
(both re-exported here).

The step
--------
``grasp_step(setup, state) -> state`` is a pure function: ``setup`` (:class:`GraspSetup`) is the
fixed model, ``state`` (:class:`GraspState`) everything that evolves, including the command for the
coming step (``grip_rate``, ``load_fraction``) and the contact evaluation at the state's own time
(``contact``, a :class:`GraspForces`). One step: RK4 with the contact forces of ``state.contact``
held over its four stages (§3: "the contact-modelling loop runs once per simulation time-step"),
fingers moved by ``grip_rate * dt``, stick state committed, then the contacts evaluated at the new
positions. A compiled step can replace it as long as it keeps this signature and these fields.

The hand (``core.hand``): each fingertip centre moves on the straight line through its planned
contact point along the outward normal there, ``c_j(s_j) = p_j + n_j (r - s_j)``, ``s_j`` the finger
advance past first touch (negative: open). One contact per fingertip: its deepest colliding face
(Eq. 19 sums over the fingertip contacts ``j = 1..N_c``; summing over every overlapped face would
scale the force with the local face count, i.e. with mesh resolution).

The support
-----------
While the grip closes the object is held kinematically: the support carries the share
``1 - w`` of whatever net force and torque act on the body (``w = load_fraction``), by removing
``(1 - w)`` of the rigid-body part of the nodal accelerations (:func:`rigid_body_part`). ``w = 0``:
the centroid and the body's orientation are held, the body deforms freely under the fingers; ``w =
1``: the body is free under gravity and held by the fingers alone, so the Eq. 19 residual ``sum_j
f_j + m g`` is exactly the net external force on it. Lift-off ramps ``w`` from 0 to 1.

References
----------
§3 (Fig. 3), §3.2-3.7 (Eq. 10-19), §5.1 (seed and clamp guards), §5.5 (Fig. 11). Hunt & Crossley
(1975). Goldstein, H., Poole, C. & Safko, J. (2002), Classical Mechanics, 3rd ed., §5.1-5.3 (rigid
body: momentum, angular momentum, inertia tensor).
"""

from __future__ import annotations

import logging
from dataclasses import replace

import numpy as np
import trimesh

from graspcampaign.core.contact import (
    ContactParams,
    StickSlipParams,
    StickSlipState,
    normal_stiffness,
)
from graspcampaign.core.grasp_contact import (
    finger_centers,
    grasp_forces,
    rigid_body_part,
)
from graspcampaign.core.grasp_state import (
    GraspForces,
    GraspParams,
    GraspSetup,
    GraspState,
)
from graspcampaign.core.hand import (
    FingerContacts,
    finger_contacts,
    hand_contact_directions,
    planned_contacts,
)
from graspcampaign.core.msd import (
    MsdBody,
    MsdParams,
    body_step_limit,
    msd_body_from_mesh,
    msd_rhs,
    rk4_step,
    state_from_positions,
)

__all__ = [
    # preparing and stepping the dynamic grasp (this module)
    "grasp_step",
    "prepare_grasp",
    # re-exported: they live in graspcampaign.core.hand
    "FingerContacts",
    "finger_contacts",
    "hand_contact_directions",
    "planned_contacts",
    # re-exported: they live in graspcampaign.core.grasp_state
    "GraspForces",
    "GraspParams",
    "GraspSetup",
    "GraspState",
    # re-exported: they live in graspcampaign.core.grasp_contact
    "finger_centers",
    "grasp_forces",
    "rigid_body_part",
]

logger = logging.getLogger(__name__)


def prepare_grasp(
    mesh: trimesh.Trimesh,
    mu: float,
    msd_params: MsdParams | None = None,
    contact: ContactParams | None = None,
    grasp: GraspParams | None = None,
    directions=None,
    *,
    points=None,
    normals=None,
    body: MsdBody | None = None,
) -> tuple[GraspSetup, GraspState]:
    """Build the fixed model and the initial state of a dynamic grasp.

    Parameters
    ----------
    mesh : trimesh.Trimesh
        Object surface [m], centred on its centroid.
    mu : float
        Friction coefficient, ``mu_s = mu_k = mu`` as in the simulation sweeps (§3.5) [-].
    msd_params : MsdParams, optional
        Body constants and mass (default :class:`core.msd.MsdParams`).
    contact : ContactParams, optional
        Normal-contact constants (default ``ContactParams.table3()``).
    grasp : GraspParams, optional
        Loop constants.
    directions : (c, 3) float, optional
        Contact directions from the centroid (default :func:`core.hand.hand_contact_directions`);
        ignored when ``points`` are given.
    points, normals : (c, 3) float, optional
        Planned contact points on the undeformed surface [m] and their outward normals (any
        planner's contacts); both or neither.
    body : MsdBody, optional
        The MSD shell of ``mesh`` with ``msd_params``' mass, when the caller already built it
        (a campaign reuses one body, and its cached stiffness spectrum, across trials); default
        :func:`core.msd.msd_body_from_mesh`.

    Returns
    -------
    setup : GraspSetup
    state : GraspState
        At t = 0: the body undeformed and at rest, held (``load_fraction = 0``), every finger
        ``open_gap`` outside the surface, not moving, with its contact evaluation.
    """
    msd_params = msd_params or MsdParams()
    contact = contact or ContactParams.table3()
    grasp = grasp or GraspParams()
    if not np.isfinite(mu) or mu < 0.0:
        raise ValueError(f"mu must be finite and >= 0, got {mu!r}")
    if body is None:
        body = msd_body_from_mesh(mesh, msd_params)
    elif body.n_nodes != len(mesh.vertices) or not np.isclose(body.mass, msd_params.mass):
        raise ValueError(f"body has {body.n_nodes} nodes and {body.mass:g} kg, the mesh "
                         f"{len(mesh.vertices)} nodes and msd_params {msd_params.mass:g} kg")
    if (points is None) != (normals is None):
        raise ValueError("points and normals must be given together")
    if points is None:
        directions = hand_contact_directions() if directions is None else np.asarray(directions, float)
        if directions.ndim != 2 or directions.shape[1] != 3:
            raise ValueError(f"directions must have shape (c, 3), got {directions.shape}")
        targets, _, approach = planned_contacts(mesh, directions)
    else:
        targets = np.array(points, dtype=np.float64)
        approach = np.array(normals, dtype=np.float64)
        if targets.ndim != 2 or targets.shape[1] != 3 or approach.shape != targets.shape:
            raise ValueError(
                f"points and normals must both have shape (c, 3), got {targets.shape} and "
                f"{approach.shape}"
            )
        approach = approach / np.linalg.norm(approach, axis=1)[:, None]
    radius = contact.fingertip_radius
    max_depth = radius if grasp.max_depth is None else float(grasp.max_depth)
    k_extra = grasp.k_t
    if contact.n >= 1.0:  # bounded and increasing: largest at the deepest depth a run reaches
        k_extra += float(normal_stiffness(max_depth, contact.k_n_per_mm_n, contact.n))
    limit = body_step_limit(body, msd_params, k_extra, grasp.c_t + contact.c_n_s_per_m)
    dt = 0.5 * limit if grasp.dt is None else float(grasp.dt)
    if dt > limit:
        logger.warning("dynamic grasp: dt = %.3g s exceeds the RK4 limit %.3g s", dt, limit)
    setup = GraspSetup(
        body=body,
        msd_params=msd_params,
        contact=contact,
        grasp=grasp,
        stick=StickSlipParams(mu_s=mu, mu_k=mu, k_t=grasp.k_t, c_t=grasp.c_t),
        targets=targets,
        approach=approach,
        dt=dt,
        max_depth=max_depth,
        valid_depth=radius,
    )
    n_fingers = len(targets)
    initial = GraspState(
        time=0.0,
        state=state_from_positions(body.rest_positions),
        grip=np.full(n_fingers, -grasp.open_gap),
        grip_rate=np.zeros(n_fingers),
        load_fraction=0.0,
        stick=StickSlipState.initial(np.zeros((n_fingers, 3))),
        slip_coords=np.zeros((n_fingers, 3)),
        contact=None,  # type: ignore[arg-type]  # filled in below
    )
    return setup, replace(initial, contact=grasp_forces(setup, initial))


def grasp_step(setup: GraspSetup, gs: GraspState) -> GraspState:
    """Advance a dynamic grasp by one step under the command carried by ``gs``.

    Parameters
    ----------
    setup : GraspSetup
    gs : GraspState
        Current state with its contact evaluation and the command (``grip_rate``,
        ``load_fraction``) for this step.

    Returns
    -------
    new : GraspState
        At ``gs.time + dt``: one RK4 step of the body with the nodal contact forces of
        ``gs.contact`` held over the stages and the support's share ``1 - w`` of the rigid-body
        accelerations removed at every stage; fingers advanced by ``grip_rate * dt``; the
        stick-slip state of ``gs.contact`` committed and the slip coordinates of the active
        contacts integrated; the same command; contacts evaluated at the new state.

    Raises
    ------
    FloatingPointError
        If the state becomes non-finite (a step beyond the stability limit).

    References
    ----------
    Fig. 3, §3 (one contact evaluation per time step), Eq. 5 (RK4), Eq. 15-16 (stick state).
    """
    dt = setup.dt
    out = gs.contact
    f_ext = out.nodal_forces
    share = 1.0 - gs.load_fraction
    body, params = setup.body, setup.msd_params

    if share > 0.0:
        def rhs(t, x):
            dx = msd_rhs(t, x, body, params, f_ext)
            nodes, rates = x.reshape(-1, 6), dx.reshape(-1, 6)
            rates[:, 3:] -= share * rigid_body_part(nodes[:, :3], rates[:, 3:])
            return dx
    else:
        def rhs(t, x):
            return msd_rhs(t, x, body, params, f_ext)

    state = rk4_step(rhs, gs.time, gs.state, dt)
    if not np.all(np.isfinite(state)):
        raise FloatingPointError(f"dynamic grasp diverged at t = {gs.time:.4g} s (dt = {dt:.3g} s)")
    active = out.contacts.active[:, None]
    new = replace(
        gs,
        time=gs.time + dt,
        state=state,
        grip=gs.grip + gs.grip_rate * dt,
        stick=out.stick,
        slip_coords=np.where(active, gs.slip_coords + out.relative_velocity * dt, 0.0),
    )
    return replace(new, contact=grasp_forces(setup, new))
