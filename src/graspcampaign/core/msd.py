"""Mass-spring-damper (MSD) surface-shell body, classical RK4, and gravity settling on a floor.

The body of §2 (Eq. 1-5): the object's surface mesh is a shell of ``n`` point masses ``m/n``
joined along the mesh edges by linear springs ``k`` with parallel dampers ``c`` acting on the
stretch rate, plus an absolute nodal damper ``b``. Forces are assembled from the edge list with one
sparse incidence matrix (no Python loop over nodes or edges).

Shape letters: ``n`` nodes, ``e`` edges, ``f`` faces, ``s`` recorded samples.

State layout
------------
``X`` is a flat float64 vector of length ``6 n`` that interleaves position and velocity per node
(the paper's ordering, §2.2)::

    X.reshape(n, 6) == [[x_0, y_0, z_0, vx_0, vy_0, vz_0],
                        [x_1, y_1, z_1, vx_1, vy_1, vz_1], ...]

so ``X[6 i : 6 i + 3]`` is the position of node ``i`` in W [m] and ``X[6 i + 3 : 6 i + 6]`` its
velocity [m/s]. :func:`positions_from_state`, :func:`velocities_from_state` return views,
:func:`state_from_positions` builds a state.

References
----------
Eq. 1-5 (§2.1-2.2); §5.4 (gravity settling, Fig. 10); §12 (missing step-size convergence study
and energy audit). Hairer, E., Norsett, S. P. & Wanner, G. (1993), Solving Ordinary Differential
Equations I, §II.1 (classical RK4) and §IV.2 (stability function and region of RK4).
Anderson, W. N. & Morley, T. D. (1985), "Eigenvalues of the Laplacian of a graph", Linear and
Multilinear Algebra 18:141-145 (lambda_max(L) <= max over edges of d_i + d_j).
"""

from __future__ import annotations

import logging
from collections.abc import Callable
from dataclasses import dataclass, field, replace
from functools import cached_property, lru_cache

import numpy as np
import scipy.sparse
import scipy.sparse.linalg
import trimesh

from graspcampaign.core.statics import GRAVITY

__all__ = [
    "RK4_IMAGINARY_AXIS_LIMIT",
    "EnergyAuditResult",
    "FloorParams",
    "IntegrationResult",
    "MsdBody",
    "MsdParams",
    "SettleResult",
    "StepConvergenceResult",
    "body_step_limit",
    "check_state",
    "dissipation_power",
    "elastic_energy",
    "enclosed_volume",
    "energy_audit",
    "floor_anchors_update",
    "floor_forces",
    "gravitational_energy",
    "integrate_rk4",
    "internal_forces",
    "kinetic_energy",
    "msd_body_from_arrays",
    "msd_body_from_mesh",
    "msd_params_from_modulus",
    "msd_rhs",
    "positions_from_state",
    "rk4_step",
    "settle_on_floor",
    "stable_step_limit",
    "state_from_positions",
    "step_convergence",
    "velocities_from_state",
    "volume_energy",
    "volume_forces",
]

logger = logging.getLogger(__name__)

RK4_IMAGINARY_AXIS_LIMIT = 2.0 * np.sqrt(2.0)
"""|R(i y)| <= 1 for |y| <= 2 sqrt(2) (Hairer et al. 1993, §IV.2): undamped oscillators."""


# ----------------------------------------------------------------------------------------------
# Parameters and body
# ----------------------------------------------------------------------------------------------


@dataclass(frozen=True)
class MsdParams:
    """Physical constants of the MSD body (Eq. 1-3), SI.

    Attributes
    ----------
    mass : float
        Total object mass m [kg]; lumped uniformly, ``m_i = m / n`` (§2.1). Default 0.4 kg, the
        representative case of §5.5.
    k : float
        Edge spring stiffness [N/m]. Default ``E2 * l_mean`` = 0.14 MPa x 10.3 mm = 1.44e3 N/m.
    c : float
        Edge damper on the stretch rate [N*s/m]. Default 1.0 N*s/m.
    b : float
        Absolute nodal damping per node [N*s/m]. Default 0.0162 N*s/m.
    g : float
        Gravitational acceleration, acting along -z [m/s^2].
    bulk_modulus : float
        Optional enclosed-volume stiffness K_b [Pa] (an extension, see Notes). Default 0: the
        paper's pure surface shell (§2.1: "no volumetric or internal-pressure term").

    Notes
    -----
    Table 3's b, k, c are in the paper's unpublished internal unit system and are not reused.
    The SI defaults come from a physical argument on the 356-node reference sphere (r = 50 mm,
    mean edge length 10.3 mm), reproduced by :func:`msd_params_from_modulus`:

    * ``k = E2 * l_mean``: the axial stiffness ``E A / L`` of a cube of side ``l_mean``, the
      usual order-of-magnitude map of a continuum modulus (E2 = 0.14 MPa, Table 2) onto a
      lattice spring. A calibration would replace it.
    * ``b`` (mass-proportional) and ``c`` (stiffness-proportional: the edge damper has the same
      projector as the edge spring) form Rayleigh damping ``zeta(w) = b/(2 m_i w) + c w/(2 k)``;
      they are fitted so that the lowest elastic mode (w1 ~ 150 rad/s at m = 0.4 kg) has
      ``zeta = 0.1`` (a lightly damped gel, §5.4: "oscillates briefly, and settles") and the
      highest mesh mode (w_max ~ 2.8e3 rad/s) is critically damped (``zeta = 1``; mesh-scale
      modes are discretisation artefacts).

    The pure shell has no bending stiffness, so a point load (one fingertip carrying the weight)
    inverts a cap of it at almost no strain-energy cost. ``bulk_modulus > 0`` adds the pressure
    term the paper lists as future work (§12): energy ``K_b (V - V0)^2 / (2 V0)`` of the enclosed
    volume V (Matyka & Ollila 2004). For a near-incompressible gel ``K_b = E2 / (3 (1 - 2 nu2))``
    = 0.47 MPa with Table 2's E2 = 0.14 MPa, nu2 = 0.45. Needs a closed, outward-wound mesh.

    References
    ----------
    Matyka, M. & Ollila, M. (2004), "Pressure model of soft body simulation", SIGRAD 2003.
    """

    mass: float = 0.4
    k: float = 1.44e3
    c: float = 1.0
    b: float = 0.0162
    g: float = GRAVITY
    bulk_modulus: float = 0.0

    def __post_init__(self) -> None:
        for name in ("mass", "k"):
            value = getattr(self, name)
            if not np.isfinite(value) or value <= 0.0:
                raise ValueError(f"MsdParams.{name} must be finite and > 0, got {value!r}")
        for name in ("c", "b", "g", "bulk_modulus"):
            value = getattr(self, name)
            if not np.isfinite(value) or value < 0.0:
                raise ValueError(f"MsdParams.{name} must be finite and >= 0, got {value!r}")


