"""Virtual rig for Tests 2-3: a documented stochastic physical model of one executed trial.

Without hardware, :func:`virtual_trial` produces the measured outcome columns of one schedule row
from the planner's predictions (:func:`graspcampaign.rig.plan.predict_trial`) and a
``numpy.random.Generator`` supplied by the caller. Every record carries ``source = "virtual"``:
these are model outputs, never hardware results.

The model, step by step (each constant's source is in :class:`RigParams` and docs/decisions.md):

0. **Beliefs.** The grip executed is the one the planner sized from its own belief
   (:mod:`graspcampaign.rig.belief`, ``belief_error = paper``), or -- the counterfactual
   ``belief_error = none`` -- the grip it would size knowing the trial's actual quantities,
   re-sized after the contacts are realised (step 2).
1. **Specimen truth** (:mod:`graspcampaign.rig.specimen`). Each object's constants are drawn once
   around its Table 4 family by the Test 1 virtual bench, keyed by (protocol seed, object id);
   the day's ambient group scales natural friction (§7.3); coatings replace it with a per-object
   spread; the true damage depth follows the specimen's cyclic constants (§7.4).
2. **Execution.** The object sits offset from where the planner believes it is: the designed pose
   error (0 or 10 mm, random horizontal direction) plus the pose-estimation error. Each finger
   closes along its planned force direction ``-n``; its achieved contact is the first surface
   point on that line (ray cast on the mesh) with the interpolated surface normal there. A finger
   that misses the object is a contact loss.
3. **Forces.** Each finger's force controller tracks the commanded grip with a multiplicative
   error; the object shifts until the horizontal squeeze balances (least-squares load sharing);
   a finger that would need a negative force loses contact.
4. **Friction budget.** The achieved contacts hold ``B_s = kappa mu_s sum_j f_j sqrt(1 - n_z,j^2)``
   of friction (the shared budget of §9.1 with the true friction and the achieved forces and
   normals; ``B_k`` with mu_k); the normal forces' own vertical resultant ``N_z`` supports part of
   the weight. The object sticks while the demand vector (vertical ``W (1 + a/g) - N_z`` plus any
   disturbance) stays inside ``B_s``; beyond it, it slides as a point mass under the kinetic
   budget ``B_k`` (Coulomb, opposing the sliding velocity) until it re-sticks or is lost.
5. **Slip.** Inside the budget the pads deflect (Mindlin partial slip with the Table 4 k_t). A
   centre of mass offset from the contact triangle swings the object until the remaining moment
   is carried (barycentric load share of the most loaded contact). Sliding adds its travel.
6. **Damage.** Indentation under constant grip creeps (QLV standard linear solid, Table 4 rho,
   tau) over the time under load; beyond the specimen's damage depth the trial is a damage event.
   A fingertip sunk deeper than its own radius is buried: ``valid_geometry`` is false, the trial
   is a damage event too (``success_unbounded`` keeps the reading without this gate), and that
   finger gives no deformation reading (the Eq. 13 patch no longer exists).
7. **Disturbances (Test 3)** (:mod:`graspcampaign.rig.disturb`) act on the same budget: lateral
   and torsion ramps are pulled until slip (detected at 2 mm, released after a latency), vertical
   loads are ramped to their level, impulses and sinusoids are integrated in time.
8. **Sensors.** Finger forces at 5 mN, vision at 0.1 mm (multi-frame aggregates stored finer),
   load cell 0.01 N, torque 0.005 N m, each with noise of 1.5 resolution steps before rounding.
9. **Aborts.** A slot the schedule marks ``rig_fault`` aborts before load (§8.1, §9.1).

Grading (§8.1, exactly): measured failures override the safety factor -- contact loss, drop,
damage, slip beyond 12 mm (in this order of precedence for the primary class; every flag is also
recorded); otherwise peak slip < 2 mm is a success, promoted to *stable* when SF_actual >= 1.25
(SF_actual: the §8.1 formula with the true friction, the commanded grip and the achieved G_geo);
2-12 mm is *partial* (a failure in the binary column). Test 3 threshold blocks (A, C) succeed
when the sustained threshold reaches the proof load and the object is retained.

References
----------
Paper §7.3-7.4, §8.1, §9.1-9.4, Table 4; SPEC §4. Johnson (1985) §7.2 (Mindlin); Findley, Lai &
Onaran (1976) §5.3 (standard linear solid creep); Moller & Trumbore (1997) (ray-triangle test).
"""

