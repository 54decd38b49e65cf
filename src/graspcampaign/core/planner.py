"""Grasp planners: the heuristic pipeline of Algorithm 1, its ablations, baselines and a reference.

Every planner maps a prepared per-body :class:`PlanContext` and a ``numpy.random.Generator`` to a
:class:`PlanResult`: three contact vertices, their H(G) components, and the quasi-static evaluation
of that triple under the planner's own contact parameters (its belief about the grasp). Names map
to callables through :data:`PLANNERS`, so a config never imports code.

Shape letters: ``n`` mesh vertices, ``f`` faces, ``m`` candidate triples, ``r`` rays.

References
----------
Algorithm 1 (§11), Eq. 6-9 (§3.1), §5.2, §6.3 (ablation), §6.5 (baselines), §6.7 and §11 (fixed
candidate budget), SPEC §2.8.
"""

from __future__ import annotations

import logging
from dataclasses import dataclass, field, replace

import numpy as np
import trimesh

from graspcampaign.core.contact import NOMINAL_CONTACT, ContactParams
from graspcampaign.core.equilibrium import EquilibriumResult, EvaluatorParams, evaluate_grasps
from graspcampaign.core.metric import (
    HeuristicContext,
    HeuristicWeights,
    heuristic_context,
    heuristic_terms,
)

__all__ = [
    "ABLATIONS",
    "DEFAULT_N_CAND",
    "PLANNERS",
    "PlanContext",
    "PlanResult",
    "evaluate_triple",
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

_CHUNK = 200_000

ABLATIONS = {
    "no_s1": "w1",
    "no_s2": "w2",
    "no_s3": "w3",
    "no_pc": "p_c",
    "no_pe": "p_e",
}
"""Single-term ablations of §6.3: planner name -> the HeuristicWeights field set to zero."""


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

    @property
    def n_vertices(self) -> int:
        """Number of mesh vertices."""
        return int(self.vertices.shape[0])


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


def _finish(
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
) -> PlanResult:
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
        **_scalar_terms(terms, 0),
    )


def _argmin_h(ctx: PlanContext, triples: np.ndarray, weights: HeuristicWeights):
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
    best, _ = _argmin_h(ctx, triples, ctx.weights)
    return best, ctx.vertices[best], ctx.normals[best]


def _heuristic_planner(name: str, weights_of, nominal: bool = False):
    def plan(ctx: PlanContext, rng: np.random.Generator) -> PlanResult:
        triples = sample_triples(ctx.sampling_weights, ctx.n_cand, rng)
        best, score = _argmin_h(ctx, triples, weights_of(ctx))
        contact = ctx.nominal_contact if nominal else ctx.contact
        return _finish(ctx, name, best, contact=contact, h_planner=score, n_scored=len(triples))

    plan.__name__ = f"plan_{name}"
    plan.__doc__ = f"Planner {name!r}: argmin over N_cand sampled triples, then Algorithm 2."
    return plan


def _ablated(field_name: str):
    return lambda ctx: replace(ctx.weights, **{field_name: 0.0})


def _s1_only(ctx: PlanContext) -> HeuristicWeights:
    return replace(ctx.weights, w2=0.0, w3=0.0, p_c=0.0, p_e=0.0)


def plan_random(ctx: PlanContext, rng: np.random.Generator) -> PlanResult:
    """Return one uniformly random triple of distinct vertices (same surface measure as line 1)."""
    triple = sample_triples(ctx.sampling_weights, 1, rng)[0]
    return _finish(ctx, "random", triple, n_scored=1)


def plan_antipodal(ctx: PlanContext, rng: np.random.Generator) -> PlanResult:
    """Return the most antipodal of N_cand sampled vertex pairs plus a perpendicular third contact.

    Notes
    -----
    Pair (i, j) with axis ``u = (p_j - p_i)/|p_j - p_i|`` scores ``min(-n_i . u, n_j . u)``, 1 for
    two contacts squeezing exactly along their common normal line (Nguyen 1988). The third contact
    is the vertex whose direction from the pair's midpoint is closest to a unit vector drawn
    uniformly in the plane perpendicular to ``u`` (random azimuth about the axis).

    References
    ----------
    §6.5; Nguyen, V.-D. (1988), "Constructing force-closure grasps", IJRR 7(3):3-16.
    """
    pairs = sample_triples(ctx.sampling_weights, ctx.n_cand, rng)[:, :2]
    p_i, p_j = ctx.vertices[pairs[:, 0]], ctx.vertices[pairs[:, 1]]
    axes = p_j - p_i
    axes /= np.linalg.norm(axes, axis=1, keepdims=True)
    score = np.minimum(
        -np.sum(ctx.normals[pairs[:, 0]] * axes, axis=1),
        np.sum(ctx.normals[pairs[:, 1]] * axes, axis=1),
    )
    best = int(np.argmax(score))
    i, j = pairs[best]
    axis = axes[best]
    midpoint = 0.5 * (ctx.vertices[i] + ctx.vertices[j])

    draw = rng.normal(size=3)
    perpendicular = draw - np.dot(draw, axis) * axis
    perpendicular /= np.linalg.norm(perpendicular)
    offsets = ctx.vertices - midpoint
    lengths = np.linalg.norm(offsets, axis=1)
    alignment = np.where(lengths > 0.0, offsets @ perpendicular / np.maximum(lengths, 1e-300), -2)
    alignment[[i, j]] = -np.inf
    k = int(np.argmax(alignment))
    return _finish(ctx, "antipodal", [i, j, k], n_scored=len(pairs))


