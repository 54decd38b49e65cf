"""Fingertip contact law: Hunt-Crossley-type normal force and Coulomb stick-slip friction.

Shape letters: ``c`` contacts, ``b`` batch (candidates or particles). Every function broadcasts
over leading axes.

Units: SI everywhere except inside :func:`normal_force` (and :func:`normal_stiffness`), whose power
term takes the penetration in millimetres with ``K`` in N*mm^-n (paper §3.5, SPEC §1). Callers
always pass depths in metres; the conversion happens here and nowhere else.

References
----------
Eq. 13-16 of the paper (§3.5). Hunt, K. H. & Crossley, F. R. E. (1975), "Coefficient of
restitution interpreted as damping in vibroimpact", J. Appl. Mech. 42(2):440-445.
Table 2 (material constants), Table 3 (identified lambda1, lambda2, n).
"""

from __future__ import annotations

import logging
from dataclasses import dataclass

import numpy as np

__all__ = [
    "ALPHA_HC_DEFAULT",
    "BENCH_RESTITUTION",
    "DAMPING_LAWS",
    "GRASP_APPROACH_SPEED",
    "MM_PER_M",
    "NOMINAL_CONTACT",
    "TABLE3_CONTACT",
    "ContactParams",
    "StickSlipParams",
    "StickSlipState",
    "contact_damping_c",
    "contact_stiffness_k",
    "depth_for_force",
    "effective_modulus",
    "normal_force",
    "normal_stiffness",
    "tangential_force",
]

logger = logging.getLogger(__name__)

MM_PER_M = 1.0e3
"""Millimetres per metre: the one unit conversion of Eq. 13 (SPEC §1)."""

DAMPING_LAWS = ("linear", "hunt_crossley")
"""Rate terms of the normal law: ``linear`` = Eq. 13's ``C delta_dot`` (the paper), ``hunt_crossley``
= the original indentation-weighted ``(3/2) alpha_hc K delta^n delta_dot`` (Hunt & Crossley 1975)."""

BENCH_RESTITUTION = 0.882
"""Energetic coefficient of restitution ``e = sqrt(W_unload / W_load) = sqrt(0.42 / 0.54)`` of the
median bench loading-unloading event (§7.2) [-]."""

GRASP_APPROACH_SPEED = 0.02
"""Approach speed at which ``BENCH_RESTITUTION`` is applied [m/s]: the fastest closing speed of
the hardware grasps (§8, Group E: 5/10/20 mm/s) and the dynamic grasp's closing speed."""

ALPHA_HC_DEFAULT = (1.0 - BENCH_RESTITUTION) / GRASP_APPROACH_SPEED
"""Default Hunt-Crossley damping factor alpha_hc = (1 - e) / v_i = 5.9 s/m (Hunt & Crossley 1975;
Marhefka & Orin 1999, Eq. 12: lambda = (3/2) alpha K)."""

PA_PER_MPA = 1.0e6


def effective_modulus(e_finger, nu_finger, e_object, nu_object):
    """Return the effective contact modulus Psi of Eq. 14.

    Parameters
    ----------
    e_finger, e_object : float or (...) float
        Young's moduli of fingertip and object [Pa].
    nu_finger, nu_object : float or (...) float
        Poisson's ratios [-].

    Returns
    -------
    psi : float or (...) float
        ``1 / ((1 - nu1^2)/E1 + (1 - nu2^2)/E2)`` [Pa].

    References
    ----------
    Eq. 14 (§3.5); Johnson, K. L. (1985), Contact Mechanics, §4.2 (E* for two elastic bodies).
    """
    return 1.0 / ((1.0 - np.square(nu_finger)) / e_finger + (1.0 - np.square(nu_object)) / e_object)


