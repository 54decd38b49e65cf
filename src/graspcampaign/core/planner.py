"""Grasp planners: the heuristic pipeline of Algorithm 1, its ablations, and the planner registry.

Names map to callables through :data:`PLANNERS`, so a config never imports code. The per-body
context, the candidate sampling and the result type live in :mod:`graspcampaign.core.candidate`
(re-exported here), the baselines in :mod:`graspcampaign.core.baseline`.

References
----------
Algorithm 1 (§11), Eq. 6-9 (§3.1), §5.2, §6.3 (ablation), §6.5 (baselines), SPEC §2.8.
"""

from __future__ import annotations

import logging
from dataclasses import replace

import numpy as np

from graspcampaign.core.baseline import (
    plan_antipodal,
    plan_centroid,
    plan_ferrari_canny,
    plan_random,
    plan_reference,
)
from graspcampaign.core.candidate import (
    DEFAULT_N_CAND,
    PlanContext,
    PlanResult,
    argmin_h,
    evaluate_triple,
    finish_plan,
    identification_contacts,
    plan_context,
    sample_triples,
    vertex_sampling_weights,
)
from graspcampaign.core.metric import HeuristicWeights

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

ABLATIONS = {
    "no_s1": "w1",
    "no_s2": "w2",
    "no_s3": "w3",
    "no_pc": "p_c",
    "no_pe": "p_e",
}
"""Single-term ablations of §6.3: planner name -> the HeuristicWeights field set to zero."""


def _heuristic_planner(name: str, weights_of, nominal: bool = False):
    def plan(ctx: PlanContext, rng: np.random.Generator) -> PlanResult:
        triples = sample_triples(ctx.sampling_weights, ctx.n_cand, rng)
        best, score = argmin_h(ctx, triples, weights_of(ctx))
        contact = ctx.nominal_contact if nominal else ctx.contact
        return finish_plan(ctx, name, best, contact=contact, h_planner=score, n_scored=len(triples))

    plan.__name__ = f"plan_{name}"
    plan.__doc__ = f"Planner {name!r}: argmin over N_cand sampled triples, then Algorithm 2."
    return plan


def _ablated(field_name: str):
    return lambda ctx: replace(ctx.weights, **{field_name: 0.0})


def _s1_only(ctx: PlanContext) -> HeuristicWeights:
    return replace(ctx.weights, w2=0.0, w3=0.0, p_c=0.0, p_e=0.0)


PLANNERS: dict = {
    "heuristic": _heuristic_planner("heuristic", lambda ctx: ctx.weights),
    "no_pso": _heuristic_planner("no_pso", lambda ctx: ctx.weights, nominal=True),
    "random": plan_random,
    "antipodal": plan_antipodal,
    "centroid": plan_centroid,
    "ferrari_canny": plan_ferrari_canny,
    "force_balance": _heuristic_planner("force_balance", _s1_only),
    **{name: _heuristic_planner(name, _ablated(term)) for name, term in ABLATIONS.items()},
    "reference": plan_reference,
}
"""Planner registry: config name -> ``planner(ctx, rng) -> PlanResult``."""
