"""One step of the dynamic three-finger grasp of a deforming MSD body (paper §3, Fig. 3; SPEC §2.6).

Every time step the pipeline of Fig. 3 runs once: collision of each fingertip with the *deformed*
mesh (``core.geometry``), normal force by the contact law with its rate term (Eq. 13), tangential
force by Coulomb stick-slip with per-finger state (Eq. 15-16), transfer to the face vertices by
Phi^T (Eq. 17-18), one RK4 step of the MSD body under gravity (Eq. 5, ``core.msd``). The phases of
Fig. 11 (closure with the object supported, lift-off, hold) and the Eq. 19 verdict are driven by
``core.grasp_phases``, which only sets the command of each step (finger advance rates and the
support's share of the load) and calls :func:`grasp_step`.

Shape letters: ``n`` nodes, ``c`` fingers (contacts).

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
from dataclasses import dataclass, replace

import numpy as np
import trimesh

from graspcampaign.core import geometry
from graspcampaign.core.contact import (
    ContactParams,
    StickSlipParams,
    StickSlipState,
    normal_force,
    normal_stiffness,
    tangential_force,
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
    "FingerContacts",
    "GraspForces",
    "GraspParams",
    "GraspSetup",
    "GraspState",
    "finger_centers",
    "finger_contacts",
    "grasp_forces",
    "grasp_step",
    "hand_contact_directions",
    "planned_contacts",
    "prepare_grasp",
    "rigid_body_part",
]

logger = logging.getLogger(__name__)


@dataclass(frozen=True)
class GraspParams:
    """Constants of the dynamic grasp (the step and the phases of Fig. 11).

    Attributes
    ----------
    tau_f : float
        Vertical-residual tolerance of Eq. 19 [N]. Default 0.5 N, the simulation criterion of
        §3.7 / §6.1.
    settle_time : float
        After lift-off the residual must stay below ``tau_f`` this long to declare the grasp
        stable [s]. Default 0.05 s, about one period of the lowest elastic mode of the 0.4 kg
        reference sphere.
    grip_speed : float
        Finger advance rate while closing, while ``|w R_z| >= tau_f`` after lift-off begins, and of
        any finger out of contact [m/s] (the grip increment is ``grip_speed * dt`` per step).
        Default 20 mm/s, a slow closing speed (§3.5: low approach speeds).
    settle_speed : float
        The centroid speed must also stay below this during ``settle_time`` [m/s]. Default
        5 mm/s. The residual test alone (§3.7) would accept a body sliding out of the hand at
        constant velocity (zero net force).
    seed_depth : float
        Closure target: each finger closes until its own penetration reaches this depth [m];
        0.5 mm, the contact seed of §5.1 and Algorithm 2 line 1.
    open_gap : float
        Fingers start this far outside the surface along their approach lines [m] (Fig. 11,
        "opening"); default 1 mm, the per-contact design limit of §5.5. Only the closure time
        depends on it: nothing touches the held body before the fingers do.
    lift_time : float
        Duration of the lift-off ramp of the load fraction ``w`` from 0 to 1 [s] (raised cosine:
        finite jerk). Default 0.1 s, over twice the period of the lowest elastic mode of the
        0.4 kg reference sphere (42 ms), so the weight reaches the fingers quasi-statically.
    t_max : float
        Simulated time budget of the whole grasp [s].
    dt : float or None
        RK4 step [s]; None: half of :func:`core.msd.body_step_limit` with the stick spring ``k_t``
        (plus the normal contact stiffness at the fingertip radius when ``n >= 1``) and the dampers
        ``c_t + C`` added per node.
    max_depth : float or None
        Stop (``"penetration_limit"``) when a fingertip penetrates deeper [m]; None: the fingertip
        radius r, the limit of ``valid_geometry`` (beyond it the sphere centre is behind the face
        plane and Eq. 11 no longer describes a surface contact). A larger value lets a run go on
        with invalid contacts, for the unbounded reading (``success_unbounded``).
    drop_distance : float
        Declare ``"dropped"`` when the centroid falls this far below its height at lift-off [m].
    k_t : float
        Tangential stick stiffness [N/m]; default 4.96 N/mm (Table 4, reference silicone,
        E = 145.5 kPa, the family closest to E2 = 0.14 MPa).
    c_t : float
        Tangential stabilising damping [N*s/m]; §3.5 leaves it unidentified ("small"). Default
        1.0 N*s/m: about 0.1 of critical for k_t on the three nodes of one face at 0.4 kg / 356.
    """

    tau_f: float = 0.5
    settle_time: float = 0.05
    grip_speed: float = 0.02
    settle_speed: float = 5e-3
    seed_depth: float = 5e-4
    open_gap: float = 1e-3
    lift_time: float = 0.1
    t_max: float = 1.0
    dt: float | None = None
    max_depth: float | None = None
    drop_distance: float = 0.02
    k_t: float = 4.96e3
    c_t: float = 1.0

    def __post_init__(self) -> None:
        for name in ("tau_f", "settle_time", "settle_speed", "t_max", "drop_distance", "k_t",
                     "seed_depth", "lift_time"):
            value = getattr(self, name)
            if not np.isfinite(value) or value <= 0.0:
                raise ValueError(f"GraspParams.{name} must be finite and > 0, got {value!r}")
        for name in ("grip_speed", "c_t", "open_gap"):
            value = getattr(self, name)
            if not np.isfinite(value) or value < 0.0:
                raise ValueError(f"GraspParams.{name} must be finite and >= 0, got {value!r}")


@dataclass(frozen=True)
class GraspForces:
    """Contact evaluation at one state (held over the RK4 stages of the following step).

    Attributes
    ----------
    contacts : FingerContacts
    normal_forces : (c,) float
        f_n [N].
    tangential : (c, 3) float
        Tangential forces on the object [N].
    forces : (c, 3) float
        Total contact forces on the object ``f_n (-n_f) + f_t`` [N].
    residual : (3,) float
        Eq. 19 ``sum_j f_j + m g`` [N] (the fingers against the full weight).
    support_force : (3,) float
        Force of the support on the body [N]: ``-(1 - w)`` times the other net external force
        ``sum_j f_j + m g - b sum_i v_i`` (edge and volume forces are internal and sum to zero),
        with ``w`` the load fraction of the step that led to this state.
    nodal_forces : (n, 3) float
        ``Phi^T`` transfer of ``forces`` to the nodes [N].
    relative_velocity : (c, 3) float
        Face material point relative to the fingertip [m/s].
    stick : StickSlipState
        Stick-slip state after this evaluation (committed by the next step).
    """

    contacts: FingerContacts
    normal_forces: np.ndarray
    tangential: np.ndarray
    forces: np.ndarray
    residual: np.ndarray
    support_force: np.ndarray
    nodal_forces: np.ndarray
    relative_velocity: np.ndarray
    stick: StickSlipState


@dataclass(frozen=True, eq=False)
class GraspSetup:
    """Fixed model of one dynamic grasp (built by :func:`prepare_grasp`).

    Attributes
    ----------
    body : MsdBody
    msd_params : MsdParams
    contact : ContactParams
    grasp : GraspParams
    stick : StickSlipParams
        ``mu_s = mu_k = mu``, k_t, c_t.
    targets : (c, 3) float
        Planned contact points on the undeformed surface [m].
    approach : (c, 3) float
        Outward unit normals of the approach lines.
    dt : float
        RK4 step [s].
    max_depth : float
        Penetration at which a run stops (``"penetration_limit"``) [m].
    valid_depth : float
        Largest penetration of a physically valid contact: the fingertip radius r [m].
    """

    body: MsdBody
    msd_params: MsdParams
    contact: ContactParams
    grasp: GraspParams
    stick: StickSlipParams
    targets: np.ndarray
    approach: np.ndarray
    dt: float
    max_depth: float
    valid_depth: float

    @property
    def mu(self) -> float:
        """Friction coefficient [-]."""
        return self.stick.mu_k

    @property
    def weight(self) -> np.ndarray:
        """(3,) weight ``(0, 0, -m g)`` [N]."""
        return np.array([0.0, 0.0, -self.msd_params.mass * self.msd_params.g])

    @property
    def n_fingers(self) -> int:
        """Number of fingers c."""
        return int(len(self.targets))


@dataclass(frozen=True)
class GraspState:
    """Evolving state of a dynamic grasp; :func:`grasp_step` returns a new one, never mutates.

    Attributes
    ----------
    time : float
        [s].
    state : (6 n,) float
        MSD state (``core.msd`` layout).
    grip : (c,) float
        Finger advance past first touch [m] (negative: open).
    grip_rate : (c,) float
        Command: finger advance rate during the next step [m/s] (also the finger velocity used
        in ``contact``, the rate of the step that led here).
    load_fraction : float
        Command: share ``w`` of the net external wrench the support leaves to the body during the
        next step [-] (0: held, 1: free).
    stick : StickSlipState
        Per-finger stick anchors in the slip-coordinate space (committed).
    slip_coords : (c, 3) float
        Integrated relative displacement of the contact material point w.r.t. the fingertip [m].
    contact : GraspForces
        Contact evaluation at this state (positions, grip, stick state above).
    """

    time: float
    state: np.ndarray
    grip: np.ndarray
    grip_rate: np.ndarray
    load_fraction: float
    stick: StickSlipState
    slip_coords: np.ndarray
    contact: GraspForces

    def commanded(self, grip_rate, load_fraction: float) -> GraspState:
        """Return this state with the command for the next step replaced."""
        # The constructor, not dataclasses.replace: this runs once per step of every grasp, and
        # replace() costs several times more.
        return GraspState(self.time, self.state, self.grip,
                          np.asarray(grip_rate, dtype=np.float64), float(load_fraction),
                          self.stick, self.slip_coords, self.contact)


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
