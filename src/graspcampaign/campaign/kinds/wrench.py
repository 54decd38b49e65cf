"""``wrench_balance``: a fixed grip command on the sphere, monitored per iteration (Sec. 6.4, Fig. 17).

The contacts are the unconstrained heuristic argmin (Sec. 6.4: a near-equilateral triangle). The
fingers close from the 0.5 mm seed to the penetration at which each carries the commanded normal
force (~65 N per finger, Sec. 6.4), in ``n_max`` equal steps; at every step the four monitors of
Sec. 6.4 are evaluated with Algorithm 1's checks (normal-only residual, torque about the centroid,
uniform-utilisation slip margin). The linear closing ramp is our reading of "fixed grip command"
(docs/decisions.md). Contact constants are the configured model (Table 3), as in the paper's run.
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import Any

import numpy as np

from graspcampaign.campaign.kind import TrialInput, TrialKind
from graspcampaign.campaign.kinds import common


@dataclass
class WrenchParams:
    nodes: int = common.DEFAULT_NODES
    grip_force_n: float = 65.0  # Sec. 6.4: "approximately 65 N per finger"


def run(inp: TrialInput, rng: np.random.Generator) -> dict[str, Any]:
    from graspcampaign.core.contact import depth_for_force
    from graspcampaign.core.equilibrium import static_checks
    from graspcampaign.core.planner import identification_contacts

    f, study, params = inp.trial.factors, inp.study, inp.params
    contact = common.contact_params(study)
    evaluator = common.evaluator_params(study)
    ctx = common.plan_context(f["shape"], common.nodes_of(f, params.nodes), f["mass_kg"], f["mu"],
                              contact, evaluator, study.evaluator.n_cand,
                              common.feature_thresholds(study))
    vertex_ids, points, normals = identification_contacts(ctx, rng)
    command = depth_for_force(params.grip_force_n, contact.k_n_per_mm_n, contact.n)
    steps = np.linspace(0.0, 1.0, evaluator.n_max)
    depths = evaluator.seed_depth + (command - evaluator.seed_depth) * steps[:, None] * np.ones(3)
    batch = evaluator.n_max
    res = static_checks(np.broadcast_to(points, (batch, 3, 3)), np.broadcast_to(normals, (batch, 3, 3)),
                        ctx.centroid, ctx.mass, ctx.mu, depths, contact.k_n_per_mm_n, contact.n,
                        evaluator)
    last = -1
    out: dict[str, Any] = {
        **common.verdict_columns(res, evaluator, last),
        "residual_norm_n": float(res.residual_norm[last]),
        "torque_norm_nm": float(res.torque_norm[last]),
        "slip_margin_n": float(res.slip_margin[last]),
        "slip_margin_ratio": float(res.slip_margin_ratio[last]),
        "eta": float(res.eta[last]),
        "delta_max_mm": float(res.delta_max_mm[last]),
        "rho": float(res.rho[last]),
        "grip_force_n": params.grip_force_n,
        "lambda1": contact.lambda1, "n_exp": contact.n,
    }
    for j in range(3):
        out[f"vertex_{j + 1}"] = int(vertex_ids[j])
        out[f"normal_force_{j + 1}_n"] = float(res.normal_forces[last, j])
    out["__tables__"] = {"iterations": {
        "iteration": list(range(1, batch + 1)),
        "residual_norm_n": res.residual_norm.tolist(),
        "residual_z_n": res.residual_z.tolist(),
        "torque_norm_nm": res.torque_norm.tolist(),
        "slip_margin_n": res.slip_margin.tolist(),
        "slip_margin_ratio": res.slip_margin_ratio.tolist(),
        "normal_force_1_n": res.normal_forces[:, 0].tolist(),
        "depth_1_mm": (1e3 * depths[:, 0]).tolist(),
    }}
    return out


WRENCH_BALANCE = TrialKind(
    name="wrench_balance", run=run, params=WrenchParams, seconds_per_trial=0.05,
    description="fixed grip command on the sphere; four monitors per closing step",
    factors=("shape", "mass_kg", "mu"), optional_factors=("nodes",),
)
