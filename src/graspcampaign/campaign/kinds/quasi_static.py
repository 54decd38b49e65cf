"""``quasi_static``: plan a grasp with one planner and judge it with the quasi-static evaluator.

One trial = one (shape, mass, friction, seed, planner) of Sec. 6.2-6.7. Each soft body
(shape x nodes x mass x friction) is identified once by PSO (Sec. 4) before its trials; the
identification is stored in ``prepared/`` and reused by every planner and seed of that body and on
resume. With ``pso.enabled=false`` the configured model constants are used instead.

The outcome of every planner is judged under the body's parameters (identified, or configured):
that is the simulated ground truth. Each planner's own belief (the ``no_pso`` planner believes the
nominal Hertzian law) is recorded beside it as ``believed_success``.

The grip law is ``evaluator.grip_law`` (Algorithm 2, ``paper``, by default) unless the study has
a ``grip_law`` factor (issue 13). The identification always uses Algorithm 2 (§4's J is defined on
its residual), so a body's parameters do not depend on the grip law it is later judged under.
``params.stream_study`` re-derives every trial's random stream from another study's scenes (the
``grip_laws`` study replays ``baseline_grid``'s draws, so its ``paper`` rows equal that study's).
"""

from __future__ import annotations

import time
from collections import OrderedDict
from dataclasses import dataclass
from typing import Any, NamedTuple

import numpy as np

from graspcampaign.campaign.kind import TrialInput, TrialKind
from graspcampaign.campaign.kinds import common
from graspcampaign.campaign.schema import NODES, config_field


@dataclass
class QuasiStaticParams:
    """Fixed parameters of the quasi-static kind."""

    # mesh resolution when `nodes` is not a factor (Sec. 6.2); the factor's bound
    nodes: int = config_field(common.DEFAULT_NODES, **NODES)
    stream_study: str = ""  # replay this study's scene streams (same seed and scene factors)
    # (H, epsilon) pairs per ferrari_canny trial kept for the figure (0: none)
    candidate_sample: int = config_field(50, ge=0)


def body_key(factors: dict[str, Any]) -> dict[str, Any]:
    """A soft body: object x resolution x mass x friction (Sec. 4: identified once per body)."""
    return {"shape": factors["shape"], "nodes": factors.get("nodes"),
            "mass_kg": factors["mass_kg"], "mu": factors["mu"]}


def context(study, shape: str, nodes: int, mass: float, mu: float, contact,
            n_cand: int | None = None, evaluator=None):
    """Return the (per-worker cached) PlanContext of one body under the study's settings."""
    evaluator = common.evaluator_params(study) if evaluator is None else evaluator
    return common.plan_context(shape, int(nodes), float(mass), float(mu), contact, evaluator,
                               int(study.evaluator.n_cand if n_cand is None else n_cand),
                               common.feature_thresholds(study),
                               fc_cone_edges=int(study.evaluator.fc_cone_edges))


def _context(study, params, body, contact, evaluator=None):
    return context(study, body["shape"], body["nodes"] or params.nodes, body["mass_kg"],
                   body["mu"], contact, evaluator=evaluator)


class Judged(NamedTuple):
    """One planned grasp judged under the body's parameters (see :func:`plan_and_judge`)."""

    ctx: Any
    plan: Any
    truth: Any
    context_time_s: float
    plan_time_s: float
    plan_cached: bool = False


RELEASED_DEPTH = 1e-12
"""A contact at or below this penetration [m] is released: line 7's ``max(0, delta + step)``
leaves 0 or the round-off of ``delta - delta`` (1e-12 m is 1e-9 of the 0.5 mm seed)."""

_PLANS: OrderedDict = OrderedDict()
_PLANS_SIZE = 64