def _ray_farthest_hits(origin, directions, triangles):
    """Return the farthest intersection of each ray with a triangle soup (Moller-Trumbore).

    Parameters
    ----------
    origin : (3,) float
        Common ray origin [m].
    directions : (r, 3) float
        Unit ray directions.
    triangles : (f, 3, 3) float
        Triangle vertices [m].

    Returns
    -------
    faces : (r,) int
        Hit face per ray, -1 for a miss.
    distances : (r,) float
        Ray parameter of the hit [m], NaN for a miss.
    barycentric : (r, 3) float
        Weights of the hit point on the face's three vertices.

    References
    ----------
    Moller, T. & Trumbore, B. (1997), "Fast, minimum storage ray-triangle intersection",
    J. Graphics Tools 2(1):21-28.
    """
    v0 = triangles[:, 0]
    e1 = triangles[:, 1] - v0
    e2 = triangles[:, 2] - v0
    d = directions[:, None, :]
    h = np.cross(d, e2[None])
    a = np.sum(e1[None] * h, axis=-1)
    s = (origin - v0)[None]
    with np.errstate(divide="ignore", invalid="ignore"):
        inv = 1.0 / a
        u = inv * np.sum(s * h, axis=-1)
        q = np.cross(np.broadcast_to(s, h.shape), e1[None])
        v = inv * np.sum(d * q, axis=-1)
        t = inv * np.sum(e2[None] * q, axis=-1)
        hit = (np.abs(a) > 1e-18) & (u >= 0.0) & (v >= 0.0) & (u + v <= 1.0) & (t > 0.0)
    t_hit = np.where(hit, t, -np.inf)
    faces = np.argmax(t_hit, axis=1)
    rows = np.arange(len(directions))
    missed = ~hit[rows, faces]
    u_best, v_best = u[rows, faces], v[rows, faces]
    barycentric = np.stack([1.0 - u_best - v_best, u_best, v_best], axis=1)
    return (
        np.where(missed, -1, faces),
        np.where(missed, np.nan, t_hit[rows, faces]),
        np.where(missed[:, None], np.nan, barycentric),
    )


