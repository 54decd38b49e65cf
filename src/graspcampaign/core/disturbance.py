"""Disturbance statics and grip sizing of the hardware campaigns (paper §8.1, §9.1; SPEC §2.10).

A three-finger grasp with per-finger grip ``F_grip`` holds a single friction budget; the safety
factor compares it with the lifted weight including the inertial term,

    SF = 3 mu_s F_grip G_geo kappa / (W (1 + a_lift / g)),        kappa = 2.4 (frozen, §8.1),

and the budget ``SF W`` is shared between the weight and a disturbance, which gives the predicted
limits ``F_lat = W sqrt(SF^2 - 1)``, ``F_down = W (SF - 1)`` and ``T = W sqrt(SF^2 - 1) r_eff``
(§9.1). Everything here is closed-form statics on a contact set; no dynamics.

Geometric efficiency ``G_geo`` (our definition; SPEC §2.10 asks for one):

    G_geo = beta * (1/3) sum_j sqrt(1 - n_z,j^2),
    beta  = 1 - |sum_j h_j| / sum_j |h_j|,     h_j = horizontal part of the outward normal n_j.

The mean term is the vertical reach of each contact's friction: a finger pressing along ``-n_j``
can only pull the object up with friction that lies in its tangent plane, whose largest vertical
component is ``mu f_n sqrt(1 - n_z^2)``; it is 1 for three horizontal normals and falls to 0 as the
normals turn vertical. ``beta`` is 1 when the horizontal squeeze balances itself (the grip does
not push the object sideways) and 0 when all three fingers push the same way. So ``G_geo`` lies in
[0, 1], equal to 1 exactly for three horizontal, self-balancing normals.

Shape letters: ``c = 3`` contacts; leading batch axes broadcast where stated.

References
----------
Paper §8.1 (SF, kappa, G_geo, grip sizing from believed quality, tau_F = 0.0886 N), §9.1 (shared
friction budget and the three limits), §7.4 (damage depth), Table 4 (constants).
Johnson, K. L. (1985), Contact Mechanics, §7.2 (Mindlin partial slip, Eq. 7.42).
Fung, Y. C. (1981), Biomechanics, ch. 7 (quasi-linear viscoelasticity); Findley, Lai & Onaran
(1976), Creep and Relaxation of Nonlinear Viscoelastic Materials, §5.3 (standard linear solid:
relaxation ratio rho, time constant tau <-> creep time constant tau / rho).
Murray, Li & Sastry (1994), A Mathematical Introduction to Robotic Manipulation, §5.2 (contact
wrenches, grasp statics).
"""

from __future__ import annotations

import logging
from dataclasses import dataclass

import numpy as np

from graspcampaign.core.contact import depth_for_force, normal_force
from graspcampaign.core.statics import GRAVITY

__all__ = [
    "A_LIFT",
    "KAPPA",
    "SF_STABLE",
    "SF_TARGET",
    "TAU_F_HARDWARE",
    "DisturbanceLimits",
    "GripSizing",
    "contact_tangential_forces",
    "creep_compliance",
    "disturbance_limits",
    "disturbance_wrench",
    "effective_radius",
    "first_slip_finger",
    "force_at_indentation",
    "geometric_efficiency",
    "grip_for_safety_factor",
    "indentation_from_force",
    "load_shared_forces",
    "microslip",
    "retention_margin",
    "safety_factor",
    "size_grip",
    "slip_load_factors",
]

logger = logging.getLogger(__name__)

KAPPA = 2.4
"""Finger-pad friction-enhancement factor, calibrated once from Test 1 and frozen (§8.1)."""
TAU_F_HARDWARE = 0.0886
"""Residual tolerance of the pre-execution ``predicted_stable`` flag [N] (§8.1, exact value)."""
SF_STABLE = 1.25
"""A non-failure trial is *stable* when SF_actual reaches this (§8.1)."""
SF_TARGET = 1.5
"""Target safety factor of grip sizing (decision, docs/decisions.md: the classical 1.5 design
margin on a friction hold; §8.1 leaves the target unpublished)."""
A_LIFT = 0.3
"""Peak lift acceleration of the trapezoidal lift profile [m/s^2] (decision: the 300 mm/s^2 of the
rig actuators, §7.1, the only acceleration the paper states)."""