@dataclass(frozen=True, eq=False)
class MsdBody:
    """Topology and rest geometry of an MSD shell (fixed during a simulation).

    Attributes
    ----------
    rest_positions : (n, 3) float
        Node positions of the undeformed body in W [m].
    edges : (e, 2) int
        Spring-damper edges (unique, ``edges[:, 0] != edges[:, 1]``).
    rest_lengths : (e,) float
        Rest lengths l0 of the edges [m].
    node_mass : float
        Lumped mass per node ``m / n`` [kg].
    faces : (f, 3) int or None
        Surface triangles (needed only for fingertip collisions).
    """

    rest_positions: np.ndarray
    edges: np.ndarray
    rest_lengths: np.ndarray
    node_mass: float
    faces: np.ndarray | None = None
    degrees: np.ndarray = field(init=False, repr=False)
    # Sparse edge-node incidence D on the flat state: (6e, 6n) maps X to the component-major edge
    # differences [dx; dy; dz; dvx; dvy; dvz] (each row block contiguous), and (6n, 3e) scatters
    # component-major edge forces [fx; fy; fz] to the acceleration slots of dX (+ on node i,
    # - on node j, i.e. the force on node i of a compressed edge).
    gather6: scipy.sparse.csr_matrix = field(init=False, repr=False)
    scatter6: scipy.sparse.csr_matrix = field(init=False, repr=False)
    # Enclosed rest volume V0 [m^3] (0 without faces) and the (n, 3f) scatter of per-corner
    # volume gradients to the nodes.
    rest_volume: float = field(init=False, repr=False)
    corner_scatter: scipy.sparse.csr_matrix | None = field(init=False, repr=False)
    # For corner (f, a): the next and previous vertex of face f, flattened (3 f,).
    corner_next: np.ndarray | None = field(init=False, repr=False)
    corner_prev: np.ndarray | None = field(init=False, repr=False)

    def __post_init__(self) -> None:
        n_nodes = self.rest_positions.shape[0]
        n_edges = self.edges.shape[0]
        object.__setattr__(self, "degrees", np.bincount(self.edges.ravel(), minlength=n_nodes))
        e0, e1 = self.edges[:, 0], self.edges[:, 1]
        comp = np.arange(6)[:, None]
        g_rows = np.concatenate([(comp * n_edges + np.arange(n_edges)).ravel()] * 2)
        g_cols = np.concatenate([(6 * e0[None, :] + comp).ravel(), (6 * e1[None, :] + comp).ravel()])
        g_vals = np.repeat([1.0, -1.0], 6 * n_edges)
        object.__setattr__(
            self,
            "gather6",
            scipy.sparse.csr_matrix((g_vals, (g_rows, g_cols)), shape=(6 * n_edges, 6 * n_nodes)),
        )
        comp3 = np.arange(3)[:, None]
        s_cols = np.concatenate([(comp3 * n_edges + np.arange(n_edges)).ravel()] * 2)
        s_rows = np.concatenate(
            [(6 * e0[None, :] + 3 + comp3).ravel(), (6 * e1[None, :] + 3 + comp3).ravel()]
        )
        s_vals = np.repeat([1.0, -1.0], 3 * n_edges)
        object.__setattr__(
            self,
            "scatter6",
            scipy.sparse.csr_matrix((s_vals, (s_rows, s_cols)), shape=(6 * n_nodes, 3 * n_edges)),
        )
        if self.faces is None:
            object.__setattr__(self, "rest_volume", 0.0)
            object.__setattr__(self, "corner_scatter", None)
            object.__setattr__(self, "corner_next", None)
            object.__setattr__(self, "corner_prev", None)
        else:
            object.__setattr__(self, "corner_next", self.faces[:, [1, 2, 0]].ravel())
            object.__setattr__(self, "corner_prev", self.faces[:, [2, 0, 1]].ravel())
            corners = self.faces.size
            scatter = scipy.sparse.csr_matrix(
                (np.ones(corners), (self.faces.ravel(), np.arange(corners))),
                shape=(n_nodes, corners),
            )
            object.__setattr__(self, "corner_scatter", scatter)
            object.__setattr__(self, "rest_volume", enclosed_volume(self, self.rest_positions))

    @property
    def n_nodes(self) -> int:
        """Number of nodes n."""
        return int(self.rest_positions.shape[0])

    @property
    def n_edges(self) -> int:
        """Number of edges e."""
        return int(self.edges.shape[0])

    @property
    def mass(self) -> float:
        """Total mass n * m_i [kg]."""
        return self.node_mass * self.n_nodes

    @property
    def max_degree(self) -> int:
        """Largest number of edges at one node."""
        return int(self.degrees.max()) if self.n_edges else 0

    @property
    def mean_edge_length(self) -> float:
        """Mean rest length [m]."""
        return float(self.rest_lengths.mean())

    @cached_property
    def unit_stiffness_max(self) -> float:
        """Largest eigenvalue of the rest stiffness matrix per unit k [-] (computed once).

        ``lambda_max(K) / k`` with ``K`` the (3n, 3n) tangent stiffness at rest; bounded above by
        ``max over edges of d_i + d_j <= 2 d_max`` (Anderson & Morley 1985).
        """
        if self.n_edges == 0:
            return 0.0
        unit = _rest_stiffness_matrix(self, 1.0)
        if unit.shape[0] <= 64:
            return float(np.linalg.eigvalsh(unit.toarray())[-1])
        # Fixed start vector: ARPACK's default is random, and dt (hence every trajectory) must
        # not change from run to run.
        start = np.linspace(1.0, 2.0, unit.shape[0])
        return float(
            scipy.sparse.linalg.eigsh(
                unit, k=1, which="LA", return_eigenvectors=False, tol=1e-10, v0=start
            )[0]
        )


def msd_body_from_arrays(positions, edges, mass, faces=None) -> MsdBody:
    """Build an :class:`MsdBody` from node positions and an edge list.

    Parameters
    ----------
    positions : (n, 3) float
        Rest positions in W [m].
    edges : (e, 2) int
        Edges; duplicates (either orientation) are merged.
    mass : float
        Total mass [kg], lumped as ``mass / n`` per node.
    faces : (f, 3) int, optional
        Surface triangles.

    Returns
    -------
    body : MsdBody

    Raises
    ------
    ValueError
        On malformed shapes, self-loops, out-of-range indices or zero-length edges.
    """
    positions = np.array(positions, dtype=np.float64)
    if positions.ndim != 2 or positions.shape[1] != 3 or positions.shape[0] < 1:
        raise ValueError(f"positions must have shape (n, 3) with n >= 1, got {positions.shape}")
    edges = np.asarray(edges, dtype=np.int64)
    if edges.ndim != 2 or edges.shape[1] != 2:
        raise ValueError(f"edges must have shape (e, 2), got {edges.shape}")
    n_nodes = positions.shape[0]
    if edges.size and (edges.min() < 0 or edges.max() >= n_nodes):
        raise ValueError(f"edge indices must lie in [0, {n_nodes}), got [{edges.min()}, {edges.max()}]")
    if np.any(edges[:, 0] == edges[:, 1]):
        raise ValueError("edges must not contain self-loops")
    edges = np.unique(np.sort(edges, axis=1), axis=0)
    lengths = np.linalg.norm(positions[edges[:, 0]] - positions[edges[:, 1]], axis=1)
    if np.any(lengths <= 0.0):
        raise ValueError("edges must have non-zero rest length")
    if not np.isfinite(mass) or mass <= 0.0:
        raise ValueError(f"mass must be finite and > 0, got {mass!r}")
    if faces is not None:
        faces = np.asarray(faces, dtype=np.int64)
        if faces.ndim != 2 or faces.shape[1] != 3:
            raise ValueError(f"faces must have shape (f, 3), got {faces.shape}")
    return MsdBody(
        rest_positions=positions,
        edges=edges,
        rest_lengths=lengths,
        node_mass=float(mass) / n_nodes,
        faces=faces,
    )


