"""Mass-spring-damper (MSD) surface-shell body: gravity settling on a rigid floor, and the model's
public face.

The body of §2 (Eq. 1-5) is split by concept; this module holds the rigid floor and gravity
settling (§5.4, Fig. 10) and re-exports every public name of the others, so
``from graspcampaign.core.msd import ...`` keeps working:

* :mod:`graspcampaign.core.msd_body`: parameters, body construction, enclosed volume;
* :mod:`graspcampaign.core.msd_state`: the ``6 n`` state layout, positions and velocities;
* :mod:`graspcampaign.core.msd_forces`: spring, damper and enclosed-volume forces, ``msd_rhs``;
* :mod:`graspcampaign.core.msd_integrate`: classical RK4 and its stable step limits;
* :mod:`graspcampaign.core.msd_audit`: energies, energy audit, step-size convergence study.

Shape letters: ``n`` nodes, ``e`` edges, ``f`` faces, ``s`` recorded samples.

References
----------
Eq. 1-5 (§2.1-2.2); §5.4 (gravity settling, Fig. 10). Hairer, E., Norsett, S. P. & Wanner, G.
(1993), Solving Ordinary Differential Equations I, §IV.2 (stability region of RK4).
"""

from __future__ import annotations

import logging
from collections.abc import Callable
from dataclasses import dataclass, replace

import numpy as np

from graspcampaign.core.msd_audit import (
    EnergyAuditResult,
    StepConvergenceResult,
    dissipation_power,
    elastic_energy,
    energy_audit,
    gravitational_energy,
    kinetic_energy,
    step_convergence,
)
from graspcampaign.core.msd_body import (
    MsdBody,
    MsdParams,
    enclosed_volume,
    msd_body_from_arrays,
    msd_body_from_mesh,
    msd_params_from_modulus,
)
from graspcampaign.core.msd_forces import (
    internal_forces,
    msd_rhs,
    volume_energy,
    volume_forces,
)
from graspcampaign.core.msd_integrate import (
    RK4_IMAGINARY_AXIS_LIMIT,
    IntegrationResult,
    body_step_limit,
    integrate_rk4,
    rk4_step,
    stable_step_limit,
)
from graspcampaign.core.msd_state import (
    check_state,
    positions_from_state,
    state_from_positions,
    velocities_from_state,
)

__all__ = [
    # rigid floor and gravity settling (this module)
    "FloorParams",
    "SettleResult",
    "floor_anchors_update",
    "floor_forces",
    "settle_on_floor",
    # re-exported: they live in graspcampaign.core.msd_body
    "MsdBody",
    "MsdParams",
    "enclosed_volume",
    "msd_body_from_arrays",
    "msd_body_from_mesh",
    "msd_params_from_modulus",
    # re-exported: they live in graspcampaign.core.msd_state
    "check_state",
    "positions_from_state",
    "state_from_positions",
    "velocities_from_state",
    # re-exported: they live in graspcampaign.core.msd_forces
    "internal_forces",
    "msd_rhs",
    "volume_energy",
    "volume_forces",
    # re-exported: they live in graspcampaign.core.msd_integrate
    "RK4_IMAGINARY_AXIS_LIMIT",
    "IntegrationResult",
    "body_step_limit",
    "integrate_rk4",
    "rk4_step",
    "stable_step_limit",
    # re-exported: they live in graspcampaign.core.msd_audit
    "EnergyAuditResult",
    "StepConvergenceResult",
    "dissipation_power",
    "elastic_energy",
    "energy_audit",
    "gravitational_energy",
    "kinetic_energy",
    "step_convergence",
]

logger = logging.getLogger(__name__)


# ----------------------------------------------------------------------------------------------
# Rigid floor and gravity settling (§5.4, Fig. 10)
# ----------------------------------------------------------------------------------------------


