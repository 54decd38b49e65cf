"""Dynamic three-finger grasp of a deforming MSD body (paper §3, Fig. 3, §5.5; SPEC §2.6).

Three spherical fingertips move on straight approach lines toward planned contacts on the object.
Every time step the pipeline of Fig. 3 runs once: collision of each fingertip with the *deformed*
mesh (``core.geometry``), normal force by the contact law with its rate term (Eq. 13), tangential
force by Coulomb stick-slip with per-finger state (Eq. 15-16), transfer to the face vertices by
Phi^T (Eq. 17-18), one RK4 step of the MSD body under gravity (Eq. 5, ``core.msd``), then the
static-equilibrium check (Eq. 19): while the vertical residual is above tau_F the grip (finger
advance) is incremented.

Shape letters: ``n`` nodes, ``f`` faces, ``s`` steps, 3 fingers.

How the object is held
----------------------
The object starts undeformed and at rest, with every fingertip already seeded at the 0.5 mm
penetration of §5.1 (Algorithm 1 line 3: end-pose ``p - n (r - 5e-4)``). Its support is removed
at t = 0 ("lift-off"): from then on the body is free under gravity and held by the fingers alone,
so the Eq. 19 residual ``sum_j f_j + m g`` is exactly the net external force on the body, and it
settles to zero only if the fingers really hold it. The approach and descent phases of Fig. 11
are kinematic and are not simulated.

The hand (SynGrasp is not available, and is not imitated): each fingertip centre moves on the
straight line through its planned contact point along the outward face normal there,
``c_j(s_j) = p_j + n_j (r - s_j)``, ``s_j`` the finger advance past first touch. The grip law is
one synchronised closing command (§5.1): all fingers advance at ``grip_speed`` while
``|R_z| >= tau_F``; in addition a finger that has lost contact keeps closing until it touches
again (Fig. 11, "finger closure with progressive contact"). The planned contacts are the surface
points hit by rays from the centroid along directions of the hand-reachable family of §5.2
(:func:`hand_contact_directions`; the paper's optimum is 45/45/-90).

Stable (Eq. 19, §3.7): ``|R_z| < tau_F`` for ``settle_time`` with, in addition, the centroid at
rest and every finger touching within that window (the residual alone would accept a body sliding
out of the hand at constant velocity).

Contact forces are evaluated once per step and held over the RK4 stages (§3: "the
contact-modelling loop runs once per simulation time-step"); the body's own forces are evaluated
at every stage. One contact per fingertip: its deepest colliding face (Eq. 19 sums over the
fingertip contacts ``j = 1..N_c``); summing over every overlapped face would scale the force with
the local face count, i.e. with mesh resolution.

References
----------
§3 (Fig. 3), §3.2-3.7 (Eq. 10-19), §5.1 (seed and clamp guards), §5.2 (reachable family), §5.5
(Figs. 12-13), §6.1 and §12 (six-component residual). Hunt & Crossley (1975).
"""

from __future__ import annotations

import logging
from dataclasses import dataclass

import numpy as np
import trimesh

from graspcampaign.core import geometry
from graspcampaign.core.contact import (
    ContactParams,
    StickSlipParams,
    StickSlipState,
    normal_force,
    tangential_force,
)
from graspcampaign.core.msd import (
    MsdBody,
    MsdParams,
    body_step_limit,
    kinetic_energy,
    msd_body_from_mesh,
    msd_rhs,
    rk4_step,
    state_from_positions,
)
from graspcampaign.core.statics import wrench_residual

__all__ = [
    "STATUSES",
    "DynamicGraspResult",
    "FingerContacts",
    "GraspForces",
    "GraspParams",
    "GraspSetup",
    "GraspState",
    "advance_grasp",
    "dynamic_grasp",
    "finger_centers",
    "finger_contacts",
    "grasp_forces",
    "hand_contact_directions",
    "planned_contacts",
    "prepare_grasp",
]

logger = logging.getLogger(__name__)

STATUSES = ("stable", "not_settled", "penetration_limit", "dropped")
"""Outcome vocabulary of :func:`dynamic_grasp` (``success`` iff ``"stable"``)."""


