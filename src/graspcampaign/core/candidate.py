"""Candidate grasps of one soft body: the shared context, the sampling of Algorithm 1 line 1, results.

Every planner (:mod:`graspcampaign.core.planner`, :mod:`graspcampaign.core.baseline`) maps a
prepared per-body :class:`PlanContext` and a ``numpy.random.Generator`` to a :class:`PlanResult`:
three contacts, their H(G) components and Ferrari-Canny epsilon, and the quasi-static evaluation
of that triple under the planner's own contact parameters (its belief about the grasp).

Shape letters: ``n`` mesh vertices, ``f`` faces, ``m`` candidate triples.

References
----------
Algorithm 1 (§11), Eq. 6-9 (§3.1), §6.7 and §11 (fixed candidate budget), SPEC §2.8; Ferrari &
Canny (1992) for epsilon (:mod:`graspcampaign.core.ferrari_canny`).
"""

from __future__ import annotations

import logging
from dataclasses import dataclass, field

import numpy as np
import trimesh

from graspcampaign.core.contact import NOMINAL_CONTACT, ContactParams
from graspcampaign.core.equilibrium import EquilibriumResult, EvaluatorParams, evaluate_grasps
from graspcampaign.core.ferrari_canny import DEFAULT_CONE_EDGES, epsilon_metric
from graspcampaign.core.metric import (
    HeuristicContext,
    HeuristicWeights,
    heuristic_context,
    heuristic_terms,
)

__all__ = [
    "DEFAULT_EXHAUSTIVE_LIMIT",
    "DEFAULT_N_CAND",
    "DEFAULT_REFERENCE_BUDGET",
    "CandidateScores",
    "PlanContext",
    "PlanResult",
    "argmin_h",
    "candidate_epsilon",
    "evaluate_triple",
    "finish_plan",
    "identification_contacts",
    "plan_context",
    "sample_triples",
    "vertex_sampling_weights",
]

logger = logging.getLogger(__name__)

DEFAULT_N_CAND = 1000
"""Candidate triples scored per plan (Algorithm 1 line 1), fixed and independent of |V|.

The paper pins N_cand without publishing it (§11). 1000 is the budget the issue's latency target
is stated at; it samples ~1e-4 of the ~1e7 triples of a 390-node mesh. See docs/decisions.md.
"""

DEFAULT_REFERENCE_BUDGET = 200_000
"""Sampled triples of the ``reference`` planner when exhaustive search is too large."""

DEFAULT_EXHAUSTIVE_LIMIT = 3_000_000
"""The ``reference`` planner enumerates all C(n, 3) triples when there are at most this many."""


@dataclass(frozen=True)
class PlanContext:
    """Everything a planner needs about one soft body (object x mass x friction).

    Attributes
    ----------
    vertices : (n, 3) float
        Mesh vertices in W [m].
    normals : (n, 3) float
        Outward unit vertex normals.
    faces : (f, 3) int
        Triangles.
    sampling_weights : (n,) float
        Probability of each vertex in Algorithm 1 line 1 (sums to 1).
    centroid : (3,) float
        Object centroid [m].
    heuristic : HeuristicContext
        Precomputed H(G) inputs (metric module).
    weights : HeuristicWeights
        Full-heuristic weights (unit weights in simulation, §5.2).
    mass : float
        Object mass [kg].
    mu : float
        Friction coefficient [-].
    contact : ContactParams
        Identified contact parameters (this body's PSO result).
    nominal_contact : ContactParams
        Uncalibrated parameters of the ``no_pso`` ablation.
    evaluator : EvaluatorParams
        Algorithm 2 settings.
    n_cand : int
        Candidate budget per plan.
    reference_budget : int
        Sampled budget of the ``reference`` planner when it cannot enumerate.
    exhaustive_limit : int
        Largest C(n, 3) the ``reference`` planner enumerates.
    fc_cone_edges : int
        Edges of the linearised friction cones of the Ferrari-Canny epsilon.
    """

    vertices: np.ndarray
    normals: np.ndarray
    faces: np.ndarray
    sampling_weights: np.ndarray
    centroid: np.ndarray
    heuristic: HeuristicContext
    weights: HeuristicWeights
    mass: float
    mu: float
    contact: ContactParams
    nominal_contact: ContactParams = NOMINAL_CONTACT
    evaluator: EvaluatorParams = field(default_factory=EvaluatorParams)
    n_cand: int = DEFAULT_N_CAND
    reference_budget: int = DEFAULT_REFERENCE_BUDGET
    exhaustive_limit: int = DEFAULT_EXHAUSTIVE_LIMIT
    fc_cone_edges: int = DEFAULT_CONE_EDGES

    @property
    def n_vertices(self) -> int:
        """Number of mesh vertices."""
        return int(self.vertices.shape[0])

    @property
    def torque_length(self) -> float:
        """Epsilon's torque scale L: the largest centroid-to-vertex distance (S3's d_max) [m]."""
        return float(self.heuristic.d_max)