def msd_body_from_mesh(mesh: trimesh.Trimesh, params: MsdParams) -> MsdBody:
    """Build the MSD shell of a triangulated surface: nodes = vertices, springs = mesh edges.

    Parameters
    ----------
    mesh : trimesh.Trimesh
        Surface mesh in W [m] (centred on its centroid by ``core.mesh``).
    params : MsdParams
        Supplies the total mass.

    Returns
    -------
    body : MsdBody
        With ``faces`` set, rest lengths from the mesh (§2.1).

    References
    ----------
    §2.2: the adjacency matrix A is the vertex adjacency of the mesh (``mesh.edges_unique``).
    """
    return msd_body_from_arrays(
        mesh.vertices, mesh.edges_unique, params.mass, faces=np.asarray(mesh.faces)
    )


def msd_params_from_modulus(
    mesh: trimesh.Trimesh,
    youngs_modulus: float = 0.14e6,
    mass: float = 0.4,
    zeta_low: float = 0.1,
    zeta_high: float = 1.0,
    g: float = GRAVITY,
) -> MsdParams:
    """Derive SI MSD constants from a modulus and two target damping ratios (see MsdParams).

    Parameters
    ----------
    mesh : trimesh.Trimesh
        Surface mesh [m].
    youngs_modulus : float
        Object modulus E2 [Pa] (Table 2: 0.14 MPa).
    mass : float
        Total mass [kg].
    zeta_low, zeta_high : float
        Target damping ratios of the lowest elastic mode and of the highest mesh mode [-].
    g : float
        Gravity [m/s^2].

    Returns
    -------
    params : MsdParams
        ``k = E2 l_mean``; ``b, c`` the Rayleigh pair through (w1, zeta_low) and
        (w_max, zeta_high), with w from the dense eigenvalues of the rest stiffness matrix.

    Notes
    -----
    Dense eigen-decomposition of a (3n, 3n) matrix: meant for n up to a few thousand. On very
    coarse meshes (``w1 / w_max > zeta_low / zeta_high``) the pair would need ``b < 0``; then
    ``b = 0`` and ``c`` keeps ``zeta_high`` (logged as a warning).
    """
    body = msd_body_from_arrays(mesh.vertices, mesh.edges_unique, mass)
    k = float(youngs_modulus * body.mean_edge_length)
    stiffness = _rest_stiffness_matrix(body, k).toarray()
    eig = np.linalg.eigvalsh(stiffness) / body.node_mass
    # Skip the 6 rigid-body modes (numerically ~0).
    omegas = np.sqrt(np.clip(eig, 0.0, None))
    elastic = omegas[omegas > 1e-6 * omegas[-1]]
    w1, wmax = float(elastic[0]), float(elastic[-1])
    # zeta(w) = alpha/(2w) + beta w/2, alpha = b/m_i, beta = c/k.
    lhs = np.array([[1.0 / (2.0 * w1), w1 / 2.0], [1.0 / (2.0 * wmax), wmax / 2.0]])
    alpha, beta = np.linalg.solve(lhs, [zeta_low, zeta_high])
    if alpha < 0.0:
        # Coarse mesh: w1 / w_max > zeta_low / zeta_high, so the stiffness-proportional part alone
        # already damps w1 more than asked. Keep zeta_high, drop the nodal damper.
        alpha, beta = 0.0, 2.0 * zeta_high / wmax
        logger.warning(
            "msd_params_from_modulus: w1/w_max = %.3f too large for zeta_low = %g; b set to 0 "
            "(zeta(w1) = %.3f)", w1 / wmax, zeta_low, beta * w1 / 2.0,
        )
    return MsdParams(mass=mass, k=k, c=float(beta * k), b=float(alpha * body.node_mass), g=g)


def _rest_stiffness_matrix(body: MsdBody, k: float) -> scipy.sparse.csr_matrix:
    """Return the (3n, 3n) tangent stiffness at rest: sum over edges of k (D^T D) kron (u u^T)."""
    d = body.rest_positions[body.edges[:, 0]] - body.rest_positions[body.edges[:, 1]]
    u = d / body.rest_lengths[:, None]
    blocks = k * u[:, :, None] * u[:, None, :]  # (e, 3, 3)
    i, j = body.edges[:, 0], body.edges[:, 1]
    comp_r, comp_c = np.meshgrid(np.arange(3), np.arange(3), indexing="ij")
    rows, cols, vals = [], [], []
    for a, bb, sign in ((i, i, 1.0), (j, j, 1.0), (i, j, -1.0), (j, i, -1.0)):
        rows.append((3 * a[:, None, None] + comp_r).ravel())
        cols.append((3 * bb[:, None, None] + comp_c).ravel())
        vals.append((sign * blocks).ravel())
    n3 = 3 * body.n_nodes
    return scipy.sparse.csr_matrix(
        (np.concatenate(vals), (np.concatenate(rows), np.concatenate(cols))), shape=(n3, n3)
    )


# ----------------------------------------------------------------------------------------------
# State helpers
# ----------------------------------------------------------------------------------------------


def check_state(state, n_nodes: int) -> np.ndarray:
    """Validate a state vector and return it as float64 of shape (6 n,).

    Raises
    ------
    ValueError
        If the shape is not ``(6 n,)`` or an entry is not finite.
    """
    state = np.asarray(state, dtype=np.float64)
    if state.shape != (6 * n_nodes,):
        raise ValueError(f"state must have shape ({6 * n_nodes},) for n = {n_nodes}, got {state.shape}")
    if not np.all(np.isfinite(state)):
        raise ValueError("state contains non-finite values")
    return state


def positions_from_state(state) -> np.ndarray:
    """Return the (n, 3) node positions [m] of a (6 n,) or (s, 6 n) state (a view)."""
    state = np.asarray(state)
    return state.reshape(*state.shape[:-1], -1, 6)[..., :3]


def velocities_from_state(state) -> np.ndarray:
    """Return the (n, 3) node velocities [m/s] of a (6 n,) or (s, 6 n) state (a view)."""
    state = np.asarray(state)
    return state.reshape(*state.shape[:-1], -1, 6)[..., 3:]


