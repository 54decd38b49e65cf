"""Virtual rig for Tests 2-3: a documented stochastic physical model of one executed trial.

Without hardware, :func:`virtual_trial` produces the measured outcome columns of one schedule row
from the planner's predictions (:func:`graspcampaign.rig.plan.predict_trial`) and a
``numpy.random.Generator`` supplied by the caller. Every record carries ``source = "virtual"``:
these are model outputs, never hardware results.

The model, step by step (each constant's source is in :class:`RigParams` and docs/decisions.md):

1. **Specimen truth.** Each physical object's constants are drawn once, around its Table 4 family,
   by the Test 1 virtual bench's own :func:`graspcampaign.core.bench.draw_specimen` (modulus from
   Table 4 mean/SD, K scaled through Eq. 14's effective modulus, friction, k_t, rho, tau, cyclic
   damage), from a generator keyed by (protocol seed, object id) -- so all trials on an object
   see the same specimen. The day's ambient group (cool/dry, normal-lab, warm/humid) scales the
   natural friction as in §7.3. Coatings replace the surface friction by the coating's value with
   a per-object spread. The true damage depth follows the specimen's cyclic constants (§7.4).
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
7. **Disturbances (Test 3)** act on the same budget: lateral ramps and torsion ramps are pulled
   until slip (detected at 2 mm, released after a latency), vertical loads are ramped to their
   level, impulses and sinusoids are integrated in time.
8. **Sensors.** Finger forces at 5 mN, vision at 0.1 mm (multi-frame aggregates stored finer),
   load cell 0.01 N, torque 0.005 N m, each with noise of 1.5 resolution steps before rounding.
9. **Aborts.** A slot the schedule marks ``rig_fault`` aborts before load (§8.1, §9.1).

Grading (§8.1, exactly): measured failures override the safety factor -- contact loss, drop,
damage, slip beyond 12 mm (in this order of precedence for the primary class; every flag is also
recorded); otherwise peak slip < 2 mm is a success, promoted to *stable* when SF_actual >= 1.25;
2-12 mm is *partial* (a failure in the binary column). Test 3 threshold blocks (A, C) succeed
when the sustained threshold reaches the proof load and the object is retained.

References
----------
Paper §7.3-7.4, §8.1, §9.1-9.4, Table 4; SPEC §4. Johnson (1985) §7.2 (Mindlin); Findley, Lai &
Onaran (1976) §5.3 (standard linear solid creep); Moller & Trumbore (1997) (ray-triangle test).
"""

from __future__ import annotations

import functools
import hashlib
import logging
import math
from dataclasses import dataclass
from typing import Any

import numpy as np

