"""Planner predictions for the hardware campaigns: each planner sizes its grip from its own belief
(:mod:`graspcampaign.rig.belief`; §8.1, SPEC §2.10) and predicts the trial before it runs.

:func:`predict_trial` gives the pre-execution predictions of one schedule row (contacts, H~ terms,
believed G_geo and mu_s, grip sizing, SF_predicted, per-finger forces and deformations,
``predicted_stable``, F_lat / F_down / T, first finger to slip, retention flag).

References
----------
Paper §8.1 (grip sizing from believed quality, kappa, tau_F), §9.1 (closed-form predicted
thresholds), §9.5 (predicted stability), §7.4 (damage depth); SPEC §2.10, §4, §7.
"""

from __future__ import annotations

import math
from typing import Any

import numpy as np

from graspcampaign.core import disturbance as dist
from graspcampaign.core import slip
from graspcampaign.core.statics import GRAVITY
from graspcampaign.rig.belief import PlannerBelief, material_model, planner_belief
from graspcampaign.rig.plan_contacts import STABLE_RESIDUAL_N, HardwarePlan, cached_plan, shape_body

__all__ = [
    "commanded_disturbance",
    "grip_time_s",
    "predict_trial",
    "predictions_from_plan",
]


# --------------------------------------------------------------------------------------------
# Predictions
# --------------------------------------------------------------------------------------------
def _num(row: dict, key: str, default: float = math.nan) -> float:
    value = row.get(key, default)
    try:
        value = float(value)
    except (TypeError, ValueError):
        return default
    return value


def grip_time_s(row: dict) -> float:
    """Return the time under grip before grading [s]: lift (50 mm at the lift speed) plus hold."""
    from graspcampaign.rig.protocol import DEFAULT_LIFT_MM_PER_S, HOLD_S, LIFT_HEIGHT_MM

    lift = _num(row, "lift_speed_mm_per_s", DEFAULT_LIFT_MM_PER_S)
    return LIFT_HEIGHT_MM / lift + _num(row, "hold_s", HOLD_S)


def commanded_disturbance(row: dict) -> tuple[str, float, float]:
    """Return (kind, level, direction_deg) of a schedule row's commanded disturbance.

    ``level`` is what the retention flag is judged against: the proof load of the threshold
    blocks (A: one weight laterally; C: the proof torque), the commanded load of B, the pulse
    peak of D, the sinusoid amplitude of E; ``("none", 0, 0)`` for Test 2 rows.
    """
    kind = str(row.get("disturbance_kind") or "none")
    if kind in ("", "nan", "none"):
        return "none", 0.0, 0.0
    direction = _num(row, "direction_deg", 0.0)
    block = row.get("block")
    if block == "A":
        return kind, _num(row, "proof_force_n"), direction
    if block == "C":
        return kind, _num(row, "proof_torque_nm"), direction
    return kind, _num(row, "load_n"), direction