def contact_stiffness_k(lambda1, psi, fingertip_radius):
    """Return the normal-contact stiffness ``K = 2 lambda1 Psi[MPa] sqrt(R[mm])`` of Eq. 14.

    Parameters
    ----------
    lambda1 : float or (...) float
        Identification scale factor [-] (absorbs the residual dimension when n != 3/2, Table 3).
    psi : float or (...) float
        Effective modulus [Pa].
    fingertip_radius : float or (...) float
        Fingertip radius R [m].

    Returns
    -------
    k_n_per_mm_n : float or (...) float
        Stiffness K [N*mm^-n] for use with the penetration in millimetres.

    References
    ----------
    Eq. 14 (§3.5); SPEC §1 (the MPa / mm reading).
    """
    return 2.0 * lambda1 * (psi / PA_PER_MPA) * np.sqrt(fingertip_radius * MM_PER_M)


def contact_damping_c(lambda2, fingertip_radius):
    """Return the normal-contact damping ``C = 4 pi R[m] lambda2`` of Eq. 14.

    Parameters
    ----------
    lambda2 : float or (...) float
        Identification scale factor [-].
    fingertip_radius : float or (...) float
        Fingertip radius R [m].

    Returns
    -------
    c_n_s_per_m : float or (...) float
        Damping C [N*s/m] for use with the penetration rate in m/s.

    References
    ----------
    Eq. 14 (§3.5); SPEC §1: lambda2 = 0.88, R = 5 mm gives C = 0.0553 N*s/m (Table 4: 0.055-0.062).
    """
    return 4.0 * np.pi * fingertip_radius * lambda2


@dataclass(frozen=True)
class ContactParams:
    """Fingertip-object contact constants of Eq. 13-14.

    Attributes
    ----------
    lambda1, lambda2 : float
        Identification scale factors of K and C [-].
    n : float
        Hunt-Crossley exponent [-] (distinct from the node count).
    fingertip_radius : float
        Fingertip radius R [m] (Table 2: 5 mm).
    e_finger, e_object : float
        Young's moduli of fingertip and object [Pa] (Table 2: 0.0893 MPa, 0.14 MPa).
    nu_finger, nu_object : float
        Poisson's ratios [-] (Table 2: 0.5, 0.45).
    damping_law : str
        Rate term of the normal law (:data:`DAMPING_LAWS`): ``"linear"`` (default, Eq. 13, the
        paper) or ``"hunt_crossley"`` (the original form, :func:`normal_force`).
    alpha_hc_s_per_m : float
        Hunt-Crossley damping factor alpha_hc [s/m], used by ``"hunt_crossley"`` only. Default
        :data:`ALPHA_HC_DEFAULT` = (1 - e)/v_i with the bench's e = 0.882 (§7.2) at the 20 mm/s
        closing speed (§8).

    Notes
    -----
    ``ContactParams.nominal()`` is the uncalibrated Hertzian set of the no-PSO ablation
    (n = 1.5, lambda1 = lambda2 = 1, SPEC §2.8); ``ContactParams.table3()`` is the paper's
    simulation identification (Table 3). The MSD constants b, k, c of Table 3 belong to the body,
    not to the contact, and are not stored here.
    """

    lambda1: float
    lambda2: float
    n: float
    fingertip_radius: float = 5.0e-3
    e_finger: float = 0.0893e6
    e_object: float = 0.14e6
    nu_finger: float = 0.5
    nu_object: float = 0.45
    damping_law: str = "linear"
    alpha_hc_s_per_m: float = ALPHA_HC_DEFAULT

    def __post_init__(self) -> None:
        if self.damping_law not in DAMPING_LAWS:
            raise ValueError(f"ContactParams.damping_law must be one of {', '.join(DAMPING_LAWS)}, "
                             f"got {self.damping_law!r}")
        if not np.isfinite(self.alpha_hc_s_per_m) or self.alpha_hc_s_per_m < 0.0:
            raise ValueError("ContactParams.alpha_hc_s_per_m must be finite and >= 0, got "
                             f"{self.alpha_hc_s_per_m!r}")
        for name in ("lambda1", "lambda2", "n", "fingertip_radius", "e_finger", "e_object"):
            value = getattr(self, name)
            if not np.isfinite(value) or value <= 0.0:
                raise ValueError(f"ContactParams.{name} must be finite and > 0, got {value!r}")
        for name in ("nu_finger", "nu_object"):
            value = getattr(self, name)
            if not 0.0 <= value <= 0.5:
                raise ValueError(f"ContactParams.{name} must lie in [0, 0.5], got {value!r}")

    @classmethod
    def nominal(cls, **materials: float) -> ContactParams:
        """Return the uncalibrated Hertzian parameters (n = 1.5, lambda1 = lambda2 = 1)."""
        return cls(lambda1=1.0, lambda2=1.0, n=1.5, **materials)

    @classmethod
    def table3(cls, **materials: float) -> ContactParams:
        """Return the paper's PSO-identified simulation parameters (Table 3)."""
        return cls(lambda1=0.332, lambda2=0.880, n=0.487, **materials)

    @property
    def psi(self) -> float:
        """Effective contact modulus Psi of Eq. 14 [Pa]."""
        psi = effective_modulus(self.e_finger, self.nu_finger, self.e_object, self.nu_object)
        return float(psi)

    @property
    def k_n_per_mm_n(self) -> float:
        """Normal stiffness K of Eq. 14 [N*mm^-n]."""
        return float(contact_stiffness_k(self.lambda1, self.psi, self.fingertip_radius))

    @property
    def c_n_s_per_m(self) -> float:
        """Normal damping C of Eq. 14 [N*s/m]."""
        return float(contact_damping_c(self.lambda2, self.fingertip_radius))