def state_from_positions(positions, velocities=None) -> np.ndarray:
    """Stack (n, 3) positions [m] and velocities [m/s] (default zero) into a (6 n,) state."""
    positions = np.asarray(positions, dtype=np.float64)
    if positions.ndim != 2 or positions.shape[1] != 3:
        raise ValueError(f"positions must have shape (n, 3), got {positions.shape}")
    state = np.zeros((positions.shape[0], 6))
    state[:, :3] = positions
    if velocities is not None:
        velocities = np.asarray(velocities, dtype=np.float64)
        if velocities.shape != positions.shape:
            raise ValueError(
                f"velocities must have shape {positions.shape}, got {velocities.shape}"
            )
        state[:, 3:] = velocities
    return state.ravel()


# ----------------------------------------------------------------------------------------------
# Forces and right-hand side (Eq. 1-5)
# ----------------------------------------------------------------------------------------------


def _edge_terms(body: MsdBody, state: np.ndarray):
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
    d, lengths, stretch_rate = _edge_terms(body, np.asarray(state, dtype=np.float64).ravel())
    tension_per_length = (params.k * (lengths - body.rest_lengths) + params.c * stretch_rate) / lengths
    return -(body.scatter6 @ (d * tension_per_length).ravel()).reshape(-1, 6)[:, 3:]


def enclosed_volume(body: MsdBody, positions) -> float:
    """Return the volume enclosed by the body's faces, ``sum_f x_a . (x_b x x_c) / 6`` [m^3].

    Parameters
    ----------
    body : MsdBody
        With outward-wound ``faces``.
    positions : (n, 3) float
        Node positions [m].
    """
    if body.faces is None:
        raise ValueError("enclosed_volume needs a body with faces")
    tri = np.asarray(positions)[body.faces]
    return float(np.einsum("ij,ij->", tri[:, 0], np.cross(tri[:, 1], tri[:, 2])) / 6.0)


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
    gradient, volume = _volume_gradient(body, np.asarray(positions, dtype=np.float64))
    return (-params.bulk_modulus * (volume - body.rest_volume) / body.rest_volume) * gradient


def _volume_gradient(body: MsdBody, positions: np.ndarray) -> tuple[np.ndarray, float]:
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


# ----------------------------------------------------------------------------------------------
# Integrator
# ----------------------------------------------------------------------------------------------


@dataclass(frozen=True)
class IntegrationResult:
    """Fixed-step trajectory.

    Attributes
    ----------
    times : (s,) float
        Sample times [s].
    states : (s, 6 n) float
        States at those times.
    """

    times: np.ndarray
    states: np.ndarray


def rk4_step(f: Callable, t: float, state: np.ndarray, dt: float) -> np.ndarray:
    """Advance ``dX/dt = f(t, X)`` by one classical fourth-order Runge-Kutta step.

    Parameters
    ----------
    f : callable
        ``f(t, X) -> dX`` with X of any shape.
    t : float
        Current time [s].
    state : ndarray
        Current state X.
    dt : float
        Step [s].

    Returns
    -------
    new_state : ndarray
        X(t + dt) to O(dt^5) locally.

    References
    ----------
    Hairer, Norsett & Wanner (1993), §II.1, Table 1.2 (Kutta 1901).
    """
    half = 0.5 * dt
    k1 = f(t, state)
    k2 = f(t + half, state + half * k1)
    k3 = f(t + half, state + half * k2)
    k4 = f(t + dt, state + dt * k3)
    return state + (dt / 6.0) * (k1 + 2.0 * (k2 + k3) + k4)


def integrate_rk4(
    f: Callable,
    t0: float,
    state0,
    dt: float,
    n_steps: int,
    record_every: int = 1,
) -> IntegrationResult:
    """Integrate with fixed-step RK4 and record every ``record_every``-th state.

    Parameters
    ----------
    f : callable
        ``f(t, X) -> dX``.
    t0 : float
        Initial time [s].
    state0 : (d,) float
        Initial state.
    dt : float
        Step [s], > 0.
    n_steps : int
        Number of steps, >= 0.
    record_every : int
        Record stride; the final state is always recorded.

    Returns
    -------
    result : IntegrationResult
        ``times`` and ``states`` including the initial and the final state.
    """
    if not dt > 0.0:
        raise ValueError(f"dt must be > 0, got {dt!r}")
    if n_steps < 0 or record_every < 1:
        raise ValueError(f"need n_steps >= 0 and record_every >= 1, got {n_steps}, {record_every}")
    state = np.array(state0, dtype=np.float64)
    recorded = list(range(0, n_steps + 1, record_every))
    if recorded[-1] != n_steps:
        recorded.append(n_steps)
    states = np.empty((len(recorded), state.size))
    states[0] = state
    slot = 1
    for step in range(1, n_steps + 1):
        state = rk4_step(f, t0 + (step - 1) * dt, state, dt)
        if slot < len(recorded) and recorded[slot] == step:
            states[slot] = state
            slot += 1
    return IntegrationResult(times=t0 + dt * np.asarray(recorded, dtype=float), states=states)


@lru_cache(maxsize=1)
def _rk4_boundary_table() -> tuple[np.ndarray, np.ndarray]:
    """Return (angles, radii): first exit radius of the RK4 stability region along each ray.

    Angles in [pi/2, pi] (closed left half-plane, upper half; the region is symmetric). Along a
    ray ``z = rho e^{i theta}``, ``|R(z)|^2 - 1`` is a degree-8 polynomial in rho with
    coefficients ``sum_{j+k=m} cos((j-k) theta) / (j! k!)``; the exit radius is its first positive
    real root where it turns positive.
    """
    angles = np.linspace(0.5 * np.pi, np.pi, 721)
    inv_fact = 1.0 / np.array([1.0, 1.0, 2.0, 6.0, 24.0])
    j, k = np.meshgrid(np.arange(5), np.arange(5), indexing="ij")
    radii = np.empty_like(angles)
    for a, theta in enumerate(angles):  # 721 small polynomials, once per process
        terms = inv_fact[j] * inv_fact[k] * np.cos((j - k) * theta)
        coeffs = np.bincount((j + k).ravel(), weights=terms.ravel(), minlength=9)
        coeffs[0] -= 1.0  # |R|^2 - 1; rho = 0 is a root: divide it out
        poly = coeffs[1:][::-1]  # highest degree first for np.roots
        roots = np.roots(poly)
        real = np.sort(roots.real[(np.abs(roots.imag) < 1e-7) & (roots.real > 1e-9)])
        exit_radius = np.inf
        for root in real:
            if np.polyval(coeffs[::-1], root * (1.0 + 1e-6)) > 0.0:
                exit_radius = root
                break
        radii[a] = exit_radius
    return angles, radii


