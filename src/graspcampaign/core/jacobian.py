"""Sparse Jacobians of the MSD body's forces with respect to node positions and velocities.

The forces are those of :mod:`graspcampaign.core.msd` (Eq. 1-4: edge springs, edge dampers on the
stretch rate, absolute nodal damping, the optional enclosed-volume term) and of its rigid floor
(``msd.floor_forces``); this module only differentiates them, for the Newton iterations of an
implicit integrator (:mod:`graspcampaign.core.implicit`).

Shape letters: ``n`` nodes, ``e`` edges, ``f`` faces. Jacobians act on the node-major flat
position (or velocity) vector ``x.ravel()`` of an ``(n, 3)`` array: entry ``(3 i + a, 3 j + b)``
is ``d F_{i,a} / d x_{j,b}``.

References
----------
Eq. 1-4 (§2.1-2.2). Baraff, D. & Witkin, A. (1998), "Large steps in cloth simulation", SIGGRAPH
'98, 43-54 (force Jacobians of springs and dampers, §5). Matyka, M. & Ollila, M. (2004), "Pressure
model of soft body simulation" (the volume term differentiated here). Cundall, P. A. & Strack,
O. D. L. (1979) (the floor's spring-slider friction).
"""

from __future__ import annotations

from dataclasses import dataclass, field

import numpy as np
import scipy.sparse

from graspcampaign.core.msd import FloorParams, MsdBody, MsdParams
from graspcampaign.core.msd_forces import volume_gradient

__all__ = [
    "BodyJacobian",
    "JacobianPattern",
    "body_jacobian",
    "floor_jacobian",
    "skew",
]


def skew(vectors: np.ndarray) -> np.ndarray:
    """Return the (..., 3, 3) cross-product matrices ``[v]_x`` (``[v]_x w = v x w``)."""
    v = np.asarray(vectors, dtype=np.float64)
    out = np.zeros(v.shape[:-1] + (3, 3))
    out[..., 0, 1], out[..., 0, 2] = -v[..., 2], v[..., 1]
    out[..., 1, 0], out[..., 1, 2] = v[..., 2], -v[..., 0]
    out[..., 2, 0], out[..., 2, 1] = -v[..., 1], v[..., 0]
    return out


@dataclass(frozen=True, eq=False)
class JacobianPattern:
    """Fixed (3n, 3n) sparsity pattern of a body's force Jacobians, built once per body.

    Holds the CSR structure of every 3x3 node block a body force can touch (each node with itself,
    the two ends of each edge, the vertices of each face) and, for each kind of block list used
    by :func:`body_jacobian`, the position of each of its 9 entries in the CSR data array, so
    that assembling a Jacobian is one ``np.bincount`` instead of a COO-to-CSR conversion.
    """

    n_nodes: int
    indptr: np.ndarray
    indices: np.ndarray
    nnz: int
    slots: dict = field(repr=False)

    @classmethod
    def of(cls, body: MsdBody) -> JacobianPattern:
        """Return the pattern of ``body`` (node self-blocks, edges, face vertex pairs)."""
        n = body.n_nodes
        pairs = {"diag": (np.arange(n), np.arange(n))}
        i, j = body.edges[:, 0], body.edges[:, 1]
        pairs.update(e_ii=(i, i), e_ij=(i, j), e_ji=(j, i), e_jj=(j, j))
        if body.faces is not None:
            corners = body.faces.ravel()
            pairs.update(c_next=(corners, body.corner_next), c_prev=(corners, body.corner_prev))
        comp_r, comp_c = np.meshgrid(np.arange(3), np.arange(3), indexing="ij")
        keys = {}
        for name, (rows, cols) in pairs.items():
            r = (3 * rows[:, None, None] + comp_r).ravel()
            c = (3 * cols[:, None, None] + comp_c).ravel()
            keys[name] = r * (3 * n) + c
        unique = np.unique(np.concatenate(list(keys.values())))
        rows = unique // (3 * n)
        indptr = np.zeros(3 * n + 1, dtype=np.int64)
        np.add.at(indptr, rows + 1, 1)
        slots = {name: np.searchsorted(unique, k) for name, k in keys.items()}
        return cls(n_nodes=n, indptr=np.cumsum(indptr), indices=unique % (3 * n),
                   nnz=int(unique.size), slots=slots)

    def assemble(self, blocks: dict[str, np.ndarray]) -> scipy.sparse.csr_matrix:
        """Sum (m, 3, 3) blocks given per block list name into one (3n, 3n) CSR matrix."""
        slots = np.concatenate([self.slots[name] for name in blocks])
        values = np.concatenate([np.asarray(b, dtype=np.float64).ravel() for b in blocks.values()])
        data = np.bincount(slots, weights=values, minlength=self.nnz)
        n3 = 3 * self.n_nodes
        return scipy.sparse.csr_matrix((data, self.indices, self.indptr), shape=(n3, n3))