from graspcampaign.core import bench
from graspcampaign.core import disturbance as dist
from graspcampaign.core.statics import GRAVITY
from graspcampaign.rig import plan as rigplan
from graspcampaign.rig.protocol import LIFT_HEIGHT_MM

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
ENVIRONMENT_PROBABILITIES = {"cool_dry": 0.25, "normal_lab": 0.5, "warm_humid": 0.25}
"""Ambient group of a campaign day (decision: the Test 1 groups, normal-lab twice as likely)."""
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
    """

    kappa: float = dist.KAPPA
    a_lift: float = dist.A_LIFT
    pose_sd: float = 1.0e-3
    grip_tracking_rel: float = 0.05
    coating_mu_rel: float = 0.10
    finger_force_resolution: float = 5.0e-3
    vision_resolution: float = 1.0e-4
    vision_noise: float = 1.0e-4
    contact_point_noise: float = 1.0e-3
    load_cell_resolution: float = 0.01
    torque_resolution: float = 0.005
    noise_steps: float = 1.5
    detection_slip: float = 2.0e-3
    release_latency: float = 0.05
    drop_travel: float = 25.0e-3
    observe: float = 1.0
    dt: float = 1.0e-3


# --------------------------------------------------------------------------------------------
# Specimens and environment
# --------------------------------------------------------------------------------------------
def _key_rng(*parts: object) -> np.random.Generator:
    digest = hashlib.sha256("|".join(map(str, parts)).encode()).digest()
    words = [int.from_bytes(digest[i:i + 4], "little") for i in range(0, 32, 4)]
    return np.random.default_rng(np.random.SeedSequence(words))


@functools.lru_cache(maxsize=256)
def day_environment(seed: int, study: str, day: int) -> str:
    """Return the ambient group of one campaign day (a draw keyed by seed, study and day)."""
    names = list(ENVIRONMENT_PROBABILITIES)
    rng = _key_rng("environment", seed, study, day)
    return str(rng.choice(names, p=list(ENVIRONMENT_PROBABILITIES.values())))


@dataclass(frozen=True)
class Specimen:
    """True constants of one object surface in one environment.

    Attributes
    ----------
    mu_s, mu_k : float
        True friction of the contacted surface.
    k_n_per_mm_n, n : float
        True Eq. 13 law.
    k_t : float
        Tangential stick stiffness [N/m].
    rho, tau : float
        Relaxation ratio and time constant [s].
    damage_depth : float
        True damage depth [m].
    environment : str
    """

    mu_s: float
    mu_k: float
    k_n_per_mm_n: float
    n: float
    k_t: float
    rho: float
    tau: float
    damage_depth: float
    environment: str


@functools.lru_cache(maxsize=1024)
def specimen_truth(seed: int, object_id: str, material: str, object_index: int,
                   friction_level: str, environment: str,
                   coating_mu_rel: float = RigParams.coating_mu_rel) -> Specimen:
    """Return the true constants of an object (the same for all its trials in one environment).

    Parameters
    ----------
    seed : int
        Protocol seed.
    object_id, material : str
    object_index : int
        Specimen number (recorded by the bench draw only).
    friction_level : str
        ``natural`` or a coating of :data:`graspcampaign.rig.plan.COATING_MU_S`.
    environment : str
        Ambient group of the trial's day (scales natural friction, §7.3).

    Returns
    -------
    Specimen
    """
    fam = bench.FAMILIES[material]
    spec = bench.draw_specimen(fam, object_index, "normal_lab", _key_rng("specimen", seed, object_id))
    spec = bench.with_environment(spec, environment)
    mu_s, mu_k = spec.mu_s, spec.mu_k
    if friction_level != "natural":
        z = _key_rng("coating", seed, object_id, friction_level).standard_normal()
        mu_s = rigplan.COATING_MU_S[friction_level] * math.exp(coating_mu_rel * z)
        mu_k = mu_s * spec.mu_k / spec.mu_s
    depth = rigplan.family_damage_depth(fam, spec.softening_ref / fam.softening_ref)
    return Specimen(mu_s=mu_s, mu_k=mu_k, k_n_per_mm_n=spec.k_n_per_mm_n, n=spec.n, k_t=spec.k_t,
                    rho=spec.rho, tau=spec.tau, damage_depth=depth, environment=environment)


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
# Sliding on the shared budget
# --------------------------------------------------------------------------------------------
@dataclass(frozen=True)
class _Slide:
    travel: float  # peak displacement [m]
    dropped: bool
    onset_time: float  # first time the budget was exceeded [s], nan if never


def _slide(times: np.ndarray, lateral: np.ndarray, vertical: np.ndarray, budget_s: float,
           budget_k: float, mass: float, drop_travel: float, settle_demand: float) -> _Slide:
    """Integrate 2-D Coulomb sliding of the object relative to the hand (semi-implicit Euler).

    ``lateral`` and ``vertical`` (down positive) are the demand on the friction budget [N];
    sticking while the demand lies inside ``budget_s``, sliding against ``budget_k``. After the
    last sample, a still-sliding object re-sticks if ``budget_k`` exceeds ``settle_demand``
    (stopping distance v^2 / 2a added), otherwise it is lost.
    """
    x = np.zeros(2)
    v = np.zeros(2)
    peak = 0.0
    onset = math.nan
    sliding = False
    dt = times[1] - times[0] if len(times) > 1 else 1e-3
    for i in range(len(times)):
        demand = np.array([lateral[i], vertical[i]])
        size = math.hypot(*demand)
        if not sliding:
            if size <= budget_s:
                continue
            sliding = True
            if math.isnan(onset):
                onset = float(times[i])
        speed = math.hypot(*v)
        direction = v / speed if speed > 1e-12 else demand / max(size, 1e-300)
        a = (demand - budget_k * direction) / mass
        v_new = v + a * dt
        if speed > 1e-12 and float(np.dot(v_new, v)) <= 0.0 and size <= budget_s:
            v[:] = 0.0
            sliding = False
            continue
        v = v_new
        x = x + v * dt
        peak = max(peak, math.hypot(*x))
        if x[1] > drop_travel:
            return _Slide(peak, True, onset)
    if sliding:
        speed = math.hypot(*v)
        if budget_k <= settle_demand:
            return _Slide(max(peak, drop_travel), True, onset)
        peak += speed * speed * mass / (2.0 * (budget_k - settle_demand))
    return _Slide(peak, peak > drop_travel, onset)


def _ramp_to_slip(rate: float, cap: float, threshold: float, budget_s: float, budget_k: float,
                  base: float, mass: float, p: RigParams) -> tuple[float, float, bool, float]:
    """Quasi-static ramp until slip, detection at 2 mm, release after the latency.

    Returns ``(measured_threshold, slip_travel, dropped, duration)``; a threshold above the cap
    returns ``(cap, 0, False, cap / rate)`` (censored by the caller).
    """
    if threshold > cap:
        return cap, 0.0, False, cap / rate
    excess = max(budget_s - budget_k, 1e-9)
    accel = excess / mass  # the demand stays at the budget while the ramp continues
    t_detect = math.sqrt(2.0 * p.detection_slip / accel)
    measured = threshold + rate * t_detect
    t_total = t_detect + p.release_latency
    speed = accel * t_total
    travel = 0.5 * accel * t_total**2
    if budget_k <= base:  # the kinetic budget cannot even carry the weight: lost after release
        return measured, max(travel, p.drop_travel), True, threshold / rate + t_total
    travel += speed * speed * mass / (2.0 * (budget_k - base))
    return measured, travel, travel > p.drop_travel, threshold / rate + t_total


def _quantise(value: float, step: float, rng: np.random.Generator, steps: float,
              floor: float | None = None) -> float:
    noisy = value + steps * step * rng.standard_normal()
    if floor is not None:
        noisy = max(noisy, floor)
    return float(np.round(noisy / step) * step)


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


def _num(row: dict, key: str, default: float = math.nan) -> float:
    try:
        return float(row.get(key, default))
    except (TypeError, ValueError):
        return default


def _planned(predictions: dict) -> tuple[np.ndarray, np.ndarray]:
    points = np.array([[predictions[f"contact_{j}_{a}_mm"] for a in "xyz"] for j in (1, 2, 3)])
    normals = np.array([[predictions[f"normal_{j}_{a}"] for a in "xyz"] for j in (1, 2, 3)])
    return points * 1e-3, normals


# --------------------------------------------------------------------------------------------
# The trial
# --------------------------------------------------------------------------------------------
def virtual_trial(row: dict, predictions: dict, rng: np.random.Generator,
                  params: RigParams | None = None) -> dict[str, Any]:
    """Execute one schedule row on the virtual rig and return its measured columns.

    Parameters
    ----------
    row : dict
        Schedule row (Test 2 or Test 3).
    predictions : dict
        :func:`graspcampaign.rig.plan.predict_trial` of the row (planned contacts, believed
        normals, grip, believed friction).
    rng : numpy.random.Generator
        The trial's own random stream (pose error, force tracking, sensor noise).
    params : RigParams, optional

    Returns
    -------
    dict
        ``aborted, abort_reason, source ("virtual"), environment, outcome, success, stable,
        slip_flag, drop_flag, damage_flag, contact_loss_flag, peak_slip_mm, sf_actual,
        g_geo_actual, normal_force_1_n..3, normal_force_mean_n, deformation_1_mm..3,
        deformation_mean_mm, max_indentation_mm, contact_point_error_mm`` and for Test 3
        ``threshold_measured_n, threshold_measured_nm, threshold_censored, first_finger_measured,
        rotation_at_limit_deg``. Aborted rows carry only the first four and ``outcome``.
    """
    p = RigParams() if params is None else params
    seed = int(row.get("protocol_seed", 0))
    study = str(row.get("study", ""))
    environment = day_environment(seed, study, int(row.get("day", 1)))
    if bool(row.get("rig_fault", False)):
        return _aborted(row, rng, environment)
    spec = specimen_truth(seed, str(row["object_id"]), str(row["material"]),
                          int(row.get("object_index", 1)), str(row.get("friction_level", "natural")),
                          environment, p.coating_mu_rel)
    body = rigplan._shape_body(str(row["shape"]))
    centroid = np.asarray(body.ctx.centroid)
    mass = float(row["mass_kg"])
    weight = mass * GRAVITY
    grip = float(predictions["grip_force_n"])
    out: dict[str, Any] = {"aborted": False, "abort_reason": "", "source": SOURCE,
                           "environment": environment}

    # 2. Execution: pose error and achieved contacts.
    pose = _num(row, "pose_err_mm", 0.0) * 1e-3
    azimuth = rng.uniform(0.0, 2.0 * math.pi)
    offset = np.array([pose * math.cos(azimuth), pose * math.sin(azimuth), 0.0])
    offset[:2] += p.pose_sd * rng.standard_normal(2)
    planned_points, planned_normals = _planned(predictions)
    points, normals, hit = realise_contacts(body.mesh, planned_points, planned_normals, offset)
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
                   stable=False, g_geo_actual=float(dist.geometric_efficiency(
                       np.where(hit[:, None], normals, planned_normals))),
                   sf_actual=0.0, contact_point_error_mm=float(errors.mean() * 1e3))
        return out
    forces = np.maximum(forces, 0.0)

    # 4. Budget and recorded safety factor.
    reach = np.sqrt(np.clip(1.0 - normals[:, 2] ** 2, 0.0, 1.0))
    budget_s = p.kappa * spec.mu_s * float(np.dot(forces, reach))
    budget_k = budget_s * spec.mu_k / spec.mu_s
    support = float(np.dot(forces, -normals[:, 2]))
    base = weight - support  # vertical demand on friction while held
    lift_demand = weight * (1.0 + p.a_lift / GRAVITY) - support
    g_actual = float(dist.geometric_efficiency(normals))
    sf_actual = float(dist.safety_factor(float(predictions["mu_s_believed"]), grip, g_actual, mass,
                                         p.a_lift, p.kappa))
    out["g_geo_actual"] = g_actual
    out["sf_actual"] = sf_actual

    # 5. Lift and hold.
    v_lift = _num(row, "lift_speed_mm_per_s", 30.0) * 1e-3
    t_lift = LIFT_HEIGHT_MM * 1e-3 / v_lift
    hold = _num(row, "hold_s", 3.0)
    dropped = False
    slide = 0.0
    if lift_demand > budget_s:  # slips during the lift acceleration
        t_acc = v_lift / p.a_lift
        accel = (lift_demand - budget_k) / mass
        speed = accel * t_acc
        slide = 0.5 * accel * t_acc**2
        if budget_k <= base:
            dropped = True
        else:
            slide += speed * speed * mass / (2.0 * (budget_k - base))
            dropped = slide > p.drop_travel
    capacity = budget_s / 3.0
    utilisation = min(max(base, 0.0) / budget_s, 1.0) if budget_s > 0 else 1.0
    micro = float(dist.microslip(utilisation, capacity, spec.k_t))
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
        res = _disturb(row, predictions, spec, p, points, normals, forces, centroid, mass,
                       budget_s, budget_k, base, rng)
        out.update(res["measures"])
        dropped = res["dropped"]
        slip = max(slip, micro + swing + res["travel"])
        graded_slip = max(graded_slip, micro + swing + res["graded_travel"])
        threshold_ok = res["threshold_ok"]
        t_load += res["duration"]
    elif test3:
        out.update(_empty_measures(True, contact=False))

    # 6. Damage: creep over the time under grip.
    creep = float(dist.creep_compliance(t_load, spec.rho, spec.tau))
    depths = dist.indentation_from_force(forces, spec.k_n_per_mm_n, spec.n, creep)
    hold_depths = dist.indentation_from_force(
        forces, spec.k_n_per_mm_n, spec.n,
        float(dist.creep_compliance(t_lift + hold, spec.rho, spec.tau)))
    damaged = bool(depths.max() > spec.damage_depth)

    # 8. Sensors.
    steps = p.noise_steps
    measured_forces = [_quantise(f, p.finger_force_resolution, rng, steps) for f in forces]
    deform = [max(float(d) + p.vision_noise * rng.standard_normal(), 0.0) * 1e3 for d in hold_depths]
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
    out.update({
        "outcome": outcome, "success": success, "stable": stable,
        "slip_flag": bool(graded_mm >= SUCCESS_SLIP_MM or not threshold_ok),
        "drop_flag": dropped, "damage_flag": damaged, "contact_loss_flag": False,
        "peak_slip_mm": round(slip_mm, 2),
        **{f"normal_force_{j + 1}_n": measured_forces[j] for j in range(3)},
        "normal_force_mean_n": float(np.mean(measured_forces)),
        **{f"deformation_{j + 1}_mm": round(deform[j], 3) for j in range(3)},
        "deformation_mean_mm": round(float(np.mean(deform)), 3),
        "max_indentation_mm": round(float(depths.max() * 1e3), 3),
        "contact_point_error_mm": round(float(cp_error.mean() * 1e3), 2),
    })
    return out


def _empty_measures(test3: bool, contact: bool = True) -> dict[str, Any]:
    out: dict[str, Any] = {}
    if contact:
        out.update({"success": False, "stable": False, "slip_flag": False, "drop_flag": False,
                    "damage_flag": False, "peak_slip_mm": math.nan,
                    **{f"normal_force_{j}_n": math.nan for j in (1, 2, 3)},
                    "normal_force_mean_n": math.nan,
                    **{f"deformation_{j}_mm": math.nan for j in (1, 2, 3)},
                    "deformation_mean_mm": math.nan, "max_indentation_mm": math.nan})
    if test3:
        out.update({"threshold_measured_n": math.nan, "threshold_measured_nm": math.nan,
                    "threshold_censored": False, "first_finger_measured": 0,
                    "rotation_at_limit_deg": math.nan})
    return out


def _disturb(row, predictions, spec: Specimen, p: RigParams, points, normals, forces, centroid,
             mass, budget_s, budget_k, base, rng) -> dict[str, Any]:
    """Apply the row's Test 3 disturbance to a held grasp; return measures and events."""
    block = str(row["block"])
    kind = str(row["disturbance_kind"])
    direction = _num(row, "direction_deg", 0.0)
    measures = _empty_measures(True, contact=False)
    travel, dropped, threshold_ok, duration = 0.0, False, True, 0.0
    first = dist.first_slip_finger(points, normals, forces, centroid, mass, spec.mu_s, kind,
                                   direction, p.kappa)
    base_pos = max(base, 0.0)
    budget_s = max(budget_s, 1e-12)  # guards the ratios below; a zero budget never holds
    lateral_limit = math.sqrt(max(budget_s**2 - base_pos**2, 0.0))
    if block == "A":
        rate, cap = _num(row, "ramp_rate_n_per_s"), _num(row, "ramp_cap_n", 15.0)
        measured, travel, dropped, duration = _ramp_to_slip(rate, cap, lateral_limit, budget_s,
                                                            budget_k, base, mass, p)
        censored = lateral_limit > cap
        measured = _quantise(measured, p.load_cell_resolution, rng, p.noise_steps, 0.0)
        measures.update(threshold_measured_n=measured, threshold_censored=censored,
                        first_finger_measured=0 if censored else first)
        threshold_ok = measured >= _num(row, "proof_force_n")
    elif block == "C":
        r_eff = max(dist.effective_radius(points, centroid), 1e-6)
        rate, cap = _num(row, "torque_ramp_nm_per_s"), _num(row, "torque_cap_nm", 1.0)
        measured, travel, dropped, duration = _ramp_to_slip(
            rate / r_eff, cap / r_eff, lateral_limit, budget_s, budget_k, base, mass, p)
        censored = lateral_limit > cap / r_eff
        torque = _quantise(measured * r_eff, p.torque_resolution, rng, p.noise_steps, 0.0)
        pad = float(dist.microslip(1.0, budget_s / 3.0, spec.k_t))
        rotation = math.degrees((pad + (0.0 if censored else p.detection_slip)) / r_eff)
        measures.update(threshold_measured_nm=torque, threshold_censored=censored,
                        first_finger_measured=0 if censored else first,
                        rotation_at_limit_deg=round(rotation + 0.1 * rng.standard_normal(), 2))
        threshold_ok = torque >= _num(row, "proof_torque_nm")
    elif block == "B":
        load = _num(row, "load_n")
        rate = _num(row, "ramp_rate_n_per_s", 0.5)
        sign = 1.0 if kind == "down" else -1.0
        demand = base + sign * load
        duration = load / rate + _num(row, "hold_s", 3.0)
        if abs(demand) <= budget_s:
            travel = float(dist.microslip(abs(demand) / budget_s, budget_s / 3.0, spec.k_t))
            measures.update(threshold_measured_n=_quantise(load, p.load_cell_resolution, rng,
                                                           p.noise_steps, 0.0),
                            threshold_censored=True, first_finger_measured=0)
        else:
            onset = budget_s - base if kind == "down" else budget_s + base
            measured, travel, dropped, _ = _ramp_to_slip(rate, load, onset, budget_s, budget_k,
                                                         base, mass, p)
            measures.update(threshold_measured_n=_quantise(measured, p.load_cell_resolution, rng,
                                                           p.noise_steps, 0.0),
                            threshold_censored=False, first_finger_measured=first)
    elif block in ("D", "E"):
        if block == "D":
            width = _num(row, "pulse_duration_ms") * 1e-3
            duration = _num(row, "duration_s", width + p.observe)
            times = np.arange(0.0, width + p.observe, p.dt)
            lateral = np.where(times <= width,
                               0.5 * _num(row, "load_n") * (1.0 - np.cos(2 * np.pi * times / width)),
                               0.0)
        else:
            duration = _num(row, "duration_s", 5.0)
            times = np.arange(0.0, duration, p.dt)
            lateral = _num(row, "amplitude_n") * np.sin(2 * np.pi * _num(row, "frequency_hz") * times)
        peak = float(np.abs(lateral).max())
        if peak <= lateral_limit:
            travel = float(dist.microslip(math.hypot(peak, base_pos) / budget_s, budget_s / 3.0,
                                          spec.k_t))
        else:
            res = _slide(times, lateral, np.full_like(times, base), budget_s, budget_k, mass,
                         p.drop_travel, base)
            travel, dropped = res.travel, res.dropped
            measures.update(first_finger_measured=first)
    # Threshold blocks are graded at their proof load: the slip of the threshold search beyond it
    # is a measurement, not a failure.
    graded = travel if block not in ("A", "C") or not threshold_ok else 0.0
    return {"measures": measures, "travel": travel, "graded_travel": graded, "dropped": dropped,
            "threshold_ok": threshold_ok, "duration": duration}