from __future__ import annotations

import logging
import math
from dataclasses import dataclass
from typing import Any

import numpy as np

from graspcampaign.analysis.hardware import VISION_QUANTUM_MM
from graspcampaign.core import bench
from graspcampaign.core import disturbance as dist
from graspcampaign.core import slip as slip_statics
from graspcampaign.core.statics import GRAVITY
from graspcampaign.rig import belief as rigbelief
from graspcampaign.rig import plan as rigplan
from graspcampaign.rig.disturb import disturb, empty_measures, num, quantise
from graspcampaign.rig.plan_contacts import shape_body
from graspcampaign.rig.protocol import LIFT_HEIGHT_MM
from graspcampaign.rig.specimen import (  # noqa: F401  (re-exported: the truth a trial runs on)
    COATING_MU_REL,
    ENVIRONMENT_PROBABILITIES,
    Specimen,
    day_environment,
    specimen_truth,
)

__all__ = [
    "ENVIRONMENT_PROBABILITIES",
    "OUTCOMES",
    "SOURCE",
    "RigParams",
    "Specimen",
    "day_environment",
    "grade",
    "specimen_truth",
    "virtual_trial",
]

logger = logging.getLogger(__name__)

SOURCE = "virtual"
OUTCOMES = ("stable", "success", "partial", "failure_slip", "failure_drop", "failure_damage",
            "failure_contact_loss")
"""Outcome classes; ``aborted`` rows carry ``outcome = "aborted"`` and enter no statistic."""
SUCCESS_SLIP_MM = 2.0
PARTIAL_SLIP_MM = 12.0
ABORT_REASONS = ("gripper_fault", "vision_dropout", "actuator_fault")


@dataclass(frozen=True)
class RigParams:
    """Constants of the virtual rig (sources in docs/decisions.md).

    Attributes
    ----------
    kappa : float
        True friction enhancement of the hand: the calibrated 2.4 (the virtual hand is defined by
        its Test 1 calibration, §8.1).
    a_lift : float
        Lift acceleration [m/s^2] (300 mm/s^2, §7.1).
    pose_sd : float
        Object-pose estimation error per horizontal axis [m] (decision: 1 mm, RGB-D).
    grip_tracking_rel : float
        Lognormal sigma of each finger's force tracking (decision: 5 %, current-based control).
    coating_mu_rel : float
        Lognormal sigma of a coating's friction from object to object (decision: 10 %).
    finger_force_resolution : float
        Finger force sensor resolution [N] (5 mN, §8.1).
    vision_resolution : float
        Vision quantisation [m] (0.1 mm, §8.1).
    vision_noise : float
        Per-trial aggregate vision noise SD [m] (decision: one quantum).
    contact_point_noise : float
        Vision localisation error of a contact point per axis [m] (decision: 1 mm).
    load_cell_resolution : float
        Disturbance load cell [N] (0.01 N, §9.1).
    torque_resolution : float
        Yaw torque sensor [N m] (0.005 N m, §9.1).
    noise_steps : float
        Sensor noise SD in resolution steps before rounding (decision, as the Test 1 bench: 1.5).
    detection_slip : float
        Slip at which a ramped disturbance is stopped [m] (the 2 mm criterion, §8.1, §9.3).
    release_latency : float
        Time from detection to load release [s] (decision: 10 samples at 200 Hz).
    drop_travel : float
        Sliding travel after which the object has left the fingertips [m] (decision: 25 mm,
        half the smallest object's half-width).
    observe : float
        Observation after a disturbance ends [s] (decision).
    dt : float
        Time step of the sliding integration [s].
    fingertip_radius : float
        Radius of the hand's silicone fingertips [m] (5 mm, §8.1): a finger indented deeper is
        buried (``valid_geometry`` false, a damage event, no deformation reading).
    """

    kappa: float = dist.KAPPA
    a_lift: float = dist.A_LIFT
    pose_sd: float = 1.0e-3
    grip_tracking_rel: float = 0.05
    coating_mu_rel: float = COATING_MU_REL
    finger_force_resolution: float = 5.0e-3
    vision_resolution: float = VISION_QUANTUM_MM / 1000.0  # mm -> m: the one §8.1 value
    vision_noise: float = 1.0e-4
    contact_point_noise: float = 1.0e-3
    load_cell_resolution: float = 0.01
    torque_resolution: float = 0.005
    noise_steps: float = 1.5
    detection_slip: float = 2.0e-3
    release_latency: float = 0.05
    drop_travel: float = 25.0e-3
    fingertip_radius: float = bench.FINGERTIP_RADIUS
    observe: float = 1.0
    dt: float = 1.0e-3


