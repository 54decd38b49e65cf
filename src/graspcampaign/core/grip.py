"""Grip laws beside Algorithm 2: ``slip`` and ``oracle`` (paper §6.5, §12 future work).

Algorithm 2 (the ``paper`` law, :mod:`graspcampaign.core.equilibrium`) advances each finger
against the *vertical normal-force* deficit only; friction is resolved after the loop. The paper
names two laws it did not run (§6.5, §12): a slip-margin-driven grip increment, and a matched-grip
control in which every planner receives an oracle-sized grip. Both are here. They share:

* **one equal grip**: all three fingers squeeze together, every finger carries the same normal
  force F (equal penetration under the body's one contact law);
* **a friction design margin** SF > 1 (``EvaluatorParams.grip_safety_factor``): the grip is sized so
  that every contact uses at most mu/SF of its friction;
* **a grip cap**: F never exceeds the force that reaches ``EvaluatorParams.grip_cap_depth``;
* **one verdict**: the force state goes to :func:`graspcampaign.core.verdict.judge`, which checks the
  *full post-friction* residual and torque (tau_F, tau_T) and the slip margin, then the validity
  gate.

``slip``
    Friction resolved as in §6.1 (uniform utilisation, ``f_t,j = eta f_n,j t_hat_j``). With equal
    forces f, ``A = sum_j n_hat_j,z`` and ``B = sum_j t_hat_j,z``: ``eta(f) = (W - f A) / (f B)``.
    The grip rises while a vertical deficit remains after the friction the margin allows,
    ``f A + (mu/SF) f B < W``; its fixed point is the closed form

        f_need = W / (A + mu B / SF)        (inf when A + mu B / SF <= 0),

    where ``eta = mu/SF`` exactly (B > 0), and ``f_need = W / A`` when no contact has a tangent
    (B = 0: the vertical deficit alone). The fingers start at Algorithm 2's 0.5 mm seed and the
    grip only rises, so ``F = min(max(f_need, K (0.5 mm)^n), f_cap)``.
``oracle``
    The smallest equal normal force F for which the §6.1 friction-cone problem (net force and
    torque zero, every contact inside its cone of half-angle atan(mu/SF)) is feasible: one LP
    (``scipy.optimize.linprog``, HiGHS) over F and the six tangential components, on the inscribed
    polyhedral cones of :mod:`graspcampaign.core.statics` (so the LP's forces lie inside the exact
    cones). Friction is the LP's own distribution. Above the cap (or with no feasible F) the grip
    stays at the cap and friction is the distribution of least utilisation at that grip (a second
    LP); if no tangential forces can balance the wrench at all, uniform utilisation is recorded
    and the residual check decides.

Shape letters: ``b`` candidates, ``c = 3`` contacts.

References
----------
Paper §6.1 (uniform utilisation, friction-cone feasibility), §6.5 and §12 (the grip-law
asymmetry and the matched-grip control left as future work), Algorithm 1 line 6 (checks).
Murray, Li & Sastry (1994), A Mathematical Introduction to Robotic Manipulation, §5.3 (polyhedral
friction cones); Huangfu & Hall (2018), "Parallelizing the dual revised simplex method", Math.
Prog. Comp. 10:119-142 (HiGHS).
"""

from __future__ import annotations

import logging

import numpy as np
from scipy.optimize import linprog

from graspcampaign.core.contact import MM_PER_M, depth_for_force
from graspcampaign.core.statics import cone_lp_matrices
from graspcampaign.core.verdict import CandidateBatch, EquilibriumResult, EvaluatorParams, judge

__all__ = ["evaluate", "min_equal_grip", "min_utilisation", "slip_grip"]

logger = logging.getLogger(__name__)


def slip_grip(batch: CandidateBatch, safety_factor: float) -> np.ndarray:
    """Return the ``slip`` law's needed equal force ``W / (A + mu B / SF)``, shape (b,) [N].

    ``inf`` when ``A + mu B / SF <= 0`` (the fingers push the object down harder than the allowed
    friction can lift it: no equal grip holds it). See the module docstring.
    """
    a = np.sum(batch.directions[..., 2], axis=1)
    b = np.sum(batch.tangent_z, axis=1)
    lift = a + batch.mu * b / safety_factor
    with np.errstate(divide="ignore"):
        return np.where(lift > 0.0, batch.weight / np.where(lift > 0.0, lift, 1.0), np.inf)


