"""Disturbance statics and grip sizing of the hardware campaigns (paper §8.1, §9.1; SPEC §2.10).

A three-finger grasp with per-finger grip ``F_grip`` holds a single friction budget; the safety
factor compares it with the lifted weight including the inertial term,

    SF = 3 mu_s F_grip G_geo kappa / (W (1 + a_lift / g)),        kappa = 2.4 (frozen, §8.1),

and the budget ``SF W`` is shared between the weight and a disturbance, which gives the predicted
limits ``F_lat = W sqrt(SF^2 - 1)``, ``F_down = W (SF - 1)`` and ``T = W sqrt(SF^2 - 1) r_eff``
(§9.1). Everything here is closed-form statics on a contact set; no dynamics. The contact-level
statics (tangential forces, first finger to slip, pad microslip) are :mod:`graspcampaign.core.slip`.

Geometric efficiency ``G_geo`` (our definition; SPEC §2.10 asks for one, issue 13 asks that it
count the sign of ``n_z``):

    G_geo = clip( (1/3) sum_j s_j (sqrt(1 - n_z,j^2) - n_z,j / (kappa mu_s)), 0, 1 ),

with ``s_j`` the load-shared normal force of finger j per unit of equal commanded grip
(:func:`load_shared_forces` of ``(1, 1, 1)``: the object shifts in the hand until the squeeze
balances horizontally) and ``G_geo = 0`` when that sharing needs a non-positive force (a finger
loses contact under equal commands). Derivation: a finger pressing along ``-n_j`` with normal force
``f_j`` lifts the object with friction in its tangent plane, whose largest vertical component is
``kappa mu_s f_j sqrt(1 - n_z,j^2)``, and with its own normal force, whose vertical component
``-f_j n_z,j`` supports the object at a lower contact (``n_z < 0``) and *adds load* at an upper one
(``n_z > 0``). The vertical capacity of the grasp is therefore

    V(f) = sum_j f_j (kappa mu_s sqrt(1 - n_z,j^2) - n_z,j)           (:func:`vertical_capacity`)

and ``G_geo`` is ``V(F s) / (3 kappa mu_s F)``, so that ``3 mu_s F G_geo kappa`` -- the §8.1 holding
term -- is exactly the vertical capacity at grip F. It is 1 for three horizontal, self-balancing
normals, falls as upper contacts turn vertical (to 0 once their push exceeds their friction reach),
and would exceed 1 for a cradle of lower contacts; it is capped at 1, the paper's range
``G_geo in (0, 1]`` (§8.1): the safety factor never credits more than the friction budget of three
horizontal contacts, which under-states a cradle (conservative). The term ``n_z / (kappa mu_s)``
converts normal support into friction-equivalent units, so G_geo depends on the friction the
caller believes: a planner's believed G_geo uses its believed mu_s, the achieved one the true mu_s.

Relation to the friction-cone LP of :mod:`graspcampaign.core.statics` (tested in
tests/core/test_disturbance.py, stated in docs/decisions.md):

1. *Necessary.* If contact forces inside the cones ``|f_t| <= kappa mu_s f_n`` balance the lifted
   weight ``W' = W (1 + a_lift/g)`` in force (torque aside) with normal forces ``f``, then
   ``V(f) >= W'``: the z-component of the balance is ``W' = sum_j (f_t,j . z - f_j n_z,j)`` and
   ``|f_t,j . z| <= kappa mu_s f_j sqrt(1 - n_z,j^2)``. So SF < 1 at grip F (uncapped G_geo) means
   no static equilibrium exists at the load-shared forces ``F s``.
2. *Sufficient for symmetric sets.* For three contacts related by 120 deg rotations about the
   vertical through the centre of mass, SF(F) >= 1 exactly when F is at least the LP's minimum
   per-finger normal force (the exact cone lies between the LP's inscribed cones at ``kappa mu_s``
   and at ``kappa mu_s / cos(pi/q)``).
3. *Neither in general.* SF ignores torque (coincident contacts beside the centre of mass: SF >= 1,
   LP infeasible) and equal commands cannot unload a harmful upper contact (a finger below the
   centre of mass with two steep upper fingers: LP feasible, G_geo = 0).

Shape letters: ``c = 3`` contacts; leading batch axes broadcast where stated.

References
----------
Paper §8.1 (SF, kappa, G_geo, grip sizing from believed quality, tau_F = 0.0886 N), §9.1 (shared
friction budget and the three limits), §7.4 (damage depth), Table 4 (constants).
Fung, Y. C. (1981), Biomechanics, ch. 7 (quasi-linear viscoelasticity); Findley, Lai & Onaran
(1976), Creep and Relaxation of Nonlinear Viscoelastic Materials, §5.3 (standard linear solid:
relaxation ratio rho, time constant tau <-> creep time constant tau / rho).
Murray, Li & Sastry (1994), A Mathematical Introduction to Robotic Manipulation, §5.2-5.3 (contact
wrenches, friction cones).
"""