NOMINAL_CONTACT = ContactParams.nominal()
"""Uncalibrated Hertzian contact (no-PSO ablation, SPEC §2.8)."""

TABLE3_CONTACT = ContactParams.table3()
"""The paper's simulation identification (Table 3); a reference value, not our identification."""


def normal_force(depth, depth_rate, k_n_per_mm_n, n, c_n_s_per_m, damping_law="linear",
                 alpha_hc_s_per_m=ALPHA_HC_DEFAULT):
    """Return the Hunt-Crossley-type normal force ``max(0, K delta_mm^n + C delta_dot)``.

    Parameters
    ----------
    depth : (...) float
        Penetration delta [m]; contacts with ``depth <= 0`` are open and carry no force.
    depth_rate : (...) float
        Penetration rate delta_dot [m/s] (positive when closing).
    k_n_per_mm_n : float or (...) float
        Stiffness K [N*mm^-n].
    n : float or (...) float
        Exponent [-].
    c_n_s_per_m : float or (...) float
        Damping C [N*s/m] (``"linear"`` law).
    damping_law : {"linear", "hunt_crossley"}
        ``"linear"`` (default): Eq. 13, ``max(0, K delta_mm^n + C delta_dot)``.
        ``"hunt_crossley"``: the original law ``max(0, K delta_mm^n (1 + (3/2) alpha_hc
        delta_dot))``, ``C`` unused.
    alpha_hc_s_per_m : float or (...) float
        Hunt-Crossley damping factor alpha_hc [s/m] (``"hunt_crossley"`` law).

    Returns
    -------
    force : (...) float
        Normal force magnitude f_n >= 0 [N].

    Notes
    -----
    The power term takes the depth in millimetres, the damper the rate in m/s (§3.5: "the two
    length conventions must not be mixed"); alpha_hc multiplies the rate in m/s, so it is in s/m
    whatever the length unit of the power term. The ``max(0, .)`` clamp removes tensile forces
    on separation (§5.1). The linear rate term gives a force step ``C delta_dot`` at contact onset
    (§5.1); the original form weights the damper by ``K delta^n`` and has none: f -> 0 as
    delta -> 0 for every delta_dot. In statics (delta_dot = 0) both are ``K delta_mm^n``.

    alpha_hc and the coefficient of restitution: for a mass striking the contact at v_i, the
    energy the damper dissipates over the (elastic) loading-unloading cycle is, to first order,
    ``(4/3) (lambda / K) v_i`` of the impact energy for every n (``lambda = (3/2) alpha_hc K``),
    so ``1 - e^2 ~ 2 (1 - e) = 2 alpha_hc v_i``: ``alpha_hc = (1 - e) / v_i`` (Hunt & Crossley
    1975; Marhefka & Orin 1999).

    References
    ----------
    Eq. 13 (§3.5); Hunt & Crossley (1975); Marhefka, D. W. & Orin, D. E. (1999), "A compliant
    contact model with nonlinear damping for simulation of robotic systems", IEEE Trans. SMC-A
    29(6):566-572, Eq. 12.
    """
    depth = np.asarray(depth, dtype=float)
    active = depth > 0.0
    depth_mm = np.where(active, depth, 0.0) * MM_PER_M
    elastic = k_n_per_mm_n * np.power(depth_mm, n)
    rate = np.asarray(depth_rate, dtype=float)
    if damping_law == "linear":
        force = np.maximum(0.0, elastic + c_n_s_per_m * rate)
    elif damping_law == "hunt_crossley":
        force = np.maximum(0.0, elastic * (1.0 + 1.5 * np.asarray(alpha_hc_s_per_m) * rate))
    else:
        raise ValueError(f"damping_law must be one of {', '.join(DAMPING_LAWS)}, got {damping_law!r}")
    return np.where(active, force, 0.0)


