"""The verdict shared by every grip law: friction resolution, the checks of Algorithm 1, validity.

Algorithm 2 (:mod:`graspcampaign.core.equilibrium`) and the ``slip`` and ``oracle`` grip laws
(:mod:`graspcampaign.core.grip`) each produce a force state; this module resolves the friction
(uniform utilisation, §6.1, unless a law supplies its own tangential forces), evaluates the checks
of Algorithm 1 line 6 and the physical-validity gate, and returns one :class:`EquilibriumResult`.
It also holds the evaluator's parameters, so every law reads one :class:`EvaluatorParams`.

Shape letters: ``b`` candidates, ``c = 3`` contacts, ``i`` loop iterations.

Conventions: contact normals are *outward* unit normals ``n_out``; a finger pushes the object along
``n_hat = -n_out`` (SPEC §1). World z is up, gravity -z. Penetrations are stored in metres.

References
----------
Algorithm 1 (§11) lines 5-6; §3.7 (Eq. 19, tau_F); §6.1 (uniform utilisation, eta not capped,
normal-only residual check, slip-margin definition); §6.4 (monitors); issue 13 (validity gate).
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from graspcampaign.core.contact import MM_PER_M, normal_force
from graspcampaign.core.statics import GRAVITY

__all__ = [
    "FAILURE_CHECKS",
    "GRIP_LAWS",
    "CandidateBatch",
    "EquilibriumResult",
    "EquilibriumTrace",
    "EvaluatorParams",
    "candidate_batch",
    "geometry_valid",
    "judge",
    "readings",
    "resolve",
]

FAILURE_CHECKS = ("none", "residual", "torque", "slip", "geometry")
"""Labels of ``EquilibriumResult.failure_check`` codes 0-4: the first failing check, in this order.

