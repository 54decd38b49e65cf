"""Rigid-contact statics of a grasp: six-component wrench residual and friction-cone feasibility.

The like-for-like checks of §6.1 and §12 (issue 6, item 5): given contact points and outward
normals on an object of mass m, does a set of contact forces inside the Coulomb friction cones
exist that balances the weight in force *and* torque? And how far from six-component balance is a
given (e.g. settled dynamic) force set? The paper's audits built on them (§12's horizontal
residual, §6.1's mu -> 0 diagnosis) are in :mod:`graspcampaign.core.statics_audit`.

Shape letters: ``c`` contacts, ``q`` cone facets.

Conventions (ARCHITECTURE.md): world z up, gravity ``(0, 0, -g)``; ``normals`` are outward unit
normals ``n_out``, so the normal force a finger applies to the object is ``f_n (-n_out)``, f_n >= 0.

Linearised friction cone
------------------------
The exact cone ``|f_t| <= mu f_n`` is a second-order cone. With ``q`` facets
``f_t . e_k <= rho mu f_n`` (``e_k`` at angles ``2 pi k / q`` in the tangent plane) the feasible set
is a regular q-gon: with ``rho = 1`` it circumscribes the circle (outer approximation: LP
infeasible => exactly infeasible); with ``rho = cos(pi / q)`` it is inscribed (inner approximation:
LP feasible => exactly feasible). Solving both brackets the exact answer without an SOCP solver:
``status`` is ``"feasible"`` or ``"infeasible"`` when they agree and ``"undetermined"`` in the thin
band ``mu cos(pi/q) < mu_required <= mu`` between them.

References
----------
§3.7 Eq. 19 (force balance), §6.1 (closed-form static feasibility of the 45/45/-90 set), §12
(six-component wrench residual, the horizontal audit of Fig. 13). Trinkle, J. C. (1992), "On the
stability and instantaneous velocity of grasped frictionless objects", IEEE Trans. Robot. Autom.
8(5):560-572; Murray, Li & Sastry (1994), A Mathematical Introduction to Robotic Manipulation,
§5.2-5.3 (friction cones, linearisation by polyhedral cones).
"""

from __future__ import annotations

import logging
from dataclasses import dataclass

import numpy as np
from scipy.optimize import linprog

__all__ = [
    "FrictionConeResult",
    "check_contacts",
    "cone_lp_matrices",
    "friction_cone_feasibility",
    "required_friction",
    "sphere_contacts_from_directions",
    "tangent_bases",
    "wrench_residual",
]

logger = logging.getLogger(__name__)

GRAVITY = 9.81
"""Gravitational acceleration [m/s^2], the one value used across core (SPEC §1, SI inside)."""


def check_contacts(points, normals) -> tuple[np.ndarray, np.ndarray]:
    """Validate contact points and normals; return float64 arrays with unit normals.

    Raises
    ------
    ValueError
        If shapes differ from ``(c, 3)``, or a normal has zero length.
    """
    points = np.asarray(points, dtype=np.float64)
    normals = np.asarray(normals, dtype=np.float64)
    if points.ndim != 2 or points.shape[1] != 3:
        raise ValueError(f"points must have shape (c, 3), got {points.shape}")
    if normals.shape != points.shape:
        raise ValueError(f"normals must have shape {points.shape}, got {normals.shape}")
    length = np.linalg.norm(normals, axis=1)
    if np.any(length <= 0.0):
        raise ValueError("normals must be non-zero")
    return points, normals / length[:, None]


def tangent_bases(normals) -> tuple[np.ndarray, np.ndarray]:
    """Return two (c, 3) unit tangents ``t1, t2`` with ``(t1, t2, n)`` right-handed per contact."""
    normals = np.asarray(normals, dtype=np.float64)
    helper = np.where(np.abs(normals[:, [2]]) < 0.9, [[0.0, 0.0, 1.0]], [[1.0, 0.0, 0.0]])
    t1 = np.cross(helper, normals)
    t1 /= np.linalg.norm(t1, axis=1)[:, None]
    return t1, np.cross(normals, t1)


def sphere_contacts_from_directions(directions, radius: float, center=(0.0, 0.0, 0.0)):
    """Return points and outward normals of contacts on a sphere along unit ``directions``.

    Parameters
    ----------
    directions : (c, 3) float
        Directions from the centre (normalised here).
    radius : float
        Sphere radius [m].
    center : (3,) float
        Sphere centre [m].

    Returns
    -------
    points : (c, 3) float
        ``center + radius * u`` [m].
    normals : (c, 3) float
        ``u`` (outward).
    """
    u = np.asarray(directions, dtype=np.float64)
    u = u / np.linalg.norm(u, axis=1)[:, None]
    return np.asarray(center, dtype=np.float64) + radius * u, u


