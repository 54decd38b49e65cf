"""The dynamic-grasp step in one compiled path: RK4 of the body, contacts, Eq. 13-18.

:func:`compiled_grasp_step` has the contract of :func:`graspcampaign.core.dynamics.grasp_step`
(``step(setup, state) -> state``, pure, the same fields), so
``run_grasp_phases(setup, state, step=compiled_grasp_step)`` runs the phases of Fig. 11 on it. One
call runs one numba kernel that does what the numpy step does, in the same order:

1. RK4 of the MSD body (:func:`core.msd_kernel.rk4_body_step`: edge springs and dampers, nodal
   damping, gravity, the optional volume term) with the nodal contact forces of ``state.contact``
   held over the four stages, the support's share ``1 - w`` of the rigid-body accelerations
   removed at every stage;
2. fingers advanced by ``grip_rate * dt``, the stick state of ``state.contact`` committed, the slip
   coordinates of the active contacts integrated;
3. the contact stage of Fig. 3 at the new state: the sphere-triangle query of
   :mod:`core.kernels` on the deformed mesh, the deepest face per finger, the contact-point
   velocity (Eq. 12), the normal force of Eq. 13 (``linear`` or ``hunt_crossley`` rate term), the
   Coulomb stick-slip of Eq. 15-16 with its return mapping, the Phi^T transfer (Eq. 17-18), the
   Eq. 19 residual and the support force.

The numpy step stays the reference: tests run both for hundreds of steps with contacts and require
the same contact faces at every step and the same forces and states to rounding
(``tests/core/test_grasp_kernel.py``). No parallel threads (``njit(cache=True)``): the campaign
runs one trial per worker process.

Shape letters: ``n`` nodes, ``c`` fingers.

References
----------
Fig. 3 and §3 (one contact evaluation per time step), Eq. 10-19, §5.1; Hunt & Crossley (1975);
Simo, J. C. & Hughes, T. J. R. (1998), Computational Inelasticity, §2.2 (return mapping).
"""

from __future__ import annotations

import math
import weakref
from dataclasses import dataclass

import numpy as np
from numba import njit

from graspcampaign.core import kernels
from graspcampaign.core.contact import MM_PER_M, StickSlipState
from graspcampaign.core.dynamics import GraspForces, GraspSetup, GraspState
from graspcampaign.core.hand import FingerContacts
from graspcampaign.core.msd_kernel import B, body_constants, rk4_body_step

__all__ = ["PackedSetup", "body_summary", "compiled_grasp_step", "contact_stage", "packed_setup",
           "step_kernel"]

# Layout of the contact-law vector ``law`` (one float64 array: fewer arguments, cheaper calls).
RADIUS, K_N, N_EXP, C_N, HUNT_CROSSLEY, ALPHA_HC, MU_S, MU_K, K_T, C_T = range(10)
# Rows of the packed outputs of contact_stage.
POINTS, NORMALS, WEIGHTS, TANGENTIAL, FORCES, REL_VEL, ANCHORS, SLIP = range(8)
N_VEC = 8
DEPTHS, NORMAL_FORCES, GRIP = range(3)
N_SCAL = 3
ACTIVE, SLIDING = range(2)
RESIDUAL, SUPPORT = range(2)