@dataclass(frozen=True)
class BodyJacobian:
    """Jacobians of the body's total force ``F`` (without external forces) at one state.

    ``dF/dx = d_position + rank_one_scale * rank_one_vector rank_one_vector^T``.

    Attributes
    ----------
    d_position : (3n, 3n) csr_matrix
        Sparse part of ``dF/dx`` [N/m].
    d_velocity : (3n, 3n) csr_matrix
        ``dF/dv`` [N*s/m].
    rank_one_vector : (3n,) float or None
        ``dV/dx`` of the volume term [m^2] (None without it).
    rank_one_scale : float
        ``-K_b / V0`` [Pa/m^3 = N/m^5] (0 without the volume term).
    """

    d_position: scipy.sparse.csr_matrix
    d_velocity: scipy.sparse.csr_matrix
    rank_one_vector: np.ndarray | None
    rank_one_scale: float

    def dense_d_position(self) -> np.ndarray:
        """Return ``dF/dx`` as a dense (3n, 3n) array (tests and small bodies only)."""
        dense = self.d_position.toarray()
        if self.rank_one_vector is not None:
            dense += self.rank_one_scale * np.outer(self.rank_one_vector, self.rank_one_vector)
        return dense


def _edge_blocks(body: MsdBody, params: MsdParams, state: np.ndarray):
    """Return (e, 3, 3) ``dF_i/dx_i`` and ``dF_i/dv_i`` of each edge's force on its first node."""
    rel = (body.gather6 @ state).reshape(6, -1)
    d, w = rel[:3].T, rel[3:].T  # (e, 3) x_i - x_j, v_i - v_j
    lengths = np.sqrt(np.einsum("ij,ij->i", d, d))
    u = d / lengths[:, None]
    uu = u[:, :, None] * u[:, None, :]
    proj = np.eye(3) - uu
    stretch_rate = np.einsum("ij,ij->i", u, w)
    # f_i = -(k (L - l0) + c l_dot) u;  du/dx_i = P / L;  dl_dot/dx_i = P w / L.
    pw = np.einsum("eab,eb->ea", proj, w)
    dx = -params.k * uu - (params.k * (lengths - body.rest_lengths) / lengths)[:, None, None] * proj
    dx -= (params.c / lengths)[:, None, None] * (
        u[:, :, None] * pw[:, None, :] + stretch_rate[:, None, None] * proj
    )
    dv = -params.c * uu
    return dx, dv


def body_jacobian(body: MsdBody, params: MsdParams, state, pattern: JacobianPattern | None = None
                  ) -> BodyJacobian:
    """Return the Jacobians of the body force of :func:`core.msd.msd_rhs` (times ``m_i``).

    Parameters
    ----------
    body, params
        The MSD body and its constants.
    state : (6 n,) float
        State (``core.msd`` layout).
    pattern : JacobianPattern, optional
        The body's pattern (built here when omitted; pass it to avoid rebuilding it).

    Returns
    -------
    jacobian : BodyJacobian
        Edge springs and dampers (exact, including the geometric terms of a stretched or
        rotating edge), nodal damping ``-b I``, and the volume term: sparse
        ``-K_b (V - V0)/V0 d2V/dx2`` plus the rank-one ``-K_b/V0 (dV/dx)(dV/dx)^T``. Gravity
        is constant and has none.

    Notes
    -----
    For edge (i, j) with ``d = x_i - x_j``, ``L = |d|``, ``u = d/L``, ``P = I - u u^T``,
    ``w = v_i - v_j`` and ``l_dot = u . w``, the force on i is ``f = -(k (L - l0) + c l_dot) u``:

    * ``df/dx_i = -k u u^T - k (L - l0)/L P - c/L (u (P w)^T + l_dot P)``,
    * ``df/dv_i = -c u u^T``,

    and ``df/dx_j = -df/dx_i``, the force on j being ``-f``. For the volume term, corner a of a
    face (a, b, c) has ``dV/dx_a = x_b x x_c / 6``, so ``d2V/dx_a dx_b = -[x_c]_x / 6`` and
    ``d2V/dx_a dx_c = [x_b]_x / 6``.

    References
    ----------
    Eq. 3-4; Baraff & Witkin (1998) §5; Matyka & Ollila (2004).
    """
    state = np.asarray(state, dtype=np.float64).ravel()
    pattern = pattern or JacobianPattern.of(body)
    dx, dv = _edge_blocks(body, params, state)
    n = body.n_nodes
    nodal = np.broadcast_to(-params.b * np.eye(3), (n, 3, 3))
    d_velocity = pattern.assemble({"diag": nodal, "e_ii": dv, "e_ij": -dv, "e_ji": -dv, "e_jj": dv})
    blocks = {"e_ii": dx, "e_ij": -dx, "e_ji": -dx, "e_jj": dx}
    vector, scale = None, 0.0
    if params.bulk_modulus > 0.0 and body.faces is not None:
        positions = state.reshape(-1, 6)[:, :3]
        gradient, volume = volume_gradient(body, positions)
        pressure = params.bulk_modulus * (volume - body.rest_volume) / body.rest_volume
        blocks["c_next"] = -pressure * (-skew(positions[body.corner_prev]) / 6.0)
        blocks["c_prev"] = -pressure * (skew(positions[body.corner_next]) / 6.0)
        vector = gradient.ravel()
        scale = -params.bulk_modulus / body.rest_volume
    return BodyJacobian(d_position=pattern.assemble(blocks), d_velocity=d_velocity,
                        rank_one_vector=vector, rank_one_scale=float(scale))