def predictions_from_plan(plan: HardwarePlan, belief: PlannerBelief, mass: float,
                          centroid=(0.0, 0.0, 0.0), kind: str = "none", level: float = 0.0,
                          direction_deg: float = 0.0, load_s: float | None = None
                          ) -> dict[str, Any]:
    """Size the grip from a planner's belief and derive every pre-execution prediction.

    Parameters
    ----------
    plan : HardwarePlan
        The planned contacts (what the rig executes: points and approach normals).
    belief : PlannerBelief
        What the planner believes (:func:`graspcampaign.rig.belief.planner_belief`, or
        :func:`~graspcampaign.rig.belief.actual_belief` for ``belief_error = none``): friction,
        the contacts and normals its statics uses, contact law, creep, grip cap.
    mass : float
        [kg].
    centroid : (3,) float
        Object centroid [m].
    kind, level, direction_deg
        Commanded disturbance (see :func:`commanded_disturbance`; ``none`` for Test 2).
    load_s : float, optional
        Time under grip the indentation creeps over (lift plus hold) for a belief with a creep
        model. Default: :func:`grip_time_s` at the default lift speed and hold.

    Returns
    -------
    dict
        Flat prediction columns (see :func:`predict_trial`).

    Notes
    -----
    The grip is sized to the target SF from the believed mu_s and G_geo, capped at the grip that
    keeps the believed most loaded finger -- and the commanded force itself -- within the cap
    depth after the believed creep (SPEC §2.10). ``predicted_stable`` follows §9.5: the believed
    retention margin under the commanded disturbance exceeds one; for Test 2 the commanded load
    is the lifted weight alone, so the margin is SF_predicted itself. The paper's Test 2 reading
    (§8.1: Algorithm 2's residual at most tau_F = 0.0886 N) is kept as
    ``predicted_stable_residual``.
    """
    if load_s is None:
        load_s = grip_time_s({})
    creep = belief.creep(load_s)
    g_geo = belief.g_geo()
    shares, _ = dist.load_shared_forces(np.ones(3), belief.normals)
    # each finger first presses with its commanded force, then the object shifts and the forces
    # share out: the cap keeps both the command and the largest shared force within the cap depth
    max_share = max(float(shares.max()), 1.0)
    sizing = dist.size_grip(mu_s=belief.mu_s, g_geo=g_geo, mass=mass,
                            k_n_per_mm_n=belief.cap_k_n_per_mm_n, n=belief.n,
                            cap_depth=belief.cap_depth, creep=creep, max_share=max_share)
    forces, feasible = dist.load_shared_forces(np.full(3, sizing.grip_force), belief.normals)
    forces = np.maximum(forces, 0.0)
    depths_mm = dist.indentation_from_force(forces, belief.k_n_per_mm_n, belief.n, creep) * 1e3
    weight = mass * GRAVITY
    r_eff = dist.effective_radius(belief.points, centroid)
    limits = dist.disturbance_limits(sizing.sf_predicted, weight, r_eff)
    first = slip.first_slip_finger(belief.points, belief.normals, forces, centroid, mass,
                                   belief.mu_s, kind, direction_deg) if feasible else 0
    margin = dist.retention_margin(sizing.sf_predicted, weight, r_eff, kind, level) \
        if sizing.sf_predicted >= 1.0 else sizing.sf_predicted
    threshold_n = {"lateral": limits.lateral_force, "down": limits.down_force}.get(kind, math.nan)
    out: dict[str, Any] = {}
    for j in range(3):
        out[f"vertex_{j + 1}"] = int(plan.vertex_ids[j])
        for a, axis in enumerate("xyz"):
            out[f"contact_{j + 1}_{axis}_mm"] = float(plan.points[j, a] * 1e3)
        for a, axis in enumerate("xyz"):
            out[f"normal_{j + 1}_{axis}"] = float(plan.normals[j, a])
    out.update({
        "h_tilde": plan.h_tilde, "s1": plan.s1, "s2": plan.s2, "s3": plan.s3,
        "pc_mag": plan.pc_mag, "pe_mag": plan.pe_mag,
        "belief_error": belief.belief_error, "belief_model": belief.model,
        "g_geo_believed": g_geo, "mu_s_believed": belief.mu_s,
        "k_believed_n_per_mm_n": belief.k_n_per_mm_n, "believed_n_exp": belief.n,
        "creep_believed": creep,
        "grip_force_n": sizing.grip_force, "grip_needed_n": sizing.needed_force,
        "grip_cap_n": sizing.cap_force, "grip_capped": sizing.capped,
        "sf_predicted": sizing.sf_predicted,
        **{f"normal_force_pred_{j + 1}_n": float(forces[j]) for j in range(3)},
        "normal_force_pred_mean_n": float(forces.mean()),
        **{f"deformation_pred_{j + 1}_mm": float(depths_mm[j]) for j in range(3)},
        "deformation_pred_mean_mm": float(depths_mm.mean()),
        "contact_loss_predicted": not feasible,
        "residual_pred_n": plan.residual_norm,
        "delta_max_pred_mm": plan.delta_max_mm,
        "predicted_stable": bool(margin > 1.0),
        "predicted_stable_residual": bool(plan.residual_norm <= STABLE_RESIDUAL_N),
        "r_eff_mm": r_eff * 1e3,
        "f_lat_pred_n": limits.lateral_force, "f_down_pred_n": limits.down_force,
        "torque_pred_nm": limits.yaw_torque,
        "threshold_pred_n": threshold_n,
        "threshold_pred_nm": limits.yaw_torque if kind == "yaw" else math.nan,
        "first_finger_pred": int(first),
        "retention_margin_pred": float(margin),
        "retention_pred": bool(margin > 1.0),
        "plan_time_s": plan.plan_time_s,
    })
    return out