@njit(cache=True, error_model="numpy")
def contact_stage(x, edges, faces, targets, approach, grip, grip_rate, slip_coords, anchors, law,
                  weight_z, damping_b, load_fraction):
    """Evaluate the fingertip contacts of one state (the compiled ``dynamics.grasp_forces``).

    Parameters
    ----------
    x : (n, 6) float
        Body state [m, m/s].
    edges : (e, 2) int
        Mesh edges (the broad phase uses the longest current edge).
    faces : (f, 3) int
        Surface triangles.
    targets, approach : (c, 3) float
        Planned contact points [m] and outward unit approach normals.
    grip, grip_rate : (c,) float
        Finger advance past first touch [m] and its rate [m/s].
    slip_coords : (c, 3) float
        Integrated relative displacements (zero for inactive fingers) [m].
    anchors : (c, 3) float
        Committed stick anchors [m].
    law : (10,) float
        ``[r, K, n, C, hunt_crossley (0/1), alpha_hc, mu_s, mu_k, k_t, c_t]`` [m, N mm^-n, -, N s/m,
        -, s/m, -, -, N/m, N s/m].
    weight_z : float
        ``-m g`` [N].
    damping_b : float
        Nodal damping b [N s/m] (its net force enters the support force).
    load_fraction : float
        ``w`` of the step that led to this state [-].

    Returns
    -------
    vec : (8, c, 3) float
        Rows (module constants) ``POINTS``, ``NORMALS``, ``WEIGHTS``, ``TANGENTIAL``, ``FORCES``,
        ``REL_VEL`` (face point relative to the fingertip), ``ANCHORS`` (evaluated stick anchors),
        ``SLIP`` (the ``slip_coords`` given).
    scal : (3, c) float
        Rows ``DEPTHS``, ``NORMAL_FORCES``, ``GRIP`` (the ``grip`` given).
    flags : (2, c) bool
        Rows ``ACTIVE``, ``SLIDING``.
    hosts : (c,) int
        Host face per finger (-1: no contact).
    sums : (2, 3) float
        Rows ``RESIDUAL`` (Eq. 19) and ``SUPPORT`` (force of the support) [N].
    nodal : (n, 3) float
        Phi^T transfer of the contact forces [N].

    References
    ----------
    §3.2-3.6, Eq. 11-18; Eq. 19 (residual).
    """
    n = x.shape[0]
    n_fingers = targets.shape[0]
    radius = law[RADIUS]
    centers = np.empty((n_fingers, 3))
    for p in range(n_fingers):
        for j in range(3):
            centers[p, j] = targets[p, j] + approach[p, j] * (radius - grip[p])
    # Broad phase. A face within r of a fingertip centre P has all three vertices within r + L
    # of P (L the longest current edge: every point of a triangle lies within its longest edge
    # of each vertex), and its bounding sphere (centroid, farthest vertex: kernels.face_bounds)
    # within r of P. Both tests are conservative, so the narrow phase sees every colliding face,
    # as with the bounding spheres alone in kernels.sphere_faces; the 1e-9 margin absorbs
    # rounding. The vertex test (one pass over nodes and faces) spares the bounding spheres of
    # the faces far from every finger.
    longest_sq = 0.0
    for e in range(edges.shape[0]):
        i, j = edges[e, 0], edges[e, 1]
        dx, dy, dz = x[i, 0] - x[j, 0], x[i, 1] - x[j, 1], x[i, 2] - x[j, 2]
        length_sq = dx * dx + dy * dy + dz * dz
        if length_sq > longest_sq:
            longest_sq = length_sq
    reach = (radius + math.sqrt(longest_sq)) * (1.0 + 1e-9)
    reach_sq = reach * reach
    near = np.zeros(n, dtype=np.uint8)  # bit p: node within reach of finger p
    for p in range(n_fingers):  # finger by finger: a branch-light loop over the nodes
        bit = np.uint8(1 << p)
        px, py, pz = centers[p, 0], centers[p, 1], centers[p, 2]
        for i in range(n):
            dx, dy, dz = x[i, 0] - px, x[i, 1] - py, x[i, 2] - pz
            if dx * dx + dy * dy + dz * dz <= reach_sq:
                near[i] |= bit
    # Narrow phase (kernels.narrow_pair) in face order; the deepest face per finger, the lowest
    # face index among equal depths (as geometry.deepest_per_finger ranks them).
    best_face = np.full(n_fingers, -1, dtype=np.int64)
    best_scalars = np.zeros((n_fingers, 4))
    best_vectors = np.zeros((n_fingers, 4, 3))
    pair_scalars = np.empty(4)
    pair_vectors = np.empty((4, 3))
    scratch = np.empty((9, 3))
    for f in range(faces.shape[0]):
        a, b, c = faces[f, 0], faces[f, 1], faces[f, 2]
        bits = near[a] & near[b] & near[c]
        if bits == 0:
            continue
        cx = (x[a, 0] + x[b, 0] + x[c, 0]) / 3.0
        cy = (x[a, 1] + x[b, 1] + x[c, 1]) / 3.0
        cz = (x[a, 2] + x[b, 2] + x[c, 2]) / 3.0
        bound_sq = 0.0
        for v in (a, b, c):
            dx, dy, dz = x[v, 0] - cx, x[v, 1] - cy, x[v, 2] - cz
            bound_sq = max(bound_sq, dx * dx + dy * dy + dz * dz)
        bound = radius + math.sqrt(bound_sq)
        for p in range(n_fingers):
            if not bits & (1 << p):
                continue
            dx, dy, dz = centers[p, 0] - cx, centers[p, 1] - cy, centers[p, 2] - cz
            if not dx * dx + dy * dy + dz * dz < bound * bound:
                continue
            key = kernels.narrow_pair(centers[p], radius, x, faces, f, scratch, pair_scalars,
                                      pair_vectors)
            if key < 0:
                continue
            if best_face[p] < 0 or pair_scalars[0] > best_scalars[p, 0]:
                best_face[p] = f
                best_scalars[p] = pair_scalars
                best_vectors[p] = pair_vectors

    # Outputs packed in a few arrays: returning each field as its own array would cost ~0.7 us
    # of boxing per array when the step returns to Python.
    vec = np.zeros((N_VEC, n_fingers, 3))
    scal = np.zeros((N_SCAL, n_fingers))
    flags = np.zeros((2, n_fingers), dtype=np.bool_)
    hosts = np.full(n_fingers, -1, dtype=np.int64)
    sums = np.empty((2, 3))
    nodal = np.zeros((n, 3))
    points, normals, weights = vec[POINTS], vec[NORMALS], vec[WEIGHTS]
    f_t, forces, v_rel, new_anchors = vec[TANGENTIAL], vec[FORCES], vec[REL_VEL], vec[ANCHORS]
    depths, f_n = scal[DEPTHS], scal[NORMAL_FORCES]
    active, sliding = flags[ACTIVE], flags[SLIDING]
    for p in range(n_fingers):
        scal[GRIP, p] = grip[p]
        for j in range(3):
            vec[SLIP, p, j] = slip_coords[p, j]
            weights[p, j] = 1.0 / 3.0
    xi = np.empty(3)
    v_t = np.empty(3)
    trial = np.empty(3)
    direction = np.empty(3)
    for p in range(n_fingers):
        if best_face[p] >= 0:
            active[p] = True
            depths[p] = best_scalars[p, 0]
            hosts[p] = best_face[p]
            for j in range(3):
                points[p, j] = best_vectors[p, 0, j]
                normals[p, j] = best_vectors[p, 2, j]
                weights[p, j] = best_vectors[p, 3, j]
        else:
            for j in range(3):
                points[p, j] = centers[p, j] - radius * approach[p, j]
                normals[p, j] = approach[p, j]
        host = hosts[p] if hosts[p] >= 0 else 0
        a, b, c = faces[host, 0], faces[host, 1], faces[host, 2]
        # Eq. 12: face material point velocity, minus the fingertip's (moving along -approach)
        for j in range(3):
            v_face = weights[p, 0] * x[a, 3 + j] + weights[p, 1] * x[b, 3 + j] \
                + weights[p, 2] * x[c, 3 + j]
            v_rel[p, j] = v_face + grip_rate[p] * approach[p, j]
        depth_rate = v_rel[p, 0] * normals[p, 0] + v_rel[p, 1] * normals[p, 1] \
            + v_rel[p, 2] * normals[p, 2]
        # Eq. 13 (depth in mm in the power term, rate in m/s), clamped at zero
        force = 0.0
        if active[p] and depths[p] > 0.0:
            elastic = law[K_N] * (depths[p] * MM_PER_M) ** law[N_EXP]
            if law[HUNT_CROSSLEY] > 0.0:
                force = max(0.0, elastic * (1.0 + 1.5 * law[ALPHA_HC] * depth_rate))
            else:
                force = max(0.0, elastic + law[C_N] * depth_rate)
        f_n[p] = force
        # Eq. 15-16 with the return mapping (contact.tangential_force)
        slip_on = active[p]
        xi_dot_n = 0.0
        v_dot_n = 0.0
        for j in range(3):
            s = slip_coords[p, j] if slip_on else 0.0
            xi[j] = s - anchors[p, j]
            v_t[j] = v_rel[p, j]
            xi_dot_n += xi[j] * normals[p, j]
            v_dot_n += v_t[j] * normals[p, j]
        trial_sq = 0.0
        speed_sq = 0.0
        for j in range(3):
            xi[j] = xi[j] - xi_dot_n * normals[p, j]
            v_t[j] = v_t[j] - v_dot_n * normals[p, j]
            trial[j] = -(law[K_T] * xi[j] + law[C_T] * v_t[j])
            trial_sq += trial[j] * trial[j]
            speed_sq += v_t[j] * v_t[j]
        trial_norm = math.sqrt(trial_sq)
        speed = math.sqrt(speed_sq)
        f_pos = max(force, 0.0)
        sliding[p] = trial_norm > law[MU_S] * f_pos
        for j in range(3):
            if speed > 0.0:
                direction[j] = -v_t[j] / speed
            else:
                direction[j] = trial[j] / trial_norm
            if not math.isfinite(direction[j]):
                direction[j] = 0.0
        slip_scale = law[MU_K] * f_pos
        for j in range(3):
            if sliding[p]:
                tangential = slip_scale * direction[j]
                s = slip_coords[p, j] if slip_on else 0.0
                new_anchors[p, j] = s + tangential / law[K_T]
            else:
                tangential = trial[j]
                new_anchors[p, j] = anchors[p, j]
            if active[p]:
                f_t[p, j] = tangential
                forces[p, j] = -force * normals[p, j] + tangential
        if active[p]:  # Phi^T (Eq. 17-18)
            for j in range(3):
                nodal[a, j] += weights[p, 0] * forces[p, j]
            for j in range(3):
                nodal[b, j] += weights[p, 1] * forces[p, j]
            for j in range(3):
                nodal[c, j] += weights[p, 2] * forces[p, j]
    residual, support = sums[RESIDUAL], sums[SUPPORT]
    residual[:] = 0.0
    for p in range(n_fingers):
        for j in range(3):
            residual[j] += forces[p, j]
    residual[2] += weight_z
    velocity_sum = np.zeros(3)
    for i in range(n):
        for j in range(3):
            velocity_sum[j] += x[i, 3 + j]
    for j in range(3):
        support[j] = -(1.0 - load_fraction) * (residual[j] - damping_b * velocity_sum[j])
    return vec, scal, flags, hosts, sums, nodal


