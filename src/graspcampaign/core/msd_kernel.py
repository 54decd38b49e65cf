"""Compiled (numba) forces and RK4 stages of the MSD body (Eq. 1-5), with the kinematic support.

The numpy implementation in :mod:`graspcampaign.core.msd` (``msd_rhs``, ``rk4_step``) and
:func:`graspcampaign.core.dynamics.rigid_body_part` is the reference; these kernels compute the
same quantities with the same formulas, node by node and edge by edge, so that one RK4 step of
the 356-node shell costs microseconds instead of the ~100 small numpy calls of the vectorised
path. Tests hold them to the reference to rounding, check RK4's fourth order and close the energy
audit on this path too (``tests/core/test_msd_kernel.py``).

Compiled with ``njit(cache=True)`` and no parallel threads: the campaign runs one trial per
process (joblib workers), so threads would oversubscribe the cores.

Shape letters: ``n`` nodes, ``e`` edges, ``f`` faces. States are ``(n, 6)`` arrays
``[x, y, z, vx, vy, vz]`` per node (the ``core.msd`` layout, reshaped).

Body constants are passed as one float64 vector ``constants`` (fewer arguments, cheaper calls):
``[node_mass, k, c, b, g, bulk_modulus, rest_volume]`` (indices ``MASS, K, C, B, G, BULK, V0``).

References
----------
Eq. 1-5 (§2.1-2.2); Hairer, E., Norsett, S. P. & Wanner, G. (1993), Solving Ordinary
Differential Equations I, §II.1 (classical RK4); Matyka, M. & Ollila, M. (2004), "Pressure model
of soft body simulation" (volume term); Goldstein, H., Poole, C. & Safko, J. (2002), Classical
Mechanics, 3rd ed., §5.1-5.3 (rigid-body part of the accelerations).
"""

from __future__ import annotations

import numpy as np
from numba import njit

__all__ = [
    "BULK",
    "MASS",
    "V0",
    "audit_stepper",
    "body_constants",
    "msd_derivative",
    "remove_rigid_part",
    "rk4_audit_step",
    "rk4_body_step",
]

MASS, K, C, B, G, BULK, V0 = range(7)


def body_constants(body, params) -> np.ndarray:
    """Pack an :class:`~graspcampaign.core.msd.MsdBody` and its ``MsdParams`` into the constant vector.

    Returns
    -------
    constants : (7,) float
        ``[node_mass, k, c, b, g, bulk_modulus, rest_volume]`` (``bulk_modulus`` is 0 for a body
        without faces: the volume term needs a closed surface, as in ``msd.msd_rhs``).
    """
    bulk = params.bulk_modulus if body.faces is not None else 0.0
    return np.array([body.node_mass, params.k, params.c, params.b, params.g, bulk,
                     body.rest_volume], dtype=np.float64)


@njit(cache=True, error_model="numpy")
def _volume_gradient(positions, faces, gradient):
    """Fill ``gradient`` (n, 3) with dV/dx and return V (corner a of a face: ``(x_b x x_c) / 6``).

    ``positions`` may be the (n, 6) state: only its first three columns are read.
    """
    gradient[:] = 0.0
    sixth = 1.0 / 6.0
    for f in range(faces.shape[0]):
        for a in range(3):
            i, nxt, prv = faces[f, a], faces[f, (a + 1) % 3], faces[f, (a + 2) % 3]
            ux, uy, uz = positions[nxt, 0], positions[nxt, 1], positions[nxt, 2]
            vx, vy, vz = positions[prv, 0], positions[prv, 1], positions[prv, 2]
            gradient[i, 0] += (uy * vz - uz * vy) * sixth
            gradient[i, 1] += (uz * vx - ux * vz) * sixth
            gradient[i, 2] += (ux * vy - uy * vx) * sixth
    volume = 0.0
    for i in range(gradient.shape[0]):
        for j in range(3):
            volume += positions[i, j] * gradient[i, j]
    return volume / 3.0


