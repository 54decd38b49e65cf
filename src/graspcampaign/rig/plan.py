"""Planner predictions for the hardware campaigns and the ``graspcampaign plan MESH`` computation.

What each planner *knows* (materials, friction, contact law, creep, geometry) lives in
:mod:`graspcampaign.rig.belief`; this module plans the contacts (the hardware form of the proposed
planner, §8.1: weights 0.45/0.30/0.25, continuous penalties, maximised score H~; the registry
baselines) and sizes each planner's grip from its own belief (§8.1, SPEC §2.10).

* :func:`predict_trial` -- the pre-execution predictions of one schedule row (contacts, H~ terms,
  believed G_geo and mu_s, grip sizing, SF_predicted, per-finger forces and deformations,
  ``predicted_stable``, F_lat / F_down / T, first finger to slip, retention flag).
* :func:`plan_mesh` -- the same pipeline for a user's mesh, plus a PNG of contacts and forces.

Per-object work is cached per process: the mesh, its sharp features and heuristic context per
shape, and each plan per ``plan_key`` (an object's plan is shared by all its trials with the same
planner; the random planner draws a new triple per slot, see :mod:`graspcampaign.rig.protocol`).

References
----------
Paper §8.1 (planners, hardware weighting, grip sizing from believed quality, kappa, tau_F), §9.1
(closed-form predicted thresholds), §7.4 (damage depth), Table 4; SPEC §2.8, §2.10, §4, §7.
"""

from __future__ import annotations

import functools
import hashlib
import logging
import math
import time
from dataclasses import dataclass, replace
from pathlib import Path
from typing import Any

import numpy as np

from graspcampaign.core import disturbance as dist
from graspcampaign.core import slip
from graspcampaign.core.contact import NOMINAL_CONTACT
from graspcampaign.core.equilibrium import EvaluatorParams, evaluate_grasps
from graspcampaign.core.metric import HARDWARE_WEIGHTS, heuristic_terms
from graspcampaign.core.planner import (
    DEFAULT_N_CAND,
    PLANNERS,
    PlanContext,
    plan_context,
    sample_triples,
)
from graspcampaign.core.statics import GRAVITY
from graspcampaign.rig.belief import (  # noqa: F401  (re-exported: the planners' knowledge)
    CHARACTERISTIC_Z,
    COATING_MU_S,
    MaterialModel,
    PlannerBelief,
    believed_contact_law,
    family_damage_depth,
    material_model,
    planner_belief,
)

__all__ = [
    "CHARACTERISTIC_Z",
    "COATING_MU_S",
    "HARDWARE_PLANNERS",
    "HardwarePlan",
    "MaterialModel",
    "commanded_disturbance",
    "family_damage_depth",
    "grip_time_s",
    "hardware_plan",
    "material_model",
    "plan_mesh",
    "predict_trial",
    "predictions_from_plan",
]

logger = logging.getLogger(__name__)

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


def _make_body(mesh) -> _Body:
    from graspcampaign.core.feature import sharp_features

    feats = sharp_features(mesh)
    ctx = plan_context(mesh, feats, mass=1.0, mu=1.0, contact=NOMINAL_CONTACT,
                       weights=HARDWARE_WEIGHTS, n_cand=DEFAULT_N_CAND)
    return _Body(mesh=mesh, ctx=ctx)