DISTURBANCE_KINDS = ("none", "lateral", "down", "up", "yaw")


# --------------------------------------------------------------------------------------------
# Geometry of the contact set
# --------------------------------------------------------------------------------------------
def _normals(normals) -> np.ndarray:
    normals = np.asarray(normals, dtype=float)
    if normals.shape[-2:] != (3, 3):
        raise ValueError(f"normals must have shape (..., 3, 3), got {normals.shape}")
    return normals / np.linalg.norm(normals, axis=-1, keepdims=True)


def geometric_efficiency(normals) -> np.ndarray | float:
    """Return G_geo of contact sets (module docstring).

    Parameters
    ----------
    normals : (..., 3, 3) float
        Outward unit contact normals ``n_out`` of the three contacts.

    Returns
    -------
    g_geo : (...) float
        In [0, 1]; 1 for three horizontal self-balancing normals.
    """
    n = _normals(normals)
    reach = np.sqrt(np.clip(1.0 - n[..., 2] ** 2, 0.0, 1.0))  # (..., 3)
    horizontal = n[..., :2]
    total = np.linalg.norm(horizontal, axis=-1).sum(axis=-1)
    net = np.linalg.norm(horizontal.sum(axis=-2), axis=-1)
    with np.errstate(invalid="ignore", divide="ignore"):
        beta = np.where(total > 1e-12, 1.0 - net / np.maximum(total, 1e-300), 0.0)
    g = np.clip(beta, 0.0, 1.0) * reach.mean(axis=-1)
    return float(g) if np.ndim(g) == 0 else g


def effective_radius(points, centroid) -> float:
    """Return r_eff: mean horizontal distance of the contacts from the vertical axis [m].

    Parameters
    ----------
    points : (3, 3) float
        Contact points [m].
    centroid : (3,) float
        Object centroid [m]; the yaw axis is the vertical through it.

    Returns
    -------
    r_eff : float
        The lever arm at which the shared friction budget resists a yaw torque (§9.1).
    """
    d = np.asarray(points, dtype=float)[:, :2] - np.asarray(centroid, dtype=float)[:2]
    return float(np.linalg.norm(d, axis=1).mean())


# --------------------------------------------------------------------------------------------
# Safety factor, grip sizing and predicted limits
# --------------------------------------------------------------------------------------------
def safety_factor(mu_s, grip_force, g_geo, mass, a_lift=A_LIFT, kappa=KAPPA, g=GRAVITY):
    """Return ``SF = 3 mu_s F_grip G_geo kappa / (W (1 + a_lift/g))`` (§8.1).

    Parameters
    ----------
    mu_s : float or (...) float
        Static friction coefficient [-].
    grip_force : float or (...) float
        Commanded grip per finger [N].
    g_geo : float or (...) float
        Geometric efficiency [-].
    mass : float or (...) float
        Object mass [kg].
    a_lift : float
        Lift acceleration [m/s^2].
    kappa : float
        Friction-enhancement factor [-].

    Returns
    -------
    sf : float or (...) float
    """
    weight = np.asarray(mass, dtype=float) * g * (1.0 + a_lift / g)
    return 3.0 * np.asarray(mu_s) * np.asarray(grip_force) * np.asarray(g_geo) * kappa / weight


def grip_for_safety_factor(target_sf, mu_s, g_geo, mass, a_lift=A_LIFT, kappa=KAPPA, g=GRAVITY):
    """Return the per-finger grip [N] that reaches ``target_sf`` (inverse of :func:`safety_factor`).

    ``inf`` when ``mu_s G_geo = 0`` (no friction reach: no grip suffices).
    """
    weight = np.asarray(mass, dtype=float) * g * (1.0 + a_lift / g)
    denom = 3.0 * np.asarray(mu_s) * np.asarray(g_geo) * kappa
    with np.errstate(divide="ignore"):
        return np.where(denom > 0.0, target_sf * weight / np.maximum(denom, 1e-300), np.inf)