@njit(cache=True, error_model="numpy")
def msd_derivative(x, edges, rest_lengths, faces, constants, f_ext, out, work, scratch):
    """Write dX/dt of Eq. 5 into ``out`` (the compiled ``msd.msd_rhs``).

    Parameters
    ----------
    x : (n, 6) float
        State [m, m/s].
    edges : (e, 2) int
        Spring-damper edges.
    rest_lengths : (e,) float
        [m].
    faces : (f, 3) int
        Outward-wound faces (used by the volume term only).
    constants : (7,) float
        :func:`body_constants`.
    f_ext : (n, 3) float
        External nodal forces held over the call [N].
    out : (n, 6) float
        Output ``[v_i, (F_int,i - b v_i + F_vol,i + f_ext,i) / m_i - g e_z]`` [m/s, m/s^2].
    work : (5, e) float
        Work array (per-edge ``x_i - x_j``, squared length then force scale, stretch-rate
        numerator).
    scratch : (n, 3) float
        Work array (the volume gradient).

    Notes
    -----
    Three passes over the edges: gather ``x_i - x_j``, the squared length and ``(v_i - v_j) .
    (x_i - x_j)``; the force scale ``(k (l - l0) + c l_dot) / l / (-m_i)`` on contiguous arrays
    (SIMD: the square root and the division dominate the cost of an edge); scatter
    ``(x_i - x_j) * scale`` to both nodes. Every edge sees the operations of ``msd.msd_rhs`` in
    the same order, so the forces agree to the summation order at the nodes (measured on the
    356-node sphere: this layout costs ~0.85 of a single fused edge loop; a node-centric gather
    over a CSR neighbour list cost more).

    References
    ----------
    Eq. 1-5 (§2.1-2.2); Matyka & Ollila (2004).
    """
    n = x.shape[0]
    n_edges = edges.shape[0]
    mass, k, c, b, g = constants[MASS], constants[K], constants[C], constants[B], constants[G]
    inv_mass = 1.0 / mass
    dxs, dys, dzs, squared, rates = work[0], work[1], work[2], work[3], work[4]
    for e in range(n_edges):
        i, j = edges[e, 0], edges[e, 1]
        dx, dy, dz = x[i, 0] - x[j, 0], x[i, 1] - x[j, 1], x[i, 2] - x[j, 2]
        dxs[e], dys[e], dzs[e] = dx, dy, dz
        squared[e] = dx * dx + dy * dy + dz * dz
        rates[e] = (x[i, 3] - x[j, 3]) * dx + (x[i, 4] - x[j, 4]) * dy + (x[i, 5] - x[j, 5]) * dz
    neg_inv_mass = -1.0 / mass
    for e in range(n_edges):
        # tension / length / (-m_i), as msd_rhs: times (x_i - x_j) it is node i's acceleration;
        # stored over `squared` (no longer needed)
        length = np.sqrt(squared[e])
        inv_len = 1.0 / length
        scale = k * (length - rest_lengths[e])
        scale += c * inv_len * rates[e]
        squared[e] = scale * (inv_len * neg_inv_mass)
    for i in range(n):
        for j in range(3):
            out[i, 3 + j] = 0.0
    for e in range(n_edges):
        i, j = edges[e, 0], edges[e, 1]
        scale = squared[e]
        fx, fy, fz = dxs[e] * scale, dys[e] * scale, dzs[e] * scale
        out[i, 3] += fx
        out[i, 4] += fy
        out[i, 5] += fz
        out[j, 3] -= fx
        out[j, 4] -= fy
        out[j, 5] -= fz
    damp = b / mass
    bulk = constants[BULK]
    factor = 0.0
    if bulk > 0.0:
        volume = _volume_gradient(x, faces, scratch)
        v0 = constants[V0]
        factor = -bulk * (volume - v0) / v0
    # the node-local terms in msd_rhs's order: nodal damping, volume, external forces, gravity
    for i in range(n):
        for j in range(3):
            v = x[i, 3 + j]
            out[i, j] = v
            acc = out[i, 3 + j]
            if b > 0.0:
                acc -= damp * v
            if bulk > 0.0:
                acc += factor * scratch[i, j] * inv_mass
            out[i, 3 + j] = acc + f_ext[i, j] * inv_mass
        out[i, 5] -= g