def plan_centroid(ctx: PlanContext, rng: np.random.Generator) -> PlanResult:
    """Return the equilateral triangle inscribed in the horizontal plane through the centroid.

    Notes
    -----
    Three horizontal rays leave the centroid at azimuths ``phi0 + (0, 120, 240) deg``, phi0
    uniform in [0, 120) deg from ``rng``; each contact is the exact surface point where its ray
    leaves the mesh (farthest hit, the outer surface a finger reaches from outside). When the
    horizontal section does not surround the centroid (the handle's open side), phi0 is redrawn
    until all three rays hit (rejection: uniform over the feasible rotations); if none of
    ``1 + 16 + 256`` draws is feasible, a missing ray takes the vertex nearest to it. The contact
    normal is the outward normal of the horizontal section curve at the point: the horizontal
    part of the smooth (barycentrically interpolated) surface normal, renormalised. That is the
    baseline of §6.5, a horizontal squeeze with ``n_z = 0``, under which Algorithm 2's gradient
    vanishes and the penetration stays at its seed. ``vertex_ids`` are the face vertices nearest
    to each exact point, for H(G) and the records.

    References
    ----------
    §6.3, §6.5 (centroid-equilateral baseline and why it scores 0 %).
    """
    triangles = ctx.vertices[ctx.faces]
    for n_draws in (1, 16, 256):  # batches of rotations; convex bodies accept the first draw
        phi0 = rng.uniform(0.0, 2.0 * np.pi / 3.0, size=n_draws)
        azimuths = (phi0[:, None] + np.array([0.0, 2.0, 4.0]) * np.pi / 3.0).ravel()
        directions = np.stack([np.cos(azimuths), np.sin(azimuths), np.zeros_like(azimuths)], 1)
        faces, distances, barycentric = _ray_farthest_hits(ctx.centroid, directions, triangles)
        feasible = np.all((faces >= 0).reshape(n_draws, 3), axis=1)
        if feasible.any():
            break
    choice = int(np.argmax(feasible))  # the first feasible draw, else the first draw
    rows = slice(3 * choice, 3 * choice + 3)
    directions, faces = directions[rows], faces[rows]
    distances, barycentric = distances[rows], barycentric[rows]

    points = np.empty((3, 3))
    smooth = np.empty((3, 3))
    vertex_ids = np.empty(3, dtype=np.int64)
    hit = faces >= 0
    face_vertices = ctx.faces[np.where(hit, faces, 0)]  # (3, 3)
    points[hit] = ctx.centroid + distances[hit, None] * directions[hit]
    smooth[hit] = np.einsum("rk,rkx->rx", barycentric[hit], ctx.normals[face_vertices[hit]])
    nearest_corner = np.argmax(np.where(hit[:, None], barycentric, -np.inf), axis=1)
    vertex_ids[hit] = face_vertices[hit, nearest_corner[hit]]
    if not np.all(hit):
        offsets = ctx.vertices - ctx.centroid
        along = offsets @ directions[~hit].T  # (n, misses)
        across = np.linalg.norm(offsets[:, None, :] - along[..., None] * directions[~hit][None], axis=2)
        across = np.where(along > 0.0, across, np.inf)
        fallback = np.argmin(across, axis=0)
        vertex_ids[~hit] = fallback
        points[~hit] = ctx.vertices[fallback]
        smooth[~hit] = ctx.normals[fallback]
        logger.debug("centroid planner: %d ray(s) missed the mesh", int((~hit).sum()))

    horizontal = smooth.copy()
    horizontal[:, 2] = 0.0
    lengths = np.linalg.norm(horizontal, axis=1, keepdims=True)
    normals = np.where(lengths > 1e-12, horizontal / np.maximum(lengths, 1e-300), directions)
    return _finish(ctx, "centroid", vertex_ids, points=points, normals=normals, n_scored=0)


def _all_triples_chunks(n_vertices: int, chunk: int):
    """Yield every triple i < j < k of ``n_vertices`` once, in chunks of about ``chunk`` rows."""
    rows, cols = np.triu_indices(n_vertices, k=1)  # pairs (j, k), j < k, sorted by j
    starts = np.searchsorted(rows, np.arange(n_vertices + 1))
    pending, size = [], 0
    for i in range(n_vertices - 2):  # a loop over first vertices; each step is a whole batch
        j, k = rows[starts[i + 1] :], cols[starts[i + 1] :]
        pending.append(np.stack([np.full(j.shape, i), j, k], axis=1))
        size += len(j)
        if size >= chunk:
            yield np.concatenate(pending)
            pending, size = [], 0
    if pending:
        yield np.concatenate(pending)


def plan_reference(ctx: PlanContext, rng: np.random.Generator) -> PlanResult:
    """Return the argmin of H(G) over every triple (small meshes) or a large sampled budget.

    Notes
    -----
    Exhaustive when ``C(n, 3) <= ctx.exhaustive_limit`` (e.g. all 487 344 triples of a 144-node
    mesh); otherwise ``ctx.reference_budget`` sampled triples. Measures how far the N_cand
    sampled argmin is from the true one (SPEC §2.8); the paper neither ran nor claims an
    exhaustive search (§11).
    """
    n_vertices = ctx.n_vertices
    n_triples = n_vertices * (n_vertices - 1) * (n_vertices - 2) // 6
    exhaustive = n_triples <= ctx.exhaustive_limit
    if exhaustive:
        chunks = _all_triples_chunks(n_vertices, _CHUNK)
        n_scored = n_triples
    else:
        budget = ctx.reference_budget
        chunks = (
            sample_triples(ctx.sampling_weights, min(_CHUNK, budget - start), rng)
            for start in range(0, budget, _CHUNK)
        )
        n_scored = budget
    best, best_score = None, np.inf
    for triples in chunks:
        candidate, score = _argmin_h(ctx, triples, ctx.weights)
        if score < best_score:
            best, best_score = candidate, score
    return _finish(ctx, "reference", best, h_planner=best_score, n_scored=n_scored, exhaustive=exhaustive)


PLANNERS: dict = {
    "heuristic": _heuristic_planner("heuristic", lambda ctx: ctx.weights),
    "no_pso": _heuristic_planner("no_pso", lambda ctx: ctx.weights, nominal=True),
    "random": plan_random,
    "antipodal": plan_antipodal,
    "centroid": plan_centroid,
    "force_balance": _heuristic_planner("force_balance", _s1_only),
    **{name: _heuristic_planner(name, _ablated(term)) for name, term in ABLATIONS.items()},
    "reference": plan_reference,
}
"""Planner registry: config name -> ``planner(ctx, rng) -> PlanResult``."""