def creep_compliance(t, rho, tau):
    """Return the normalised creep compliance ``J(t)`` of a standard linear solid.

    Parameters
    ----------
    t : float or (...) float
        Time under constant force [s].
    rho : float
        Steady relaxation ratio ``F_inf / F_0`` of the hold-relaxation test (Table 4) [-].
    tau : float
        Relaxation time constant [s] (Table 4).

    Returns
    -------
    j : float or (...) float
        ``1/rho - (1/rho - 1) exp(-rho t / tau)``: 1 at t = 0, ``1/rho`` as t grows. Under QLV the
        elastic force ``K delta^n`` at constant applied force ``F`` is ``F J(t)``.

    References
    ----------
    Findley, Lai & Onaran (1976) §5.3; Fung (1981) ch. 7.
    """
    t = np.asarray(t, dtype=float)
    return 1.0 / rho - (1.0 / rho - 1.0) * np.exp(-rho * np.maximum(t, 0.0) / tau)


def indentation_from_force(force, k_n_per_mm_n, n, creep=1.0):
    """Return the indentation [m] at which ``K delta_mm^n = force * creep`` (Eq. 13, static).

    Parameters
    ----------
    force : float or (...) float
        Normal force [N]; non-positive forces give zero indentation.
    k_n_per_mm_n : float
        K [N mm^-n].
    n : float
        Exponent [-].
    creep : float or (...) float
        Creep compliance factor ``J(t)`` (1 = instantaneous).
    """
    return depth_for_force(np.asarray(force, dtype=float) * creep, k_n_per_mm_n, n)


def force_at_indentation(depth, k_n_per_mm_n, n, creep=1.0):
    """Return the constant force [N] whose indentation reaches ``depth`` [m] after creep ``J``."""
    return normal_force(depth, 0.0, k_n_per_mm_n, n, 0.0) / creep


@dataclass(frozen=True)
class GripSizing:
    """Grip chosen by a planner from its believed quality.

    Attributes
    ----------
    grip_force : float
        Commanded grip per finger [N] (``min(needed, cap)``).
    needed_force : float
        Grip that reaches the target SF under the planner's belief [N] (inf when G mu = 0).
    cap_force : float
        Grip whose (believed) indentation after the hold reaches the cap depth [N].
    capped : bool
        The damage cap binds.
    sf_predicted : float
        Believed SF at ``grip_force``.
    depth : float
        Believed indentation of the most loaded finger at the end of the hold [m].
    """

    grip_force: float
    needed_force: float
    cap_force: float
    capped: bool
    sf_predicted: float
    depth: float


def size_grip(*, mu_s: float, g_geo: float, mass: float, k_n_per_mm_n: float, n: float,
              cap_depth: float, creep: float = 1.0, max_share: float = 1.0,
              target_sf: float = SF_TARGET, a_lift: float = A_LIFT,
              kappa: float = KAPPA) -> GripSizing:
    """Size the grip to a target SF, capped at the grip that reaches the damage depth (§8.1).

    Parameters
    ----------
    mu_s, g_geo, mass : float
        The planner's believed friction, geometric efficiency and the object mass [-, -, kg].
    k_n_per_mm_n, n : float
        The planner's believed contact law (Eq. 13).
    cap_depth : float
        Indentation not to exceed [m] (the material's damage depth, possibly with a margin).
    creep : float
        ``J(t_hold)`` the planner expects over the hold (1 when it models no creep).
    max_share : float
        Largest finger force per unit commanded grip after load sharing
        (:func:`load_shared_forces` of ones); the cap keeps *that* finger within ``cap_depth``.
    target_sf : float
        Target safety factor.

    Returns
    -------
    GripSizing
    """
    needed = float(grip_for_safety_factor(target_sf, mu_s, g_geo, mass, a_lift, kappa))
    if not max_share > 0.0:
        raise ValueError(f"max_share must be positive, got {max_share!r}")
    cap = float(force_at_indentation(cap_depth, k_n_per_mm_n, n, creep)) / max_share
    grip = min(needed, cap)
    sf = float(safety_factor(mu_s, grip, g_geo, mass, a_lift, kappa))
    depth = float(indentation_from_force(grip * max_share, k_n_per_mm_n, n, creep))
    return GripSizing(grip_force=grip, needed_force=needed, cap_force=cap, capped=bool(cap < needed),
                      sf_predicted=sf, depth=depth)