def floor_jacobian(state, floor: FloorParams, anchors=None) -> tuple[np.ndarray, np.ndarray]:
    """Return per-node (n, 3, 3) ``dF/dx`` and ``dF/dv`` of :func:`core.msd.floor_forces`.

    Parameters
    ----------
    state : (6 n,) float
        State vector.
    floor : FloorParams
    anchors : (n, 2) float, optional
        Stick anchors held fixed over the step (None: frictionless).

    Returns
    -------
    d_position, d_velocity : (n, 3, 3) float
        [N/m], [N*s/m]; zero for nodes off the floor or with a clamped (zero) normal force. The
        floor couples no two nodes, so these are the diagonal blocks of the (3n, 3n) Jacobians.

    Notes
    -----
    Normal ``f_z = k_f p - c_f v_z`` (p = h - z) while positive. Friction: a sticking node has
    ``f_t = s = -k_t (x_t - a) - c_t v_t``; a sliding node ``f_t = mu f_z s / |s|``, whose
    derivative is ``mu f_z / |s| (I - s_hat s_hat^T) ds + mu s_hat df_z``. The stick/slip and
    contact sets are those at ``state`` (the Jacobian of the branch in force there).
    """
    nodes = np.asarray(state, dtype=np.float64).reshape(-1, 6)
    n = nodes.shape[0]
    d_pos, d_vel = np.zeros((n, 3, 3)), np.zeros((n, 3, 3))
    penetration = floor.height - nodes[:, 2]
    normal = floor.stiffness * penetration - floor.damping * nodes[:, 5]
    loaded = (penetration > 0.0) & (normal > 0.0)
    if not np.any(loaded):
        return d_pos, d_vel
    d_pos[loaded, 2, 2] = -floor.stiffness
    d_vel[loaded, 2, 2] = -floor.damping
    if anchors is None or floor.mu == 0.0:
        return d_pos, d_vel
    idx = np.flatnonzero(loaded)
    trial = (-floor.tangential_stiffness * (nodes[idx, :2] - anchors[idx])
             - floor.tangential_damping * nodes[idx, 3:5])
    size = np.sqrt(np.sum(trial * trial, axis=1))
    cap = floor.mu * normal[idx]
    stick = size <= cap
    eye2 = np.eye(2)
    st, sl = idx[stick], idx[~stick]
    d_pos[st, :2, :2] = -floor.tangential_stiffness * eye2
    d_vel[st, :2, :2] = -floor.tangential_damping * eye2
    if sl.size:
        s_hat = trial[~stick] / size[~stick, None]
        tangent = (cap[~stick] / size[~stick])[:, None, None] * (
            eye2 - s_hat[:, :, None] * s_hat[:, None, :])
        d_pos[sl, :2, :2] = -floor.tangential_stiffness * tangent
        d_vel[sl, :2, :2] = -floor.tangential_damping * tangent
        d_pos[sl, :2, 2] = floor.mu * s_hat * -floor.stiffness
        d_vel[sl, :2, 2] = floor.mu * s_hat * -floor.damping
    return d_pos, d_vel