def depth_for_force(force, k_n_per_mm_n, n):
    """Return the static penetration at which ``K delta_mm^n`` equals a given normal force.

    Parameters
    ----------
    force : (...) float
        Normal force f_n >= 0 [N].
    k_n_per_mm_n : float or (...) float
        Stiffness K [N*mm^-n].
    n : float or (...) float
        Exponent [-].

    Returns
    -------
    depth : (...) float
        ``(f_n / K)^(1/n)`` millimetres, returned in metres [m].

    Notes
    -----
    The inverse of the elastic term of Eq. 13, e.g. to turn a fixed grip command per finger
    (§6.4) into penetrations for :func:`graspcampaign.core.equilibrium.static_checks`.
    """
    force = np.maximum(np.asarray(force, dtype=float), 0.0)
    return np.power(force / k_n_per_mm_n, 1.0 / np.asarray(n, dtype=float)) / MM_PER_M


def normal_stiffness(depth, k_n_per_mm_n, n):
    """Return the static stiffness ``d(K delta_mm^n)/d delta`` of Eq. 13 per metre.

    Parameters
    ----------
    depth : (...) float
        Penetration delta >= 0 [m].
    k_n_per_mm_n : float or (...) float
        Stiffness K [N*mm^-n].
    n : float or (...) float
        Exponent [-].

    Returns
    -------
    stiffness : (...) float
        ``1000 n K delta_mm^(n-1)`` [N/m]; at ``depth == 0`` this is ``inf`` for n < 1,
        ``1000 K`` for n = 1 and 0 for n > 1 (the one-sided derivative).

    References
    ----------
    Eq. 13 (§3.5); §5.1 (divergence of ``n K delta^(n-1)`` as delta -> 0+ for n < 1).
    """
    depth_mm = np.maximum(np.asarray(depth, dtype=float), 0.0) * MM_PER_M
    with np.errstate(divide="ignore"):
        return MM_PER_M * n * k_n_per_mm_n * np.power(depth_mm, np.subtract(n, 1.0))


@dataclass(frozen=True)
class StickSlipParams:
    """Coulomb stick-slip constants of Eq. 15-16.

    Attributes
    ----------
    mu_s : float
        Static coefficient: the stick-to-slip transition test [-].
    mu_k : float
        Kinetic coefficient: the sliding force of Eq. 15 [-].
    k_t : float
        Tangential (stick) stiffness [N/m] (Table 4).
    c_t : float
        Tangential stabilising damping [N*s/m] (§3.5: not identified; vanishes at equilibrium).
    """

    mu_s: float
    mu_k: float
    k_t: float
    c_t: float = 0.0

    def __post_init__(self) -> None:
        for name in ("mu_s", "mu_k", "k_t", "c_t"):
            value = getattr(self, name)
            if not np.isfinite(value) or value < 0.0:
                raise ValueError(f"StickSlipParams.{name} must be finite and >= 0, got {value!r}")
        if self.k_t == 0.0:
            raise ValueError("StickSlipParams.k_t must be > 0 (the stick spring), got 0.0")