def _planned(ctx, planner: str, rng: np.random.Generator, body: tuple):
    """Plan, reusing this worker's plan of the same body, planner and generator state.

    A planner's choice depends on the body, its settings and the random draws, never on the grip
    law; only its own evaluation (``equilibrium``, the belief) does. So a trial that differs from
    an earlier one only in the grip law (``grip_laws``, ``ablation``) gets that plan with the
    belief re-evaluated under its own law: the same record as re-planning, at a third of the
    cost. The key holds the generator's exact state, so no two different draws can share a plan.
    """
    from dataclasses import replace

    from graspcampaign.core.planner import PLANNERS, evaluate_triple

    state = rng.bit_generator.state
    key = (body, planner, ctx.n_cand, ctx.fc_cone_edges, ctx.weights, repr(state))
    cached = _PLANS.get(key)
    if cached is not None:
        _PLANS.move_to_end(key)
        belief = evaluate_triple(ctx, cached.points, cached.normals, cached.contact)
        return replace(cached, equilibrium=belief), True
    plan = PLANNERS[planner](ctx, rng)
    _PLANS[key] = plan
    while len(_PLANS) > _PLANS_SIZE:
        _PLANS.popitem(last=False)
    return plan, False


def plan_and_judge(study, shape: str, nodes: int, mass: float, mu: float, contact, planner: str,
                   rng: np.random.Generator, n_cand: int | None = None,
                   evaluator=None, reuse: bool = False) -> Judged:
    """Plan with ``planner`` and evaluate its triple under ``contact`` (the simulated truth).

    The planner's own evaluation is the truth unless it believed other contact parameters
    (``no_pso``); then the triple is evaluated again under ``contact``. ``context_time_s`` is the
    per-body preparation (cached per worker), ``plan_time_s`` Algorithm 1 with its candidate
    search and Algorithm 2. With ``reuse`` (studies whose trials differ only in the grip law) a
    plan this worker already made is reused (:func:`_planned`); ``plan_time_s`` is then only the
    re-evaluation, flagged by ``plan_cached``. Timing studies never reuse.
    """
    from graspcampaign.core.planner import evaluate_triple

    start = time.perf_counter()
    ctx = context(study, shape, nodes, mass, mu, contact, n_cand, evaluator)
    context_time = time.perf_counter() - start
    start = time.perf_counter()
    body = (shape, int(nodes), float(mass), float(mu), contact,
            common.feature_thresholds(study))
    if reuse:
        plan, cached = _planned(ctx, planner, rng, body)
    else:
        from graspcampaign.core.planner import PLANNERS

        plan, cached = PLANNERS[planner](ctx, rng), False
    plan_time = time.perf_counter() - start
    truth = plan.equilibrium
    if plan.contact != ctx.contact:
        truth = evaluate_triple(ctx, plan.points, plan.normals, contact=ctx.contact)
    return Judged(ctx, plan, truth, context_time, plan_time, cached)


def prepare(study, params, body, rng: np.random.Generator) -> dict[str, Any]:
    """Identify the body's contact parameters with PSO on J (Sec. 4, Sec. 11)."""
    from graspcampaign.core.identify import identify_body
    from graspcampaign.core.planner import identification_contacts

    material = common.contact_params(study)
    if not study.pso.enabled:
        return {"identified": False, "lambda1": material.lambda1, "lambda2": material.lambda2,
                "n_exp": material.n}
    ctx = _context(study, params, body, material, common.evaluator_params(study, grip_law="paper"))
    _, points, normals = identification_contacts(ctx, rng)
    result = identify_body(points, normals, ctx.centroid, ctx.mass, ctx.mu, rng,
                           material=material, evaluator=ctx.evaluator,
                           n_particles=study.pso.n_particles, n_iterations=study.pso.n_iterations)
    return {"identified": True, **common.identification_record(result)}


def body_contact(study, prepared: dict[str, Any] | None):
    """ContactParams of a body from its stored identification (or the configured model)."""
    if not prepared or not prepared.get("identified"):
        return common.contact_params(study)
    return common.contact_params(study, lambda1=prepared["lambda1"], lambda2=prepared["lambda2"],
                                 n=prepared["n_exp"])


