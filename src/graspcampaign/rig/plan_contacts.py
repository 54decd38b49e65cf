"""Contacts planned on the hardware objects: the hardware form of the proposed planner (§8.1: weights
0.45/0.30/0.25, continuous penalties, maximised score H~) and the registry baselines.

Per-object work is cached per process: the mesh, its sharp features and heuristic context per
shape, and each plan per ``plan_key`` (an object's plan is shared by all its trials with the same
planner; the random planner draws a new triple per slot, see :mod:`graspcampaign.rig.protocol`).

References
----------
Paper §8.1 (planners, hardware weighting), Table 4; SPEC §2.8, §2.10.
"""

from __future__ import annotations

import functools
import hashlib
import time
from dataclasses import dataclass, replace
from typing import Any

import numpy as np

from graspcampaign.core import disturbance as dist
from graspcampaign.core.contact import NOMINAL_CONTACT
from graspcampaign.core.equilibrium import evaluate_grasps
from graspcampaign.core.metric import HARDWARE_WEIGHTS, heuristic_terms
from graspcampaign.core.planner import DEFAULT_N_CAND, PLANNERS, PlanContext, plan_context, sample_triples
from graspcampaign.rig.belief import believed_contact_law, material_model

__all__ = [
    "HARDWARE_PLANNERS",
    "N_NODES",
    "STABLE_RESIDUAL_N",
    "HardwarePlan",
    "cached_plan",
    "hardware_plan",
    "make_body",
    "shape_body",
]


HARDWARE_PLANNERS = ("heuristic", "no_pso", "centroid", "force_balance", "random")
"""The proposed planner and the four hardware baselines of §8.1."""

STABLE_RESIDUAL_N = dist.TAU_F_HARDWARE
N_NODES = 390
"""Mesh resolution of the hardware objects (the §6 multi-shape remesh)."""


# --------------------------------------------------------------------------------------------
# Bodies and plans
# --------------------------------------------------------------------------------------------
@dataclass(frozen=True)
class _Body:
    mesh: Any
    ctx: PlanContext


def make_body(mesh) -> _Body:
    """The mesh and its planning context at unit mass and friction (the hardware weights)."""
    from graspcampaign.core.feature import sharp_features

    feats = sharp_features(mesh)
    ctx = plan_context(mesh, feats, mass=1.0, mu=1.0, contact=NOMINAL_CONTACT,
                       weights=HARDWARE_WEIGHTS, n_cand=DEFAULT_N_CAND)
    return _Body(mesh=mesh, ctx=ctx)


@functools.lru_cache(maxsize=16)
def shape_body(shape: str, n_nodes: int = N_NODES) -> _Body:
    """The body of a named shape at ``n_nodes`` (cached; see :func:`make_body`)."""
    from graspcampaign.core.mesh import make_object

    return make_body(make_object(shape, n_nodes))


@dataclass(frozen=True)
class HardwarePlan:
    """A planner's contacts on one object and its own evaluation of them.

    Attributes
    ----------
    planner : str
    vertex_ids : (3,) int
    points : (3, 3) float
        Planned contact points [m].
    normals : (3, 3) float
        The outward normals the planner believes it has (centroid: horizontal by construction).
    s1, s2, s3, pc_mag, pe_mag : float
        H(G) components at ``vertex_ids`` (continuous penalties, §8.1).
    h_tilde : float
        Hardware quality score ``sum w_i (1 - S_i) - P_c - P_e`` (§8.1).
    residual_norm : float
        Algorithm 2's normal-only residual |R| under the planner's own contact law [N].
    delta_max_mm : float
        Algorithm 2's largest penetration [mm].
    plan_time_s : float
    """

    planner: str
    vertex_ids: np.ndarray
    points: np.ndarray
    normals: np.ndarray
    s1: float
    s2: float
    s3: float
    pc_mag: float
    pe_mag: float
    h_tilde: float
    residual_norm: float
    delta_max_mm: float
    plan_time_s: float


def hardware_plan(ctx: PlanContext, planner: str, rng: np.random.Generator,
                  believed_k: float, believed_n: float) -> HardwarePlan:
    """Choose three contacts with one hardware planner and evaluate them under its own belief.

    Parameters
    ----------
    ctx : PlanContext
        Body context with ``mass`` and ``mu`` set.
    planner : str
        ``heuristic`` and ``no_pso`` maximise H~ (hardware weights) over ``ctx.n_cand`` sampled
        triples; ``centroid``, ``force_balance`` and ``random`` are the registry planners of
        :data:`graspcampaign.core.planner.PLANNERS` (S1-only argmin = argmax of w1 (1 - S1)).
    rng : numpy.random.Generator
    believed_k, believed_n : float
        Contact law of the planner's own Algorithm 2 evaluation.

    Returns
    -------
    HardwarePlan
    """
    if planner not in HARDWARE_PLANNERS:
        raise ValueError(f"unknown hardware planner {planner!r}: use one of "
                         f"{', '.join(HARDWARE_PLANNERS)}")
    start = time.perf_counter()
    if planner in ("heuristic", "no_pso"):
        triples = sample_triples(ctx.sampling_weights, ctx.n_cand, rng)
        scores = heuristic_terms(ctx.heuristic, triples).score_hardware(HARDWARE_WEIGHTS)
        vertex_ids = triples[int(np.argmax(scores))]
        points, normals = ctx.vertices[vertex_ids], ctx.normals[vertex_ids]
    else:
        result = PLANNERS[planner](ctx, rng)
        vertex_ids, points, normals = result.vertex_ids, result.points, result.normals
    terms = heuristic_terms(ctx.heuristic, np.asarray(vertex_ids)[None])
    eq = evaluate_grasps(points, normals, ctx.centroid, ctx.mass, ctx.mu, believed_k, believed_n,
                         ctx.evaluator)
    return HardwarePlan(
        planner=planner, vertex_ids=np.asarray(vertex_ids, dtype=np.int64),
        points=np.asarray(points, dtype=float), normals=np.asarray(normals, dtype=float),
        s1=float(terms.s1[0]), s2=float(terms.s2[0]), s3=float(terms.s3[0]),
        pc_mag=float(terms.pc_mag[0]), pe_mag=float(terms.pe_mag[0]),
        h_tilde=float(terms.score_hardware(HARDWARE_WEIGHTS)[0]),
        residual_norm=float(eq.residual_norm[0]), delta_max_mm=float(eq.delta_max_mm[0]),
        plan_time_s=time.perf_counter() - start)


def _plan_rng(seed: int, plan_key: str) -> np.random.Generator:
    digest = hashlib.sha256(plan_key.encode()).digest()
    key = tuple(int.from_bytes(digest[i:i + 4], "little") for i in range(0, 16, 4))
    return np.random.default_rng(np.random.SeedSequence(int(seed), spawn_key=key))


@functools.lru_cache(maxsize=4096)
def cached_plan(shape: str, planner: str, plan_key: str, seed: int, mass: float, material: str,
                friction_level: str) -> HardwarePlan:
    """The planner's contacts on a shape at the object's mass and material (cached per plan key)."""
    body = shape_body(shape)
    mat = material_model(material, friction_level)
    ctx = replace(body.ctx, mass=mass, mu=mat.mu_s, contact=mat.contact_params())
    k, n = believed_contact_law(planner, mat)
    return hardware_plan(ctx, planner, _plan_rng(seed, plan_key), k, n)