@njit(cache=True, error_model="numpy")
def step_kernel(x, dt, edges, rest_lengths, faces, constants, f_ext, share, grip, grip_rate,
                slip_coords, active, v_rel, anchors, targets, approach, law, weight_z,
                load_fraction):
    """One compiled step on packed arrays: RK4, finger advance, slip integration, contact stage.

    Returns ``(finite, new_state (n, 6), *contact_stage outputs)``; ``anchors`` are the stick
    anchors committed by the previous evaluation (``contact.stick.anchors`` of the state).
    """
    new_x = rk4_body_step(x, dt, edges, rest_lengths, faces, constants, f_ext, share)
    finite = True
    for i in range(new_x.shape[0]):
        for j in range(6):
            if not math.isfinite(new_x[i, j]):
                finite = False
    n_fingers = grip.shape[0]
    new_grip = np.empty(n_fingers)
    new_slip = np.zeros((n_fingers, 3))
    for p in range(n_fingers):
        new_grip[p] = grip[p] + grip_rate[p] * dt
        if active[p]:
            for j in range(3):
                new_slip[p, j] = slip_coords[p, j] + v_rel[p, j] * dt
    vec, scal, flags, hosts, sums, nodal = contact_stage(
        new_x, edges, faces, targets, approach, new_grip, grip_rate, new_slip, anchors, law,
        weight_z, constants[B], load_fraction)
    return finite, new_x, vec, scal, flags, hosts, sums, nodal