@dataclass(frozen=True)
class CandidateScores:
    """Both quality measures over one plan's N_cand sampled triples (same draw, same order).

    Attributes
    ----------
    h_total : (m,) float
        Full H(G) of each candidate (lower is better).
    epsilon : (m,) float
        Ferrari-Canny epsilon of each candidate (higher is better; 0 without force closure).
    """

    h_total: np.ndarray
    epsilon: np.ndarray


@dataclass(frozen=True)
class PlanResult:
    """A planner's chosen contact triple and its own belief about it.

    Attributes
    ----------
    planner : str
        Registry name.
    vertex_ids : (3,) int
        Contact vertices (for ``centroid``: the vertex nearest each exact contact point).
    points : (3, 3) float
        Contact points in W [m].
    normals : (3, 3) float
        Outward unit contact normals given to the evaluator.
    s1, s2, s3 : float
        Heuristic components of the triple (Eq. 7-9) at ``vertex_ids``.
    n_c, n_e : int
        Sharp-vertex and sharp-edge penalty counts.
    h_total : float
        Full H(G) with the context's weights (recomputable ablation axis, §6.3).
    h_planner : float
        The objective this planner minimised (ablated weights, S1 only, ...); NaN for planners
        that do not minimise H.
    n_scored : int
        Candidate triples (or pairs) scored.
    exhaustive : bool
        True when every triple of the mesh was scored (``reference`` on small meshes).
    contact : ContactParams
        Contact parameters of the planner's own evaluation.
    equilibrium : EquilibriumResult
        Algorithm 2 + checks on the triple under ``contact`` (batch of one): the planner's
        believed outcome.
    epsilon_fc : float
        Ferrari-Canny epsilon of the triple (:func:`candidate_epsilon`).
    candidates : CandidateScores or None
        H(G) and epsilon of every scored candidate, for planners that compute both
        (``ferrari_canny``).
    """

    planner: str
    vertex_ids: np.ndarray
    points: np.ndarray
    normals: np.ndarray
    s1: float
    s2: float
    s3: float
    n_c: int
    n_e: int
    h_total: float
    h_planner: float
    n_scored: int
    exhaustive: bool
    contact: ContactParams
    equilibrium: EquilibriumResult
    epsilon_fc: float = float("nan")
    candidates: CandidateScores | None = None

    @property
    def believed_success(self) -> bool:
        """The planner's own pass/fail verdict (Algorithm 1 line 6 under its parameters)."""
        return bool(self.equilibrium.success[0])


def vertex_sampling_weights(mesh: trimesh.Trimesh) -> np.ndarray:
    """Return area-uniform vertex sampling probabilities (one third of incident face areas).

    Parameters
    ----------
    mesh : trimesh.Trimesh
        Surface mesh.

    Returns
    -------
    weights : (n,) float
        Barycentric vertex areas normalised to sum to 1.

    Notes
    -----
    Algorithm 1 line 1 samples "uniformly over the surface"; with contacts restricted to vertices,
    weighting each vertex by the surface area it represents (its barycentric cell) is the discrete
    uniform surface measure and does not depend on how densely a region is meshed.
    """
    faces = np.asarray(mesh.faces)
    areas = np.repeat(np.asarray(mesh.area_faces) / 3.0, 3)
    vertex_areas = np.bincount(faces.ravel(), weights=areas, minlength=len(mesh.vertices))
    return vertex_areas / vertex_areas.sum()