from __future__ import annotations

import logging
from dataclasses import dataclass

import numpy as np

from graspcampaign.core.contact import depth_for_force, normal_force
from graspcampaign.core.statics import GRAVITY

__all__ = [
    "A_LIFT",
    "DISTURBANCE_KINDS",
    "KAPPA",
    "SF_STABLE",
    "SF_TARGET",
    "TAU_F_HARDWARE",
    "DisturbanceLimits",
    "GripSizing",
    "creep_compliance",
    "disturbance_limits",
    "effective_radius",
    "force_at_indentation",
    "geometric_efficiency",
    "grip_for_safety_factor",
    "indentation_from_force",
    "load_shared_forces",
    "retention_margin",
    "safety_factor",
    "size_grip",
    "unit_normals",
    "vertical_capacity",
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
"""Disturbance families of Test 3 (§9.1); ``none`` is Test 2's lift and hold."""


# --------------------------------------------------------------------------------------------
# Geometry of the contact set
# --------------------------------------------------------------------------------------------
def unit_normals(normals) -> np.ndarray:
    """Return (..., 3, 3) contact normals scaled to unit length; refuse another shape."""
    normals = np.asarray(normals, dtype=float)
    if normals.shape[-2:] != (3, 3):
        raise ValueError(f"normals must have shape (..., 3, 3), got {normals.shape}")
    return normals / np.linalg.norm(normals, axis=-1, keepdims=True)


def _shares(commanded, normals) -> np.ndarray:
    """Batched least-squares horizontal load sharing (:func:`load_shared_forces`), (..., 3)."""
    n = unit_normals(normals)
    c = np.broadcast_to(np.asarray(commanded, dtype=float), n.shape[:-1])
    a = -np.swapaxes(n[..., :2], -1, -2)  # (..., 2, 3): horizontal force directions -h_j
    gram = a @ np.swapaxes(a, -1, -2)  # (..., 2, 2), symmetric positive semi-definite
    ac = np.einsum("...ij,...j->...i", a, c)
    return c - np.einsum("...ji,...j->...i", a, np.einsum("...ij,...j->...i", _pinv2(gram), ac))


#: Sum of squared horizontal normal components below which the normals are vertical (1e-12 each).
VERTICAL_TRACE = 1e-24


def _pinv2(m: np.ndarray) -> np.ndarray:
    """Moore-Penrose inverse of symmetric PSD (..., 2, 2) matrices in closed form.

    With the trace ``t`` scaled out (``pinv(m) = pinv(m / t) / t``): full rank, the adjugate over
    the determinant; rank one (``m = lambda u u^T``), ``m / t^2``; zero, zero. Rank is judged as
    ``numpy.linalg.pinv`` does, a singular value below 1e-15 times the largest counting as zero.
    Written out because ``pinv`` (an SVD) of a 2 x 2 costs ~0.1 ms and this runs per prediction.
    A trace below :data:`VERTICAL_TRACE` is zero: the Gram matrix of unit normals' horizontal parts,
    whose components are then below 1e-12 (round-off of a vertical normal; ``pinv`` would divide by
    a subnormal and return inf).
    """
    tr = m[..., 0, 0] + m[..., 1, 1]
    tr = np.where(tr > VERTICAL_TRACE, tr, 0.0)
    scale = np.where(tr > 0.0, tr, 1.0)[..., None, None]
    u = m / scale  # trace 1 (or a zero matrix)
    det = u[..., 0, 0] * u[..., 1, 1] - u[..., 0, 1] * u[..., 1, 0]
    t = u[..., 0, 0] + u[..., 1, 1]
    small = np.maximum(t - np.sqrt(np.maximum(t * t - 4.0 * det, 0.0)), 0.0) / 2.0
    adj = np.stack([np.stack([u[..., 1, 1], -u[..., 0, 1]], -1),
                    np.stack([-u[..., 1, 0], u[..., 0, 0]], -1)], -2)
    full = (small > 1e-15 * (t - small)) & (tr > 0.0)  # a zero matrix (unscaled u) is not full rank
    inv = np.where(full[..., None, None], adj / np.where(full, det, 1.0)[..., None, None], u)
    return np.where((tr > 0.0)[..., None, None], inv / scale, 0.0)


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
    f = _shares(c, np.asarray(normals, dtype=float).reshape(3, 3))
    return f, bool(np.all(f > 1e-9))


def vertical_capacity(normals, normal_forces, mu_eff) -> np.ndarray | float:
    """Return the largest vertical force the contacts can exert on the object [N].

    Parameters
    ----------
    normals : (..., 3, 3) float
        Outward unit contact normals ``n_out``.
    normal_forces : (..., 3) float
        Normal force of each finger [N] (applied along ``-n_out``).
    mu_eff : float or (...) float
        Effective friction coefficient of each contact (``kappa mu_s`` for the hand) [-].

    Returns
    -------
    capacity : (...) float
        ``V = sum_j f_j (mu_eff sqrt(1 - n_z,j^2) - n_z,j)``: friction pulling straight up the
        tangent plane at its limit, plus the vertical component of each normal push (negative at
        an upper contact). Vertical force balance against a load ``W'`` is possible with these
        normal forces exactly when ``W' <= V`` (module docstring, relation 1).

    References
    ----------
    Coulomb cone, Eq. 15; Murray, Li & Sastry (1994) §5.2.
    """
    n = unit_normals(normals)
    f = np.asarray(normal_forces, dtype=float)
    reach = np.sqrt(np.clip(1.0 - n[..., 2] ** 2, 0.0, 1.0))
    mu = np.asarray(mu_eff, dtype=float)[..., None]
    v = np.sum(f * (mu * reach - n[..., 2]), axis=-1)
    return float(v) if np.ndim(v) == 0 else v


def geometric_efficiency(normals, mu_s, kappa=KAPPA) -> np.ndarray | float:
    """Return G_geo of contact sets under equal commanded grip (module docstring).

    Parameters
    ----------
    normals : (..., 3, 3) float
        Outward unit contact normals ``n_out`` of the three contacts.
    mu_s : float or (...) float
        Static friction coefficient the caller uses (a planner its believed value, the rig the
        true one) [-].
    kappa : float
        Friction-enhancement factor [-].

    Returns
    -------
    g_geo : (...) float
        In [0, 1]: 1 for three horizontal self-balancing normals; smaller as upper contacts tilt
        (their push adds load); 0 when equal commands cannot be shared with positive forces or the
        upper contacts' push exceeds the friction reach; capped at 1 for a cradle of lower
        contacts.
    """
    n = unit_normals(normals)
    shares = _shares(np.ones(3), n)
    mu_eff = kappa * np.asarray(mu_s, dtype=float)
    per_grip = vertical_capacity(n, shares, mu_eff)
    ok = np.all(shares > 1e-9, axis=-1) & (mu_eff > 0.0)
    with np.errstate(invalid="ignore", divide="ignore", over="ignore"):  # tiny mu: G -> cap
        g = np.where(ok, per_grip / (3.0 * np.where(mu_eff > 0.0, mu_eff, 1.0)), 0.0)
    g = np.clip(g, 0.0, 1.0)
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