def wrench_residual(points, forces, mass: float, center, g: float = GRAVITY) -> np.ndarray:
    """Return the six-component residual of Eq. 19 extended to torque.

    Parameters
    ----------
    points : (c, 3) float
        Points of application of the contact forces in W [m].
    forces : (c, 3) float
        Total contact forces on the object (normal + tangential) [N].
    mass : float
        Object mass [kg]; its weight ``(0, 0, -m g)`` acts at ``center``.
    center : (3,) float
        Centre of mass, the torque reference [m].
    g : float
        Gravity [m/s^2].

    Returns
    -------
    residual : (6,) float
        ``[sum f + m g_vec, sum (p - center) x f]`` [N, N*m]; zero at static equilibrium.

    References
    ----------
    Eq. 19 (§3.7) for the force part; §12 (the six-component audit the paper left open).
    """
    points = np.asarray(points, dtype=np.float64).reshape(-1, 3)
    forces = np.asarray(forces, dtype=np.float64).reshape(-1, 3)
    center = np.asarray(center, dtype=np.float64)
    force = forces.sum(axis=0) + np.array([0.0, 0.0, -mass * g])
    torque = np.cross(points - center, forces).sum(axis=0)
    return np.concatenate([force, torque])


@dataclass(frozen=True)
class FrictionConeResult:
    """Outcome of the friction-cone feasibility LPs.

    Attributes
    ----------
    status : str
        ``"feasible"`` (inner LP feasible), ``"infeasible"`` (outer LP infeasible) or
        ``"undetermined"`` (only the outer LP is feasible: ``mu`` within a factor cos(pi/q) of
        the minimum required).
    feasible_inner, feasible_outer : bool
        Feasibility of the inscribed / circumscribed polyhedral cones.
    forces : (c, 3) float or None
        A force set of the inner LP (minimum total normal force), else of the outer LP, else None
        [N].
    normal_forces : (c,) float or None
        Their normal components f_n >= 0 [N].
    tangential_forces : (c,) float or None
        Magnitudes of their tangential components [N].
    residual : (6,) float or None
        :func:`wrench_residual` of ``forces`` (round-off only) [N, N*m].
    mu : float
        Friction coefficient tested [-].
    n_facets : int
        Facets q of the polyhedral cones.
    """

    status: str
    feasible_inner: bool
    feasible_outer: bool
    forces: np.ndarray | None
    normal_forces: np.ndarray | None
    tangential_forces: np.ndarray | None
    residual: np.ndarray | None
    mu: float
    n_facets: int

    @property
    def feasible(self) -> bool:
        """True when feasibility is certain (inner LP feasible)."""
        return self.feasible_inner


def _check_cone(mu, n_facets) -> None:
    if mu < 0.0 or not np.isfinite(mu):
        raise ValueError(f"mu must be finite and >= 0, got {mu!r}")
    if n_facets < 3:
        raise ValueError(f"n_facets must be >= 3, got {n_facets}")


def cone_lp_matrices(points, normals, mu, rho, mass, center, g, n_facets):
    """Assemble the friction-cone LP of :func:`friction_cone_feasibility` (shared by core.grip).

    Unknowns per contact j: ``x_j = (f_n, a, b)`` with the force ``-f_n n + a t1 + b t2``.

    Returns
    -------
    basis : (c, 3, 3) float
        Columns map ``x_j`` to the force vector.
    a_eq : (6, 3c) float
        Net force and torque about ``center`` (Eq. 19 with torque).
    b_eq : (6,) float
        ``(0, 0, m g, 0, 0, 0)``.
    a_ub : (c q, 3c) float
        Facets ``e_k . (a, b) - rho mu f_n <= 0`` of the polyhedral cones (right-hand side 0).
    """
    n_contacts = len(points)
    t1, t2 = tangent_bases(normals)
    basis = np.stack([-normals, t1, t2], axis=2)  # (c, 3, 3): columns map x_j -> force
    arms = points - center
    a_eq = np.zeros((6, 3 * n_contacts))
    for_torque = np.cross(arms[:, None, :], np.transpose(basis, (0, 2, 1)))  # (c, 3 cols, 3)
    a_eq[:3] = np.transpose(basis, (1, 0, 2)).reshape(3, -1)
    a_eq[3:] = np.transpose(for_torque, (2, 0, 1)).reshape(3, -1)
    b_eq = np.array([0.0, 0.0, mass * g, 0.0, 0.0, 0.0])
    angles = 2.0 * np.pi * np.arange(n_facets) / n_facets
    facets = np.column_stack([-rho * mu * np.ones(n_facets), np.cos(angles), np.sin(angles)])
    a_ub = np.zeros((n_contacts * n_facets, 3 * n_contacts))
    for j in range(n_contacts):  # c <= a handful of contacts: building the LP, not the physics
        a_ub[j * n_facets : (j + 1) * n_facets, 3 * j : 3 * j + 3] = facets
    return basis, a_eq, b_eq, a_ub


