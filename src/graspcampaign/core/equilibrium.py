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
§6.4 (per-iteration monitors); §6.5 (grip law, horizontal normals).
"""

from __future__ import annotations

import logging
from dataclasses import dataclass

import numpy as np

from graspcampaign.core.contact import MM_PER_M, normal_force
from graspcampaign.core.statics import GRAVITY

__all__ = [
    "FAILURE_CHECKS",
    "EquilibriumResult",
    "EquilibriumTrace",
    "EvaluatorParams",
    "evaluate_grasps",
    "static_checks",
]

logger = logging.getLogger(__name__)

FAILURE_CHECKS = ("none", "residual", "torque", "slip")
"""Labels of ``EquilibriumResult.failure_check`` codes 0-3 (first failing check, in this order)."""


@dataclass(frozen=True)
class EvaluatorParams:
    """Constants of the quasi-static evaluator (Algorithms 1-2).

    Attributes
    ----------
    seed_depth : float
        Initial penetration of every contact [m] (Algorithm 2 line 1: 0.5 mm).
    n_max : int
        Equilibrium-loop iterations (§11: 100).
    alpha : float
        Step gain of Algorithm 2 line 7 [-]. Default 1: the published denominator already holds
        ``2 sum|g_j|``, so alpha = 1 closes half of the linearised vertical residual per iteration
        (contraction 1/2; alpha = 2 would be the undamped Newton step, which overshoots for the
        convex n > 1 law). See docs/decisions.md.
    eps : float
        Regulariser of line 7 [N/m] (the gradient is taken per metre of penetration). Default
        1e-6 N/m: it only prevents 0/0 when every g_k vanishes (all normals horizontal or all
        contacts released); it is >= 4 orders below the vertical stiffness of any engaged contact
        within the PSO bounds, so it never alters a real step. See docs/decisions.md.
    tau_f : float
        Force-residual tolerance on the normal-only ``|R|`` [N] (§3.7, §6.1: 0.5 N).
    tau_t : float
        Torque-residual tolerance on ``|tau|`` about the centroid [N*m]. Default 0.025 N*m: the
        force tolerance 0.5 N acting at the 5 cm reference object radius (Table 2). The paper pins
        it without publishing it and notes it is never binding (§3.7).
    g : float
        Gravitational acceleration [m/s^2].
    residual_check : {"norm", "vertical"}
        Quantity compared with tau_f. ``"norm"`` (default): the normal-only 3-vector residual
        ``|R|`` of Algorithm 1 line 6 and SPEC §2.7. ``"vertical"``: ``|R_z|`` only, the reading of
        the paper's prose (§3.7, §6.2, §6.5 speak of the vertical normal-only residual). Both
        quantities are always returned; see docs/decisions.md.
    normal_z_tol : float
        ``|n_z|`` below this counts as exactly horizontal (no vertical gradient) and ``1 - |n_z|``
        below it as exactly vertical (no tangent, excluded from the slip margin) [-]. A float-noise
        guard for mesh normals, not a physical constant.
    """

    seed_depth: float = 5.0e-4
    n_max: int = 100
    alpha: float = 1.0
    eps: float = 1.0e-6
    tau_f: float = 0.5
    tau_t: float = 0.025
    g: float = GRAVITY
    residual_check: str = "norm"
    normal_z_tol: float = 1.0e-9

    def __post_init__(self) -> None:
        if not (np.isfinite(self.seed_depth) and self.seed_depth > 0.0):
            raise ValueError(f"EvaluatorParams.seed_depth must be > 0 m, got {self.seed_depth!r}")
        if int(self.n_max) != self.n_max or self.n_max < 0:
            raise ValueError(f"EvaluatorParams.n_max must be a non-negative int, got {self.n_max!r}")
        for name in ("alpha", "eps", "tau_f", "tau_t", "g"):
            value = getattr(self, name)
            if not (np.isfinite(value) and value > 0.0):
                raise ValueError(f"EvaluatorParams.{name} must be finite and > 0, got {value!r}")
        if self.residual_check not in ("norm", "vertical"):
            raise ValueError(
                f"EvaluatorParams.residual_check must be 'norm' or 'vertical', got {self.residual_check!r}"
            )
        if not 0.0 <= self.normal_z_tol < 1.0:
            raise ValueError(f"EvaluatorParams.normal_z_tol must lie in [0, 1), got {self.normal_z_tol!r}")


@dataclass(frozen=True)
class EquilibriumTrace:
    """Per-iteration monitors of Algorithm 2 (the four quantities of §6.4), batch first.

    Entry ``[:, i]`` is evaluated at the penetrations used by iteration ``i + 1`` (lines 3-5),
    i.e. before that iteration's update.

    Attributes
    ----------
    residual_norm : (b, i) float
        Normal-only force residual ``|R|`` [N].
    residual_z : (b, i) float
        Its vertical component R_z [N].
    torque_norm : (b, i) float
        Normal-only torque ``|tau|`` about the centroid [N*m].
    slip_margin : (b, i) float
        ``min_j f_n,j (mu - |eta|)`` under uniform utilisation at those forces [N].
    slip_margin_ratio : (b, i) float
        Normalised margin ``min_j (mu f_n,j - |f_t,j|)/(mu f_n,j) = 1 - |eta|/mu`` (§6.4) [-].
    eta : (b, i) float
        Utilisation [-].
    normal_forces : (b, i, 3) float
        Per-finger normal forces [N] (finger 1 is ``[:, :, 0]``).
    depths : (b, i, 3) float
        Penetrations [m].
    """

    residual_norm: np.ndarray
    residual_z: np.ndarray
    torque_norm: np.ndarray
    slip_margin: np.ndarray
    slip_margin_ratio: np.ndarray
    eta: np.ndarray
    normal_forces: np.ndarray
    depths: np.ndarray


@dataclass(frozen=True)
class EquilibriumResult:
    """Outcome of the quasi-static evaluator for ``b`` candidate grasps.

    Attributes
    ----------
    success : (b,) bool
        All three checks of Algorithm 1 line 6 pass.
    failure_check : (b,) int8
        First failing check, coded by :data:`FAILURE_CHECKS`: 0 none, 1 residual, 2 torque,
        3 slip (checked in that order).
    residual_ok, torque_ok, slip_ok : (b,) bool
        The three checks separately (``|R| < tau_F`` (or ``|R_z| < tau_F``, see
        ``EvaluatorParams.residual_check``), ``|tau| < tau_T``, slip margin > 0).
    residual_norm : (b,) float
        Normal-only force residual ``|sum_k f_n,k n_hat_k + m g|`` at the returned depths,
        before friction [N] (§6.1: the quantity the 0.5 N criterion applies to).
    residual_z : (b,) float
        Its vertical component R_z [N].
    torque_norm : (b,) float
        Normal-only torque ``|sum_k r_k x f_n,k n_hat_k|`` about the centroid [N*m].
    slip_margin : (b,) float
        ``min_j (mu f_n,j - |f_t,j|) = min_j f_n,j (mu - |eta|)`` over contacts with a tangent
        [N], taken over *loaded* contacts (f_n > 0) whose normal is not vertical; ``+inf`` when
        there is none (the empty minimum: friction carries nothing, the slip check passes
        vacuously and the normal-only residual check alone decides).
    slip_margin_ratio : (b,) float
        ``1 - |eta|/mu`` over the same contacts (§6.4's normalised margin) [-]; same conventions.
    eta : (b,) float
        Uniform utilisation ``-R_z / sum_j f_n,j t_hat_j,z`` (not capped at mu; negative when
        the normal forces over-support the weight) [-]; ``nan`` when no loaded contact has a
        tangent.
    post_friction_residual_z : (b,) float
        Vertical residual after adding ``f_t,j = eta f_n,j t_hat_j`` [N]; zero by construction
        whenever eta is finite (§6.1).
    normal_forces : (b, 3) float
        Normal force per finger at the returned depths [N].
    depths : (b, 3) float
        Returned penetrations delta [m].
    delta_max_mm : (b,) float
        Largest penetration [mm] (the 1 mm design limit of §4 is not enforced here).
    iterations : (b,) int
        Index of the last iteration that changed delta (N_max if it never reached a fixed point;
        0 if the seed was already a fixed point, e.g. all normals horizontal). The loop itself
        always runs the published N_max iterations; iterations past a fixed point are no-ops.
    trace : EquilibriumTrace or None
        Per-iteration monitors when requested.
    """

    success: np.ndarray
    failure_check: np.ndarray
    residual_ok: np.ndarray
    torque_ok: np.ndarray
    slip_ok: np.ndarray
    residual_norm: np.ndarray
    residual_z: np.ndarray
    torque_norm: np.ndarray
    slip_margin: np.ndarray
    slip_margin_ratio: np.ndarray
    eta: np.ndarray
    post_friction_residual_z: np.ndarray
    normal_forces: np.ndarray
    depths: np.ndarray
    delta_max_mm: np.ndarray
    iterations: np.ndarray
    trace: EquilibriumTrace | None = None

    def failure_labels(self) -> np.ndarray:
        """Return ``failure_check`` as strings from :data:`FAILURE_CHECKS`, shape (b,)."""
        return np.asarray(FAILURE_CHECKS, dtype=object)[self.failure_check]


def _check_contacts(points, normals) -> tuple[np.ndarray, np.ndarray]:
    points = np.asarray(points, dtype=float)
    normals = np.asarray(normals, dtype=float)
    if points.ndim == 2:
        points = points[None]
    if normals.ndim == 2:
        normals = normals[None]
    if points.ndim != 3 or points.shape[1:] != (3, 3):
        raise ValueError(f"points must have shape (b, 3, 3), got {points.shape}")
    if normals.shape != points.shape:
        raise ValueError(f"normals must have shape {points.shape}, got {normals.shape}")
    lengths = np.linalg.norm(normals, axis=-1)
    if not np.allclose(lengths, 1.0, atol=1e-6):
        raise ValueError(
            f"normals must be unit vectors, got lengths in [{lengths.min():.3g}, {lengths.max():.3g}]"
        )
    return points, normals


def _per_candidate(value, n_batch: int, name: str) -> np.ndarray:
    array = np.asarray(value, dtype=float)
    if array.ndim == 0:
        return np.full(n_batch, float(array))
    if array.shape != (n_batch,):
        raise ValueError(f"{name} must be a scalar or have shape ({n_batch},), got {array.shape}")
    return array


@dataclass(frozen=True)
class _Candidates:
    """Per-candidate geometry and constants shared by the loop and the checks."""

    directions: np.ndarray  # (b, 3, 3) force directions n_hat = -n_out
    arms: np.ndarray  # (b, 3, 3) r_k = p_k - centroid [m]
    direction_z: np.ndarray  # (b, 3) n_hat_z with float noise zeroed
    tangent_z: np.ndarray  # (b, 3) t_hat_z = |proj of +z on the tangent plane|
    has_tangent: np.ndarray  # (b, 3) bool
    weight: np.ndarray  # (b,) m g [N]
    mu: np.ndarray  # (b,)
    k: np.ndarray  # (b,) K [N*mm^-n]
    n: np.ndarray  # (b,)


def _candidates(points, normals, centroid, mass, mu, k_n_per_mm_n, n, params) -> _Candidates:
    """Validate the inputs shared by :func:`evaluate_grasps` and :func:`static_checks`."""
    points, normals = _check_contacts(points, normals)
    n_batch = points.shape[0]
    weight = _per_candidate(mass, n_batch, "mass") * params.g
    mu = _per_candidate(mu, n_batch, "mu")
    k = _per_candidate(k_n_per_mm_n, n_batch, "k_n_per_mm_n")
    n = _per_candidate(n, n_batch, "n")
    if np.any(~np.isfinite(k) | (k <= 0.0) | ~np.isfinite(n) | (n <= 0.0)):
        raise ValueError("k_n_per_mm_n and n must be finite and > 0")
    tol = params.normal_z_tol
    directions = -normals
    direction_z = np.where(np.abs(directions[..., 2]) <= tol, 0.0, directions[..., 2])
    # t_hat_j is the unit projection of -g_hat = +z on the tangent plane; its z-component is
    # sqrt(1 - n_z^2) >= 0, so friction along +eta t_hat supports the weight (§6.1, Alg. 1 l.5).
    has_tangent = np.abs(normals[..., 2]) < 1.0 - tol
    tangent_z = np.where(has_tangent, np.sqrt(np.clip(1.0 - normals[..., 2] ** 2, 0.0, 1.0)), 0.0)
    return _Candidates(
        directions=directions,
        arms=points - np.asarray(centroid, dtype=float),
        direction_z=direction_z,
        tangent_z=tangent_z,
        has_tangent=has_tangent,
        weight=weight,
        mu=mu,
        k=k,
        n=n,
    )


@dataclass(frozen=True)
class _Wrench:
    forces: np.ndarray  # (b, 3)
    residual: np.ndarray  # (b, 3)
    torque: np.ndarray  # (b, 3)
    eta: np.ndarray  # (b,)
    slip_margin: np.ndarray  # (b,)
    slip_margin_ratio: np.ndarray  # (b,)
    post_friction_residual_z: np.ndarray  # (b,)


def _wrench(batch: _Candidates, depths) -> _Wrench:
    """Evaluate lines 3-5 of Algorithm 2 and line 5 of Algorithm 1 at the given depths."""
    forces = normal_force(depths, 0.0, batch.k[:, None], batch.n[:, None], 0.0)
    residual = np.einsum("bk,bkx->bx", forces, batch.directions)
    residual[:, 2] -= batch.weight
    torque = np.einsum("bkx,bk->bx", np.cross(batch.arms, batch.directions), forces)

    # Friction acts only at loaded contacts with a tangent: a vertical normal has no tangent
    # plane direction (§6.1) and a released contact (f_n = 0) carries no tangential load under
    # f_t = eta f_n t_hat either, so both are left out of the minimum.
    carrying = batch.has_tangent & (forces > 0.0)
    support = np.sum(np.where(carrying, forces * batch.tangent_z, 0.0), axis=1)
    loaded = np.any(carrying, axis=1) & (support > 0.0)
    with np.errstate(divide="ignore", invalid="ignore"):
        eta = np.where(loaded, -residual[:, 2] / support, np.nan)
    post_friction_z = np.where(loaded, residual[:, 2] + eta * support, residual[:, 2])

    mu = batch.mu
    abs_eta = np.where(loaded, np.abs(eta), 0.0)
    per_contact = np.where(carrying, forces * (mu[:, None] - abs_eta[:, None]), np.inf)
    margin = np.min(per_contact, axis=1)  # +inf for the empty set
    ratio = np.where(loaded, 1.0 - abs_eta / mu, np.inf)
    return _Wrench(forces, residual, torque, eta, margin, ratio, post_friction_z)


class _Loop:
    """Algorithm 2 lines 3-7 for a whole batch, with per-candidate constants hoisted."""

    def __init__(self, batch: _Candidates, alpha: float, eps: float):
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
    batch = _candidates(points, normals, centroid, mass, mu, k_n_per_mm_n, n, params)
    n_batch = batch.weight.shape[0]
    depths = np.asarray(depths, dtype=float).reshape(n_batch, 3)
    return _result(batch, depths, params, np.zeros(n_batch, dtype=int), None)


def _result(batch: _Candidates, depths, params, iterations, trace) -> EquilibriumResult:
    wrench = _wrench(batch, depths)
    residual_norm = np.linalg.norm(wrench.residual, axis=1)
    torque_norm = np.linalg.norm(wrench.torque, axis=1)
    checked = residual_norm if params.residual_check == "norm" else np.abs(wrench.residual[:, 2])
    residual_ok = checked < params.tau_f
    torque_ok = torque_norm < params.tau_t
    slip_ok = wrench.slip_margin > 0.0
    failure = np.select([~residual_ok, ~torque_ok, ~slip_ok], [1, 2, 3], default=0).astype(np.int8)
    return EquilibriumResult(
        success=residual_ok & torque_ok & slip_ok,
        failure_check=failure,
        residual_ok=residual_ok,
        torque_ok=torque_ok,
        slip_ok=slip_ok,
        residual_norm=residual_norm,
        residual_z=wrench.residual[:, 2],
        torque_norm=torque_norm,
        slip_margin=wrench.slip_margin,
        slip_margin_ratio=wrench.slip_margin_ratio,
        eta=wrench.eta,
        post_friction_residual_z=wrench.post_friction_residual_z,
        normal_forces=wrench.forces,
        depths=depths,
        delta_max_mm=np.max(depths, axis=1) * MM_PER_M,
        iterations=iterations,
        trace=trace,
    )


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
        Seed, N_max, alpha, eps, tolerances (defaults when omitted).
    record_trace : bool
        Also return the per-iteration monitors of §6.4.

    Returns
    -------
    result : EquilibriumResult
        Batch-first arrays; see its attributes.

    Notes
    -----
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
    batch = _candidates(points, normals, centroid, mass, mu, k_n_per_mm_n, n, params)
    n_batch = batch.weight.shape[0]
    loop = _Loop(batch, params.alpha, params.eps)
    depths = np.full((n_batch, 3), params.seed_depth)
    last_change = np.zeros(n_batch, dtype=int)
    monitors = [] if record_trace else None
    with np.errstate(divide="ignore", invalid="ignore"):
        for iteration in range(1, params.n_max + 1):
            forces = loop.forces(depths)
            if monitors is not None:
                monitors.append((depths, _wrench(batch, depths)))
            updated = loop.step(depths, forces, loop.residual_z(forces))
            changed = np.any(updated != depths, axis=1)
            last_change[changed] = iteration
            depths = updated
            if monitors is None and not changed.any():
                break  # every candidate is at a floating-point fixed point: the rest are no-ops

    trace = None
    if monitors is not None:
        trace = _stack_trace(monitors, n_batch)
    return _result(batch, depths, params, last_change, trace)


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