@njit(cache=True, error_model="numpy")
def remove_rigid_part(x, rates, share):
    """Subtract ``share`` times the rigid-body part ``A + alpha x r_i`` of the accelerations.

    Parameters
    ----------
    x : (n, 6) float
        State (positions in the first three columns) [m].
    rates : (n, 6) float
        dX/dt; its acceleration columns are modified in place [m/s^2].
    share : float
        ``1 - w``, the share of the net wrench the support carries [-].

    Notes
    -----
    The compiled :func:`graspcampaign.core.dynamics.rigid_body_part`: ``A`` the mean acceleration,
    ``alpha = I^-1 tau`` with ``tau = sum_i r_i x a_i`` and ``I = tr(G) 1 - G``, ``G = sum_i r_i
    r_i^T`` (per unit node mass). The symmetric 3 x 3 system is solved by its adjugate
    (Cramer's rule) instead of LAPACK's LU: the same solution to rounding, without a library call
    per RK4 stage (``I`` is positive definite for any body that is not a line of nodes).

    References
    ----------
    Goldstein, Poole & Safko (2002) §5.1-5.3.
    """
    n = x.shape[0]
    inv_n = 1.0 / n
    c0 = c1 = c2 = 0.0
    m0 = m1 = m2 = 0.0
    for i in range(n):
        c0 += inv_n * x[i, 0]
        c1 += inv_n * x[i, 1]
        c2 += inv_n * x[i, 2]
        m0 += inv_n * rates[i, 3]
        m1 += inv_n * rates[i, 4]
        m2 += inv_n * rates[i, 5]
    t0 = t1 = t2 = 0.0  # torque sum_i r_i x a_i
    g00 = g01 = g02 = g11 = g12 = g22 = 0.0  # G = sum_i r_i r_i^T
    for i in range(n):
        r0, r1, r2 = x[i, 0] - c0, x[i, 1] - c1, x[i, 2] - c2
        a0, a1, a2 = rates[i, 3], rates[i, 4], rates[i, 5]
        t0 += r1 * a2 - r2 * a1
        t1 += r2 * a0 - r0 * a2
        t2 += r0 * a1 - r1 * a0
        g00 += r0 * r0
        g01 += r0 * r1
        g02 += r0 * r2
        g11 += r1 * r1
        g12 += r1 * r2
        g22 += r2 * r2
    # I = tr(G) 1 - G (symmetric): solve I alpha = tau by the adjugate
    i00, i11, i22 = g11 + g22, g00 + g22, g00 + g11
    i01, i02, i12 = -g01, -g02, -g12
    adj00 = i11 * i22 - i12 * i12
    adj01 = i02 * i12 - i01 * i22
    adj02 = i01 * i12 - i02 * i11
    adj11 = i00 * i22 - i02 * i02
    adj12 = i01 * i02 - i00 * i12
    adj22 = i00 * i11 - i01 * i01
    inv_det = 1.0 / (i00 * adj00 + i01 * adj01 + i02 * adj02)
    al0 = (adj00 * t0 + adj01 * t1 + adj02 * t2) * inv_det
    al1 = (adj01 * t0 + adj11 * t1 + adj12 * t2) * inv_det
    al2 = (adj02 * t0 + adj12 * t1 + adj22 * t2) * inv_det
    for i in range(n):
        r0, r1, r2 = x[i, 0] - c0, x[i, 1] - c1, x[i, 2] - c2
        rates[i, 3] -= share * (m0 + (al1 * r2 - al2 * r1))
        rates[i, 4] -= share * (m1 + (al2 * r0 - al0 * r2))
        rates[i, 5] -= share * (m2 + (al0 * r1 - al1 * r0))