def predict_trial(row: dict, belief: PlannerBelief | None = None) -> dict[str, Any]:
    """Return the planner's pre-execution predictions for one schedule row.

    Parameters
    ----------
    row : dict
        A row of :func:`graspcampaign.rig.protocol.test2_schedule` or ``test3_schedule``
        (needs ``shape, material, mass_kg, planner, plan_key, protocol_seed, friction_level,
        hold_s``; Test 3 rows also the disturbance columns).
    belief : PlannerBelief, optional
        Replaces the planner's own belief (:func:`graspcampaign.rig.belief.planner_belief`):
        the virtual rig passes the actual quantities for ``belief_error = none``.

    Returns
    -------
    dict
        ``vertex_1..3``; ``contact_j_{x,y,z}_mm`` and ``normal_j_{x,y,z}`` (planned contacts and
        their outward normals: the fingers close along ``-normal``); ``h_tilde, s1, s2, s3,
        pc_mag, pe_mag``; ``belief_error`` (paper | none), ``belief_model`` (calibrated,
        nominal_law, nominal_geometry, actual); ``g_geo_believed, mu_s_believed,
        k_believed_n_per_mm_n, believed_n_exp, creep_believed``; ``grip_force_n`` (commanded per
        finger), ``grip_needed_n``, ``grip_cap_n``, ``grip_capped``, ``sf_predicted`` (the
        believed SF); ``normal_force_pred_j_n``, ``normal_force_pred_mean_n``,
        ``deformation_pred_j_mm``, ``deformation_pred_mean_mm``; ``contact_loss_predicted``;
        ``residual_pred_n``, ``delta_max_pred_mm``; ``predicted_stable`` (believed retention
        margin > 1, §9.5), ``predicted_stable_residual`` (residual <= 0.0886 N, §8.1);
        ``r_eff_mm``, ``f_lat_pred_n``, ``f_down_pred_n``, ``torque_pred_nm``,
        ``threshold_pred_n`` / ``threshold_pred_nm`` (for the row's disturbance),
        ``first_finger_pred`` (1-3, 0 = none), ``retention_margin_pred``, ``retention_pred``
        (= ``predicted_stable``), ``plan_time_s`` (0 when the plan came from the cache).
    """
    planner = str(row["planner"])
    shape = str(row["shape"])
    mass = float(row["mass_kg"])
    material = material_model(str(row["material"]), str(row.get("friction_level") or "natural"))
    hits = cached_plan.cache_info().hits
    plan = cached_plan(shape, planner, str(row["plan_key"]), int(row.get("protocol_seed", 0)),
                       mass, material.material, material.friction_level)
    cached = cached_plan.cache_info().hits > hits
    centroid = shape_body(shape).ctx.centroid
    if belief is None:
        belief = planner_belief(planner, plan.points, plan.normals, material, centroid)
    kind, level, direction = commanded_disturbance(row)
    out = predictions_from_plan(plan, belief, mass, centroid, kind, level, direction,
                                grip_time_s(row))
    if cached:
        out["plan_time_s"] = 0.0
    return out