@dataclass(frozen=True)
class PackedSetup:
    """The arrays and constant vectors of one GraspSetup, as :func:`step_kernel` takes them."""

    edges: np.ndarray
    rest_lengths: np.ndarray
    faces: np.ndarray
    constants: np.ndarray
    law: np.ndarray
    targets: np.ndarray
    approach: np.ndarray
    weight_z: float


_PACKED: weakref.WeakKeyDictionary = weakref.WeakKeyDictionary()


def packed_setup(setup: GraspSetup) -> PackedSetup:
    """Return the kernel arrays of a setup (built once per setup, then cached weakly)."""
    packed = _PACKED.get(setup)
    if packed is None:
        body, contact, stick = setup.body, setup.contact, setup.stick
        law = np.array([contact.fingertip_radius, contact.k_n_per_mm_n, contact.n,
                        contact.c_n_s_per_m, float(contact.damping_law == "hunt_crossley"),
                        contact.alpha_hc_s_per_m, stick.mu_s, stick.mu_k, stick.k_t, stick.c_t])
        packed = PackedSetup(
            edges=np.ascontiguousarray(body.edges, dtype=np.int64),
            rest_lengths=np.ascontiguousarray(body.rest_lengths, dtype=np.float64),
            faces=np.ascontiguousarray(body.faces, dtype=np.int64),
            constants=body_constants(body, setup.msd_params),
            law=law,
            targets=np.ascontiguousarray(setup.targets, dtype=np.float64),
            approach=np.ascontiguousarray(setup.approach, dtype=np.float64),
            weight_z=float(setup.weight[2]),
        )
        _PACKED[setup] = packed
    return packed