@njit(cache=True, error_model="numpy")
def _stage(x, edges, rest_lengths, faces, constants, f_ext, share, out, work, scratch):
    msd_derivative(x, edges, rest_lengths, faces, constants, f_ext, out, work, scratch)
    if share > 0.0:
        remove_rigid_part(x, out, share)


@njit(cache=True, error_model="numpy")
def rk4_body_step(x, dt, edges, rest_lengths, faces, constants, f_ext, share):
    """Return the state after one classical RK4 step (the compiled ``msd.rk4_step`` of a grasp).

    Parameters
    ----------
    x : (n, 6) float
        State [m, m/s].
    dt : float
        Step [s].
    edges, rest_lengths, faces, constants
        As :func:`msd_derivative`.
    f_ext : (n, 3) float
        External nodal forces held over the four stages (the contact forces of §3) [N].
    share : float
        Share ``1 - w`` of the rigid-body accelerations the support removes at every stage
        (0: free body) [-].

    Returns
    -------
    new : (n, 6) float
        ``x + dt/6 (k1 + 2 (k2 + k3) + k4)``.

    Notes
    -----
    Three (n, 6) work arrays instead of the four stages: ``k1``, the running sum ``k2 + k3`` and
    the current stage, and ``new`` holds the stage inputs ``x + h k`` until it receives the
    result. The stage combinations run over the flattened arrays (one loop of 6 n instead of
    the (n, 6) double loop with its inner trip count of 6). Every
    element sees the operations of ``msd.rk4_step`` in its order, ``k2 + k3`` summed before it
    is doubled, so the result is the same to the last bit (measured on the 356-node sphere in one
    process against the four-stage layout, shared machine: 5 % less CPU per free-body step, ~2 us
    of ~40 us; no change measurable with the support's share, where ``remove_rigid_part`` adds
    ~2.4 us per stage). The four force evaluations are ~8 us each and bound the step: their edge
    passes are limited by loads and stores (a fused edge loop, a node-centric CSR gather and
    other edge orders were each measured slower).

    References
    ----------
    Hairer, Norsett & Wanner (1993) §II.1 (Kutta 1901); Eq. 5.
    """
    n = x.shape[0]
    work = np.empty((5, edges.shape[0]))
    scratch = np.empty((n, 3))
    k1 = np.empty((n, 6))
    k23 = np.empty((n, 6))
    k = np.empty((n, 6))
    new = np.empty((n, 6))
    flat_x, flat_new = x.reshape(-1), new.reshape(-1)
    flat_k1, flat_k23, flat_k = k1.reshape(-1), k23.reshape(-1), k.reshape(-1)
    half = 0.5 * dt
    _stage(x, edges, rest_lengths, faces, constants, f_ext, share, k1, work, scratch)
    for m in range(flat_x.shape[0]):
        flat_new[m] = flat_x[m] + half * flat_k1[m]
    _stage(new, edges, rest_lengths, faces, constants, f_ext, share, k23, work, scratch)
    for m in range(flat_x.shape[0]):
        flat_new[m] = flat_x[m] + half * flat_k23[m]
    _stage(new, edges, rest_lengths, faces, constants, f_ext, share, k, work, scratch)
    for m in range(flat_x.shape[0]):
        flat_new[m] = flat_x[m] + dt * flat_k[m]
        flat_k23[m] += flat_k[m]
    _stage(new, edges, rest_lengths, faces, constants, f_ext, share, k, work, scratch)
    sixth = dt / 6.0
    for m in range(flat_x.shape[0]):
        flat_new[m] = flat_x[m] + sixth * (flat_k1[m] + 2.0 * flat_k23[m] + flat_k[m])
    return new