@dataclass(frozen=True)
class FloorParams:
    """Penalty contact of the nodes with a rigid horizontal floor (spring-slider friction).

    Attributes
    ----------
    height : float
        Floor plane z [m].
    stiffness : float
        Normal penalty stiffness per node [N/m]. Default 1.4e4 N/m = 10 k: at 0.4 kg the
        sphere's weight then sinks the few support nodes by well under 0.1 mm.
    damping : float
        Normal penalty damping per node [N*s/m]. Default 8 N*s/m: critical for one node of
        0.4 kg / 356 on that spring (``2 sqrt(k_f m_i)`` = 7.9).
    mu : float
        Floor friction coefficient [-]. Default 0.5 (an assumption: a gel on a table; the paper
        does not state it).
    tangential_stiffness, tangential_damping : float
        Stick spring and damper of the friction slider per node [N/m], [N*s/m]; default equal
        to the normal ones (isotropic penalty).

    Notes
    -----
    Normal force per node ``f_n = max(0, k_f p - c_f v_z)``, p the depth below the floor (no
    adhesion). Friction is a Cundall-Strack spring-slider: each touching node has a stick anchor
    ``a``; the trial force ``-k_t (x_t - a) - c_t v_t`` (horizontal) is capped at ``mu f_n``, and
    after each step the anchor of a sliding node is dragged so that the spring sits on the cone.
    A regularised viscous Coulomb law was tried first and rejected: its slope ``mu f_n / v_s`` is
    stiff enough to chatter under explicit RK4 unless ``v_s`` is so large that the base creeps.
    The floor is our modelling choice: §5.4 says only "placed on a flat surface".

    References
    ----------
    Cundall, P. A. & Strack, O. D. L. (1979), "A discrete numerical model for granular
    assemblies", Geotechnique 29(1):47-65 (spring-slider contact).
    """

    height: float = 0.0
    stiffness: float = 1.4e4
    damping: float = 8.0
    mu: float = 0.5
    tangential_stiffness: float = 1.4e4
    tangential_damping: float = 8.0


def floor_forces(state, floor: FloorParams, anchors=None) -> np.ndarray:
    """Return the (n, 3) penalty forces [N] of a rigid floor on the nodes of a (6 n,) state.

    Parameters
    ----------
    state : (6 n,) float
        State vector.
    floor : FloorParams
    anchors : (n, 2) float, optional
        Horizontal stick anchors [m] (see :func:`floor_anchors_update`); None: frictionless.

    Returns
    -------
    forces : (n, 3) float
        Normal (+z) and friction (x, y) forces [N]; zero for nodes above the floor.
    """
    nodes = np.asarray(state).reshape(-1, 6)
    penetration = floor.height - nodes[:, 2]
    forces = np.zeros((nodes.shape[0], 3))
    touching = penetration > 0.0
    if not np.any(touching):
        return forces
    v = nodes[touching, 3:]
    normal = _floor_normal(penetration[touching], v[:, 2], floor)
    forces[touching, 2] = normal
    if anchors is not None and floor.mu > 0.0:
        forces[touching, :2] = _floor_friction(
            nodes[touching, :2], v[:, :2], anchors[touching], normal, floor
        )
    return forces


def _floor_normal(penetration, v_z, floor: FloorParams) -> np.ndarray:
    """Return the penalty normal force ``max(0, k_f p - c_f v_z)`` [N] (no adhesion)."""
    return np.maximum(0.0, floor.stiffness * penetration - floor.damping * v_z)


def _floor_friction(xy, v_xy, anchors, normal, floor: FloorParams) -> np.ndarray:
    trial = -floor.tangential_stiffness * (xy - anchors) - floor.tangential_damping * v_xy
    size = np.sqrt(np.sum(trial * trial, axis=1))
    cap = floor.mu * normal
    scale = np.where(size > cap, cap / np.where(size > 0.0, size, 1.0), 1.0)
    return trial * scale[:, None]


def floor_anchors_update(state, floor: FloorParams, anchors) -> np.ndarray:
    """Return the stick anchors after a step (return mapping of the spring-slider).

    Parameters
    ----------
    state : (6 n,) float
        State at the end of the step.
    floor : FloorParams
    anchors : (n, 2) float
        Anchors used during the step [m].

    Returns
    -------
    anchors : (n, 2) float
        Nodes off the floor: anchor at the node. Sliding nodes: anchor moved along the spring so
        that ``k_t |x_t - a| = mu f_n``. Sticking nodes: unchanged.
    """
    nodes = np.asarray(state).reshape(-1, 6)
    xy = nodes[:, :2]
    new = np.array(anchors, dtype=np.float64, copy=True)
    penetration = floor.height - nodes[:, 2]
    normal = _floor_normal(penetration, nodes[:, 5], floor)
    touching = (penetration > 0.0) & (normal > 0.0)
    new[~touching] = xy[~touching]
    stretch = xy - new
    length = np.sqrt(np.sum(stretch * stretch, axis=1))
    allowed = floor.mu * normal / floor.tangential_stiffness
    sliding = touching & (length > allowed)
    if np.any(sliding):
        new[sliding] = xy[sliding] - stretch[sliding] * (allowed[sliding] / length[sliding])[:, None]
    return new


