"""``quasi_static``: plan a grasp with one planner and judge it with the quasi-static evaluator.

One trial = one (shape, mass, friction, seed, planner) of Sec. 6.2-6.7. Each soft body
(shape x nodes x mass x friction) is identified once by PSO (Sec. 4) before its trials; the
identification is stored in ``prepared/`` and reused by every planner and seed of that body and on
resume. With ``pso.enabled=false`` the configured model constants are used instead.

The outcome of every planner is judged under the body's parameters (identified, or configured):
that is the simulated ground truth. Each planner's own belief (the ``no_pso`` planner believes the
nominal Hertzian law) is recorded beside it as ``believed_success``.
"""

from __future__ import annotations

import time
from dataclasses import dataclass
from typing import Any, NamedTuple

import numpy as np

from graspcampaign.campaign.kind import TrialInput, TrialKind
from graspcampaign.campaign.kinds import common


@dataclass
class QuasiStaticParams:
    """Fixed parameters of the quasi-static kind."""

    nodes: int = common.DEFAULT_NODES  # mesh resolution when `nodes` is not a factor (Sec. 6.2)


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
                               common.feature_thresholds(study))


def _context(study, params, body, contact):
    return context(study, body["shape"], body["nodes"] or params.nodes, body["mass_kg"],
                   body["mu"], contact)


class Judged(NamedTuple):
    """One planned grasp judged under the body's parameters (see :func:`plan_and_judge`)."""

    ctx: Any
    plan: Any
    truth: Any
    context_time_s: float
    plan_time_s: float


def plan_and_judge(study, shape: str, nodes: int, mass: float, mu: float, contact, planner: str,
                   rng: np.random.Generator, n_cand: int | None = None,
                   evaluator=None) -> Judged:
    """Plan with ``planner`` and evaluate its triple under ``contact`` (the simulated truth).

    The planner's own evaluation is the truth unless it believed other contact parameters
    (``no_pso``); then the triple is evaluated again under ``contact``. ``context_time_s`` is the
    per-body preparation (cached per worker), ``plan_time_s`` Algorithm 1 with its candidate
    search and Algorithm 2.
    """
    from graspcampaign.core.planner import PLANNERS, evaluate_triple

    start = time.perf_counter()
    ctx = context(study, shape, nodes, mass, mu, contact, n_cand, evaluator)
    context_time = time.perf_counter() - start
    start = time.perf_counter()
    plan = PLANNERS[planner](ctx, rng)
    plan_time = time.perf_counter() - start
    truth = plan.equilibrium
    if plan.contact != ctx.contact:
        truth = evaluate_triple(ctx, plan.points, plan.normals, contact=ctx.contact)
    return Judged(ctx, plan, truth, context_time, plan_time)


def prepare(study, params, body, rng: np.random.Generator) -> dict[str, Any]:
    """Identify the body's contact parameters with PSO on J (Sec. 4, Sec. 11)."""
    from graspcampaign.core.identify import identify_body
    from graspcampaign.core.planner import identification_contacts

    material = common.contact_params(study)
    if not study.pso.enabled:
        return {"identified": False, "lambda1": material.lambda1, "lambda2": material.lambda2,
                "n_exp": material.n}
    ctx = _context(study, params, body, material)
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


def verdicts(eq, evaluator) -> dict[str, bool]:
    """Both readings of Algorithm 1 line 6 from one evaluation (batch of one).

    ``success_norm`` checks the normal-only |R| (SPEC 2.7, the default), ``success_vertical``
    |R_z| (the paper's prose, Sec. 3.7 and 6.5); torque and slip checks are shared.
    """
    rest = bool(eq.torque_ok[0]) and bool(eq.slip_ok[0])
    return {"success_norm": bool(eq.residual_norm[0] < evaluator.tau_f) and rest,
            "success_vertical": bool(abs(eq.residual_z[0]) < evaluator.tau_f) and rest}


def plan_record(ctx, plan, truth) -> dict[str, Any]:
    """Flatten a PlanResult and its ground-truth evaluation into record columns."""
    eq = truth
    out: dict[str, Any] = {
        "success": bool(eq.success[0]),
        **verdicts(eq, ctx.evaluator),
        "failure_check": str(eq.failure_labels()[0]),
        "residual_norm_n": float(eq.residual_norm[0]),
        "residual_z_n": float(eq.residual_z[0]),
        "torque_norm_nm": float(eq.torque_norm[0]),
        "slip_margin_n": float(eq.slip_margin[0]),
        "slip_margin_ratio": float(eq.slip_margin_ratio[0]),
        "eta": float(eq.eta[0]),
        "delta_max_mm": float(eq.delta_max_mm[0]),
        "exceeds_1mm": bool(eq.delta_max_mm[0] > 1.0),
        "iterations": int(eq.iterations[0]),
        "believed_success": bool(plan.believed_success),
        "believed_residual_norm_n": float(plan.equilibrium.residual_norm[0]),
        "h_total": float(plan.h_total),
        "h_planner": float(plan.h_planner),
        "s1": float(plan.s1), "s2": float(plan.s2), "s3": float(plan.s3),
        "n_c": int(plan.n_c), "n_e": int(plan.n_e),
        "n_scored": int(plan.n_scored), "exhaustive": bool(plan.exhaustive),
    }
    for j in range(3):
        out[f"vertex_{j + 1}"] = int(plan.vertex_ids[j])
        out[f"delta_{j + 1}_mm"] = float(eq.depths[0, j] * 1e3)
        out[f"normal_force_{j + 1}_n"] = float(eq.normal_forces[0, j])
        out[f"contact_normal_z_{j + 1}"] = float(plan.normals[j, 2])
    return out


def run(inp: TrialInput, rng: np.random.Generator) -> dict[str, Any]:
    """Plan with the trial's planner and evaluate under the body's parameters."""
    f, study = inp.trial.factors, inp.study
    body = body_key(f)
    nodes = body["nodes"] or inp.params.nodes
    contact = body_contact(study, inp.prepared)
    ctx, plan, truth, context_time, plan_time = plan_and_judge(
        study, body["shape"], nodes, body["mass_kg"], body["mu"], contact, f["planner"], rng)
    _, features = common.body_mesh(body["shape"], nodes, common.feature_thresholds(study))
    out = plan_record(ctx, plan, truth)
    out.update({
        "nodes": len(ctx.vertices),
        "n_cand": ctx.n_cand,
        "n_sharp_vertex": int(np.count_nonzero(features.sharp_vertices)),
        "n_sharp_edge": int(len(features.sharp_edges)),
        "lambda1": contact.lambda1, "lambda2": contact.lambda2, "n_exp": contact.n,
        "believed_lambda1": plan.contact.lambda1, "believed_n_exp": plan.contact.n,
        "context_time_s": context_time,
        "plan_time_s": plan_time,
    })
    if "nodes" in f:
        out.pop("nodes")
    return out


QUASI_STATIC = TrialKind(
    name="quasi_static",
    run=run,
    params=QuasiStaticParams,
    seconds_per_trial=0.01,
    body_key=body_key,
    prepare=prepare,
    description="plan with one planner, judge with the quasi-static evaluator (Algorithms 1-2)",
)