def plan_record(ctx, plan, truth) -> dict[str, Any]:
    """Flatten a PlanResult and its ground-truth evaluation into record columns."""
    eq = truth
    forces, normals_z = eq.normal_forces[0], plan.normals[:, 2]
    support = forces * -normals_z  # vertical support of each normal force (n_hat = -n_out)
    positive = support[support > 0.0].sum()
    out: dict[str, Any] = {
        **common.verdict_columns(eq, ctx.evaluator),
        "grip_law": ctx.evaluator.grip_law,
        "residual_norm_n": float(eq.residual_norm[0]),
        "residual_z_n": float(eq.residual_z[0]),
        "torque_norm_nm": float(eq.torque_norm[0]),
        "full_residual_norm_n": float(eq.full_residual_norm[0]),
        "full_torque_norm_nm": float(eq.full_torque_norm[0]),
        "slip_margin_n": float(eq.slip_margin[0]),
        "slip_margin_ratio": float(eq.slip_margin_ratio[0]),
        "eta": float(eq.eta[0]),
        "rho": float(eq.rho[0]),
        "n_released": int(np.count_nonzero(eq.depths[0] <= RELEASED_DEPTH)),
        "n_upper": int(np.count_nonzero(normals_z > ctx.evaluator.normal_z_tol)),
        "n_loaded": int(np.count_nonzero(forces > 0.0)),
        "support_share_max": float(support.max() / positive) if positive > 0.0 else float("nan"),
        "grip_force_n": float(eq.grip_force[0]),
        "grip_needed_n": float(eq.grip_needed[0]),
        "grip_capped": bool(eq.grip_needed[0] > eq.grip_force[0]),
        "grip_needed_depth_mm": needed_depth_mm(eq.grip_needed[0], ctx.contact),
        "delta_max_mm": float(eq.delta_max_mm[0]),
        "exceeds_1mm": bool(eq.delta_max_mm[0] > 1.0),
        "iterations": int(eq.iterations[0]),
        "believed_success": bool(plan.believed_success),
        "believed_residual_norm_n": float(plan.equilibrium.residual_norm[0]),
        "epsilon_fc": float(plan.epsilon_fc),
        "h_total": float(plan.h_total),
        "h_planner": float(plan.h_planner),
        "s1": float(plan.s1), "s2": float(plan.s2), "s3": float(plan.s3),
        "n_c": int(plan.n_c), "n_e": int(plan.n_e),
        "n_scored": int(plan.n_scored), "exhaustive": bool(plan.exhaustive),
        **candidate_columns(plan),
    }
    for j in range(3):
        out[f"vertex_{j + 1}"] = int(plan.vertex_ids[j])
        out[f"delta_{j + 1}_mm"] = float(eq.depths[0, j] * 1e3)
        out[f"normal_force_{j + 1}_n"] = float(eq.normal_forces[0, j])
        out[f"contact_normal_z_{j + 1}"] = float(plan.normals[j, 2])
    return out


def needed_depth_mm(force: float, contact) -> float:
    """Penetration at which the body's law carries ``force`` [mm] (inf/NaN pass through)."""
    if not np.isfinite(force):
        return float(force)
    from graspcampaign.core.contact import depth_for_force

    return float(depth_for_force(force, contact.k_n_per_mm_n, contact.n) * 1e3)