# --------------------------------------------------------------------------------------------
# Execution geometry
# --------------------------------------------------------------------------------------------
def _first_hits(origins: np.ndarray, directions: np.ndarray, triangles: np.ndarray):
    """Nearest ray-triangle hit per ray (Moller-Trumbore); face -1 and t = inf on a miss."""
    v0 = triangles[:, 0]
    e1 = triangles[:, 1] - v0
    e2 = triangles[:, 2] - v0
    d = directions[:, None, :]
    h = np.cross(d, e2[None])
    a = np.einsum("fk,rfk->rf", e1, h)
    s = origins[:, None, :] - v0[None]
    with np.errstate(divide="ignore", invalid="ignore"):
        inv = 1.0 / a
        u = inv * np.einsum("rfk,rfk->rf", s, h)
        q = np.cross(s, e1[None])
        v = inv * np.einsum("rfk,rfk->rf", d * np.ones_like(q), q)
        t = inv * np.einsum("fk,rfk->rf", e2, q)
        hit = (np.abs(a) > 1e-18) & (u >= 0.0) & (v >= 0.0) & (u + v <= 1.0) & (t > 0.0)
    t_hit = np.where(hit, t, np.inf)
    faces = np.argmin(t_hit, axis=1)
    rows = np.arange(len(origins))
    missed = ~hit[rows, faces]
    bary = np.stack([1.0 - u[rows, faces] - v[rows, faces], u[rows, faces], v[rows, faces]], 1)
    return np.where(missed, -1, faces), t_hit[rows, faces], bary


def realise_contacts(mesh, planned_points, planned_normals, offset):
    """Return achieved contacts when the object sits at ``offset`` from its believed pose.

    Parameters
    ----------
    mesh : trimesh.Trimesh
        Object surface in its own frame [m].
    planned_points, planned_normals : (3, 3) float
        Planned contacts and the normals the planner believes, object frame.
    offset : (3,) float
        True object position minus believed position [m].

    Returns
    -------
    points : (3, 3) float
        Achieved contacts in the object frame (NaN rows for a finger that misses).
    normals : (3, 3) float
        Outward surface normals there (barycentric interpolation of vertex normals).
    hit : (3,) bool
    """
    normals = np.asarray(planned_normals, dtype=float)
    size = float(np.ptp(np.asarray(mesh.vertices), axis=0).max())
    origins = np.asarray(planned_points, dtype=float) - offset + size * normals
    faces, t, bary = _first_hits(origins, -normals, np.asarray(mesh.triangles))
    hit = faces >= 0
    points = np.full((3, 3), np.nan)
    out_normals = np.full((3, 3), np.nan)
    points[hit] = origins[hit] - t[hit, None] * normals[hit]
    corner = np.asarray(mesh.faces)[np.where(hit, faces, 0)]
    smooth = np.einsum("rk,rkx->rx", bary, np.asarray(mesh.vertex_normals)[corner])
    out_normals[hit] = smooth[hit] / np.linalg.norm(smooth[hit], axis=1, keepdims=True)
    return points, out_normals, hit


# --------------------------------------------------------------------------------------------
# Grading
# --------------------------------------------------------------------------------------------
def grade(*, contact_loss: bool, dropped: bool, damaged: bool, slip_mm: float, sf_actual: float,
          threshold_ok: bool = True) -> tuple[str, bool, bool]:
    """Return ``(outcome, success, stable)`` by the §8.1 rules.

    Measured failures override the safety factor (precedence contact loss, drop, damage, slip
    beyond 12 mm); then slip < 2 mm is a success, stable when ``sf_actual >= 1.25``; 2-12 mm is
    partial. ``threshold_ok = False`` (a Test 3 threshold block whose sustained load stayed below
    its proof load) makes a retained trial a slip failure.
    """
    if contact_loss:
        return "failure_contact_loss", False, False
    if dropped:
        return "failure_drop", False, False
    if damaged:
        return "failure_damage", False, False
    if not threshold_ok:
        return "failure_slip", False, False
    if slip_mm > PARTIAL_SLIP_MM:
        return "failure_slip", False, False
    if slip_mm >= SUCCESS_SLIP_MM:
        return "partial", False, False
    stable = bool(sf_actual >= dist.SF_STABLE)
    return ("stable" if stable else "success"), True, stable