def stable_step_limit(
    k: float,
    node_mass: float,
    max_degree: int,
    c: float = 0.0,
    b: float = 0.0,
    k_extra: float = 0.0,
    c_extra: float = 0.0,
) -> float:
    """Return the largest RK4 step that keeps every linearised mode of the shell stable.

    Parameters
    ----------
    k : float
        Edge stiffness [N/m].
    node_mass : float
        Mass per node [kg].
    max_degree : int
        Largest node degree of the edge graph.
    c, b : float
        Edge damper and absolute nodal damper [N*s/m].
    k_extra, c_extra : float
        Extra per-node stiffness / damping (floor penalty, contact) [N/m], [N*s/m].

    Returns
    -------
    dt_max : float
        Step limit [s]. Undamped: ``2 sqrt(2) / w_max`` (RK4 on the imaginary axis).

    Notes
    -----
    Linearised at rest, the stiffness is ``K = sum_e k (D^T D)_e kron u_e u_e^T`` and
    ``x^T K x <= k x^T (L kron I3) x``, so ``lambda_max(K) <= k lambda_max(L) <= 2 k d_max``
    (Anderson & Morley 1985), hence ``w_max^2 <= (2 k d_max + k_extra) / m_i`` (= 4 k / m for a
    chain, d = 2). On the 356-node sphere the bound (4.2e3 rad/s) is 1.47x the true w_max.
    The edge damper has the same projectors, so the damping rates are bounded by
    ``nu_max = (b + 2 c d_max + c_extra) / m_i``. Every mode then solves
    ``s^2 + nu s + w^2 = 0`` with ``0 <= w <= w_max``, ``b/m_i <= nu <= nu_max``; the returned
    step is the minimum over a grid of such (w, nu) of the exit radius of the RK4 region along
    ``arg(s)`` divided by ``|s|`` (2 sqrt 2 on the imaginary axis, 2.785 on the real axis,
    2.6155 at its narrowest, arg s = 122.7 deg). Geometric (pre-stress) stiffness of strained
    edges is neglected: valid for small strains. Contact stiffness of Eq. 13 with n < 1 is
    unbounded as delta -> 0; the contact forces are held per step (see ``core.dynamics``).

    References
    ----------
    Hairer & Wanner (1996), Solving ODEs II, §IV.2 (stability region of RK4);
    Anderson & Morley (1985).
    """
    if node_mass <= 0.0 or k < 0.0 or max_degree < 0:
        raise ValueError("need node_mass > 0, k >= 0, max_degree >= 0")
    return _shell_step_limit(2.0 * max_degree, k, c, b, node_mass, k_extra, c_extra)


def body_step_limit(body: MsdBody, params: MsdParams, k_extra: float = 0.0, c_extra: float = 0.0) -> float:
    """Return the RK4 step limit of :func:`stable_step_limit` with the body's exact lambda_max(K).

    Parameters
    ----------
    body : MsdBody
    params : MsdParams
    k_extra, c_extra : float
        Extra per-node stiffness / damping (floor penalty, contact) [N/m], [N*s/m].

    Returns
    -------
    dt_max : float
        Step limit [s] of the linearisation at rest; uses ``body.unit_stiffness_max`` (sparse
        eigensolver) instead of the ``2 d_max`` bound, which is 2.2x loose on the 356-node sphere.
        With ``bulk_modulus > 0`` the eigenvalue of the rank-one volume stiffness is added to
        ``k_extra`` (a bound: ``lambda_max(A + B) <= lambda_max(A) + lambda_max(B)``).
    """
    if params.bulk_modulus > 0.0 and body.faces is not None:
        # Rank-one volume stiffness (K_b / V0) g g^T: its eigenvalue is (K_b / V0) |dV/dx|^2.
        grads, _ = _volume_gradient(body, body.rest_positions)
        k_extra = k_extra + params.bulk_modulus / body.rest_volume * float(np.sum(grads * grads))
    return _shell_step_limit(
        body.unit_stiffness_max, params.k, params.c, params.b, body.node_mass, k_extra, c_extra
    )


def _shell_step_limit(
    kappa: float, k: float, c: float, b: float, m: float, k_extra: float, c_extra: float
) -> float:
    """Return the RK4 step limit of modes bounded by ``lambda_max(K) <= k kappa`` (Notes of
    :func:`stable_step_limit`): ``w_max^2 = (k kappa + k_extra) / m``, damping rates in
    ``[b / m, (b + c kappa + c_extra) / m]``."""
    return _rk4_step_limit(np.sqrt((k * kappa + k_extra) / m), b / m, (b + c * kappa + c_extra) / m)


def _rk4_step_limit(w_max: float, nu_lo: float, nu_hi: float) -> float:
    """Return min over modes s^2 + nu s + w^2 = 0 (w <= w_max, nu in [nu_lo, nu_hi]) of h*(s)."""
    if w_max == 0.0 and nu_hi == 0.0:
        return float("inf")
    if nu_hi == 0.0:
        return float(RK4_IMAGINARY_AXIS_LIMIT / w_max)
    angles, exit_radius = _rk4_boundary_table()
    w = np.linspace(0.0, w_max, 257)[:, None]
    nu = np.linspace(nu_lo, nu_hi, 65)[None, :]
    disc = (nu / 2.0) ** 2 - w**2
    sq = np.sqrt(np.abs(disc))
    # Fastest root: complex pair -nu/2 +- i sq, or the real root -nu/2 - sq.
    re = np.where(disc < 0.0, -nu / 2.0, -nu / 2.0 - sq)
    im = np.where(disc < 0.0, sq, 0.0)
    modulus = np.hypot(re, im)
    angle = np.arctan2(im, re)
    valid = modulus > 0.0
    radius = np.interp(angle[valid], angles, exit_radius)
    # Guard against interpolation between table nodes with the neighbouring minimum.
    step = angles[1] - angles[0]
    radius = np.minimum(radius, np.interp(angle[valid] + step, angles, exit_radius))
    radius = np.minimum(radius, np.interp(angle[valid] - step, angles, exit_radius))
    return float(np.min(radius / modulus[valid]))


# ----------------------------------------------------------------------------------------------
# Energies
# ----------------------------------------------------------------------------------------------


def kinetic_energy(body: MsdBody, state) -> np.ndarray:
    """Return the kinetic energy ``1/2 m_i sum |v_i|^2`` [J] of a (6 n,) or (s, 6 n) state."""
    velocities = velocities_from_state(state)
    return 0.5 * body.node_mass * np.sum(velocities * velocities, axis=(-2, -1))


def elastic_energy(body: MsdBody, params: MsdParams, state) -> np.ndarray:
    """Return the spring energy ``1/2 k sum (|x_ij| - l0)^2`` [J] of a (6 n,) or (s, 6 n) state."""
    positions = positions_from_state(state)
    d = positions[..., body.edges[:, 0], :] - positions[..., body.edges[:, 1], :]
    stretch = np.linalg.norm(d, axis=-1) - body.rest_lengths
    return 0.5 * params.k * np.sum(stretch * stretch, axis=-1)


def gravitational_energy(body: MsdBody, params: MsdParams, state) -> np.ndarray:
    """Return ``m_i g sum z_i`` [J] (zero at z = 0) of a (6 n,) or (s, 6 n) state."""
    positions = positions_from_state(state)
    return body.node_mass * params.g * np.sum(positions[..., 2], axis=-1)