def candidate_columns(plan) -> dict[str, Any]:
    """H(G) against epsilon over the plan's N_cand candidates (``ferrari_canny`` plans only).

    ``spearman_h_epsilon`` over all candidates (ties at epsilon = 0 take average ranks) and
    ``spearman_h_epsilon_fc`` over the force-closure candidates (epsilon > 0); both negative
    when the two measures agree (H lower is better, epsilon higher). ``epsilon_h_argmin`` is the
    epsilon of the triple the heuristic would pick from the same candidates.
    """
    scores = plan.candidates
    if scores is None:
        return {}
    from scipy.stats import spearmanr

    h, eps = scores.h_total, scores.epsilon
    closure = eps > 0.0

    def rank_corr(x, y):
        if len(x) < 3 or np.ptp(x) == 0.0 or np.ptp(y) == 0.0:
            return float("nan")
        return float(spearmanr(x, y).statistic)

    return {
        "spearman_h_epsilon": rank_corr(h, eps),
        "spearman_h_epsilon_fc": rank_corr(h[closure], eps[closure]),
        "n_force_closure": int(closure.sum()),
        "epsilon_h_argmin": float(eps[int(np.argmin(h))]),
    }


def candidate_table(plan, n_sample: int) -> dict[str, list] | None:
    """The first ``n_sample`` candidates' (H, epsilon): a uniform subsample (iid draws)."""
    if plan.candidates is None or n_sample <= 0:
        return None
    k = min(n_sample, len(plan.candidates.h_total))
    return {"candidate": list(range(k)),
            "h_total": plan.candidates.h_total[:k].tolist(),
            "epsilon_fc": plan.candidates.epsilon[:k].tolist()}


def trial_rng(inp: TrialInput, rng: np.random.Generator) -> np.random.Generator:
    """The trial's stream, or the same scene's stream of ``params.stream_study`` when set."""
    study = getattr(inp.params, "stream_study", "")
    if not study:
        return rng
    from graspcampaign.campaign.grid import stream_key

    method = set(inp.study.method_factors)
    scene = {k: v for k, v in inp.trial.factors.items() if k not in method}
    return np.random.default_rng(np.random.SeedSequence(
        inp.study.seed, spawn_key=stream_key({"study": study, "scene": scene})))


def run(inp: TrialInput, rng: np.random.Generator) -> dict[str, Any]:
    """Plan with the trial's planner and evaluate under the body's parameters."""
    f, study = inp.trial.factors, inp.study
    body = body_key(f)
    nodes = body["nodes"] or inp.params.nodes
    contact = body_contact(study, inp.prepared)
    evaluator = common.evaluator_params(study, grip_law=f.get("grip_law", study.evaluator.grip_law))
    ctx, plan, truth, context_time, plan_time, cached = plan_and_judge(
        study, body["shape"], nodes, body["mass_kg"], body["mu"], contact, f["planner"],
        trial_rng(inp, rng), evaluator=evaluator, reuse="grip_law" in f)
    _, features = common.body_mesh(body["shape"], nodes, common.feature_thresholds(study))
    out = plan_record(ctx, plan, truth)
    out.update({
        "nodes": len(ctx.vertices),
        "n_cand": ctx.n_cand,
        "n_sharp_vertex": int(np.count_nonzero(features.sharp_vertices)),
        "n_sharp_edge": int(len(features.sharp_edges)),
        "lambda1": contact.lambda1, "lambda2": contact.lambda2, "n_exp": contact.n,
        "believed_lambda1": plan.contact.lambda1, "believed_n_exp": plan.contact.n,
        "pso_at_bound": common.at_bound_text(inp.prepared),
        "context_time_s": context_time,
        "plan_time_s": plan_time,
        "plan_cached": cached,
    })
    if "nodes" in f:
        out.pop("nodes")
    if "grip_law" in f:
        out.pop("grip_law")
    table = candidate_table(plan, inp.params.candidate_sample)
    if table is not None:
        out["__tables__"] = {"candidates": table}
    return out


QUASI_STATIC = TrialKind(
    name="quasi_static",
    run=run,
    params=QuasiStaticParams,
    seconds_per_trial=0.01,
    body_key=body_key,
    prepare=prepare,
    description="plan with one planner, judge with the quasi-static evaluator (Algorithms 1-2)",
    stages="a PSO identification of each soft body before its trials (Sec. 4; none with "
           "pso.enabled=false)",
    factors=("shape", "mass_kg", "mu", "planner"),
    optional_factors=("nodes", "grip_law"),
)