def sample_triples(weights: np.ndarray, n_triples: int, rng: np.random.Generator) -> np.ndarray:
    """Draw vertex triples of three distinct vertices, each vertex with probability ``weights``.

    Parameters
    ----------
    weights : (n,) float
        Vertex probabilities (sum to 1).
    n_triples : int
        Number of triples m.
    rng : numpy.random.Generator
        Random source.

    Returns
    -------
    triples : (m, 3) int
        Vertex ids; rows with a repeated vertex are redrawn as a batch until none remain.
    """
    n_vertices = weights.shape[0]
    if n_vertices < 3:
        raise ValueError(f"need at least 3 vertices to sample triples, got {n_vertices}")
    cumulative = np.cumsum(weights)
    cumulative /= cumulative[-1]

    def draw(shape):
        picks = np.searchsorted(cumulative, rng.random(shape), side="right")
        return np.minimum(picks, n_vertices - 1)

    triples = draw((n_triples, 3))
    while True:
        bad = (
            (triples[:, 0] == triples[:, 1])
            | (triples[:, 1] == triples[:, 2])
            | (triples[:, 0] == triples[:, 2])
        )
        n_bad = int(bad.sum())
        if n_bad == 0:
            return triples
        triples[bad] = draw((n_bad, 3))


def plan_context(
    mesh: trimesh.Trimesh,
    features,
    *,
    mass: float,
    mu: float,
    contact: ContactParams,
    weights: HeuristicWeights | None = None,
    evaluator: EvaluatorParams | None = None,
    n_cand: int = DEFAULT_N_CAND,
    d_opt: float | None = None,
    nominal_contact: ContactParams = NOMINAL_CONTACT,
    reference_budget: int = DEFAULT_REFERENCE_BUDGET,
    exhaustive_limit: int = DEFAULT_EXHAUSTIVE_LIMIT,
    fc_cone_edges: int = DEFAULT_CONE_EDGES,
) -> PlanContext:
    """Prepare the per-body context shared by every planner of one scene.

    Parameters
    ----------
    mesh : trimesh.Trimesh
        Object surface centred on its centroid [m].
    features : SharpFeatures
        Output of :func:`graspcampaign.core.feature.sharp_features` for ``mesh``.
    mass : float
        Object mass [kg].
    mu : float
        Friction coefficient [-].
    contact : ContactParams
        Identified contact parameters of this body.
    weights : HeuristicWeights, optional
        Heuristic weights (the metric module's default when omitted).
    evaluator : EvaluatorParams, optional
        Algorithm 2 settings.
    n_cand : int
        Candidate budget per plan.
    d_opt : float, optional
        Target side length of S2 [m] (the metric module's default when omitted).
    nominal_contact : ContactParams
        Parameters of the ``no_pso`` ablation.
    reference_budget, exhaustive_limit : int
        Budget of the ``reference`` planner.
    fc_cone_edges : int
        Cone edges of the Ferrari-Canny epsilon.

    Returns
    -------
    context : PlanContext
    """
    if int(n_cand) != n_cand or n_cand < 1:
        raise ValueError(f"n_cand must be a positive int, got {n_cand!r}")
    heuristic = heuristic_context(mesh, features, d_opt=d_opt)
    return PlanContext(
        vertices=np.asarray(heuristic.vertices, dtype=float),
        normals=np.asarray(heuristic.normals, dtype=float),
        faces=np.asarray(mesh.faces, dtype=np.int64),
        sampling_weights=vertex_sampling_weights(mesh),
        centroid=np.asarray(heuristic.centroid, dtype=float),
        heuristic=heuristic,
        weights=HeuristicWeights() if weights is None else weights,
        mass=float(mass),
        mu=float(mu),
        contact=contact,
        nominal_contact=nominal_contact,
        evaluator=EvaluatorParams() if evaluator is None else evaluator,
        n_cand=int(n_cand),
        reference_budget=int(reference_budget),
        exhaustive_limit=int(exhaustive_limit),
        fc_cone_edges=int(fc_cone_edges),
    )


def evaluate_triple(
    ctx: PlanContext, points, normals, contact: ContactParams | None = None, **kwargs
) -> EquilibriumResult:
    """Run the quasi-static evaluator on one contact triple of this body.

    Parameters
    ----------
    ctx : PlanContext
        Body (centroid, mass, friction, evaluator settings).
    points : (3, 3) float
        Contact points [m].
    normals : (3, 3) float
        Outward unit normals.
    contact : ContactParams, optional
        Contact parameters (``ctx.contact`` when omitted).
    **kwargs
        Passed to :func:`graspcampaign.core.equilibrium.evaluate_grasps` (``record_trace``).

    Returns
    -------
    result : EquilibriumResult
        Batch of one.
    """
    contact = ctx.contact if contact is None else contact
    return evaluate_grasps(
        points,
        normals,
        ctx.centroid,
        ctx.mass,
        ctx.mu,
        contact.k_n_per_mm_n,
        contact.n,
        ctx.evaluator,
        **kwargs,
    )