def dissipation_power(body: MsdBody, params: MsdParams, state) -> float:
    """Return the power dissipated by the nodal and edge dampers ``b sum|v|^2 + c sum l_dot^2`` [W]."""
    state = np.asarray(state, dtype=np.float64).ravel()
    _, _, stretch_rate = _edge_terms(body, state)
    velocities = velocities_from_state(state)
    return float(params.b * np.sum(velocities * velocities) + params.c * np.sum(stretch_rate**2))


@dataclass(frozen=True)
class EnergyAuditResult:
    """Energy balance of an RK4 run (no contact).

    Attributes
    ----------
    times : (s,) float
        [s].
    kinetic, elastic, gravitational : (s,) float
        Energies [J]; ``elastic`` includes the volume term when ``bulk_modulus > 0``.
    mechanical : (s,) float
        Their sum [J].
    dissipated : (s,) float
        Energy removed by the dampers since t0, integrated with the same RK4 [J].
    external_work : (s,) float
        Work done by the constant external nodal forces since t0 [J].
    balance_error : (s,) float
        ``mechanical - mechanical[0] + dissipated - external_work`` [J]; zero for the exact flow.
    max_relative_error : float
        ``max |balance_error| / max(scale)`` with scale the largest of the energy magnitudes [-].
    n_increases : int
        Steps at which ``mechanical`` grew by more than round-off although no external power
        entered (only meaningful with ``f_ext = None``).
    """

    times: np.ndarray
    kinetic: np.ndarray
    elastic: np.ndarray
    gravitational: np.ndarray
    mechanical: np.ndarray
    dissipated: np.ndarray
    external_work: np.ndarray
    balance_error: np.ndarray
    max_relative_error: float
    n_increases: int


def energy_audit(
    body: MsdBody,
    params: MsdParams,
    state0,
    dt: float,
    n_steps: int,
    f_ext=None,
    record_every: int = 1,
    stepper: Callable | None = None,
) -> EnergyAuditResult:
    """Run an integrator without contact and close the energy balance step by step.

    Parameters
    ----------
    body, params
        The MSD body.
    state0 : (6 n,) float
        Initial state.
    dt : float
        Step [s].
    n_steps : int
        Number of steps.
    f_ext : (n, 3) float, optional
        Constant external nodal forces [N].
    record_every : int
        Record stride.
    stepper : callable, optional
        ``stepper(state, dt) -> (new_state, dissipated, work)``: one step of another integrator
        with the energy its dampers removed and the external work done over the step [J] (e.g.
        ``core.implicit.ImplicitIntegrator.audit_stepper(f_ext)``, which holds its own
        ``f_ext``). Default: classical RK4 with ``f_ext``.

    Returns
    -------
    result : EnergyAuditResult

    Notes
    -----
    With RK4 the dissipated energy ``D`` and the external work ``W`` are appended to the state as
    two extra ODE components (``D_dot`` = damper power, ``W_dot = f_ext . v``) and integrated by
    the same RK4, so the balance error measures only the integrator's truncation error (O(dt^4)
    globally), not a quadrature error. A ``stepper`` reports ``D`` and ``W`` as its own method
    integrates them (the implicit midpoint rule: ``dt P`` at the midpoint state). This is the
    energy audit the paper lists as missing (§12).
    """
    state0 = check_state(state0, body.n_nodes)
    n6 = 6 * body.n_nodes
    if stepper is not None and f_ext is not None:
        raise ValueError("energy_audit: give f_ext to the stepper, not to energy_audit")
    stepper = stepper or _rk4_audit_stepper(body, params, f_ext)
    run = _run_audit_stepper(stepper, state0, dt, n_steps, record_every)
    states = run.states[:, :n6]
    kinetic = kinetic_energy(body, states)
    elastic = elastic_energy(body, params, states) + volume_energy(body, params, states)
    gravitational = gravitational_energy(body, params, states)
    mechanical = kinetic + elastic + gravitational
    dissipated = run.states[:, n6]
    external_work = run.states[:, n6 + 1]
    balance = mechanical - mechanical[0] + dissipated - external_work
    scale = max(
        float(np.max(np.abs(kinetic))),
        float(np.max(np.abs(elastic))),
        float(np.max(np.abs(mechanical - mechanical[0]))),
        float(np.max(np.abs(dissipated))),
        np.finfo(float).tiny,
    )
    roundoff = 64.0 * np.finfo(float).eps * (np.abs(mechanical[:-1]) + scale)
    increases = int(np.sum(np.diff(mechanical) > roundoff))
    return EnergyAuditResult(
        times=run.times,
        kinetic=kinetic,
        elastic=elastic,
        gravitational=gravitational,
        mechanical=mechanical,
        dissipated=dissipated,
        external_work=external_work,
        balance_error=balance,
        max_relative_error=float(np.max(np.abs(balance)) / scale),
        n_increases=increases,
    )


def _rk4_audit_stepper(body: MsdBody, params: MsdParams, f_ext) -> Callable:
    """Return the RK4 audit step: the state with ``D`` and ``W`` as two extra ODE components."""
    n6 = 6 * body.n_nodes
    f_ext_arr = None if f_ext is None else np.asarray(f_ext, dtype=np.float64)

    def augmented(t, y):
        x = y[:n6]
        dx = msd_rhs(t, x, body, params, f_ext_arr)
        velocities = x.reshape(-1, 6)[:, 3:]
        work = 0.0 if f_ext_arr is None else float(np.sum(f_ext_arr * velocities))
        return np.concatenate([dx, [dissipation_power(body, params, x), work]])

    def step(state, dt):
        y = rk4_step(augmented, 0.0, np.concatenate([state, [0.0, 0.0]]), dt)
        return y[:n6], float(y[n6]), float(y[n6 + 1])

    return step


def _run_audit_stepper(stepper: Callable, state0, dt: float, n_steps: int,
                       record_every: int) -> IntegrationResult:
    """Run ``stepper`` and record ``[state, D, W]`` (accumulated) like :func:`integrate_rk4`."""
    if not dt > 0.0:
        raise ValueError(f"dt must be > 0, got {dt!r}")
    if n_steps < 0 or record_every < 1:
        raise ValueError(f"need n_steps >= 0 and record_every >= 1, got {n_steps}, {record_every}")
    recorded = list(range(0, n_steps + 1, record_every))
    if recorded[-1] != n_steps:
        recorded.append(n_steps)
    states = np.empty((len(recorded), state0.size + 2))
    states[0] = np.concatenate([state0, [0.0, 0.0]])
    state, dissipated, work = np.array(state0, dtype=np.float64), 0.0, 0.0
    slot = 1
    for step in range(1, n_steps + 1):
        state, d_inc, w_inc = stepper(state, dt)
        dissipated += d_inc
        work += w_inc
        if slot < len(recorded) and recorded[slot] == step:
            states[slot, :-2] = state
            states[slot, -2:] = (dissipated, work)
            slot += 1
    return IntegrationResult(times=dt * np.asarray(recorded, dtype=float), states=states)


# ----------------------------------------------------------------------------------------------
# Step-size convergence study
# ----------------------------------------------------------------------------------------------