def _solve_cone_lp(points, normals, mu, rho, mass, center, g, n_facets, min_normal_force):
    """Solve min sum f_n s.t. wrench balance and polyhedral cones.

    Returns ``(forces (c, 3), x (c, 3))``, or None when the LP is infeasible.
    """
    n_contacts = len(points)
    basis, a_eq, b_eq, a_ub = cone_lp_matrices(points, normals, mu, rho, mass, center, g, n_facets)
    b_ub = np.zeros(n_contacts * n_facets)
    cost = np.tile([1.0, 0.0, 0.0], n_contacts)
    bounds = [(min_normal_force, None), (None, None), (None, None)] * n_contacts
    result = linprog(cost, A_ub=a_ub, b_ub=b_ub, A_eq=a_eq, b_eq=b_eq, bounds=bounds, method="highs")
    if result.status == 2:
        return None
    if result.status != 0:
        raise RuntimeError(f"friction-cone LP failed: {result.message}")
    x = result.x.reshape(n_contacts, 3)
    return np.einsum("cij,cj->ci", basis, x), x


def friction_cone_feasibility(
    points,
    normals,
    mu: float,
    mass: float,
    center=(0.0, 0.0, 0.0),
    n_facets: int = 16,
    g: float = GRAVITY,
    min_normal_force: float = 0.0,
) -> FrictionConeResult:
    """Decide whether contact forces inside the friction cones can hold the object statically.

    Parameters
    ----------
    points : (c, 3) float
        Contact points in W [m].
    normals : (c, 3) float
        Outward unit normals at the contacts.
    mu : float
        Coulomb friction coefficient [-], >= 0 (``mu = 0``: normal forces only, exact).
    mass : float
        Object mass [kg].
    center : (3,) float
        Centre of mass (torque reference) [m].
    n_facets : int
        Facets q of the polyhedral cone approximations, >= 3.
    g : float
        Gravity [m/s^2].
    min_normal_force : float
        Lower bound on every f_n [N] (0: a contact may go slack).

    Returns
    -------
    result : FrictionConeResult

    Notes
    -----
    Unknowns: the three components of every contact force. Constraints: net force + weight = 0
    and net torque about ``center`` = 0 (six equalities), ``f_n >= min_normal_force``, and the
    polyhedral cones of the module docstring. Objective: minimum total normal force (any feasible
    point would do; this one is reproducible). Contacts are rigid Coulomb point contacts, as in
    §6.1: this certifies static feasibility of the contact geometry, not the outcome of a grip law.

    References
    ----------
    §6.1 (the closed-form check), Murray, Li & Sastry (1994) §5.3.
    """
    points, normals = check_contacts(points, normals)
    _check_cone(mu, n_facets)
    center = np.asarray(center, dtype=np.float64)
    args = (mass, center, g, n_facets, min_normal_force)
    inner = _solve_cone_lp(points, normals, mu, np.cos(np.pi / n_facets), *args)
    # The inscribed cone lies inside the circumscribed one: a feasible inner LP answers both.
    outer = inner if inner is not None else _solve_cone_lp(points, normals, mu, 1.0, *args)
    if inner is not None:
        status = "feasible"
    elif outer is not None:
        status = "undetermined"
    else:
        status = "infeasible"
    if outer is None:
        forces = normal = tangential = residual = None
    else:
        forces, x = outer  # the inner solution whenever there is one
        normal = x[:, 0]
        tangential = np.hypot(x[:, 1], x[:, 2])
        residual = wrench_residual(points, forces, mass, center, g)
    return FrictionConeResult(
        status=status,
        feasible_inner=inner is not None,
        feasible_outer=outer is not None,
        forces=forces,
        normal_forces=normal,
        tangential_forces=tangential,
        residual=residual,
        mu=float(mu),
        n_facets=int(n_facets),
    )


def required_friction(
    points,
    normals,
    mass: float,
    center=(0.0, 0.0, 0.0),
    n_facets: int = 16,
    g: float = GRAVITY,
    mu_max: float = 10.0,
    tol: float = 1e-6,
) -> float:
    """Return the smallest mu for which the inner-cone LP is feasible (bisection).

    Parameters
    ----------
    points, normals, mass, center, n_facets, g
        As :func:`friction_cone_feasibility`.
    mu_max : float
        Upper end of the search [-].
    tol : float
        Absolute tolerance on mu [-].

    Returns
    -------
    mu_required : float
        0.0 when normal forces alone can hold the object; ``inf`` when even ``mu_max`` cannot.
        The exact-cone value lies in ``[cos(pi/q) mu_required, mu_required]``.

    Notes
    -----
    Each bisection step solves only the inner-cone LP (what
    ``friction_cone_feasibility(...).feasible`` reports), without its outer-cone bracket.
    """
    points, normals = check_contacts(points, normals)
    _check_cone(mu_max, n_facets)
    center = np.asarray(center, dtype=np.float64)
    rho = np.cos(np.pi / n_facets)

    def feasible(mu):
        return _solve_cone_lp(points, normals, mu, rho, mass, center, g, n_facets, 0.0) is not None

    if feasible(0.0):
        return 0.0
    if not feasible(mu_max):
        return float("inf")
    low, high = 0.0, mu_max
    while high - low > tol:
        mid = 0.5 * (low + high)
        low, high = (low, mid) if feasible(mid) else (mid, high)
    return high