@dataclass(frozen=True)
class StickSlipState:
    """Evolving stick-slip state of ``c`` contacts.

    Attributes
    ----------
    anchors : (c, 3) float
        Stick anchor of each contact in W [m]; the elastic deflection xi is the tangential part
        of ``contact_point - anchor``.
    sliding : (c,) bool
        Whether the contact slid in the last call.
    """

    anchors: np.ndarray
    sliding: np.ndarray

    @classmethod
    def initial(cls, contact_points) -> StickSlipState:
        """Return a relaxed state: anchors at the contact points, every contact sticking."""
        points = np.array(contact_points, dtype=float)
        if points.ndim != 2 or points.shape[1] != 3:
            raise ValueError(f"contact_points must have shape (c, 3), got {points.shape}")
        return cls(anchors=points, sliding=np.zeros(points.shape[0], dtype=bool))


def _tangential_part(vectors: np.ndarray, normals: np.ndarray) -> np.ndarray:
    return vectors - np.sum(vectors * normals, axis=-1, keepdims=True) * normals


def tangential_force(state, params, contact_points, normal_force, tangential_velocity, normals):
    """Return the Coulomb stick-slip tangential forces and the updated state (Eq. 15-16).

    Parameters
    ----------
    state : StickSlipState
        Anchors and sliding flags before this step.
    params : StickSlipParams
        mu_s, mu_k, k_t, c_t.
    contact_points : (c, 3) float
        Current contact points in W [m].
    normal_force : (c,) float
        Normal force magnitudes f_n >= 0 [N].
    tangential_velocity : (c, 3) float
        Contact-point velocity relative to the fingertip in W [m/s]; only its tangential part is
        used (it is projected on the tangent plane here).
    normals : (c, 3) float
        Unit normals of the tangent plane (either orientation).

    Returns
    -------
    forces : (c, 3) float
        Tangential force on the object at each contact [N].
    new_state : StickSlipState
        Updated anchors and sliding flags (the input state is not modified).

    Notes
    -----
    Trial stick force ``f_stick = -(k_t xi + c_t xi_dot)`` with ``xi`` the tangential part of
    ``contact_point - anchor`` and ``xi_dot = V_t`` (Eq. 16). The contact sticks while
    ``|f_stick| <= mu_s f_n``; otherwise it slides with ``-mu_k f_n V_t/|V_t|`` (Eq. 15; along the
    trial force when ``V_t = 0``) and its anchor is dragged to ``contact_point + f_slip / k_t`` so
    the elastic deflection saturates at the kinetic cone and the spring force is continuous at
    the next step (a return mapping). A contact with ``f_n = 0`` carries no friction and its anchor
    resets to the contact point.

    References
    ----------
    Eq. 15-16 (§3.5); Simo, J. C. & Hughes, T. J. R. (1998), Computational Inelasticity, §2.2
    (return mapping of a rate-independent slip law).
    """
    points = np.asarray(contact_points, dtype=float)
    unit_normals = np.asarray(normals, dtype=float)
    f_n = np.maximum(np.asarray(normal_force, dtype=float), 0.0)
    xi = _tangential_part(points - state.anchors, unit_normals)
    v_t = _tangential_part(np.asarray(tangential_velocity, dtype=float), unit_normals)

    trial = -(params.k_t * xi + params.c_t * v_t)
    trial_norm = np.linalg.norm(trial, axis=-1)
    sliding = trial_norm > params.mu_s * f_n

    speed = np.linalg.norm(v_t, axis=-1)
    moving = speed > 0.0
    with np.errstate(invalid="ignore", divide="ignore"):
        against_velocity = -v_t / speed[:, None]
        along_trial = trial / trial_norm[:, None]
    direction = np.where(moving[:, None], against_velocity, along_trial)
    direction = np.where(np.isfinite(direction), direction, 0.0)
    slip_force = (params.mu_k * f_n)[:, None] * direction

    forces = np.where(sliding[:, None], slip_force, trial)
    anchors = np.where(sliding[:, None], points + slip_force / params.k_t, state.anchors)
    return forces, StickSlipState(anchors=anchors, sliding=sliding)