@dataclass(frozen=True)
class DisturbanceLimits:
    """Predicted sustainable disturbances (§9.1); NaN below SF = 1 for the square-root forms."""

    lateral_force: float
    down_force: float
    yaw_torque: float


def disturbance_limits(sf: float, weight: float, r_eff: float) -> DisturbanceLimits:
    """Return ``F_lat = W sqrt(SF^2-1)``, ``F_down = W (SF-1)``, ``T = W sqrt(SF^2-1) r_eff``.

    Parameters
    ----------
    sf : float
        Safety factor [-].
    weight : float
        Object weight W [N] (the static weight, without the lift term).
    r_eff : float
        Effective yaw lever [m].

    Returns
    -------
    DisturbanceLimits
        Below SF = 1 the grasp cannot hold its own weight: every limit is 0 (nothing sustainable).
    """
    if not sf >= 1.0:
        return DisturbanceLimits(0.0, 0.0, 0.0)
    root = weight * np.sqrt(sf * sf - 1.0)
    return DisturbanceLimits(float(root), float(weight * (sf - 1.0)), float(root * r_eff))


def retention_margin(sf: float, weight: float, r_eff: float, kind: str, level: float) -> float:
    """Return the believed retention margin under a commanded disturbance (§9.5).

    Parameters
    ----------
    sf : float
        Believed safety factor.
    weight : float
        W [N].
    r_eff : float
        Yaw lever [m].
    kind : {"none", "lateral", "down", "up", "yaw"}
        Disturbance family.
    level : float
        Commanded magnitude: force [N] (lateral, down, up) or torque [N m] (yaw).

    Returns
    -------
    margin : float
        Sustainable / commanded with the shared budget: ``F_lat/level``, ``F_down/level``,
        ``T/level``; for ``up`` the budget ``SF W`` over the remaining demand ``|W - level|``;
        for ``none`` the SF itself. The retention flag is ``margin > 1``.
    """
    if kind not in DISTURBANCE_KINDS:
        raise ValueError(f"kind must be one of {DISTURBANCE_KINDS}, got {kind!r}")
    if kind == "none" or level <= 0.0:
        return float(sf)
    limits = disturbance_limits(sf, weight, r_eff)
    if kind == "lateral":
        return limits.lateral_force / level
    if kind == "down":
        return limits.down_force / level
    if kind == "yaw":
        return limits.yaw_torque / level
    demand = abs(weight - level)
    return float(np.inf) if demand == 0.0 else float(sf * weight / demand)


# --------------------------------------------------------------------------------------------
# Contact-level statics: load sharing, tangential forces, first finger to slip
# --------------------------------------------------------------------------------------------
def load_shared_forces(commanded, normals) -> tuple[np.ndarray, bool]:
    """Return the per-finger normal forces closest to the commands that balance horizontally.

    Parameters
    ----------
    commanded : (3,) float
        Commanded normal force of each finger [N].
    normals : (3, 3) float
        Outward unit normals.

    Returns
    -------
    forces : (3,) float
        ``f = c - A^T (A A^T)^+ A c`` with ``A`` the 2 x 3 matrix of horizontal force directions
        ``-h_j``: the least-squares correction of the commands under which the squeeze exerts no
        net horizontal force on the object (the object shifts in the hand until the fingers'
        forces balance).
    feasible : bool
        False when balance needs a non-positive finger force: that finger loses contact.
    """
    c = np.asarray(commanded, dtype=float).reshape(3)
    a = -_normals(normals)[:, :2].T  # (2, 3)
    f = c - a.T @ (np.linalg.pinv(a @ a.T) @ (a @ c))
    return f, bool(np.all(f > 1e-9))


