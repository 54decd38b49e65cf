"""Quasi-static grasp evaluator: Algorithm 2 (equilibrium loop) and the checks of Algorithm 1.

Shape letters: ``b`` candidates (a plan's triples, a PSO swarm), ``c = 3`` contacts, ``i`` loop
iterations. Every candidate advances through the loop together as arrays; the only Python loop is
over Algorithm 2's N_max iterations.

Conventions: contact normals are *outward* unit normals ``n_out``; a finger pushes the object along
``n_hat = -n_out`` (SPEC §1), which is the ``n_hat_k`` of Algorithm 2. World z is up, gravity -z.
Penetrations are stored in metres; the contact law converts to millimetres at its boundary.

References
----------
Algorithms 1-2 and §11 of the paper (seed, N_max, update rule, checks); §3.7 (Eq. 19, tau_F);
§6.1 (uniform utilisation, eta not capped, normal-only residual check, slip-margin definition);
§6.4 (per-iteration monitors); §6.5 (grip law, horizontal normals). The other grip laws
(``slip``, ``oracle``; §6.5, §12 future work) live in :mod:`graspcampaign.core.grip` and return
the same :class:`EquilibriumResult`, judged by the same checks (:func:`graspcampaign.core.verdict.judge`).
"""

from __future__ import annotations

import logging

import numpy as np

from graspcampaign.core.contact import MM_PER_M
from graspcampaign.core.equilibrium_loop import algorithm2_depths
from graspcampaign.core.verdict import (
    FAILURE_CHECKS,
    GRIP_LAWS,
    CandidateBatch,
    EquilibriumResult,
    EquilibriumTrace,
    EvaluatorParams,
    candidate_batch,
    geometry_valid,
    judge,
    resolve,
)

__all__ = [
    "FAILURE_CHECKS",
    "GRIP_LAWS",
    "EquilibriumResult",
    "EquilibriumTrace",
    "EvaluatorParams",
    "evaluate_grasps",
    "geometry_valid",
    "static_checks",
]

logger = logging.getLogger(__name__)


class _Loop:
    """Algorithm 2 lines 3-7 for a whole batch, with per-candidate constants hoisted."""

    def __init__(self, batch: CandidateBatch, alpha: float, eps: float):
        self.k = batch.k[:, None]
        self.n = batch.n[:, None]
        self.force_z = batch.directions[..., 2]
        self.gradient_z = batch.direction_z
        self.weight = batch.weight
        self.alpha = alpha
        self.eps = eps
        # One-sided stiffness at delta = 0 [N/m]: 1000 K for n = 1, 0 for n > 1, and 0 for n < 1
        # where it is literally infinite: a released contact carries no force and taking the
        # infinite gradient literally would make every other contact's step finite/inf = 0,
        # freezing the candidate. So it stays released, as it does literally for n > 1.
        self.stiffness_at_zero = np.where(self.n == 1.0, MM_PER_M * self.k, 0.0)

    def forces(self, depths):
        """Line 3: ``f_n,k = K delta_k^n`` (delta in mm; the rate term vanishes).

        ``contact.normal_force`` without its open-contact and clamp guards, which are no-ops
        here (the loop keeps delta >= 0 and the rate term is zero): this runs N_max times per
        batch.
        """
        return self.k * np.power(depths * MM_PER_M, self.n)

    def residual_z(self, forces):
        """Line 4, vertical component: ``R_z = sum_k f_n,k n_hat_k,z - m g``."""
        return np.sum(forces * self.force_z, axis=1) - self.weight

    def step(self, depths, forces, residual_z):
        """Lines 6-7 on every candidate at once; returns the new depths."""
        # d(K (1000 delta)^n)/d delta = n f / delta per metre of penetration (0/0 at a released
        # contact is replaced; the caller silences that warning once for the whole loop).
        stiffness = np.where(depths <= 0.0, self.stiffness_at_zero, self.n * forces / depths)
        gradient = self.gradient_z * stiffness  # g_k = n_hat_k,z n K delta^(n-1)
        denominator = 2.0 * np.sum(np.abs(gradient), axis=1) + self.eps
        scale = self.alpha * (-residual_z) / denominator
        return np.maximum(0.0, depths + scale[:, None] * np.sign(gradient))


def static_checks(points, normals, centroid, mass, mu, depths, k_n_per_mm_n, n, params=None):
    """Return the checks of Algorithm 1 lines 5-6 at given penetrations, without the loop.

    Used for the final checks of :func:`evaluate_grasps` and for fixed-grip studies (§6.4).

    Parameters
    ----------
    points : (b, 3, 3) float
        Contact points in W [m].
    normals : (b, 3, 3) float
        Outward unit surface normals at the contacts.
    centroid : (3,) float
        Object centroid in W [m] (torque reference; the weight acts here).
    mass : float or (b,) float
        Object mass [kg].
    mu : float or (b,) float
        Friction coefficient [-].
    depths : (b, 3) float
        Penetrations [m].
    k_n_per_mm_n : float or (b,) float
        Contact stiffness K [N*mm^-n].
    n : float or (b,) float
        Contact exponent [-].
    params : EvaluatorParams, optional
        Tolerances and g (defaults when omitted).

    Returns
    -------
    result : EquilibriumResult
        With ``iterations`` zero and no trace.
    """
    params = EvaluatorParams() if params is None else params
    batch = candidate_batch(points, normals, centroid, mass, mu, k_n_per_mm_n, n, params)
    n_batch = batch.weight.shape[0]
    depths = np.asarray(depths, dtype=float).reshape(n_batch, 3)
    return judge(batch, depths, params, np.zeros(n_batch, dtype=int), None)


