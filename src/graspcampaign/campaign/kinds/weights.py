"""``heuristic_weights``: uniform weight scaling and weight ratios on the sphere (Sec. 5.2).

All weight settings of one seed score the *same* candidate triples (``weight_scale`` is a method
factor), so a moved argmin can only come from the weights. Uniform scaling multiplies every H by
the same factor and cannot move the argmin; the ratio sweep (w1:w2:w3 of 2:1:1, 1:2:1, 1:1:2)
probes what scaling cannot. The hand-reachable 45/45/-90 deg set of Sec. 5.2 is scored beside it.
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import Any

import numpy as np

from graspcampaign.campaign.kind import TrialInput, TrialKind
from graspcampaign.campaign.kinds import common

RATIOS = {"2_1_1": (2.0, 1.0, 1.0), "1_2_1": (1.0, 2.0, 1.0), "1_1_2": (1.0, 1.0, 2.0)}


@dataclass
class WeightsParams:
    shape: str = "sphere"
    nodes: int = 356  # Sec. 5.1: the 356-node sphere of the original study


def reachable_triple(vertices: np.ndarray) -> np.ndarray:
    """Vertices nearest the 45/45/-90 deg set: two at 45 deg above the equator on opposite
    sides of one plane through the centre, the third at the bottom pole (Sec. 5.2, Fig. 8)."""
    c = np.sqrt(0.5)
    directions = np.array([[c, 0.0, c], [-c, 0.0, c], [0.0, 0.0, -1.0]])
    unit = vertices / np.linalg.norm(vertices, axis=1, keepdims=True)
    return np.argmax(unit @ directions.T, axis=0)


def run(inp: TrialInput, rng: np.random.Generator) -> dict[str, Any]:
    from graspcampaign.core.metric import HeuristicWeights, heuristic_terms
    from graspcampaign.core.planner import sample_triples

    study, params, scale = inp.study, inp.params, inp.trial.factors["weight_scale"]
    ctx = common.plan_context(params.shape, params.nodes, 0.4, 0.3, common.contact_params(study),
                              common.evaluator_params(study), study.evaluator.n_cand,
                              common.feature_thresholds(study))
    triples = sample_triples(ctx.sampling_weights, ctx.n_cand, rng)
    terms = heuristic_terms(ctx.heuristic, triples)
    weights = HeuristicWeights().scaled(scale)
    best = int(np.argmin(terms.total(weights)))
    reach = heuristic_terms(ctx.heuristic, reachable_triple(ctx.vertices)[None, :])
    out: dict[str, Any] = {
        "argmin_key": "-".join(map(str, sorted(triples[best].tolist()))),
        "h_total": float(terms.total(weights)[best]),
        "s1": float(terms.s1[best]), "s2": float(terms.s2[best]), "s3": float(terms.s3[best]),
        "n_c": int(terms.n_c[best]), "n_e": int(terms.n_e[best]),
        "h_reachable": float(reach.total(weights)[0]),
        "s1_reachable": float(reach.s1[0]), "s2_reachable": float(reach.s2[0]),
        "s3_reachable": float(reach.s3[0]),
        "n_candidates": int(len(triples)),
    }
    for j in range(3):
        out[f"vertex_{j + 1}"] = int(triples[best, j])
    for name, (w1, w2, w3) in RATIOS.items():
        h = terms.total(HeuristicWeights(w1, w2, w3, 1.0, 1.0).scaled(scale))
        out[f"argmin_key_ratio_{name}"] = "-".join(map(str, sorted(triples[int(np.argmin(h))])))
    return out


HEURISTIC_WEIGHTS = TrialKind(
    name="heuristic_weights", run=run, params=WeightsParams, seconds_per_trial=0.05,
    description="argmin of H(G) under uniform weight scaling and weight ratios",
    factors=("weight_scale",), optional_factors=(),
)