def compiled_grasp_step(setup: GraspSetup, gs: GraspState) -> GraspState:
    """Advance a dynamic grasp by one step in one compiled call (the contract of ``grasp_step``).

    Parameters
    ----------
    setup : GraspSetup
    gs : GraspState
        Current state with its contact evaluation and the command (``grip_rate``,
        ``load_fraction``) for this step.

    Returns
    -------
    new : GraspState
        As :func:`graspcampaign.core.dynamics.grasp_step` returns it, to rounding.

    Raises
    ------
    FloatingPointError
        If the state becomes non-finite (a step beyond the stability limit).

    References
    ----------
    Fig. 3, §3, Eq. 5, Eq. 11-19.
    """
    packed = packed_setup(setup)
    out = gs.contact
    dt = setup.dt
    finite, new_x, vec, scal, flags, hosts, sums, nodal = step_kernel(
        gs.state.reshape(-1, 6), dt, packed.edges, packed.rest_lengths, packed.faces,
        packed.constants, out.nodal_forces, 1.0 - gs.load_fraction, gs.grip, gs.grip_rate,
        gs.slip_coords, out.contacts.active, out.relative_velocity, out.stick.anchors,
        packed.targets, packed.approach, packed.law, packed.weight_z, gs.load_fraction,
    )
    if not finite:
        raise FloatingPointError(f"dynamic grasp diverged at t = {gs.time:.4g} s (dt = {dt:.3g} s)")
    stick = StickSlipState(anchors=vec[ANCHORS], sliding=flags[SLIDING])
    hits = FingerContacts(active=flags[ACTIVE], depths=scal[DEPTHS], faces=hosts, points=vec[POINTS],
                          normals=vec[NORMALS], weights=vec[WEIGHTS])
    contact = GraspForces(
        contacts=hits, normal_forces=scal[NORMAL_FORCES], tangential=vec[TANGENTIAL],
        forces=vec[FORCES], residual=sums[RESIDUAL], support_force=sums[SUPPORT],
        nodal_forces=nodal, relative_velocity=vec[REL_VEL], stick=stick)
    return GraspState(
        time=gs.time + dt, state=new_x.reshape(-1), grip=scal[GRIP], grip_rate=gs.grip_rate,
        load_fraction=gs.load_fraction, stick=out.stick, slip_coords=vec[SLIP], contact=contact)


@njit(cache=True, error_model="numpy")
def body_summary(state):
    """Return ``[mean x, y, z, mean vx, vy, vz, sum |v|^2]`` of a (6 n,) state in one pass.

    What the phase driver reads at every step (centroid, centroid velocity, kinetic energy up to
    ``m_i / 2``), without the ~10 numpy calls it would otherwise cost per step.
    """
    n = state.shape[0] // 6
    out = np.zeros(7)
    for i in range(n):
        for j in range(6):
            out[j] += state[6 * i + j]
        for j in range(3, 6):
            out[6] += state[6 * i + j] * state[6 * i + j]
    for j in range(6):
        out[j] /= n
    return out