def _scalar_terms(terms, index: int) -> dict[str, float | int]:
    return {
        "s1": float(np.asarray(terms.s1)[index]),
        "s2": float(np.asarray(terms.s2)[index]),
        "s3": float(np.asarray(terms.s3)[index]),
        "n_c": int(np.asarray(terms.n_c)[index]),
        "n_e": int(np.asarray(terms.n_e)[index]),
    }


def finish_plan(
    ctx: PlanContext,
    name: str,
    vertex_ids,
    *,
    points=None,
    normals=None,
    contact: ContactParams | None = None,
    h_planner: float = float("nan"),
    n_scored: int = 0,
    exhaustive: bool = False,
    candidates: CandidateScores | None = None,
) -> PlanResult:
    """Assemble a planner's result: H(G) terms, epsilon and its own evaluation of the triple."""
    vertex_ids = np.asarray(vertex_ids, dtype=np.int64).reshape(3)
    points = ctx.vertices[vertex_ids] if points is None else np.asarray(points, dtype=float)
    normals = ctx.normals[vertex_ids] if normals is None else np.asarray(normals, dtype=float)
    terms = heuristic_terms(ctx.heuristic, vertex_ids[None])
    contact = ctx.contact if contact is None else contact
    return PlanResult(
        planner=name,
        vertex_ids=vertex_ids,
        points=points,
        normals=normals,
        h_total=float(np.asarray(terms.total(ctx.weights))[0]),
        h_planner=float(h_planner),
        n_scored=int(n_scored),
        exhaustive=exhaustive,
        contact=contact,
        equilibrium=evaluate_triple(ctx, points, normals, contact),
        epsilon_fc=float(_epsilon(ctx, points[None], normals[None])[0]),
        candidates=candidates,
        **_scalar_terms(terms, 0),
    )


def _epsilon(ctx: PlanContext, points, normals) -> np.ndarray:
    return epsilon_metric(points, normals, ctx.mu, ctx.centroid, ctx.torque_length,
                          ctx.fc_cone_edges)


def candidate_epsilon(ctx: PlanContext, triples: np.ndarray) -> np.ndarray:
    """Return the Ferrari-Canny epsilon of vertex triples of this body, shape (m,).

    Contacts are the vertices with their outward vertex normals (the ones H(G) and Algorithm 2
    see), friction ``ctx.mu``, torques about the centroid over :attr:`PlanContext.torque_length`,
    ``ctx.fc_cone_edges`` cone edges (:func:`graspcampaign.core.ferrari_canny.epsilon_metric`).
    """
    return _epsilon(ctx, ctx.vertices[triples], ctx.normals[triples])


def argmin_h(ctx: PlanContext, triples: np.ndarray, weights: HeuristicWeights):
    """Return the candidate of least H(G) under ``weights`` and its score (ties: first drawn)."""
    scores = np.asarray(heuristic_terms(ctx.heuristic, triples).total(weights), dtype=float)
    best = int(np.argmin(scores))  # ties: the first drawn
    return triples[best], float(scores[best])


def identification_contacts(ctx: PlanContext, rng: np.random.Generator):
    """Return the heuristic argmin triple used to identify this body's contact parameters.

    Parameters
    ----------
    ctx : PlanContext
        Body context (its ``contact`` is not used).
    rng : numpy.random.Generator
        Source of the N_cand candidates (derive it from the body, not the trial).

    Returns
    -------
    vertex_ids : (3,) int
    points : (3, 3) float
        Contact points [m].
    normals : (3, 3) float
        Outward unit normals.

    Notes
    -----
    Algorithm 1 lines 1-2 only: H(G) is geometric, so the identification contact set does not
    depend on the parameters being identified.
    """
    triples = sample_triples(ctx.sampling_weights, ctx.n_cand, rng)
    best, _ = argmin_h(ctx, triples, ctx.weights)
    return best, ctx.vertices[best], ctx.normals[best]