def evaluate_grasps(
    points,
    normals,
    centroid,
    mass,
    mu,
    k_n_per_mm_n,
    n,
    params=None,
    *,
    record_trace: bool = False,
) -> EquilibriumResult:
    """Run Algorithm 2 on a batch of three-contact grasps, then the checks of Algorithm 1.

    Parameters
    ----------
    points : (b, 3, 3) float
        Contact points in W [m] (a single (3, 3) grasp is accepted as b = 1).
    normals : (b, 3, 3) float
        Outward unit surface normals ``n_out`` at the contacts; forces push along ``-n_out``.
    centroid : (3,) float
        Object centroid in W [m].
    mass : float or (b,) float
        Object mass [kg].
    mu : float or (b,) float
        Friction coefficient [-] (mu_s = mu_k in the simulation sweeps, §3.5).
    k_n_per_mm_n : float or (b,) float
        Contact stiffness K [N*mm^-n] (per candidate for a PSO swarm).
    n : float or (b,) float
        Contact exponent [-].
    params : EvaluatorParams, optional
        Seed, N_max, alpha, eps, tolerances, grip law (defaults when omitted).
    record_trace : bool
        Also return the per-iteration monitors of §6.4 (``paper`` law only; the other laws are
        not iterative and return no trace).

    Returns
    -------
    result : EquilibriumResult
        Batch-first arrays; see its attributes.

    Notes
    -----
    ``params.grip_law`` other than ``"paper"`` hands the batch to :mod:`graspcampaign.core.grip`.
    Literal Algorithm 2: ``delta_k = 0.5 mm``; ``N_max`` times: ``f_n,k = K delta_k^n`` (the rate
    term vanishes), ``R = sum_k f_n,k n_hat_k + m g``, ``tau = sum_k r_k x f_n,k n_hat_k``,
    ``g_k = n_hat_k,z dF/d delta_k``, ``delta_k <- max(0, delta_k + alpha (-R_z) sgn(g_k) /
    (2 sum_j |g_j| + eps))``. The gradient is per metre of penetration (the same step as working
    in millimetres with eps/1000 N/mm); mixing the two conventions would scale the step by 1000.
    Only R_z is controlled: horizontal residuals are whatever the geometry leaves (§6.1, §11).
    The checks then use the normal-only ``|R|`` and ``|tau|`` at the returned depths and the slip
    margin after uniform utilisation (Algorithm 1 lines 5-6). Penetrations are never capped or
    rescaled; ``delta_max_mm`` reports them (SPEC §2.7).

    References
    ----------
    Algorithms 1-2, §6.1, §6.5, §11; Eq. 13, Eq. 19.
    """
    params = EvaluatorParams() if params is None else params
    batch = candidate_batch(points, normals, centroid, mass, mu, k_n_per_mm_n, n, params)
    if params.grip_law != "paper":
        from graspcampaign.core import grip  # grip builds on this module's checks

        return grip.evaluate(batch, params)
    if record_trace:
        monitors = []
        depths, last_change = algorithm2_numpy(batch, params, monitors)
        return judge(batch, depths, params, last_change, _stack_trace(monitors, len(batch.weight)))
    depths, last_change = algorithm2_depths(
        batch.k, batch.n, np.ascontiguousarray(batch.directions[..., 2]), batch.direction_z,
        batch.weight, float(params.seed_depth), int(params.n_max), float(params.alpha),
        float(params.eps))
    return judge(batch, depths, params, last_change, None)


def algorithm2_numpy(batch: CandidateBatch, params: EvaluatorParams, monitors: list | None = None):
    """Algorithm 2 lines 3-7 in numpy: ``(depths (b, 3) [m], last_change (b,))``.

    The reference of the compiled loop (:func:`graspcampaign.core.equilibrium_loop.algorithm2_depths`,
    the same numbers bit for bit where numpy rounds as libm) and the traced path: with ``monitors``
    a list, the depths and resolved wrench of every iteration are appended to it and all N_max
    iterations run.
    """
    n_batch = batch.weight.shape[0]
    loop = _Loop(batch, params.alpha, params.eps)
    depths = np.full((n_batch, 3), params.seed_depth)
    last_change = np.zeros(n_batch, dtype=int)
    with np.errstate(divide="ignore", invalid="ignore"):
        for iteration in range(1, params.n_max + 1):
            forces = loop.forces(depths)
            if monitors is not None:
                monitors.append((depths, resolve(batch, depths)))
            updated = loop.step(depths, forces, loop.residual_z(forces))
            changed = np.any(updated != depths, axis=1)
            last_change[changed] = iteration
            depths = updated
            if monitors is None and not changed.any():
                break  # every candidate is at a floating-point fixed point: the rest are no-ops
    return depths, last_change


def _stack_trace(monitors, n_batch: int) -> EquilibriumTrace:
    if not monitors:
        empty = np.zeros((n_batch, 0))
        return EquilibriumTrace(
            empty, empty, empty, empty, empty, empty, np.zeros((n_batch, 0, 3)), np.zeros((n_batch, 0, 3))
        )
    depths = np.stack([d for d, _ in monitors], axis=1)
    wrenches = [w for _, w in monitors]
    return EquilibriumTrace(
        residual_norm=np.stack([np.linalg.norm(w.residual, axis=1) for w in wrenches], axis=1),
        residual_z=np.stack([w.residual[:, 2] for w in wrenches], axis=1),
        torque_norm=np.stack([np.linalg.norm(w.torque, axis=1) for w in wrenches], axis=1),
        slip_margin=np.stack([w.slip_margin for w in wrenches], axis=1),
        slip_margin_ratio=np.stack([w.slip_margin_ratio for w in wrenches], axis=1),
        eta=np.stack([w.eta for w in wrenches], axis=1),
        normal_forces=np.stack([w.forces for w in wrenches], axis=1),
        depths=depths,
    )
