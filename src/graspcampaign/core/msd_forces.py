"""Forces and right-hand side of the MSD shell body (Eq. 1-5): springs, dampers, enclosed volume.

Forces are assembled from the edge list with one sparse incidence matrix (no Python loop over
nodes or edges). The body and state layout are those of :mod:`graspcampaign.core.msd_body` and
:mod:`graspcampaign.core.msd_state`.

References
----------
Eq. 1-5 (§2.1-2.2).
"""

from __future__ import annotations

import numpy as np

from graspcampaign.core.msd_body import MsdBody, MsdParams
from graspcampaign.core.msd_state import positions_from_state

__all__ = [
    "edge_terms",
    "internal_forces",
    "msd_rhs",
    "volume_energy",
    "volume_forces",
    "volume_gradient",
]


# ----------------------------------------------------------------------------------------------
# Forces and right-hand side (Eq. 1-5)
# ----------------------------------------------------------------------------------------------


def edge_terms(body: MsdBody, state: np.ndarray):
    """Return component-major relative positions d (3, e), lengths (e,), and stretch rates (e,)."""
    rel = (body.gather6 @ state).reshape(6, -1)  # [x_i - x_j; v_i - v_j]
    d = rel[:3]
    lengths = np.sqrt(np.einsum("ij,ij->j", d, d))
    stretch_rate = np.einsum("ij,ij->j", rel[3:], d) / lengths
    return d, lengths, stretch_rate


def internal_forces(body: MsdBody, params: MsdParams, state) -> np.ndarray:
    """Return the spring-damper edge forces gathered at the nodes (Eq. 3).

    Parameters
    ----------
    body : MsdBody
    params : MsdParams
    state : (6 n,) float
        State vector (module layout).

    Returns
    -------
    forces : (n, 3) float
        ``-sum_j (k (|x_ij| - l0) + c l_dot_ij) x_hat_ij`` on each node i [N]: a stretched edge
        pulls its two nodes together.

    References
    ----------
    Eq. 3-4 (§2.1-2.2).
    """
    d, lengths, stretch_rate = edge_terms(body, np.asarray(state, dtype=np.float64).ravel())
    tension_per_length = (params.k * (lengths - body.rest_lengths) + params.c * stretch_rate) / lengths
    return -(body.scatter6 @ (d * tension_per_length).ravel()).reshape(-1, 6)[:, 3:]


def volume_forces(body: MsdBody, params: MsdParams, positions) -> np.ndarray:
    """Return the nodal forces of the enclosed-volume (pressure) term [N].

    Parameters
    ----------
    body : MsdBody
        With faces.
    params : MsdParams
        ``bulk_modulus`` K_b [Pa].
    positions : (n, 3) float
        Node positions [m].

    Returns
    -------
    forces : (n, 3) float
        ``-K_b (V - V0) / V0 * dV/dx_i`` with ``dV/dx_a = sum_faces (x_b x x_c) / 6``: a
        compressed body (V < V0) pushes its nodes outward, like an internal pressure.

    References
    ----------
    Matyka & Ollila (2004); §12 of the paper (pressure term as future work).
    """
    gradient, volume = volume_gradient(body, np.asarray(positions, dtype=np.float64))
    return (-params.bulk_modulus * (volume - body.rest_volume) / body.rest_volume) * gradient


def volume_gradient(body: MsdBody, positions: np.ndarray) -> tuple[np.ndarray, float]:
    """Return dV/dx (n, 3) and V: corner a of a face gets ``(x_b x x_c) / 6``, (a, b, c) cyclic."""
    # np.take is several times faster than fancy indexing on small (n, 3) arrays.
    u = np.take(positions, body.corner_next, axis=0)
    v = np.take(positions, body.corner_prev, axis=0)
    corner = np.empty_like(u)
    corner[:, 0] = u[:, 1] * v[:, 2] - u[:, 2] * v[:, 1]
    corner[:, 1] = u[:, 2] * v[:, 0] - u[:, 0] * v[:, 2]
    corner[:, 2] = u[:, 0] * v[:, 1] - u[:, 1] * v[:, 0]
    corner *= 1.0 / 6.0
    gradient = body.corner_scatter @ corner
    # Each face's triple product appears at its three corners: V = sum_i x_i . dV/dx_i / 3.
    return gradient, float(np.einsum("ij,ij->", positions, gradient)) / 3.0


def volume_energy(body: MsdBody, params: MsdParams, state) -> np.ndarray:
    """Return ``K_b (V - V0)^2 / (2 V0)`` [J] of a (6 n,) or (s, 6 n) state (0 without K_b)."""
    positions = positions_from_state(state)
    if params.bulk_modulus == 0.0 or body.faces is None:
        return np.zeros(positions.shape[:-2]) if positions.ndim > 2 else np.float64(0.0)
    tri = positions[..., body.faces, :]  # (..., f, 3, 3)
    volume = np.einsum("...fj,...fj->...", tri[..., 0, :], np.cross(tri[..., 1, :], tri[..., 2, :])) / 6.0
    return 0.5 * params.bulk_modulus * (volume - body.rest_volume) ** 2 / body.rest_volume


def msd_rhs(t, state, body: MsdBody, params: MsdParams, f_ext=None) -> np.ndarray:
    """Return dX/dt of Eq. 5 for the MSD body under gravity and optional nodal forces.

    Parameters
    ----------
    t : float
        Time [s] (unused: the body is autonomous; kept for the ``f(t, X)`` signature).
    state : (6 n,) float
        State vector (module layout).
    body : MsdBody
    params : MsdParams
    f_ext : (n, 3) float, optional
        External nodal forces [N] (contacts, floor), held constant over the call.

    Returns
    -------
    dstate : (6 n,) float
        ``[v_i, (F_int,i - b v_i + F_vol,i + f_ext,i) / m_i - g e_z]`` per node, same layout as
        the state (``F_vol`` only when ``params.bulk_modulus > 0``).

    References
    ----------
    Eq. 1-5 (§2.1-2.2): ``m_i a_i = -b v_i - sum_j f_ij + f_ext,i`` with gravity in f_ext.
    """
    state = np.asarray(state, dtype=np.float64)
    rel = (body.gather6 @ state).reshape(6, -1)  # component-major edge differences
    d = rel[:3]
    lengths = np.sqrt(np.einsum("ij,ij->j", d, d))
    inv_len = 1.0 / lengths
    # Tension / length / (-m_i): times (x_i - x_j) gives the acceleration of node i.
    scale = params.k * (lengths - body.rest_lengths)
    scale += params.c * inv_len * np.einsum("ij,ij->j", rel[3:], d)  # c * stretch rate
    scale *= inv_len * (-1.0 / body.node_mass)
    out = body.scatter6 @ (d * scale).ravel()
    nodes = state.reshape(-1, 6)
    out_nodes = out.reshape(-1, 6)
    velocities = nodes[:, 3:]
    out_nodes[:, :3] = velocities
    accel = out_nodes[:, 3:]
    if params.b > 0.0:
        accel -= (params.b / body.node_mass) * velocities
    if params.bulk_modulus > 0.0:
        accel += volume_forces(body, params, nodes[:, :3]) * (1.0 / body.node_mass)
    if f_ext is not None:
        accel += np.asarray(f_ext) * (1.0 / body.node_mass)
    out_nodes[:, 5] -= params.g
    return out
