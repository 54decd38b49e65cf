"""Conversions from config dataclasses to core parameter objects, and per-worker caches.

Meshes, sharp features and plan contexts are cached per worker process: every trial of one body
reuses them, and none of them depends on a trial's random stream.
"""

from __future__ import annotations

from functools import lru_cache

from graspcampaign.campaign.schema import StudyCfg

DEFAULT_NODES = 390  # Sec. 6.2: the multi-shape studies use ~390-node meshes


def contact_params(study: StudyCfg, **overrides):
    """Return the configured ContactParams (Table 2 materials, Table 3 or nominal lambdas)."""
    from graspcampaign.core.contact import ContactParams

    m = study.model
    values = dict(lambda1=m.lambda1, lambda2=m.lambda2, n=m.n_exp,
                  fingertip_radius=m.fingertip_radius_m, e_finger=m.e_finger_pa,
                  e_object=m.e_object_pa, nu_finger=m.nu_finger, nu_object=m.nu_object,
                  damping_law=m.damping_law, alpha_hc_s_per_m=m.alpha_hc_s_per_m)
    values.update(overrides)
    return ContactParams(**values)


def evaluator_params(study: StudyCfg, **overrides):
    """Return the configured EvaluatorParams (Algorithms 1-2, grip law, validity bound)."""
    from graspcampaign.core.equilibrium import EvaluatorParams

    e = study.evaluator
    values = dict(seed_depth=e.seed_depth_m, n_max=e.n_max, alpha=e.alpha, eps=e.eps,
                  tau_f=e.tau_f_n, tau_t=e.tau_t_nm, residual_check=e.residual_check,
                  fingertip_radius=study.model.fingertip_radius_m, grip_law=e.grip_law,
                  grip_safety_factor=e.grip_safety_factor, grip_cap_depth=grip_cap_depth(study),
                  cone_facets=e.oracle_cone_facets)
    values.update(overrides)
    return EvaluatorParams(**values)


def grip_cap_depth(study: StudyCfg) -> float:
    """Deepest penetration the slip/oracle grip laws may command [m].

    ``evaluator.grip_cap_depth_m`` when set; otherwise the damage depth (§7.4,
    ``bench.true_damage_depth``) of the Table 4 family whose modulus is nearest
    ``model.e_object_pa``, bounded by the fingertip radius (deeper is not a contact, issue 13).
    """
    if study.evaluator.grip_cap_depth_m is not None:
        return float(study.evaluator.grip_cap_depth_m)
    return _default_cap_depth(float(study.model.e_object_pa), float(study.model.fingertip_radius_m))


@lru_cache(maxsize=8)
def _default_cap_depth(e_object_pa: float, fingertip_radius_m: float) -> float:
    from graspcampaign.core.bench import FAMILIES, true_damage_depth

    family = min(FAMILIES.values(), key=lambda f: abs(f.modulus_mean - e_object_pa))
    return min(float(true_damage_depth(family).depth), fingertip_radius_m)


def verdict_columns(eq, evaluator, index: int = 0) -> dict:
    """Record columns of one evaluation's verdict: the one rule every kind records (issue 13).

    ``success`` requires the checks and ``valid_geometry`` (every active contact within the
    fingertip radius); ``success_unbounded`` is the checks alone; ``success_norm``,
    ``success_vertical``, ``success_no_torque`` the other readings
    (:func:`graspcampaign.core.verdict.readings`); ``failure_check`` the first failing check and
    ``residual_ok``, ``torque_ok``, ``slip_ok`` each check on its own.
    """
    from graspcampaign.core.verdict import readings

    out = {name: bool(value[index]) for name, value in readings(eq, evaluator).items()}
    out.update({
        "valid_geometry": bool(eq.valid_geometry[index]),
        "failure_check": str(eq.failure_labels()[index]),
        "residual_ok": bool(eq.residual_ok[index]),
        "torque_ok": bool(eq.torque_ok[index]),
        "slip_ok": bool(eq.slip_ok[index]),
    })
    return out


def feature_thresholds(study: StudyCfg):
    from graspcampaign.core.feature import FeatureThresholds

    f = study.features
    return FeatureThresholds(vertex_defect_rad=f.vertex_defect_rad,
                             edge_dihedral_deg=f.edge_dihedral_deg,
                             edge_proximity_factor=f.edge_proximity_factor,
                             resolution_aware=f.resolution_aware)


@lru_cache(maxsize=64)
def body_mesh(shape: str, nodes: int, thresholds):
    """Return ``(mesh, features)`` of an object (cached per worker)."""
    from graspcampaign.core.feature import sharp_features
    from graspcampaign.core.mesh import make_object

    mesh = make_object(shape, nodes)
    return mesh, sharp_features(mesh, thresholds)


@lru_cache(maxsize=256)
def plan_context(shape: str, nodes: int, mass: float, mu: float, contact, evaluator, n_cand: int,
                 thresholds, weights=None, fc_cone_edges: int = 8):
    """Return the PlanContext of one soft body (cached per worker)."""
    from graspcampaign.core.planner import plan_context as make_context

    mesh, features = body_mesh(shape, nodes, thresholds)
    return make_context(mesh, features, mass=mass, mu=mu, contact=contact, evaluator=evaluator,
                        n_cand=n_cand, weights=weights, fc_cone_edges=fc_cone_edges)


def nodes_of(factors: dict, default: int = DEFAULT_NODES) -> int:
    return int(factors.get("nodes", default))


# IdentificationResult.to_record() names -> record column names (docs/records.md)
_IDENTIFICATION_COLUMNS = {"n_exponent": "n_exp", "msd_b": "b", "msd_k": "k", "msd_c": "c",
                           "pso_best_cost": "best_cost", "pso_n_evaluations": "n_evaluations"}


def at_bound_text(prepared: dict | None) -> str:
    """The parameters a trial's prepared body ended on a PSO bound at, comma-joined; "" for a body
    not identified (no key, or the null its row of a stored prepared/ table reads back as)."""
    return str((prepared or {}).get("at_bound") or "")


def identification_record(result) -> dict:
    """Flatten an IdentificationResult into the record columns of docs/records.md."""
    return {_IDENTIFICATION_COLUMNS.get(k, k): v for k, v in result.to_record().items()}