@functools.lru_cache(maxsize=16)
def _shape_body(shape: str, n_nodes: int = N_NODES) -> _Body:
    from graspcampaign.core.mesh import make_object

    return _make_body(make_object(shape, n_nodes))


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
def _cached_plan(shape: str, planner: str, plan_key: str, seed: int, mass: float, material: str,
                 friction_level: str) -> HardwarePlan:
    body = _shape_body(shape)
    mat = material_model(material, friction_level)
    ctx = replace(body.ctx, mass=mass, mu=mat.mu_s, contact=mat.contact_params())
    k, n = believed_contact_law(planner, mat)
    return hardware_plan(ctx, planner, _plan_rng(seed, plan_key), k, n)


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
        "k_believed_n_per_mm_n": belief.k_n_per_mm_n, "n_believed": belief.n,
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
        k_believed_n_per_mm_n, n_believed, creep_believed``; ``grip_force_n`` (commanded per
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
    hits = _cached_plan.cache_info().hits
    plan = _cached_plan(shape, planner, str(row["plan_key"]), int(row.get("protocol_seed", 0)),
                        mass, material.material, material.friction_level)
    cached = _cached_plan.cache_info().hits > hits
    centroid = _shape_body(shape).ctx.centroid
    if belief is None:
        belief = planner_belief(planner, plan.points, plan.normals, material, centroid)
    kind, level, direction = commanded_disturbance(row)
    out = predictions_from_plan(plan, belief, mass, centroid, kind, level, direction,
                                grip_time_s(row))
    if cached:
        out["plan_time_s"] = 0.0
    return out


# --------------------------------------------------------------------------------------------
# graspcampaign plan MESH
# --------------------------------------------------------------------------------------------
DEFAULT_PLAN_MATERIAL = "silicone_ref"
"""Contact law used by ``plan`` when only ``--mu`` is given (the stiffest, Table 4 reference)."""


def _check_plausible(value: object, name: str, quantity: str, unit: str) -> float:
    """Return ``value`` as a float inside its plausible range (``core.plausible.PLAUSIBLE``)."""
    from graspcampaign.core.plausible import PLAUSIBLE

    try:
        number = float(value)  # type: ignore[arg-type]
    except (TypeError, ValueError):
        raise ValueError(f"{name} must be a number, got {value!r}.") from None
    rng = PLAUSIBLE[quantity]
    if not rng.contains(number):
        unit = f" {unit}" if unit else ""
        raise ValueError(f"{name} = {value!r} is out of range; allowed: {rng.text()}{unit} "
                         f"({rng.why}).")
    return number


def _check_size(mesh, name: str, unit: str) -> float:
    """Return the object's size [mm]; refuse one no hand can grasp, naming the likely unit."""
    from graspcampaign.core.mesh import UNITS
    from graspcampaign.core.plausible import OBJECT_SIZE_MM

    size_mm = float(np.ptp(np.asarray(mesh.vertices), axis=0).max()) * 1e3
    if OBJECT_SIZE_MM.contains(size_mm):
        return size_mm
    raw = size_mm * 1e-3 / UNITS[unit]  # the size in the file's own numbers
    fits = [u for u, scale in UNITS.items() if OBJECT_SIZE_MM.contains(raw * scale * 1e3)]
    hint = (f"its coordinates look like {' or '.join(_UNIT_WORDS[u] for u in fits)}: pass "
            f"--unit {fits[0]}" if fits else "no length unit makes it graspable")
    across = f"{size_mm / 1e3:.3g} m" if size_mm >= 1e3 else f"{size_mm:.3g} mm"
    raise ValueError(f"mesh {name!r} is {across} across read with --unit {unit}, outside "
                     f"the {OBJECT_SIZE_MM.low:g}-{OBJECT_SIZE_MM.high:g} mm a three-finger hand "
                     f"grasps; {hint}.")


_UNIT_WORDS = {"m": "metres", "cm": "centimetres", "mm": "millimetres"}
UNLOADED_N = 1e-6
"""A finger pressing with less than this [N] carries no load (the plan's forces are N-scale)."""


def plan_mesh(mesh_or_path, *, mass_kg: float, material: str | None = None, mu: float | None = None,
              fingertip_radius_mm: float = 5.0, unit: str = "mm", png_path=None,
              seed: int = 0) -> dict[str, Any]:
    """Plan a proposed-planner grasp on a user's mesh and predict its disturbance limits.

    Parameters
    ----------
    mesh_or_path : str, path or trimesh.Trimesh
        Mesh file (STL/OBJ/PLY, read with :func:`graspcampaign.core.mesh.load_mesh`) or a mesh.
    mass_kg : float
        Object mass, in its plausible range (``core.plausible.PLAUSIBLE``: (0, 10] kg).
    material : str, optional
        Table 4 family; default ``silicone_ref`` for the contact law when only ``mu`` is given.
    mu : float, optional
        Static friction [0, 3]; overrides the material's mu_s.
    fingertip_radius_mm : float
        Fingertip radius (0, 50] mm (K scales with sqrt(R), Eq. 14).
    unit : str
        Length unit of the mesh file.
    png_path : path, optional
        Where to write the picture (mesh, contacts, force arrows); none when omitted.
    seed : int
        Candidate sampling seed.

    Returns
    -------
    dict
        ``mesh`` (name, nodes, faces, size_mm), ``material``, ``mu_s``, ``mass_kg``, ``weight_n``,
        ``contacts`` (per finger: point mm, outward normal, normal force N, deformation mm),
        ``h`` (``h_tilde, s1, s2, s3, pc_mag, pe_mag``), ``g_geo``, ``grip_force_n``,
        ``grip_capped``, ``sf_predicted``, ``f_lat_n``, ``f_down_n``, ``torque_nm``, ``r_eff_mm``,
        ``first_finger`` (per disturbance: lateral +x, +y, down, yaw), ``predicted_stable``
        (the residual criterion, and every finger loaded), ``unloaded_fingers`` (1-based, fingers
        whose normal force is not above :data:`UNLOADED_N`), ``png``.

    Raises
    ------
    graspcampaign.core.mesh.MeshError
        Unreadable or invalid mesh.
    ValueError
        Out-of-range mass, friction, radius, an unknown material, or an object whose size no
        three-finger hand grasps (``core.plausible.OBJECT_SIZE_MM``; the message names the unit
        its coordinates look like).
    """
    from graspcampaign.core.mesh import load_mesh

    mass = _check_plausible(mass_kg, "mass_kg", "mass_kg", "kg")
    radius_mm = _check_plausible(fingertip_radius_mm, "fingertip_radius_mm", "fingertip_radius_mm",
                                 "mm")
    if mu is not None:
        mu = _check_plausible(mu, "mu", "mu", "")
    name_material = material or DEFAULT_PLAN_MATERIAL
    mat = material_model(name_material, "natural", radius_mm * 1e-3)
    if mu is not None:
        mat = replace(mat, mu_s=mu, mu_k=mu * mat.mu_k / mat.mu_s, friction_level="user")
    if isinstance(mesh_or_path, (str, Path)):
        mesh = load_mesh(mesh_or_path, unit=unit)
        name = Path(mesh_or_path).name
    else:
        mesh = mesh_or_path
        name = "mesh"
    size_mm = _check_size(mesh, name, unit)
    body = _make_body(mesh)
    ctx = replace(body.ctx, mass=mass, mu=mat.mu_s,
                  contact=mat.contact_params(radius_mm * 1e-3), n_cand=DEFAULT_N_CAND,
                  evaluator=EvaluatorParams())
    plan = hardware_plan(ctx, "heuristic", np.random.default_rng(seed), mat.k_n_per_mm_n, mat.n)
    belief = planner_belief("heuristic", plan.points, plan.normals, mat, ctx.centroid)
    pred = predictions_from_plan(plan, belief, mass, ctx.centroid)
    forces = np.array([pred[f"normal_force_pred_{j}_n"] for j in (1, 2, 3)])
    first = {}
    for label, kind, direction in (("lateral_x", "lateral", 0.0), ("lateral_y", "lateral", 90.0),
                                   ("down", "down", 0.0), ("yaw", "yaw", 0.0)):
        first[label] = slip.first_slip_finger(plan.points, plan.normals, forces, ctx.centroid,
                                              mass, mat.mu_s, kind, direction)
    contacts = [{"finger": j + 1, "vertex": int(plan.vertex_ids[j]),
                 "point_mm": [round(float(v) * 1e3, 3) for v in plan.points[j]],
                 "normal": [round(float(v), 4) for v in plan.normals[j]],
                 "normal_force_n": float(forces[j]),
                 "deformation_mm": pred[f"deformation_pred_{j + 1}_mm"]} for j in range(3)]
    # a finger that presses on nothing leaves a two-finger grasp: never stable (Sec. 8.1 needs all
    # three contacts loaded), whatever the residual criterion says
    unloaded = [j + 1 for j in range(3) if not forces[j] > UNLOADED_N]
    out = {
        "mesh": {"name": name, "nodes": int(len(mesh.vertices)), "faces": int(len(mesh.faces)),
                 "size_mm": size_mm},
        "material": name_material, "mu_s": mat.mu_s, "mass_kg": mass, "weight_n": mass * GRAVITY,
        "fingertip_radius_mm": radius_mm, "kappa": dist.KAPPA, "target_sf": dist.SF_TARGET,
        "contacts": contacts,
        "h": {k: pred[k] for k in ("h_tilde", "s1", "s2", "s3", "pc_mag", "pe_mag")},
        "g_geo": pred["g_geo_believed"], "grip_force_n": pred["grip_force_n"],
        "grip_capped": pred["grip_capped"], "grip_cap_n": pred["grip_cap_n"],
        "sf_predicted": pred["sf_predicted"], "f_lat_n": pred["f_lat_pred_n"],
        "f_down_n": pred["f_down_pred_n"], "torque_nm": pred["torque_pred_nm"],
        "r_eff_mm": pred["r_eff_mm"], "first_finger": first,
        "predicted_stable": bool(pred["predicted_stable"]) and not unloaded,
        "unloaded_fingers": unloaded, "residual_n": pred["residual_pred_n"],
        "png": None,
    }
    if png_path is not None:
        out["png"] = str(plot_plan(mesh, plan.points, plan.normals, forces, png_path,
                                   title=f"{name}: SF {out['sf_predicted']:.2f}, "
                                         f"F_lat {out['f_lat_n']:.2f} N"))
    return out


def plot_plan(mesh, points, normals, forces, path, title: str = "") -> Path:
    """Write a PNG of the mesh with the contacts and their force arrows (matplotlib Agg).

    Arrows start at each contact and point along the applied force ``-n_out``, their length
    proportional to the finger's normal force (the largest drawn at 40 % of the object's size).
    """
    import matplotlib

    matplotlib.use("Agg")
    from matplotlib.figure import Figure

    path = Path(path)
    v = np.asarray(mesh.vertices) * 1e3
    p = np.asarray(points) * 1e3
    size = float(np.ptp(v, axis=0).max())
    f = np.asarray(forces, dtype=float)
    scale = 0.4 * size / max(float(f.max()), 1e-9)
    arrows = -np.asarray(normals) * (f * scale)[:, None]
    fig = Figure(figsize=(6, 6))
    ax = fig.add_subplot(projection="3d")
    ax.plot_trisurf(v[:, 0], v[:, 1], v[:, 2], triangles=np.asarray(mesh.faces), color="0.8",
                    alpha=0.35, linewidth=0.1, edgecolor="0.5")
    colours = ("tab:red", "tab:green", "tab:blue")
    for j in range(3):
        ax.scatter(*p[j], color=colours[j], s=50, depthshade=False)
        ax.quiver(*(p[j] - arrows[j]), *arrows[j], color=colours[j], linewidth=2,
                  arrow_length_ratio=0.25)
        ax.text(*(p[j] - 1.1 * arrows[j]), f"{j + 1}: {f[j]:.2f} N", color=colours[j])
    ax.set_xlabel("x [mm]")
    ax.set_ylabel("y [mm]")
    ax.set_zlabel("z [mm]")
    ax.set_box_aspect(np.ptp(v, axis=0))
    ax.set_title(title, fontsize=9)
    path.parent.mkdir(parents=True, exist_ok=True)
    fig.savefig(path, dpi=100)
    return path