def _aborted(row: dict, rng: np.random.Generator, environment: str) -> dict[str, Any]:
    return {"aborted": True, "abort_reason": str(rng.choice(ABORT_REASONS)), "outcome": "aborted",
            "source": SOURCE, "environment": environment}


def _planned(predictions: dict) -> tuple[np.ndarray, np.ndarray]:
    points = np.array([[predictions[f"contact_{j}_{a}_mm"] for a in "xyz"] for j in (1, 2, 3)])
    normals = np.array([[predictions[f"normal_{j}_{a}"] for a in "xyz"] for j in (1, 2, 3)])
    return points * 1e-3, normals


# --------------------------------------------------------------------------------------------
# The trial
# --------------------------------------------------------------------------------------------
def virtual_trial(row: dict, predictions: dict, rng: np.random.Generator,
                  params: RigParams | None = None, belief_error: str = "paper") -> dict[str, Any]:
    """Execute one schedule row on the virtual rig and return its measured columns.

    Parameters
    ----------
    row : dict
        Schedule row (Test 2 or Test 3).
    predictions : dict
        :func:`graspcampaign.rig.plan.predict_trial` of the row (planned contacts and normals,
        commanded grip, believed friction).
    rng : numpy.random.Generator
        The trial's own random stream (pose error, force tracking, sensor noise). Both belief
        readings draw the pose error and the force-tracking errors first and in the same order,
        so one seed gives both the same execution up to the grip.
    params : RigParams, optional
    belief_error : {"paper", "none"}
        ``paper``: the grip of ``predictions`` is executed. ``none``: after the contacts are
        realised, the planner's grip is re-sized from the trial's *actual* quantities
        (:func:`graspcampaign.rig.belief.actual_belief`: realised contacts, true friction, law,
        creep and damage depth) and the returned dict also carries those prediction columns,
        replacing the pre-execution ones (believed G_geo, mu_s, SF then equal the actual ones).

    Returns
    -------
    dict
        ``aborted, abort_reason, source ("virtual"), environment, outcome, success, stable,
        slip_flag, drop_flag, damage_flag, contact_loss_flag, peak_slip_mm, mu_s_actual,
        g_geo_actual, sf_actual, normal_force_1_n..3, normal_force_mean_n, deformation_1_mm..3,
        deformation_mean_mm, max_indentation_mm, contact_point_error_mm`` and for Test 3
        ``threshold_measured_n, threshold_measured_nm, threshold_censored, first_finger_measured,
        rotation_at_limit_deg``. Aborted rows carry only the first four and ``outcome``.
        ``mu_s_actual`` is the true static friction of the contacted surface on the trial's day;
        ``g_geo_actual`` the G_geo of the realised contacts under it; ``sf_actual`` the §8.1 SF
        with that friction, the commanded grip and ``g_geo_actual``.
    """
    if belief_error not in rigbelief.BELIEF_ERRORS:
        raise ValueError(f"belief_error must be one of {', '.join(rigbelief.BELIEF_ERRORS)}, "
                         f"got {belief_error!r}")
    p = RigParams() if params is None else params
    seed = int(row.get("protocol_seed", 0))
    study = str(row.get("study", ""))
    environment = day_environment(seed, study, int(row.get("day", 1)))
    if bool(row.get("rig_fault", False)):
        return _aborted(row, rng, environment)
    spec = specimen_truth(seed, str(row["object_id"]), str(row["material"]),
                          int(row.get("object_index", 1)), str(row.get("friction_level", "natural")),
                          environment, p.coating_mu_rel)
    body = shape_body(str(row["shape"]))
    centroid = np.asarray(body.ctx.centroid)
    mass = float(row["mass_kg"])
    weight = mass * GRAVITY
    out: dict[str, Any] = {"aborted": False, "abort_reason": "", "source": SOURCE,
                           "environment": environment}

    # 2. Execution: pose error and achieved contacts.
    pose = num(row, "pose_err_mm", 0.0) * 1e-3
    azimuth = rng.uniform(0.0, 2.0 * math.pi)
    offset = np.array([pose * math.cos(azimuth), pose * math.sin(azimuth), 0.0])
    offset[:2] += p.pose_sd * rng.standard_normal(2)
    planned_points, planned_normals = _planned(predictions)
    points, normals, hit = realise_contacts(body.mesh, planned_points, planned_normals, offset)
    seen_normals = np.where(hit[:, None], normals, planned_normals)
    if belief_error == "none":  # the planner re-sizes its grip knowing the actual quantities
        actual = rigbelief.actual_belief(
            np.where(hit[:, None], points, planned_points), seen_normals, mu_s=spec.mu_s,
            k_n_per_mm_n=spec.k_n_per_mm_n, n=spec.n, rho=spec.rho, tau=spec.tau,
            damage_depth=spec.damage_depth, fingertip_radius=p.fingertip_radius)
        predictions = rigplan.predict_trial(row, belief=actual)
        out.update({k: v for k, v in predictions.items() if k != "plan_time_s"})
    grip = float(predictions["grip_force_n"])
    # a finger that misses the object achieves no contact: nothing of the grasp is left
    g_actual = float(dist.geometric_efficiency(seen_normals, spec.mu_s, p.kappa)) \
        if hit.all() else 0.0
    out.update(mu_s_actual=spec.mu_s, g_geo_actual=g_actual,
               sf_actual=float(dist.safety_factor(spec.mu_s, grip, g_actual, mass, p.a_lift,
                                                  p.kappa)))
    # 3. Forces: tracking error, load sharing.
    commanded = grip * np.exp(p.grip_tracking_rel * rng.standard_normal(3))
    forces = np.zeros(3)
    feasible = bool(hit.all()) and grip > 0.0
    if feasible:
        forces, feasible = dist.load_shared_forces(commanded, normals)
    test3 = "block" in row and str(row.get("block", "")) not in ("", "nan")
    if not feasible:
        errors = np.linalg.norm(np.where(hit[:, None], points - planned_points, 0.0), axis=1)
        out.update(_empty_measures(test3))
        out.update(contact_loss_flag=True, outcome="failure_contact_loss", success=False,
                   stable=False, contact_point_error_mm=float(errors.mean() * 1e3))
        return out
    forces = np.maximum(forces, 0.0)

    # 4. Budget and recorded safety factor.
    reach = np.sqrt(np.clip(1.0 - normals[:, 2] ** 2, 0.0, 1.0))
    budget_s = p.kappa * spec.mu_s * float(np.dot(forces, reach))
    budget_k = budget_s * spec.mu_k / spec.mu_s
    support = float(np.dot(forces, -normals[:, 2]))
    base = weight - support  # vertical demand on friction while held
    lift_demand = weight * (1.0 + p.a_lift / GRAVITY) - support
    sf_actual = out["sf_actual"]

    # 5. Lift and hold.
    v_lift = num(row, "lift_speed_mm_per_s", 30.0) * 1e-3
    t_lift = LIFT_HEIGHT_MM * 1e-3 / v_lift
    hold = num(row, "hold_s", 3.0)
    dropped = False
    slide = 0.0
    if lift_demand > budget_s:  # slips during the lift acceleration
        t_acc = v_lift / p.a_lift
        accel = (lift_demand - budget_k) / mass
        speed = accel * t_acc
        slide = 0.5 * accel * t_acc**2
        if budget_k <= base:  # kinetic friction cannot carry the weight: it slides until lost
            dropped = True
            slide = max(slide, p.drop_travel)
        else:
            slide += speed * speed * mass / (2.0 * (budget_k - base))
            dropped = slide > p.drop_travel
    capacity = budget_s / 3.0
    utilisation = min(max(base, 0.0) / budget_s, 1.0) if budget_s > 0 else 1.0
    micro = float(slip_statics.microslip(utilisation, capacity, spec.k_t))
    swing = 0.0
    sf_hold = budget_s / base if base > 0 else math.inf
    if not dropped and sf_hold >= 1.0:
        offset_com = np.linalg.norm(points.mean(axis=0)[:2] - centroid[:2])
        spread = float(np.linalg.norm(points[:, :2] - points.mean(axis=0)[:2], axis=1).mean())
        sustainable = spread * (sf_hold - 1.0) / 2.0
        swing = max(offset_com - sustainable, 0.0)
    slip = micro + swing + slide
    graded_slip = slip
    t_load = t_lift + hold

    # 7. Disturbance (Test 3).
    threshold_ok = True
    if test3 and not dropped:
        res = disturb(row, predictions, spec, p, points, normals, forces, centroid, mass,
                       budget_s, budget_k, base, rng)
        out.update(res["measures"])
        dropped = res["dropped"]
        slip = max(slip, micro + swing + res["travel"])
        graded_slip = max(graded_slip, micro + swing + res["graded_travel"])
        threshold_ok = res["threshold_ok"]
        t_load += res["duration"]
    elif test3:
        out.update(empty_measures())

    # 6. Damage: creep over the time under grip.
    creep = float(dist.creep_compliance(t_load, spec.rho, spec.tau))
    depths = dist.indentation_from_force(forces, spec.k_n_per_mm_n, spec.n, creep)
    hold_depths = dist.indentation_from_force(
        forces, spec.k_n_per_mm_n, spec.n,
        float(dist.creep_compliance(t_lift + hold, spec.rho, spec.tau)))
    # A fingertip sunk deeper than its own radius is buried in the specimen: no longer the contact
    # of Eq. 13 (issue 13, item 1), a measured damage event, and its patch is no vision reading.
    valid_geometry = bool(depths.max() <= p.fingertip_radius)
    beyond_damage_depth = bool(depths.max() > spec.damage_depth)
    damaged = beyond_damage_depth or not valid_geometry

    # 8. Sensors.
    steps = p.noise_steps
    measured_forces = [quantise(f, p.finger_force_resolution, rng, steps) for f in forces]
    deform = [max(float(d) + p.vision_noise * rng.standard_normal(), 0.0) * 1e3 for d in hold_depths]
    deform = [x if d <= p.fingertip_radius else math.nan for x, d in zip(deform, hold_depths,
                                                                       strict=True)]
    point_noise = p.contact_point_noise * rng.standard_normal((3, 3))
    cp_error = np.linalg.norm(points + offset - planned_points + point_noise, axis=1)
    # A lost object is tracked until it leaves the fingertips: the record stops at drop_travel.
    slip, graded_slip = min(slip, p.drop_travel), min(graded_slip, p.drop_travel)
    noise = p.vision_noise * rng.standard_normal()
    slip_mm = max(slip + noise, 0.0) * 1e3
    graded_mm = max(graded_slip + noise, 0.0) * 1e3
    outcome, success, stable = grade(contact_loss=False, dropped=dropped, damaged=damaged,
                                     slip_mm=graded_mm, sf_actual=sf_actual,
                                     threshold_ok=threshold_ok)
    unbounded = grade(contact_loss=False, dropped=dropped, damaged=beyond_damage_depth,
                      slip_mm=graded_mm, sf_actual=sf_actual, threshold_ok=threshold_ok)[1]
    readable = [x for x in deform if not math.isnan(x)]
    out.update({
        "outcome": outcome, "success": success, "stable": stable,
        "valid_geometry": valid_geometry, "success_unbounded": unbounded,
        "slip_flag": bool(graded_mm >= SUCCESS_SLIP_MM or not threshold_ok),
        "drop_flag": dropped, "damage_flag": damaged, "contact_loss_flag": False,
        "peak_slip_mm": round(slip_mm, 2),
        **{f"normal_force_{j + 1}_n": measured_forces[j] for j in range(3)},
        "normal_force_mean_n": float(np.mean(measured_forces)),
        **{f"deformation_{j + 1}_mm": round(deform[j], 3) for j in range(3)},
        "deformation_mean_mm": round(float(np.mean(readable)), 3) if readable else math.nan,
        "max_indentation_mm": round(float(depths.max() * 1e3), 3) if valid_geometry else math.nan,
        "contact_point_error_mm": round(float(cp_error.mean() * 1e3), 2),
    })
    return out


def _empty_measures(test3: bool) -> dict[str, Any]:
    """Measured columns of a trial whose fingers lost contact: no reading of a hold."""
    out: dict[str, Any] = {"success": False, "stable": False, "valid_geometry": True,
                           "success_unbounded": False, "slip_flag": False, "drop_flag": False,
                           "damage_flag": False, "peak_slip_mm": math.nan,
                           **{f"normal_force_{j}_n": math.nan for j in (1, 2, 3)},
                           "normal_force_mean_n": math.nan,
                           **{f"deformation_{j}_mm": math.nan for j in (1, 2, 3)},
                           "deformation_mean_mm": math.nan, "max_indentation_mm": math.nan}
    if test3:
        out.update(empty_measures())
    return out