@dataclass(frozen=True)
class GraspParams:
    """Constants of the dynamic grasp loop.

    Attributes
    ----------
    tau_f : float
        Vertical-residual tolerance of Eq. 19 [N]. Default 0.5 N, the simulation criterion of
        §3.7 / §6.1.
    settle_time : float
        The residual must stay below ``tau_f`` this long to declare the grasp stable [s].
        Default 0.05 s, about one period of the lowest elastic mode of the 0.4 kg reference sphere.
    grip_speed : float
        Finger advance rate while ``|R_z| >= tau_f``, and of any finger out of contact [m/s]
        (the grip increment is ``grip_speed * dt`` per step). Default 20 mm/s, a slow closing
        speed (§3.5: low approach speeds).
    settle_speed : float
        The centroid speed must also stay below this during ``settle_time`` [m/s]. Default
        5 mm/s. The residual test alone (§3.7) would accept a body sliding out of the hand at
        constant velocity (zero net force).
    seed_depth : float
        Initial finger advance ``s`` past first touch [m]; 0.5 mm (§5.1, Algorithm 2 line 1).
    t_max : float
        Simulated time budget [s].
    dt : float or None
        RK4 step [s]; None: half of :func:`core.msd.body_step_limit` with the stick spring
        ``k_t`` and the dampers ``c_t + C`` added per node.
    max_depth : float or None
        Abort when a fingertip penetrates deeper [m]; None: the fingertip radius (beyond it the
        sphere centre is behind the face plane and Eq. 11 no longer describes a surface contact).
    drop_distance : float
        Declare ``"dropped"`` when the centroid falls this far below its start [m].
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
    t_max: float = 1.0
    dt: float | None = None
    max_depth: float | None = None
    drop_distance: float = 0.02
    k_t: float = 4.96e3
    c_t: float = 1.0

    def __post_init__(self) -> None:
        for name in ("tau_f", "settle_time", "settle_speed", "t_max", "drop_distance", "k_t"):
            value = getattr(self, name)
            if not np.isfinite(value) or value <= 0.0:
                raise ValueError(f"GraspParams.{name} must be finite and > 0, got {value!r}")
        for name in ("grip_speed", "seed_depth", "c_t"):
            value = getattr(self, name)
            if not np.isfinite(value) or value < 0.0:
                raise ValueError(f"GraspParams.{name} must be finite and >= 0, got {value!r}")


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
    directions : (3, 3) float
        Ray directions from ``mesh.centroid``.

    Returns
    -------
    points : (3, 3) float
        Outermost hit of each ray [m].
    faces : (3,) int
        Hit faces.
    normals : (3, 3) float
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
    distances = _ray_triangle_distances(origin, directions, triangles)  # (3, f), inf = miss
    points = np.empty_like(directions)
    faces = np.empty(len(directions), dtype=np.int64)
    for j in range(len(directions)):  # three rays
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
    Moller, T. & Trumbore, B. (1997), "Fast, minimum storage ray-triangle intersection",
    Journal of Graphics Tools 2(1):21-28 (symbols e1, e2, p, q, s, u, v, t as in the paper).
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
    active : (3,) bool
        Fingertip touches the mesh.
    depths : (3,) float
        Penetration delta_max of Eq. 11 [m] (0 when inactive).
    faces : (3,) int
        Host face (-1 when inactive).
    points : (3, 3) float
        Contact point P_face [m] (the fingertip's nearest surface point direction when inactive).
    normals : (3, 3) float
        Outward face normal n_f (the approach normal when inactive).
    weights : (3, 3) float
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
    centers : (p, 3) float
        Fingertip centres [m].
    radius : float
        Fingertip radius [m].
    approach_normals : (p, 3) float
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
    targets : (3, 3) float
        Planned contact points on the undeformed surface [m].
    approach : (3, 3) float
        Outward unit normals of the approach lines.
    dt : float
        RK4 step [s].
    max_depth : float
        Validity limit of a penetration [m].
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

    @property
    def mu(self) -> float:
        """Friction coefficient [-]."""
        return self.stick.mu_k

    @property
    def weight(self) -> np.ndarray:
        """(3,) weight ``(0, 0, -m g)`` [N]."""
        return np.array([0.0, 0.0, -self.msd_params.mass * self.msd_params.g])


@dataclass
class GraspState:
    """Evolving state of a dynamic grasp (mutated in place by :func:`advance_grasp`).

    Attributes
    ----------
    time : float
        [s].
    state : (6 n,) float
        MSD state (``core.msd`` layout).
    grip : (3,) float
        Finger advance past first touch [m].
    grip_rate : (3,) float
        Finger advance rate during the last step [m/s].
    stick : StickSlipState
        Per-finger stick anchors in the slip-coordinate space.
    slip_coords : (3, 3) float
        Integrated relative displacement of the contact material point w.r.t. the fingertip [m].
    """

    time: float
    state: np.ndarray
    grip: np.ndarray
    grip_rate: np.ndarray
    stick: StickSlipState
    slip_coords: np.ndarray

    def copy(self) -> GraspState:
        """Return an independent copy (e.g. to rerun a grasp from its initial state)."""
        return GraspState(
            time=self.time,
            state=self.state.copy(),
            grip=self.grip.copy(),
            grip_rate=self.grip_rate.copy(),
            stick=self.stick,  # frozen, and replaced (never mutated) by advance_grasp
            slip_coords=self.slip_coords.copy(),
        )


@dataclass(frozen=True)
class GraspForces:
    """Contact evaluation of one step (held over the RK4 stages).

    Attributes
    ----------
    contacts : FingerContacts
    normal_forces : (3,) float
        f_n [N].
    tangential : (3, 3) float
        Tangential forces on the object [N].
    forces : (3, 3) float
        Total contact forces on the object ``f_n (-n_f) + f_t`` [N].
    residual : (3,) float
        Eq. 19 ``sum_j f_j + m g`` [N].
    nodal_forces : (n, 3) float
        ``Phi^T`` transfer of ``forces`` to the nodes [N].
    relative_velocity : (3, 3) float
        Face material point relative to the fingertip [m/s].
    stick : StickSlipState
        Updated stick-slip state.
    """

    contacts: FingerContacts
    normal_forces: np.ndarray
    tangential: np.ndarray
    forces: np.ndarray
    residual: np.ndarray
    nodal_forces: np.ndarray
    relative_velocity: np.ndarray
    stick: StickSlipState


def prepare_grasp(
    mesh: trimesh.Trimesh,
    mu: float,
    msd_params: MsdParams | None = None,
    contact: ContactParams | None = None,
    grasp: GraspParams | None = None,
    directions=None,
) -> tuple[GraspSetup, GraspState]:
    """Build the fixed model and the initial state of a dynamic grasp (see :func:`dynamic_grasp`)."""
    msd_params = msd_params or MsdParams()
    contact = contact or ContactParams.table3()
    grasp = grasp or GraspParams()
    if not np.isfinite(mu) or mu < 0.0:
        raise ValueError(f"mu must be finite and >= 0, got {mu!r}")
    body = msd_body_from_mesh(mesh, msd_params)
    directions = hand_contact_directions() if directions is None else np.asarray(directions, float)
    if directions.shape != (3, 3):
        raise ValueError(f"directions must have shape (3, 3), got {directions.shape}")
    targets, _, approach = planned_contacts(mesh, directions)
    limit = body_step_limit(body, msd_params, grasp.k_t, grasp.c_t + contact.c_n_s_per_m)
    dt = 0.5 * limit if grasp.dt is None else float(grasp.dt)
    if dt > limit:
        logger.warning("dynamic_grasp: dt = %.3g s exceeds the RK4 limit %.3g s", dt, limit)
    setup = GraspSetup(
        body=body,
        msd_params=msd_params,
        contact=contact,
        grasp=grasp,
        stick=StickSlipParams(mu_s=mu, mu_k=mu, k_t=grasp.k_t, c_t=grasp.c_t),
        targets=targets,
        approach=approach,
        dt=dt,
        max_depth=contact.fingertip_radius if grasp.max_depth is None else grasp.max_depth,
    )
    n_fingers = len(targets)
    initial = GraspState(
        time=0.0,
        state=state_from_positions(body.rest_positions),
        grip=np.full(n_fingers, grasp.seed_depth),
        grip_rate=np.zeros(n_fingers),
        stick=StickSlipState.initial(np.zeros((n_fingers, 3))),
        slip_coords=np.zeros((n_fingers, 3)),
    )
    return setup, initial


def finger_centers(setup: GraspSetup, grip) -> np.ndarray:
    """Return the (3, 3) fingertip centres ``p_j + n_j (r - s_j)`` for finger advances ``grip`` [m]."""
    radius = setup.contact.fingertip_radius
    return setup.targets + setup.approach * (radius - np.asarray(grip))[:, None]


def grasp_forces(setup: GraspSetup, gs: GraspState) -> GraspForces:
    """Run the contact-modelling stage of Fig. 3 once on the current state.

    Returns
    -------
    forces : GraspForces
        Contacts, Eq. 13 normal and Eq. 15-16 tangential forces, their Phi^T transfer (Eq. 17-18)
        and the Eq. 19 residual. ``gs`` is not modified.
    """
    body, contact = setup.body, setup.contact
    nodes = gs.state.reshape(-1, 6)
    positions, velocities = nodes[:, :3], nodes[:, 3:]
    hits = finger_contacts(
        positions, body, finger_centers(setup, gs.grip), contact.fingertip_radius, setup.approach
    )
    host_nodes = body.faces[np.maximum(hits.faces, 0)]  # (3, 3)
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
    return GraspForces(
        contacts=hits,
        normal_forces=f_n,
        tangential=np.where(hits.active[:, None], f_t, 0.0),
        forces=forces,
        residual=forces.sum(axis=0) + setup.weight,
        nodal_forces=nodal,
        relative_velocity=v_rel,
        stick=stick,
    )


def advance_grasp(setup: GraspSetup, gs: GraspState, forces: GraspForces) -> None:
    """Take one RK4 step with the contact forces held, then apply the grip law (in place).

    Notes
    -----
    Grip law (Fig. 3 / §3: "increments its grip"): every finger advances by ``grip_speed * dt``
    while ``|R_z| >= tau_F``; a finger out of contact keeps closing until it touches (Fig. 11,
    "finger closure with progressive contact"); otherwise it holds its position.
    """
    dt = setup.dt
    f_ext = forces.nodal_forces

    def rhs(t, x):
        return msd_rhs(t, x, setup.body, setup.msd_params, f_ext)

    gs.state = rk4_step(rhs, gs.time, gs.state, dt)
    if not np.all(np.isfinite(gs.state)):
        raise FloatingPointError(f"dynamic_grasp diverged at t = {gs.time:.4g} s (dt = {dt:.3g} s)")
    gs.time += dt
    gs.stick = forces.stick
    gs.slip_coords = np.where(
        forces.contacts.active[:, None], gs.slip_coords + forces.relative_velocity * dt, 0.0
    )
    closing = (~forces.contacts.active) | (abs(forces.residual[2]) >= setup.grasp.tau_f)
    gs.grip_rate = np.where(closing, setup.grasp.grip_speed, 0.0)
    gs.grip = gs.grip + gs.grip_rate * dt


@dataclass(frozen=True)
class DynamicGraspResult:
    """Traces and outcome of one dynamic grasp (the data of Figs. 12-13).

    Attributes
    ----------
    times : (s,) float
        Time at the start of each step [s].
    residual : (s, 3) float
        Eq. 19 force residual ``sum_j f_j + m g`` at each step [N].
    residual_z : (s,) float
        Its vertical component (Fig. 12 top) [N].
    total_penetration : (s,) float
        ``sum_j delta_j`` (Fig. 12 bottom) [m].
    normal_forces : (s, 3) float
        Per-finger normal force f_n (Fig. 13) [N].
    tangential_forces : (s, 3) float
        Per-finger tangential force magnitude [N].
    depths : (s, 3) float
        Per-finger penetration [m].
    sliding : (s, 3) bool
        Per-finger slip flag of the stick-slip law.
    in_contact : (s, 3) bool
        Per-finger contact flag.
    grip : (s, 3) float
        Per-finger advance s_j past first touch [m].
    centroid : (s, 3) float
        Mean node position [m].
    kinetic_energy : (s,) float
        [J].
    status : str
        One of :data:`STATUSES`.
    success : bool
        ``status == "stable"``.
    settled_at : float
        Time at which the residual had stayed below tau_F for ``settle_time`` [s] (nan if never).
    wrench : (6,) float
        Six-component residual (force [N], torque about the centroid [N*m]) at the last step.
    contact_points : (3, 3) float
        Final contact points [m].
    contact_forces : (3, 3) float
        Final contact forces on the object [N].
    slip_margin : float
        ``min_j (mu f_n - |f_t|) / (mu f_n)`` over active fingers at the last step (§6.4) [-].
    delta_max : float
        Largest single-finger penetration over the run [m] (design limit 1 mm, §4).
    positions : (n, 3) float
        Final node positions [m].
    dt : float
        RK4 step [s].
    n_steps : int
        Steps taken.
    """

    times: np.ndarray
    residual: np.ndarray
    residual_z: np.ndarray
    total_penetration: np.ndarray
    normal_forces: np.ndarray
    tangential_forces: np.ndarray
    depths: np.ndarray
    sliding: np.ndarray
    in_contact: np.ndarray
    grip: np.ndarray
    centroid: np.ndarray
    kinetic_energy: np.ndarray
    status: str
    success: bool
    settled_at: float
    wrench: np.ndarray
    contact_points: np.ndarray
    contact_forces: np.ndarray
    slip_margin: float
    delta_max: float
    positions: np.ndarray
    dt: float
    n_steps: int


def dynamic_grasp(
    mesh: trimesh.Trimesh,
    mu: float,
    msd_params: MsdParams | None = None,
    contact: ContactParams | None = None,
    grasp: GraspParams | None = None,
    directions=None,
) -> DynamicGraspResult:
    """Simulate the dynamic grasp pipeline of Fig. 3 on a deformable MSD body.

    Parameters
    ----------
    mesh : trimesh.Trimesh
        Object surface [m], centred on its centroid.
    mu : float
        Friction coefficient, ``mu_s = mu_k = mu`` as in the simulation sweeps (§3.5) [-].
    msd_params : MsdParams, optional
        Body constants and mass (default :class:`core.msd.MsdParams`).
    contact : ContactParams, optional
        Normal-contact constants (default ``ContactParams.table3()``, the paper's identification
        with the Table 2 materials).
    grasp : GraspParams, optional
        Loop constants.
    directions : (3, 3) float, optional
        Contact directions from the centroid (default :func:`hand_contact_directions`).

    Returns
    -------
    result : DynamicGraspResult

    Notes
    -----
    Per step: contacts on the current mesh -> ``f_n = max(0, K delta_mm^n + C delta_dot)`` with
    ``delta_dot = (V_face - V_finger) . n_f`` -> stick-slip with the relative tangential velocity
    (anchors in the finger's translating frame) -> forces ``f_n (-n_f) + f_t`` to the face nodes by
    Phi^T -> one RK4 step -> residual check and grip increment. The loop stops when the vertical
    residual has stayed below ``tau_f`` for ``settle_time`` (``"stable"``), when a penetration
    exceeds ``max_depth`` (``"penetration_limit"``: the contact law is outside its geometric
    validity), when the centroid has fallen ``drop_distance`` (``"dropped"``), or at ``t_max``
    (``"not_settled"``).

    References
    ----------
    Fig. 3, Eq. 11-19, §5.1, §5.5.
    """
    setup, gs = prepare_grasp(mesh, mu, msd_params, contact, grasp, directions)
    grasp, msd_params, body, dt = setup.grasp, setup.msd_params, setup.body, setup.dt
    n_max = int(np.ceil(grasp.t_max / dt))
    settle_steps = max(1, int(np.ceil(grasp.settle_time / dt)))
    centroid0 = body.rest_positions.mean(axis=0)
    keys = (
        "times", "residual", "normal_forces", "tangential_forces", "depths", "sliding",
        "in_contact", "grip", "centroid", "kinetic_energy",
    )
    traces: dict[str, list] = {key: [] for key in keys}
    quiet = 0
    since_touch = np.full(len(setup.targets), settle_steps)
    status, settled_at = "not_settled", float("nan")
    n_steps = 0
    for _ in range(n_max):
        n_steps += 1
        out = grasp_forces(setup, gs)
        nodes = gs.state.reshape(-1, 6)
        centroid = nodes[:, :3].mean(axis=0)
        hits = out.contacts
        traces["times"].append(gs.time)
        traces["residual"].append(out.residual)
        traces["normal_forces"].append(out.normal_forces)
        traces["tangential_forces"].append(np.linalg.norm(out.tangential, axis=1))
        traces["depths"].append(hits.depths)
        traces["sliding"].append(out.stick.sliding & hits.active)
        traces["in_contact"].append(hits.active)
        traces["grip"].append(gs.grip)
        traces["centroid"].append(centroid)
        traces["kinetic_energy"].append(float(kinetic_energy(body, gs.state)))

        if hits.depths.max() > setup.max_depth:
            status = "penetration_limit"
            break
        if centroid0[2] - centroid[2] > grasp.drop_distance:
            status = "dropped"
            break
        speed = float(np.linalg.norm(nodes[:, 3:].mean(axis=0)))
        # Held: Eq. 19 below tau_F, the object at rest, and every finger touching within the
        # last settle window (a light contact may flicker at the onset of Eq. 13, n < 1).
        since_touch = np.where(hits.active, 0, since_touch + 1)
        held = (
            abs(out.residual[2]) < grasp.tau_f
            and speed < grasp.settle_speed
            and since_touch.max() < settle_steps
        )
        quiet = quiet + 1 if held else 0
        if quiet >= settle_steps:
            status, settled_at = "stable", gs.time
            break
        advance_grasp(setup, gs, out)

    arrays = {key: np.asarray(value) for key, value in traces.items()}
    mu_f_n = setup.mu * out.normal_forces
    loaded = hits.active & (mu_f_n > 0.0)
    if np.any(loaded):
        margins = (mu_f_n[loaded] - np.linalg.norm(out.tangential[loaded], axis=1)) / mu_f_n[loaded]
        slip_margin = float(margins.min())
    else:
        slip_margin = float("nan")
    logger.info(
        "dynamic_grasp mu=%.2f m=%.2f kg: %s after %d steps (%.3f s), R_z=%.3g N, delta_max=%.3g mm",
        setup.mu, msd_params.mass, status, n_steps, n_steps * dt, arrays["residual"][-1, 2],
        1e3 * arrays["depths"].max(),
    )
    depths = arrays["depths"]
    return DynamicGraspResult(
        times=arrays["times"],
        residual=arrays["residual"],
        residual_z=arrays["residual"][:, 2],
        total_penetration=np.where(arrays["in_contact"], depths, 0.0).sum(axis=1),
        normal_forces=arrays["normal_forces"],
        tangential_forces=arrays["tangential_forces"],
        depths=depths,
        sliding=arrays["sliding"],
        in_contact=arrays["in_contact"],
        grip=arrays["grip"],
        centroid=arrays["centroid"],
        kinetic_energy=arrays["kinetic_energy"],
        status=status,
        success=status == "stable",
        settled_at=settled_at,
        wrench=wrench_residual(
            hits.points, out.forces, msd_params.mass, arrays["centroid"][-1], msd_params.g
        ),
        contact_points=hits.points.copy(),
        contact_forces=out.forces.copy(),
        slip_margin=slip_margin,
        delta_max=float(depths.max()),
        positions=gs.state.reshape(-1, 6)[:, :3].copy(),
        dt=float(dt),
        n_steps=n_steps,
    )