@dataclass(frozen=True)
class StepConvergenceResult:
    """Global error of a fixed-step integrator (RK4 by default) against a tight reference.

    Attributes
    ----------
    dts : (q,) float
        Step sizes, decreasing [s].
    errors : (q,) float
        Max-norm position error at ``t_end`` against the reference [m].
    orders : (q - 1,) float
        Observed orders ``log(e_i / e_{i+1}) / log(dt_i / dt_{i+1})`` [-] (4 for RK4, 2 for the
        implicit midpoint rule).
    t_end : float
        Comparison time [s].
    reference : str
        How the reference solution was obtained.
    """

    dts: np.ndarray
    errors: np.ndarray
    orders: np.ndarray
    t_end: float
    reference: str


def step_convergence(
    body: MsdBody,
    params: MsdParams,
    state0,
    t_end: float,
    dts,
    f_ext=None,
    rtol: float = 1e-11,
    atol: float = 1e-14,
    stepper: Callable | None = None,
) -> StepConvergenceResult:
    """Measure the global error of a fixed-step integrator as the step shrinks (§12).

    Parameters
    ----------
    body, params
        The MSD body (no contact).
    state0 : (6 n,) float
        Initial state.
    t_end : float
        Comparison time [s]; every ``dt`` must divide it (checked to 1e-9 relative).
    dts : (q,) float
        Steps to test [s].
    f_ext : (n, 3) float, optional
        Constant nodal forces [N].
    rtol, atol : float
        Tolerances of the ``scipy.integrate.solve_ivp`` DOP853 reference.
    stepper : callable, optional
        ``stepper(state, dt) -> (new_state, ...)``: one step of the integrator under study, with
        the same ``f_ext`` (e.g. ``core.implicit.ImplicitIntegrator.audit_stepper(f_ext)``).
        Default: classical RK4.

    Returns
    -------
    result : StepConvergenceResult
    """
    from scipy.integrate import solve_ivp

    state0 = check_state(state0, body.n_nodes)
    dts = np.sort(np.asarray(dts, dtype=float))[::-1]

    def rhs(t, x):
        return msd_rhs(t, x, body, params, f_ext)

    reference = solve_ivp(rhs, (0.0, t_end), state0, method="DOP853", rtol=rtol, atol=atol)
    if not reference.success:
        raise RuntimeError(f"reference solve_ivp failed: {reference.message}")
    ref_positions = positions_from_state(reference.y[:, -1])
    errors = []
    for dt in dts:
        n_steps = int(round(t_end / dt))
        if abs(n_steps * dt - t_end) > 1e-9 * t_end:
            raise ValueError(f"dt = {dt} does not divide t_end = {t_end}")
        if stepper is None:
            final = integrate_rk4(rhs, 0.0, state0, t_end / n_steps, n_steps, n_steps).states[-1]
        else:
            final = state0
            for _ in range(n_steps):
                final = stepper(final, t_end / n_steps)[0]
        errors.append(float(np.max(np.abs(positions_from_state(final) - ref_positions))))
    errors = np.asarray(errors)
    orders = np.log(errors[:-1] / errors[1:]) / np.log(dts[:-1] / dts[1:])
    return StepConvergenceResult(
        dts=dts,
        errors=errors,
        orders=orders,
        t_end=float(t_end),
        reference=f"scipy.integrate.solve_ivp DOP853 rtol={rtol:g} atol={atol:g}",
    )


# ----------------------------------------------------------------------------------------------
# Rigid floor and gravity settling (§5.4, Fig. 10)
# ----------------------------------------------------------------------------------------------


@dataclass(frozen=True)
class FloorParams:
    """Penalty contact of the nodes with a rigid horizontal floor (spring-slider friction).

    Attributes
    ----------
    height : float
        Floor plane z [m].
    stiffness : float
        Normal penalty stiffness per node [N/m]. Default 1.4e4 N/m = 10 k: at 0.4 kg the
        sphere's weight then sinks the few support nodes by well under 0.1 mm.
    damping : float
        Normal penalty damping per node [N*s/m]. Default 8 N*s/m: critical for one node of
        0.4 kg / 356 on that spring (``2 sqrt(k_f m_i)`` = 7.9).
    mu : float
        Floor friction coefficient [-]. Default 0.5 (an assumption: a gel on a table; the paper
        does not state it).
    tangential_stiffness, tangential_damping : float
        Stick spring and damper of the friction slider per node [N/m], [N*s/m]; default equal
        to the normal ones (isotropic penalty).

    Notes
    -----
    Normal force per node ``f_n = max(0, k_f p - c_f v_z)``, p the depth below the floor (no
    adhesion). Friction is a Cundall-Strack spring-slider: each touching node has a stick anchor
    ``a``; the trial force ``-k_t (x_t - a) - c_t v_t`` (horizontal) is capped at ``mu f_n``, and
    after each step the anchor of a sliding node is dragged so that the spring sits on the cone.
    A regularised viscous Coulomb law was tried first and rejected: its slope ``mu f_n / v_s`` is
    stiff enough to chatter under explicit RK4 unless ``v_s`` is so large that the base creeps.
    The floor is our modelling choice: §5.4 says only "placed on a flat surface".

    References
    ----------
    Cundall, P. A. & Strack, O. D. L. (1979), "A discrete numerical model for granular
    assemblies", Geotechnique 29(1):47-65 (spring-slider contact).
    """

    height: float = 0.0
    stiffness: float = 1.4e4
    damping: float = 8.0
    mu: float = 0.5
    tangential_stiffness: float = 1.4e4
    tangential_damping: float = 8.0


def floor_forces(state, floor: FloorParams, anchors=None) -> np.ndarray:
    """Return the (n, 3) penalty forces [N] of a rigid floor on the nodes of a (6 n,) state.

    Parameters
    ----------
    state : (6 n,) float
        State vector.
    floor : FloorParams
    anchors : (n, 2) float, optional
        Horizontal stick anchors [m] (see :func:`floor_anchors_update`); None: frictionless.

    Returns
    -------
    forces : (n, 3) float
        Normal (+z) and friction (x, y) forces [N]; zero for nodes above the floor.
    """
    nodes = np.asarray(state).reshape(-1, 6)
    penetration = floor.height - nodes[:, 2]
    forces = np.zeros((nodes.shape[0], 3))
    touching = penetration > 0.0
    if not np.any(touching):
        return forces
    v = nodes[touching, 3:]
    normal = _floor_normal(penetration[touching], v[:, 2], floor)
    forces[touching, 2] = normal
    if anchors is not None and floor.mu > 0.0:
        forces[touching, :2] = _floor_friction(
            nodes[touching, :2], v[:, :2], anchors[touching], normal, floor
        )
    return forces


def _floor_normal(penetration, v_z, floor: FloorParams) -> np.ndarray:
    """Return the penalty normal force ``max(0, k_f p - c_f v_z)`` [N] (no adhesion)."""
    return np.maximum(0.0, floor.stiffness * penetration - floor.damping * v_z)