def _linprog(cost, a_ub, a_eq, b_eq, bounds, what: str):
    """Solve with HiGHS; on an undecided status (numerical trouble on a near-degenerate contact
    set) retry with its interior-point and dual-simplex solvers. Returns the result, or None
    when the LP is infeasible or stays undecided (logged: the law then treats it as infeasible).
    """
    result = None
    for method in ("highs", "highs-ipm", "highs-ds"):
        result = linprog(cost, A_ub=a_ub, b_ub=np.zeros(len(a_ub)), A_eq=a_eq, b_eq=b_eq,
                         bounds=bounds, method=method)
        if result.status in (0, 2):
            return result if result.status == 0 else None
    logger.warning("%s LP undecided (%s); treated as infeasible", what, result.message)
    return None


def _equal_grip_columns(a_eq, a_ub):
    """Merge the three f_n columns into one shared F (equal grip): returns (a_eq, a_ub, tangential cols)."""
    normal_cols = np.arange(0, a_eq.shape[1], 3)
    tangential = np.setdiff1d(np.arange(a_eq.shape[1]), normal_cols)
    return a_eq[:, normal_cols].sum(axis=1), a_ub[:, normal_cols].sum(axis=1), tangential


def min_equal_grip(points, normals, mu: float, mass: float, center, n_facets: int, g: float):
    """Return the smallest equal normal force with a feasible friction-cone problem (LP).

    Parameters
    ----------
    points : (c, 3) float
        Contact points [m].
    normals : (c, 3) float
        Outward unit normals.
    mu : float
        Friction coefficient the cones allow [-] (the oracle passes mu/SF).
    mass : float
        Object mass [kg].
    center : (3,) float
        Centroid, the torque reference [m].
    n_facets : int
        Facets of the inscribed polyhedral cones.
    g : float
        Gravity [m/s^2].

    Returns
    -------
    grip : float
        Smallest F [N]; ``inf`` when no equal grip is feasible.
    friction : (c, 3) float or None
        Tangential force vectors of that solution [N].
    """
    rho = np.cos(np.pi / n_facets)
    basis, a_eq, b_eq, a_ub = cone_lp_matrices(points, normals, mu, rho, mass, center, g, n_facets)
    shared_eq, shared_ub, tangential = _equal_grip_columns(a_eq, a_ub)
    cost = np.zeros(1 + len(tangential))
    cost[0] = 1.0
    result = _linprog(cost, np.column_stack([shared_ub, a_ub[:, tangential]]),
                      np.column_stack([shared_eq, a_eq[:, tangential]]), b_eq,
                      [(0.0, None)] + [(None, None)] * len(tangential), "equal-grip")
    if result is None:
        return np.inf, None
    ab = result.x[1:].reshape(-1, 2)
    return float(result.x[0]), np.einsum("cij,cj->ci", basis[:, :, 1:], ab)


def min_utilisation(points, normals, grip: float, mass: float, center, n_facets: int, g: float):
    """Return the least friction utilisation that balances the object at a fixed equal grip (LP).

    Minimises s subject to zero net force and torque with every tangential force inside the
    inscribed polygon of radius ``s * grip`` (so ``|f_t,j| <= s * grip``).

    Returns
    -------
    utilisation : float
        s [-]; ``inf`` when no tangential forces can balance the wrench at this grip.
    friction : (c, 3) float or None
        Tangential force vectors [N].
    """
    rho = np.cos(np.pi / n_facets)
    basis, a_eq, b_eq, a_ub = cone_lp_matrices(points, normals, 1.0, rho, mass, center, g, n_facets)
    shared_eq, shared_ub, tangential = _equal_grip_columns(a_eq, a_ub)
    # F is fixed: its equality column moves to the right-hand side; the facet rows
    # e_k . t - rho * 1 * F_j <= 0 become e_k . t - rho s F <= 0 with s the unknown.
    cost = np.zeros(len(tangential) + 1)
    cost[-1] = 1.0
    result = _linprog(cost, np.column_stack([a_ub[:, tangential], shared_ub * grip]),
                      np.column_stack([a_eq[:, tangential], np.zeros(6)]), b_eq - shared_eq * grip,
                      [(None, None)] * len(tangential) + [(0.0, None)], "least-utilisation")
    if result is None:
        return np.inf, None
    ab = result.x[:-1].reshape(-1, 2)
    return float(result.x[-1]), np.einsum("cij,cj->ci", basis[:, :, 1:], ab)