@njit(cache=True, error_model="numpy")
def _audit_rates(x, edges, rest_lengths, faces, constants, f_ext, out, work, scratch):
    """dX/dt plus the damper power ``b sum |v|^2 + c sum l_dot^2`` and the power ``f_ext . v``."""
    msd_derivative(x, edges, rest_lengths, faces, constants, f_ext, out, work, scratch)
    kinetic = 0.0
    for i in range(x.shape[0]):
        for j in range(3):
            kinetic += x[i, 3 + j] * x[i, 3 + j]
    stretch = 0.0
    for e in range(edges.shape[0]):  # l_dot = (v_i - v_j) . (x_i - x_j) / l
        i, j = edges[e, 0], edges[e, 1]
        dx, dy, dz = x[i, 0] - x[j, 0], x[i, 1] - x[j, 1], x[i, 2] - x[j, 2]
        rate = work[4, e] / np.sqrt(dx * dx + dy * dy + dz * dz)
        stretch += rate * rate
    power = 0.0
    for i in range(x.shape[0]):
        for j in range(3):
            power += f_ext[i, j] * x[i, 3 + j]
    return constants[B] * kinetic + constants[C] * stretch, power


@njit(cache=True, error_model="numpy")
def rk4_audit_step(x, dt, edges, rest_lengths, faces, constants, f_ext):
    """One RK4 step of the body with the dissipated energy and the external work as two extra ODE
    components (the compiled step of ``msd.energy_audit``; free body, no support).

    Returns
    -------
    new : (n, 6) float
        State after the step.
    dissipated, work : float
        Energy removed by the dampers and work done by ``f_ext`` over the step, integrated by the
        same RK4 [J].

    References
    ----------
    §12 (energy audit); Hairer, Norsett & Wanner (1993) §II.1.
    """
    n = x.shape[0]
    work = np.empty((5, edges.shape[0]))
    scratch = np.empty((n, 3))
    stages = np.empty((4, n, 6))
    powers = np.empty((4, 2))
    y = np.empty((n, 6))
    for s in range(4):
        if s == 0:
            current = x
        else:
            h = dt if s == 3 else 0.5 * dt
            previous = stages[s - 1]
            for i in range(n):
                for j in range(6):
                    y[i, j] = x[i, j] + h * previous[i, j]
            current = y
        powers[s, 0], powers[s, 1] = _audit_rates(current, edges, rest_lengths, faces, constants,
                                                  f_ext, stages[s], work, scratch)
    k1, k2, k3, k4 = stages[0], stages[1], stages[2], stages[3]
    sixth = dt / 6.0
    for i in range(n):
        for j in range(6):
            y[i, j] = x[i, j] + sixth * (k1[i, j] + 2.0 * (k2[i, j] + k3[i, j]) + k4[i, j])
    dissipated = sixth * (powers[0, 0] + 2.0 * (powers[1, 0] + powers[2, 0]) + powers[3, 0])
    work_done = sixth * (powers[0, 1] + 2.0 * (powers[1, 1] + powers[2, 1]) + powers[3, 1])
    return y, dissipated, work_done


def audit_stepper(body, params, f_ext=None):
    """Return the compiled RK4 step of a free body as an energy-audit stepper.

    Parameters
    ----------
    body : MsdBody
    params : MsdParams
    f_ext : (n, 3) float, optional
        Constant external nodal forces [N].

    Returns
    -------
    stepper : callable
        ``stepper(state, dt) -> (new_state, dissipated, work)`` on flat (6 n,) states, the
        contract of ``msd.energy_audit(..., stepper=)`` and ``msd.step_convergence(..., stepper=)``
        (which reads the state only).
    """
    edges = np.ascontiguousarray(body.edges, dtype=np.int64)
    rest = np.ascontiguousarray(body.rest_lengths, dtype=np.float64)
    faces = (np.zeros((0, 3), dtype=np.int64) if body.faces is None
             else np.ascontiguousarray(body.faces, dtype=np.int64))
    constants = body_constants(body, params)
    forces = (np.zeros((body.n_nodes, 3)) if f_ext is None
              else np.ascontiguousarray(f_ext, dtype=np.float64))

    def step(state, dt):
        new, dissipated, work = rk4_audit_step(np.asarray(state, dtype=np.float64).reshape(-1, 6),
                                               float(dt), edges, rest, faces, constants, forces)
        return new.reshape(-1), float(dissipated), float(work)

    return step