@dataclass(frozen=True)
class SettleResult:
    """Outcome of a gravity-settling run on a floor (Fig. 10).

    Attributes
    ----------
    times : (s,) float
        Recorded times [s].
    kinetic_energy : (s,) float
        Kinetic energy trace [J].
    height_ratio : (s,) float
        Current height (max z - min z) over the undeformed height [-].
    squash_ratio : float
        Final ``height_ratio`` [-].
    positions : (n, 3) float
        Settled node positions [m].
    initial_positions : (n, 3) float
        Undeformed positions resting on the floor [m].
    settled : bool
        Whether the kinetic energy stayed below tolerance over the final window.
    dt : float
        Step used [s].
    n_steps : int
        Steps taken.
    max_floor_penetration : float
        Deepest node below the floor at the end [m] (penalty artefact, should be << l_mean).
    """

    times: np.ndarray
    kinetic_energy: np.ndarray
    height_ratio: np.ndarray
    squash_ratio: float
    positions: np.ndarray
    initial_positions: np.ndarray
    settled: bool
    dt: float
    n_steps: int
    max_floor_penetration: float


def settle_on_floor(
    body: MsdBody,
    params: MsdParams,
    floor: FloorParams | None = None,
    dt: float | None = None,
    t_max: float = 2.0,
    ke_tol: float | None = None,
    window: float = 0.05,
    record_every: int = 10,
    stepper: Callable | None = None,
) -> SettleResult:
    """Place the undeformed body on a rigid floor, release it under gravity, and let it settle.

    Parameters
    ----------
    body, params
        The MSD body.
    floor : FloorParams, optional
        Floor constants; its ``height`` is ignored and set to the lowest rest node, so the body
        starts touching the floor at rest.
    dt : float, optional
        Step [s]; default (RK4 only) half of :func:`body_step_limit` including the floor penalty.
    t_max : float
        Time budget [s].
    ke_tol : float, optional
        Kinetic-energy tolerance [J]; default ``1e-7 m g H0`` (H0 the undeformed height).
    window : float
        The kinetic energy must stay below ``ke_tol`` this long to stop [s].
    record_every : int
        Record stride of the traces (the stop test uses every step).
    stepper : callable, optional
        ``stepper(state, floor, anchors, dt) -> state``: one step of another integrator with the
        floor forces (anchors held over the step), e.g.
        ``core.implicit.ImplicitIntegrator.floor_stepper()``; then ``dt`` is required. Default:
        classical RK4 with the floor forces evaluated at every stage.

    Returns
    -------
    result : SettleResult

    References
    ----------
    §5.4, Fig. 10.
    """
    rest = body.rest_positions
    floor = replace(floor or FloorParams(), height=float(rest[:, 2].min()))
    height0 = float(np.ptp(rest[:, 2]))
    limit = body_step_limit(
        body,
        params,
        max(floor.stiffness, floor.tangential_stiffness),
        max(floor.damping, floor.tangential_damping),
    )
    if stepper is not None:
        if dt is None:
            raise ValueError("settle_on_floor: a stepper needs an explicit dt")
    elif dt is None:
        dt = 0.5 * limit
    elif dt > limit:
        logger.warning("settle_on_floor: dt = %.3g s exceeds the RK4 limit %.3g s", dt, limit)
    if ke_tol is None:
        ke_tol = 1e-7 * body.mass * params.g * height0

    state = state_from_positions(rest)
    anchors = rest[:, :2].copy()

    def rhs(t, x):
        return msd_rhs(t, x, body, params, floor_forces(x, floor, anchors))

    max_steps = int(np.ceil(t_max / dt))
    window_steps = max(1, int(np.ceil(window / dt)))
    times, kinetic, ratio = [0.0], [0.0], [1.0]
    quiet = 0
    settled = False
    step = 0
    min_steps = window_steps  # the body starts at rest: do not stop before it has moved
    for step in range(1, max_steps + 1):
        if stepper is None:
            state = rk4_step(rhs, (step - 1) * dt, state, dt)
        else:
            state = stepper(state, floor, anchors, dt)
        anchors[:] = floor_anchors_update(state, floor, anchors)
        ke = float(kinetic_energy(body, state))
        if not np.isfinite(ke):
            raise FloatingPointError(f"settle_on_floor diverged at step {step} (dt = {dt:.3g} s)")
        quiet = quiet + 1 if ke < ke_tol else 0
        done = step > min_steps and quiet >= window_steps
        if step % record_every == 0 or done or step == max_steps:
            positions = positions_from_state(state)
            times.append(step * dt)
            kinetic.append(ke)
            ratio.append(float(np.ptp(positions[:, 2])) / height0)
        if done:
            settled = True
            break
    positions = positions_from_state(state).copy()
    logger.info(
        "settle_on_floor: %s after %d steps (%.3f s), squash ratio %.4f",
        "settled" if settled else "not settled",
        step,
        step * dt,
        ratio[-1],
    )
    return SettleResult(
        times=np.asarray(times),
        kinetic_energy=np.asarray(kinetic),
        height_ratio=np.asarray(ratio),
        squash_ratio=ratio[-1],
        positions=positions,
        initial_positions=rest.copy(),
        settled=settled,
        dt=float(dt),
        n_steps=step,
        max_floor_penetration=float(max(0.0, floor.height - positions[:, 2].min())),
    )