def _tangent_bases(normals: np.ndarray) -> np.ndarray:
    """Return (3, 3, 2) orthonormal tangent bases; the first tangent points as far up as possible."""
    z = np.array([0.0, 0.0, 1.0])
    bases = np.empty((3, 3, 2))
    for j, nj in enumerate(normals):
        up = z - nj[2] * nj
        if np.linalg.norm(up) < 1e-9:  # vertical normal: any horizontal pair
            up = np.array([1.0, 0.0, 0.0]) - nj[0] * nj
        t1 = up / np.linalg.norm(up)
        bases[j, :, 0] = t1
        bases[j, :, 1] = np.cross(nj, t1)
    return bases


def contact_tangential_forces(points, normals, normal_forces, centroid, force, moment):
    """Solve the determinate statics of three contacts with given normal forces.

    Parameters
    ----------
    points : (3, 3) float
        Contact points [m].
    normals : (3, 3) float
        Outward unit normals.
    normal_forces : (3,) float
        Normal force of each finger [N] (applied along ``-n``).
    centroid : (3,) float
        Reference point of the moments (object centre of mass) [m].
    force : (3,) float
        External force on the object other than the contacts, incl. weight [N].
    moment : (3,) float
        External moment about ``centroid`` [N m].

    Returns
    -------
    tangential : (3, 3) float
        Tangential (friction) force of each contact [N]: the unique in-plane forces (6 unknowns)
        that satisfy force and moment balance (6 equations); least-norm when the 6 x 6 system is
        singular.

    References
    ----------
    Murray, Li & Sastry (1994) §5.2.
    """
    p = np.asarray(points, dtype=float) - np.asarray(centroid, dtype=float)
    n = _normals(normals)
    fn = np.asarray(normal_forces, dtype=float).reshape(3)
    bases = _tangent_bases(n)
    a = np.zeros((6, 6))
    for j in range(3):
        for k in range(2):
            t = bases[j, :, k]
            a[:3, 2 * j + k] = t
            a[3:, 2 * j + k] = np.cross(p[j], t)
    normal_vectors = -fn[:, None] * n
    rhs = np.concatenate([
        -(normal_vectors.sum(axis=0) + np.asarray(force, dtype=float)),
        -(np.cross(p, normal_vectors).sum(axis=0) + np.asarray(moment, dtype=float)),
    ])
    x = np.linalg.lstsq(a, rhs, rcond=None)[0]
    return np.einsum("jik,jk->ji", bases, x.reshape(3, 2))


def disturbance_wrench(kind: str, level: float, direction_deg: float = 0.0):
    """Return the external (force [N], moment [N m]) of a unit-described disturbance at the COM.

    ``lateral``: horizontal force ``level`` at azimuth ``direction_deg``; ``down`` / ``up``:
    vertical force; ``yaw``: moment ``level`` about +z; ``none``: zero.
    """
    force = np.zeros(3)
    moment = np.zeros(3)
    if kind == "lateral":
        a = np.radians(direction_deg)
        force[:2] = level * np.array([np.cos(a), np.sin(a)])
    elif kind == "down":
        force[2] = -level
    elif kind == "up":
        force[2] = level
    elif kind == "yaw":
        moment[2] = level
    elif kind != "none":
        raise ValueError(f"kind must be one of {DISTURBANCE_KINDS}, got {kind!r}")
    return force, moment