def _cap_force(batch: CandidateBatch, params: EvaluatorParams) -> np.ndarray:
    """Force that reaches the cap depth under each candidate's law, shape (b,) [N]."""
    return batch.k * np.power(params.grip_cap_depth * MM_PER_M, batch.n)


def evaluate(batch: CandidateBatch, params: EvaluatorParams) -> EquilibriumResult:
    """Run the ``slip`` or ``oracle`` grip law on a validated batch and judge it.

    Parameters
    ----------
    batch : CandidateBatch
        From :func:`graspcampaign.core.verdict.candidate_batch`.
    params : EvaluatorParams
        ``grip_law`` selects the law; ``grip_safety_factor``, ``grip_cap_depth``, ``cone_facets``
        configure it; the tolerances judge it.

    Returns
    -------
    result : EquilibriumResult
        ``iterations`` 0 (closed form / LP, no loop), no trace; ``grip_force`` and
        ``grip_needed`` filled.
    """
    n_batch = batch.weight.shape[0]
    cap = _cap_force(batch, params)
    sf = params.grip_safety_factor
    friction = None
    if params.grip_law == "slip":
        needed = slip_grip(batch, sf)
        seed = batch.k * np.power(params.seed_depth * MM_PER_M, batch.n)
        grip = np.minimum(np.maximum(needed, seed), cap)
    elif params.grip_law == "oracle":
        needed, grip = np.empty(n_batch), np.empty(n_batch)
        friction = np.zeros((n_batch, 3, 3))
        uniform = np.zeros(n_batch, dtype=bool)
        normals = -batch.directions
        for i in range(n_batch):  # one LP per candidate; campaigns pass one triple at a time
            args = (batch.weight[i] / params.g, np.zeros(3), params.cone_facets, params.g)
            needed[i], tangential = min_equal_grip(batch.arms[i], normals[i], batch.mu[i] / sf,
                                                   *args)
            grip[i] = min(needed[i], cap[i])
            if needed[i] > cap[i]:
                _, tangential = min_utilisation(batch.arms[i], normals[i], grip[i], *args)
            if tangential is None:
                uniform[i] = True
            else:
                friction[i] = tangential
        if uniform.any():
            # No tangential set balances the wrench: record uniform utilisation (§6.1) instead
            # (with equal forces a vertical contact's own margin mu F is never the minimum).
            logger.debug("oracle: %d candidate(s) without a balancing friction set", uniform.sum())
            friction = _uniform_rows(batch, grip, friction, uniform)
    else:
        raise ValueError(f"grip law {params.grip_law!r} is not one of slip, oracle")
    # grip <= cap, so the depth is <= the cap depth; the minimum only removes the round-off of
    # K (d/K)^(1/n) that would otherwise put a capped finger a hair beyond the cap (and r).
    depth = np.minimum(depth_for_force(grip, batch.k, batch.n), params.grip_cap_depth)
    depths = np.repeat(depth[:, None], 3, axis=1)
    return judge(batch, depths, params, np.zeros(n_batch, dtype=int), None, friction=friction,
                 grip_force=grip, grip_needed=needed)


def _uniform_rows(batch: CandidateBatch, grip, friction, uniform):
    """Fill the rows flagged ``uniform`` with the §6.1 uniform-utilisation friction at ``grip``."""
    forces = np.repeat(grip[:, None], 3, axis=1)
    weight_z = batch.weight
    carrying = batch.has_tangent
    support = np.sum(np.where(carrying, forces * batch.tangent_z, 0.0), axis=1)
    normal_z = np.sum(forces * batch.directions[..., 2], axis=1)
    with np.errstate(divide="ignore", invalid="ignore"):
        eta = np.where(support > 0.0, (weight_z - normal_z) / support, 0.0)
    uniform_friction = (eta[:, None] * forces * carrying)[..., None] * batch.tangents
    return np.where(uniform[:, None, None], uniform_friction, friction)
