"""Baseline planners: random, antipodal, centroid-equilateral, the large-budget reference, and the
Ferrari-Canny planner (the classical wrench-space reference, §1).

Shape letters: ``n`` mesh vertices, ``f`` faces, ``m`` candidate triples, ``r`` rays.

References
----------
§6.3 (ablation baselines), §6.5 (baselines), §11 (candidate budget), SPEC §2.8; Nguyen (1988);
Moller & Trumbore (1997); Ferrari & Canny (1992).
"""

from __future__ import annotations

import logging

import numpy as np

from graspcampaign.core.candidate import (
    CandidateScores,
    PlanContext,
    PlanResult,
    argmin_h,
    candidate_epsilon,
    finish_plan,
    sample_triples,
)
from graspcampaign.core.metric import heuristic_terms

__all__ = ["plan_antipodal", "plan_centroid", "plan_ferrari_canny", "plan_random", "plan_reference"]

logger = logging.getLogger(__name__)

_CHUNK = 200_000


def plan_random(ctx: PlanContext, rng: np.random.Generator) -> PlanResult:
    """Return one uniformly random triple of distinct vertices (same surface measure as line 1)."""
    triple = sample_triples(ctx.sampling_weights, 1, rng)[0]
    return finish_plan(ctx, "random", triple, n_scored=1)


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
    return finish_plan(ctx, "antipodal", [i, j, k], n_scored=len(pairs))


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
    return finish_plan(ctx, "centroid", vertex_ids, points=points, normals=normals, n_scored=0)


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
        candidate, score = argmin_h(ctx, triples, ctx.weights)
        if score < best_score:
            best, best_score = candidate, score
    return finish_plan(ctx, "reference", best, h_planner=best_score, n_scored=n_scored, exhaustive=exhaustive)


def plan_ferrari_canny(ctx: PlanContext, rng: np.random.Generator) -> PlanResult:
    """Return the triple of largest Ferrari-Canny epsilon among the heuristic's N_cand candidates.

    Notes
    -----
    The candidates are drawn exactly as the ``heuristic`` planner draws them (same call on the
    same generator first), so for one scene draw both planners choose from the *same* N_cand
    triples: the comparison is between the two quality measures, not the searches. Ties (e.g. no
    candidate in force closure, every epsilon 0) go to the first drawn. The H(G) and epsilon of
    every candidate are returned in ``candidates`` (the H-versus-epsilon comparison of issue 17).

    References
    ----------
    Ferrari & Canny (1992); Algorithm 1 line 1 (the candidate set).
    """
    triples = sample_triples(ctx.sampling_weights, ctx.n_cand, rng)
    epsilon = candidate_epsilon(ctx, triples)
    h_total = np.asarray(heuristic_terms(ctx.heuristic, triples).total(ctx.weights), dtype=float)
    best = int(np.argmax(epsilon))
    return finish_plan(ctx, "ferrari_canny", triples[best], n_scored=len(triples),
                       candidates=CandidateScores(h_total=h_total, epsilon=epsilon))