def slip_load_factors(points, normals, normal_forces, centroid, capacities, base_force,
                      base_moment, unit_force, unit_moment) -> np.ndarray:
    """Return, per contact, the disturbance scale at which its friction reaches its capacity.

    The tangential forces are affine in the disturbance scale ``s``:
    ``f_t,j(s) = a_j + s b_j`` (base wrench plus ``s`` times the unit wrench); contact j saturates
    at the smallest ``s >= 0`` with ``|a_j + s b_j| = capacity_j``.

    Returns
    -------
    scales : (3,) float
        0 when the contact already slips under the base wrench; inf when it never saturates.
    """
    a = contact_tangential_forces(points, normals, normal_forces, centroid, base_force, base_moment)
    ab = contact_tangential_forces(points, normals, normal_forces, centroid,
                                   np.asarray(base_force) + unit_force,
                                   np.asarray(base_moment) + unit_moment)
    b = ab - a
    cap = np.asarray(capacities, dtype=float).reshape(3)
    qa = np.einsum("ij,ij->i", b, b)
    qb = 2.0 * np.einsum("ij,ij->i", a, b)
    qc = np.einsum("ij,ij->i", a, a) - cap**2
    out = np.full(3, np.inf)
    for j in range(3):
        if qc[j] >= 0.0:
            out[j] = 0.0
        elif qa[j] > 1e-18:
            out[j] = (-qb[j] + np.sqrt(qb[j] ** 2 - 4.0 * qa[j] * qc[j])) / (2.0 * qa[j])
    return out


def first_slip_finger(points, normals, normal_forces, centroid, mass, mu_s, kind, direction_deg=0.0,
                      kappa=KAPPA, g=GRAVITY) -> int:
    """Return the finger (1-3) whose contact saturates first as a disturbance grows; 0 if none.

    Parameters
    ----------
    points, normals : (3, 3) float
        Contacts and outward normals.
    normal_forces : (3,) float
        Per-finger normal forces [N].
    centroid : (3,) float
        Object centre of mass [m].
    mass : float
        [kg]; the weight is the base load.
    mu_s : float
        Friction coefficient; each contact's capacity is ``kappa mu_s f_n,j``.
    kind : {"none", "lateral", "down", "up", "yaw"}
        Disturbance family (``none``: the weight itself is scaled).
    direction_deg : float
        Azimuth of a lateral disturbance.

    Returns
    -------
    finger : int
        1-based index, ties broken by the lower index.
    """
    weight = np.array([0.0, 0.0, -mass * g])
    caps = kappa * mu_s * np.asarray(normal_forces, dtype=float)
    if kind == "none":
        base_f, base_m = np.zeros(3), np.zeros(3)
        unit_f, unit_m = weight, np.zeros(3)
    else:
        base_f, base_m = weight, np.zeros(3)
        unit_f, unit_m = disturbance_wrench(kind, 1.0, direction_deg)
    scales = slip_load_factors(points, normals, normal_forces, centroid, caps, base_f, base_m,
                               unit_f, unit_m)
    if not np.any(np.isfinite(scales)):
        return 0
    return int(np.argmin(scales)) + 1


def microslip(utilisation, capacity, k_t):
    """Return the Mindlin partial-slip tangential displacement of a contact [m].

    Parameters
    ----------
    utilisation : float or (...) float
        ``Q / Q_cap`` in [0, 1] (clipped).
    capacity : float or (...) float
        Tangential capacity ``Q_cap`` of the contact [N].
    k_t : float or (...) float
        Initial tangential (stick) stiffness [N/m] (Table 4).

    Returns
    -------
    displacement : float or (...) float
        ``(3 Q_cap / (2 k_t)) (1 - (1 - u)^(2/3))``: ``Q / k_t`` for small u, ``1.5 Q_cap / k_t``
        at the onset of gross slip.

    References
    ----------
    Johnson (1985) Eq. 7.42 with the initial stiffness ``k_t = 8 a G*``.
    """
    u = np.clip(np.asarray(utilisation, dtype=float), 0.0, 1.0)
    return 1.5 * np.asarray(capacity) / np.asarray(k_t) * (1.0 - (1.0 - u) ** (2.0 / 3.0))