def _floor_friction(xy, v_xy, anchors, normal, floor: FloorParams) -> np.ndarray:
    trial = -floor.tangential_stiffness * (xy - anchors) - floor.tangential_damping * v_xy
    size = np.sqrt(np.sum(trial * trial, axis=1))
    cap = floor.mu * normal
    scale = np.where(size > cap, cap / np.where(size > 0.0, size, 1.0), 1.0)
    return trial * scale[:, None]


def floor_anchors_update(state, floor: FloorParams, anchors) -> np.ndarray:
    """Return the stick anchors after a step (return mapping of the spring-slider).

    Parameters
    ----------
    state : (6 n,) float
        State at the end of the step.
    floor : FloorParams
    anchors : (n, 2) float
        Anchors used during the step [m].

    Returns
    -------
    anchors : (n, 2) float
        Nodes off the floor: anchor at the node. Sliding nodes: anchor moved along the spring so
        that ``k_t |x_t - a| = mu f_n``. Sticking nodes: unchanged.
    """
    nodes = np.asarray(state).reshape(-1, 6)
    xy = nodes[:, :2]
    new = np.array(anchors, dtype=np.float64, copy=True)
    penetration = floor.height - nodes[:, 2]
    normal = _floor_normal(penetration, nodes[:, 5], floor)
    touching = (penetration > 0.0) & (normal > 0.0)
    new[~touching] = xy[~touching]
    stretch = xy - new
    length = np.sqrt(np.sum(stretch * stretch, axis=1))
    allowed = floor.mu * normal / floor.tangential_stiffness
    sliding = touching & (length > allowed)
    if np.any(sliding):
        new[sliding] = xy[sliding] - stretch[sliding] * (allowed[sliding] / length[sliding])[:, None]
    return new


@dataclass(frozen=True)
class SettleResult:
    """Outcome of a gravity-settling run on a floor (Fig. 10).

    Attributes
    ----------
    times : (s,) float
        Recorded times [s].
    kinetic_energy : (s,) float
        Kinetic energy trace [J].
    height_ratio : (s,) float
        Current height (max z - min z) over the undeformed height [-].
    squash_ratio : float
        Final ``height_ratio`` [-].
    positions : (n, 3) float
        Settled node positions [m].
    initial_positions : (n, 3) float
        Undeformed positions resting on the floor [m].
    settled : bool
        Whether the kinetic energy stayed below tolerance over the final window.
    dt : float
        Step used [s].
    n_steps : int
        Steps taken.
    max_floor_penetration : float
        Deepest node below the floor at the end [m] (penalty artefact, should be << l_mean).
    """

    times: np.ndarray
    kinetic_energy: np.ndarray
    height_ratio: np.ndarray
    squash_ratio: float
    positions: np.ndarray
    initial_positions: np.ndarray
    settled: bool
    dt: float
    n_steps: int
    max_floor_penetration: float


def settle_on_floor(
    body: MsdBody,
    params: MsdParams,
    floor: FloorParams | None = None,
    dt: float | None = None,
    t_max: float = 2.0,
    ke_tol: float | None = None,
    window: float = 0.05,
    record_every: int = 10,
    stepper: Callable | None = None,
) -> SettleResult:
    """Place the undeformed body on a rigid floor, release it under gravity, and let it settle.

    Parameters
    ----------
    body, params
        The MSD body.
    floor : FloorParams, optional
        Floor constants; its ``height`` is ignored and set to the lowest rest node, so the body
        starts touching the floor at rest.
    dt : float, optional
        Step [s]; default (RK4 only) half of :func:`body_step_limit` including the floor penalty.
    t_max : float
        Time budget [s].
    ke_tol : float, optional
        Kinetic-energy tolerance [J]; default ``1e-7 m g H0`` (H0 the undeformed height).
    window : float
        The kinetic energy must stay below ``ke_tol`` this long to stop [s].
    record_every : int
        Record stride of the traces (the stop test uses every step).
    stepper : callable, optional
        ``stepper(state, floor, anchors, dt) -> state``: one step of another integrator with the
        floor forces (anchors held over the step), e.g.
        ``core.implicit.ImplicitIntegrator.floor_stepper()``; then ``dt`` is required. Default:
        classical RK4 with the floor forces evaluated at every stage.

    Returns
    -------
    result : SettleResult

    References
    ----------
    §5.4, Fig. 10.
    """
    rest = body.rest_positions
    floor = replace(floor or FloorParams(), height=float(rest[:, 2].min()))
    height0 = float(np.ptp(rest[:, 2]))
    limit = body_step_limit(
        body,
        params,
        max(floor.stiffness, floor.tangential_stiffness),
        max(floor.damping, floor.tangential_damping),
    )
    if stepper is not None:
        if dt is None:
            raise ValueError("settle_on_floor: a stepper needs an explicit dt")
    elif dt is None:
        dt = 0.5 * limit
    elif dt > limit:
        logger.warning("settle_on_floor: dt = %.3g s exceeds the RK4 limit %.3g s", dt, limit)
    if ke_tol is None:
        ke_tol = 1e-7 * body.mass * params.g * height0

    state = state_from_positions(rest)
    anchors = rest[:, :2].copy()

    def rhs(t, x):
        return msd_rhs(t, x, body, params, floor_forces(x, floor, anchors))

    max_steps = int(np.ceil(t_max / dt))
    window_steps = max(1, int(np.ceil(window / dt)))
    times, kinetic, ratio = [0.0], [0.0], [1.0]
    quiet = 0
    settled = False
    step = 0
    min_steps = window_steps  # the body starts at rest: do not stop before it has moved
    for step in range(1, max_steps + 1):
        if stepper is None:
            state = rk4_step(rhs, (step - 1) * dt, state, dt)
        else:
            state = stepper(state, floor, anchors, dt)
        anchors[:] = floor_anchors_update(state, floor, anchors)
        ke = float(kinetic_energy(body, state))
        if not np.isfinite(ke):
            raise FloatingPointError(f"settle_on_floor diverged at step {step} (dt = {dt:.3g} s)")
        quiet = quiet + 1 if ke < ke_tol else 0
        done = step > min_steps and quiet >= window_steps
        if step % record_every == 0 or done or step == max_steps:
            positions = positions_from_state(state)
            times.append(step * dt)
            kinetic.append(ke)
            ratio.append(float(np.ptp(positions[:, 2])) / height0)
        if done:
            settled = True
            break
    positions = positions_from_state(state).copy()
    logger.info(
        "settle_on_floor: %s after %d steps (%.3f s), squash ratio %.4f",
        "settled" if settled else "not settled",
        step,
        step * dt,
        ratio[-1],
    )
    return SettleResult(
        times=np.asarray(times),
        kinetic_energy=np.asarray(kinetic),
        height_ratio=np.asarray(ratio),
        squash_ratio=ratio[-1],
        positions=positions,
        initial_positions=rest.copy(),
        settled=settled,
        dt=float(dt),
        n_steps=step,
        max_floor_penetration=float(max(0.0, floor.height - positions[:, 2].min())),
    )
