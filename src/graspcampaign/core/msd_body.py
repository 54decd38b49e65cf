"""Mass-spring-damper (MSD) surface-shell body: parameters, body construction, enclosed volume.

The body of §2 (Eq. 1-5): the object's surface mesh is a shell of ``n`` point masses ``m/n``
joined along the mesh edges by linear springs ``k`` with parallel dampers ``c`` acting on the
stretch rate, plus an absolute nodal damper ``b``. The body holds the sparse edge incidence
matrices the forces of :mod:`graspcampaign.core.msd_forces` are assembled with.

Shape letters: ``n`` nodes, ``e`` edges, ``f`` faces.

The ``6 n`` state vector of the body is laid out as described in :mod:`graspcampaign.core.msd_state`.

References
----------
Eq. 1-5 (§2.1-2.2).
"""

from __future__ import annotations

import logging
from dataclasses import dataclass, field
from functools import cached_property

import numpy as np
import scipy.sparse
import scipy.sparse.linalg
import trimesh

from graspcampaign.core.statics import GRAVITY

__all__ = [
    "MsdBody",
    "MsdParams",
    "enclosed_volume",
    "msd_body_from_arrays",
    "msd_body_from_mesh",
    "msd_params_from_modulus",
    "rest_stiffness_matrix",
]

logger = logging.getLogger(__name__)


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
        unit = rest_stiffness_matrix(self, 1.0)
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
    stiffness = rest_stiffness_matrix(body, k).toarray()
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


def rest_stiffness_matrix(body: MsdBody, k: float) -> scipy.sparse.csr_matrix:
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