``geometry`` (a contact deeper than the fingertip radius) comes last, so it is the label exactly
when the validity gate alone rejected a grasp the three checks of Algorithm 1 passed."""

GRIP_LAWS = ("paper", "slip", "oracle")
"""Grip laws: Algorithm 2 (the paper's, default) and the two of :mod:`graspcampaign.core.grip`."""


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
    fingertip_radius : float
        Validity bound r [m]: a contact deeper than the fingertip radius is not a contact
        (:func:`geometry_valid`); Table 2's 5 mm by default.
    grip_law : {"paper", "slip", "oracle"}
        Which law sets the grip (:data:`GRIP_LAWS`); ``"paper"`` is Algorithm 2 as published.
    grip_safety_factor : float
        Friction design margin SF > 1 of the ``slip`` and ``oracle`` laws: they size the grip so
        that every contact uses at most mu/SF of its friction (:mod:`graspcampaign.core.grip`).
    grip_cap_depth : float
        Deepest penetration the ``slip`` and ``oracle`` laws may command [m] (their grip cap);
        5 mm, the default fingertip radius, here; the campaign passes the material's damage
        depth bounded by the radius. Algorithm 2 has no cap.
    cone_facets : int
        Facets of the polyhedral friction cones of the ``oracle`` law's LP (statics module).
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
    fingertip_radius: float = 5.0e-3
    grip_law: str = "paper"
    grip_safety_factor: float = 1.5
    grip_cap_depth: float = 5.0e-3
    cone_facets: int = 16

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
        if self.grip_law not in GRIP_LAWS:
            raise ValueError(f"EvaluatorParams.grip_law must be one of {', '.join(GRIP_LAWS)}, "
                             f"got {self.grip_law!r}")
        if not (self.fingertip_radius > 0.0 and 0.0 < self.grip_cap_depth < np.inf
                and self.grip_safety_factor > 1.0 and self.cone_facets >= 3):
            raise ValueError("EvaluatorParams needs fingertip_radius > 0, a finite grip_cap_depth > 0, "
                             "grip_safety_factor > 1 and cone_facets >= 3")


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
        All three checks of Algorithm 1 line 6 pass *and* the geometry is valid.
    success_unbounded : (b,) bool
        The three checks alone (Algorithm 1 line 6 as published, no validity gate).
    valid_geometry : (b,) bool
        Every active contact (delta > 0) lies within the fingertip radius (:func:`geometry_valid`).
    failure_check : (b,) int8
        First failing check, coded by :data:`FAILURE_CHECKS`: 0 none, 1 residual, 2 torque,
        3 slip, 4 geometry (checked in that order).
    residual_ok, torque_ok, slip_ok : (b,) bool
        The three checks separately. ``paper`` law: ``|R| < tau_F`` (or ``|R_z| < tau_F``, see
        ``EvaluatorParams.residual_check``) and ``|tau| < tau_T`` on the normal-only residuals;
        ``slip`` and ``oracle`` laws: the same on the full post-friction residuals
        (``full_residual_norm``, its z-component, ``full_torque_norm``); slip margin > 0.
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
        At ``mu = 0`` its limits: 1 when no friction is demanded (``eta = 0``), ``-inf`` otherwise.
    eta : (b,) float
        Uniform utilisation ``-R_z / sum_j f_n,j t_hat_j,z`` (not capped at mu; negative when
        the normal forces over-support the weight) [-]; ``nan`` when no loaded contact has a
        tangent.
    post_friction_residual_z : (b,) float
        Vertical residual after adding the friction forces [N] (uniform utilisation
        ``f_t,j = eta f_n,j t_hat_j``: zero by construction whenever eta is finite, §6.1).
    full_residual_norm : (b,) float
        ``|sum_j (f_n,j n_hat_j + f_t,j) + m g|`` with the law's friction forces [N].
    full_torque_norm : (b,) float
        ``|sum_j r_j x (f_n,j n_hat_j + f_t,j)|`` about the centroid [N*m].
    rho : (b,) float
        Horizontal normal-only residual over the weight, ``|R_xy| / (m g)`` [-].
    grip_force : (b,) float
        Per-finger normal force the ``slip``/``oracle`` law commands [N] (NaN for ``paper``).
    grip_needed : (b,) float
        The force that law needs before its cap [N] (``inf``: no finite grip; NaN for ``paper``).
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
    success_unbounded: np.ndarray
    valid_geometry: np.ndarray
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
    full_residual_norm: np.ndarray
    full_torque_norm: np.ndarray
    rho: np.ndarray
    normal_forces: np.ndarray
    depths: np.ndarray
    delta_max_mm: np.ndarray
    iterations: np.ndarray
    grip_force: np.ndarray
    grip_needed: np.ndarray
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
class CandidateBatch:
    """Per-candidate geometry and constants shared by every grip law and the checks."""

    directions: np.ndarray  # (b, 3, 3) force directions n_hat = -n_out
    arms: np.ndarray  # (b, 3, 3) r_k = p_k - centroid [m]
    direction_z: np.ndarray  # (b, 3) n_hat_z with float noise zeroed
    tangents: np.ndarray  # (b, 3, 3) t_hat = unit projection of +z on the tangent plane (0 if none)
    tangent_z: np.ndarray  # (b, 3) t_hat_z = |proj of +z on the tangent plane|
    has_tangent: np.ndarray  # (b, 3) bool
    weight: np.ndarray  # (b,) m g [N]
    mu: np.ndarray  # (b,)
    k: np.ndarray  # (b,) K [N*mm^-n]
    n: np.ndarray  # (b,)


def candidate_batch(points, normals, centroid, mass, mu, k_n_per_mm_n, n, params) -> CandidateBatch:
    """Validate a batch of contact triples and precompute what every grip law needs."""
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
    projected = np.array([0.0, 0.0, 1.0]) - normals[..., 2:3] * normals
    with np.errstate(divide="ignore", invalid="ignore"):
        tangents = np.where(has_tangent[..., None], projected / tangent_z[..., None], 0.0)
    return CandidateBatch(
        directions=directions,
        arms=points - np.asarray(centroid, dtype=float),
        direction_z=direction_z,
        tangents=tangents,
        tangent_z=tangent_z,
        has_tangent=has_tangent,
        weight=weight,
        mu=mu,
        k=k,
        n=n,
    )


@dataclass(frozen=True)
class Resolved:
    forces: np.ndarray  # (b, 3)
    residual: np.ndarray  # (b, 3) normal-only
    torque: np.ndarray  # (b, 3) normal-only
    eta: np.ndarray  # (b,)
    slip_margin: np.ndarray  # (b,)
    slip_margin_ratio: np.ndarray  # (b,)
    full_residual: np.ndarray  # (b, 3) with friction
    full_torque: np.ndarray  # (b, 3) with friction


def resolve(batch: CandidateBatch, depths, friction=None) -> Resolved:
    """Evaluate lines 3-5 of Algorithm 2 and line 5 of Algorithm 1 at the given depths.

    ``friction`` (b, 3, 3) replaces uniform utilisation by given tangential force vectors [N]
    (the ``oracle`` law's LP solution); the slip margin then runs over every loaded contact.
    """
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
    mu = batch.mu
    if friction is None:
        abs_eta = np.where(loaded, np.abs(eta), 0.0)
        per_contact = np.where(carrying, forces * (mu[:, None] - abs_eta[:, None]), np.inf)
        # 1 - |eta|/mu and its limits at mu = 0: no demand uses none of the cone, any demand
        # exceeds it (-inf); np.where evaluates every row, so the unloaded rows' 0/0 is kept out
        with np.errstate(divide="ignore"):
            used = np.where(abs_eta > 0.0, abs_eta / np.where(abs_eta > 0.0, mu, 1.0), 0.0)
        ratio = np.where(loaded, 1.0 - used, np.inf)
        scale = np.where(carrying, np.where(loaded, eta, 0.0)[:, None] * forces, 0.0)
        friction = scale[..., None] * batch.tangents
    else:
        eta = np.full_like(eta, np.nan)
        used = np.linalg.norm(friction, axis=2)
        carrying = forces > 0.0
        per_contact = np.where(carrying, mu[:, None] * forces - used, np.inf)
        with np.errstate(divide="ignore", invalid="ignore"):
            ratio = np.min(np.where(carrying, 1.0 - used / (mu[:, None] * forces), np.inf), axis=1)
    margin = np.min(per_contact, axis=1)  # +inf for the empty set
    full_residual = residual + friction.sum(axis=1)
    full_torque = torque + np.cross(batch.arms, friction).sum(axis=1)
    return Resolved(forces, residual, torque, eta, margin, ratio, full_residual, full_torque)


def geometry_valid(depths, radius: float) -> np.ndarray:
    """Return whether every active contact lies within the fingertip radius, shape (b,).

    Parameters
    ----------
    depths : (b, c) float
        Penetrations delta [m]; delta = 0 is a released contact.
    radius : float
        Fingertip radius r [m].

    Notes
    -----
    A fingertip sphere buried deeper than its own radius has its centre inside the object: the
    contact geometry of §3.2-3.3 (a cap of the fingertip pressed into a face) no longer exists,
    so such a state is physically invalid, whatever the force balance says. One rule for every
    grip law and every study (issue 13, item 1).
    """
    return np.all(np.asarray(depths, dtype=float) <= radius, axis=-1)


def judge(batch: CandidateBatch, depths, params, iterations, trace, friction=None,
            grip_force=None, grip_needed=None) -> EquilibriumResult:
    """Judge a force state with the checks of Algorithm 1 line 6 and the validity gate.

    One verdict rule for every grip law: the ``paper`` law checks the normal-only residuals
    (Algorithm 1 line 6, §6.1), the ``slip`` and ``oracle`` laws the full post-friction ones.
    """
    wrench = resolve(batch, depths, friction)
    residual_norm = np.linalg.norm(wrench.residual, axis=1)
    torque_norm = np.linalg.norm(wrench.torque, axis=1)
    full_residual_norm = np.linalg.norm(wrench.full_residual, axis=1)
    full_torque_norm = np.linalg.norm(wrench.full_torque, axis=1)
    paper = params.grip_law == "paper"
    residual = wrench.residual if paper else wrench.full_residual
    checked = np.linalg.norm(residual, axis=1) if params.residual_check == "norm" else np.abs(residual[:, 2])
    residual_ok = checked < params.tau_f
    torque_ok = (torque_norm if paper else full_torque_norm) < params.tau_t
    slip_ok = wrench.slip_margin > 0.0
    valid = geometry_valid(depths, params.fingertip_radius)
    unbounded = residual_ok & torque_ok & slip_ok
    failure = np.select([~residual_ok, ~torque_ok, ~slip_ok, ~valid], [1, 2, 3, 4], default=0)
    nan = np.full(depths.shape[0], np.nan)
    return EquilibriumResult(
        success=unbounded & valid,
        success_unbounded=unbounded,
        valid_geometry=valid,
        failure_check=failure.astype(np.int8),
        residual_ok=residual_ok,
        torque_ok=torque_ok,
        slip_ok=slip_ok,
        residual_norm=residual_norm,
        residual_z=wrench.residual[:, 2],
        torque_norm=torque_norm,
        slip_margin=wrench.slip_margin,
        slip_margin_ratio=wrench.slip_margin_ratio,
        eta=wrench.eta,
        post_friction_residual_z=wrench.full_residual[:, 2],
        full_residual_norm=full_residual_norm,
        full_torque_norm=full_torque_norm,
        rho=np.linalg.norm(wrench.residual[:, :2], axis=1) / batch.weight,
        normal_forces=wrench.forces,
        depths=depths,
        delta_max_mm=np.max(depths, axis=1) * MM_PER_M,
        iterations=iterations,
        grip_force=nan if grip_force is None else grip_force,
        grip_needed=nan if grip_needed is None else grip_needed,
        trace=trace,
    )


def readings(result: EquilibriumResult, params: EvaluatorParams) -> dict[str, np.ndarray]:
    """Return every reading of the verdict from one result, each (b,) bool.

    ``success`` (the configured checks and the validity gate), ``success_unbounded`` (the checks
    alone), ``success_norm`` / ``success_vertical`` (the residual check on ``|R|`` / ``|R_z|``
    of the residual the law checks: normal-only for ``paper``, post-friction otherwise, with the
    torque and slip checks and the gate), ``success_no_torque`` (the configured residual check,
    the slip check and the gate: tau_T switched off). One rule for every study (issue 13).
    """
    paper = params.grip_law == "paper"
    norm = result.residual_norm if paper else result.full_residual_norm
    vertical = np.abs(result.residual_z if paper else result.post_friction_residual_z)
    rest = result.torque_ok & result.slip_ok & result.valid_geometry
    return {
        "success": result.success,
        "success_unbounded": result.success_unbounded,
        "success_norm": (norm < params.tau_f) & rest,
        "success_vertical": (vertical < params.tau_f) & rest,
        "success_no_torque": result.residual_ok & result.slip_ok & result.valid_geometry,
    }
