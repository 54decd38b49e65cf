"""``pso_repeatability``: PSO restarts on one soft body (Sec. 6.8, Fig. 21; Table 3).

Every restart identifies the same body on the same contact set (the body's heuristic argmin, drawn
from a stream derived from the body, not the restart), so the spread across seeds is the
identification's own: restart variance plus non-identifiability. The ``budget`` factor selects the
reduced repeatability budget (``pso`` group: 8 particles x 15 iterations) or the converged budget
of Sec. 11 (about 5e4 evaluations).
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import Any

import numpy as np

from graspcampaign.campaign.grid import stream_key
from graspcampaign.campaign.kind import TrialInput, TrialKind
from graspcampaign.campaign.kinds import common
from graspcampaign.campaign.schema import PSO_BUDGETS

REPEATABILITY, CONVERGED = PSO_BUDGETS


@dataclass
class PsoRepeatabilityParams:
    nodes: int = common.DEFAULT_NODES
    converged_particles: int = 50  # Sec. 11: ~5e4 evaluations = 50 x 1000
    converged_iterations: int = 1000


def run(inp: TrialInput, rng: np.random.Generator) -> dict[str, Any]:
    from graspcampaign.core.identify import identify_body
    from graspcampaign.core.planner import identification_contacts

    f, study, params = inp.trial.factors, inp.study, inp.params
    material = common.contact_params(study)
    ctx = common.plan_context(f["shape"], common.nodes_of(f, params.nodes), f["mass_kg"], f["mu"],
                              material, common.evaluator_params(study), study.evaluator.n_cand,
                              common.feature_thresholds(study))
    body = {k: f.get(k) for k in ("shape", "nodes", "mass_kg", "mu")}
    body_rng = np.random.default_rng(np.random.SeedSequence(study.seed, spawn_key=stream_key(body)))
    _, points, normals = identification_contacts(ctx, body_rng)
    converged = f.get("budget", REPEATABILITY) == CONVERGED
    particles = params.converged_particles if converged else study.pso.n_particles
    iterations = params.converged_iterations if converged else study.pso.n_iterations
    result = identify_body(points, normals, ctx.centroid, ctx.mass, ctx.mu, rng, material=material,
                           evaluator=ctx.evaluator, n_particles=particles, n_iterations=iterations)
    out = common.identification_record(result)
    out.update(n_particles=particles, n_iterations=iterations)
    history = result.pso
    out["__tables__"] = {"pso_trace": {
        "iteration": list(range(1, len(history.history_best_cost) + 1)),
        "n_evaluations": [int(v) for v in history.history_n_evaluations],
        "best_cost": [float(v) for v in history.history_best_cost],
    }}
    return out


PSO_REPEATABILITY = TrialKind(
    name="pso_repeatability", run=run, params=PsoRepeatabilityParams, seconds_per_trial=1.0,
    description="PSO identification restarts on one soft body",
    factors=("shape", "mass_kg", "mu"), optional_factors=("nodes", "budget"),
)
