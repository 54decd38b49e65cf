"""The dynamic grasp in the paper's order (Fig. 11): closure on a held object, lift-off, hold.

:func:`run_grasp_phases` drives :func:`core.dynamics.grasp_step` (or any step with its signature,
e.g. a compiled one) through the phases of Fig. 11 and judges the hold by Eq. 19:

``closure``
    The object is held by the support (load fraction ``w = 0``: its translation and rotation are
    held, its shape is free). The fingers start ``open_gap`` outside the surface ("opening",
    "descent" and "approach" are kinematic and touch nothing) and close at ``grip_speed``; each
    finger stops when its own penetration reaches the §5.1 seed depth ("finger closure with
    progressive contact"). The closure ends when every finger has reached it.
``lift``
    Lift-off: the support lets go over ``lift_time`` (``w`` rises 0 -> 1 as a raised cosine), so
    the weight passes to the fingers. From here on the grip law of §3 runs: every finger advances
    at ``grip_speed`` while ``|w R_z| >= tau_F`` (``R_z`` the Eq. 19 residual of the fingers
    against the full weight, ``w R_z`` the part the support no longer carries), and a finger out
    of contact keeps closing until it touches again.
``hold``
    ``w = 1``: the body is free under gravity and held by the fingers alone. Stable (Eq. 19, §3.7):
    ``|R_z| < tau_F`` for ``settle_time`` with the centroid at rest and every finger touching
    within that window.

Stops: ``"stable"``; ``"penetration_limit"`` when a penetration exceeds ``max_depth`` (default the
fingertip radius, the ``valid_geometry`` limit); ``"dropped"`` when the centroid has fallen
``drop_distance`` below its height at lift-off; ``"not_settled"`` at ``t_max``. ``success``
requires ``"stable"`` and ``valid_geometry`` (every penetration of the run within the fingertip
radius); ``success_unbounded`` is the Eq. 19 verdict alone.

Shape letters: ``s`` recorded steps, ``c`` fingers, ``n`` nodes.

References
----------
Fig. 11 and §5.5 (opening, descent, closure with progressive contact, lift-off), §3 (grip
increment while equilibrium fails), §3.7 Eq. 19, §5.1 (seed), §12 (six-component residual).
"""

from __future__ import annotations

import logging
import math
from collections.abc import Callable
from dataclasses import dataclass

import numpy as np
import trimesh

from graspcampaign.core.contact import ContactParams, depth_for_force
from graspcampaign.core.dynamics import (
    GraspParams,
    GraspSetup,
    GraspState,
    grasp_step,
    prepare_grasp,
)
from graspcampaign.core.grasp_kernel import body_summary
from graspcampaign.core.msd import MsdParams
from graspcampaign.core.statics import wrench_residual

__all__ = [
    "PHASES",
    "STATUSES",
    "DynamicGraspResult",
    "PhaseTimes",
    "dynamic_grasp",
    "grasp_result",
    "load_fraction",
    "run_grasp_phases",
]

logger = logging.getLogger(__name__)

PHASES = ("closure", "lift", "hold")
"""Simulated phases of Fig. 11, in order (opening and descent are kinematic: nothing touches)."""

STATUSES = ("stable", "not_settled", "penetration_limit", "dropped")
"""Outcome vocabulary of :func:`run_grasp_phases` (``success`` needs ``"stable"``)."""

Step = Callable[[GraspSetup, GraspState], GraspState]


def load_fraction(elapsed, lift_time: float):
    """Return the share ``w`` of the load left to the fingers ``elapsed`` seconds into lift-off.

    Parameters
    ----------
    elapsed : float or (...) float
        Time since lift-off began [s] (clipped to ``[0, lift_time]``).
    lift_time : float
        Ramp duration [s].

    Returns
    -------
    w : float or (...) float
        ``(1 - cos(pi t / T)) / 2``: 0 at the start, 1 at the end, zero slope at both ends (the
        support's force changes with finite jerk).
    """
    tau = np.clip(np.asarray(elapsed, dtype=float) / lift_time, 0.0, 1.0)
    return 0.5 * (1.0 - np.cos(np.pi * tau))


@dataclass(frozen=True)
class PhaseTimes:
    """When each phase of Fig. 11 began and ended [s] (nan: not reached).

    Attributes
    ----------
    closure_start, closure_end : float
        Fingers start closing; every finger has reached the seed depth.
    touch : (c,) float
        First contact of each finger (progressive contact).
    lift_start, lift_end : float
        The support begins to let go (= ``closure_end``); it carries nothing any more.
    hold_start, hold_end : float
        The settled window of Eq. 19 (``hold_end`` = the time the grasp was declared stable).
    """

    closure_start: float
    closure_end: float
    touch: np.ndarray
    lift_start: float
    lift_end: float
    hold_start: float
    hold_end: float


@dataclass(frozen=True)
class DynamicGraspResult:
    """Traces and outcome of one dynamic grasp (the data of Figs. 12-13, per step).

    Attributes
    ----------
    times : (s,) float
        Time of each recorded state [s].
    phase : (s,) str
        Phase of the step starting at that state (:data:`PHASES`).
    load_fraction : (s,) float
        Share ``w`` of the load left to the fingers during that step [-].
    residual : (s, 3) float
        Eq. 19 force residual ``sum_j f_j + m g`` (fingers against the full weight) [N].
    residual_z : (s,) float
        Its vertical component (Fig. 12 top) [N].
    support_force : (s, 3) float
        Force of the support on the body [N].
    total_penetration : (s,) float
        ``sum_j delta_j`` (Fig. 12 bottom) [m].
    normal_forces : (s, c) float
        Per-finger normal force f_n (Fig. 13) [N].
    tangential_forces : (s, c) float
        Per-finger tangential force magnitude [N].
    depths : (s, c) float
        Per-finger penetration [m].
    sliding : (s, c) bool
        Per-finger slip flag of the stick-slip law.
    in_contact : (s, c) bool
        Per-finger contact flag.
    grip : (s, c) float
        Per-finger advance s_j past first touch [m].
    centroid : (s, 3) float
        Mean node position [m].
    kinetic_energy : (s,) float
        [J].
    status : str
        One of :data:`STATUSES`.
    final_phase : str
        Phase in which the run stopped.
    valid_geometry : bool
        Every penetration of the run stayed within the fingertip radius.
    success_unbounded : bool
        ``status == "stable"`` (the Eq. 19 verdict without the validity gate).
    success : bool
        ``success_unbounded and valid_geometry``.
    phase_times : PhaseTimes
    settled_at : float
        ``phase_times.hold_end`` [s].
    delta_required : float
        Closed form ``(m g / K)^(1/n)`` (mm inside the power law, returned in m): the penetration
        at which one fingertip alone carries the weight statically [m].
    wrench : (6,) float
        Six-component residual (force [N], torque about the centroid [N*m]) at the last state.
    contact_points : (c, 3) float
        Final contact points [m].
    contact_forces : (c, 3) float
        Final contact forces on the object [N].
    slip_margin : float
        ``min_j (mu f_n - |f_t|) / (mu f_n)`` over active fingers at the last state (§6.4) [-].
    delta_max : float
        Largest single-finger penetration over the run [m] (design limit 1 mm, §5.5).
    positions : (n, 3) float
        Final node positions [m].
    dt : float
        RK4 step [s].
    n_steps : int
        Steps taken.
    """

    times: np.ndarray
    phase: np.ndarray
    load_fraction: np.ndarray
    residual: np.ndarray
    residual_z: np.ndarray
    support_force: np.ndarray
    total_penetration: np.ndarray
    normal_forces: np.ndarray
    tangential_forces: np.ndarray
    depths: np.ndarray
    sliding: np.ndarray
    in_contact: np.ndarray
    grip: np.ndarray
    centroid: np.ndarray
    kinetic_energy: np.ndarray
    status: str
    final_phase: str
    valid_geometry: bool
    success_unbounded: bool
    success: bool
    phase_times: PhaseTimes
    settled_at: float
    delta_required: float
    wrench: np.ndarray
    contact_points: np.ndarray
    contact_forces: np.ndarray
    slip_margin: float
    delta_max: float
    positions: np.ndarray
    dt: float
    n_steps: int


_TRACES = ("times", "phase", "load_fraction", "residual", "support_force", "normal_forces",
           "tangential", "sliding", "depths", "in_contact", "grip", "centroid", "kinetic_energy")


def run_grasp_phases(setup: GraspSetup, state: GraspState, step: Step = grasp_step) -> DynamicGraspResult:
    """Drive a prepared grasp through closure, lift-off and hold (Fig. 11) and judge Eq. 19.

    Parameters
    ----------
    setup : GraspSetup
        Fixed model (:func:`core.dynamics.prepare_grasp`).
    state : GraspState
        Initial state: body at rest and held, fingers open.
    step : callable
        ``step(setup, state) -> state``, one time step under the state's command; default
        :func:`core.dynamics.grasp_step` (a compiled step with the same contract can be passed).

    Returns
    -------
    result : DynamicGraspResult

    Notes
    -----
    Each iteration reads the contact evaluation of the current state, records it, applies the
    stops and the phase logic of the module docstring, sets the command of the next step
    (``grip_rate``, ``load_fraction``) and calls ``step``. Nothing else touches the state.
    """
    grasp, dt = setup.grasp, setup.dt
    n_fingers = setup.n_fingers
    n_max = int(np.ceil(grasp.t_max / dt))
    settle_steps = max(1, int(np.ceil(grasp.settle_time / dt)))
    traces: dict[str, list] = {key: [] for key in _TRACES}
    record = [traces[key].append for key in _TRACES]
    phase, status = "closure", "not_settled"
    closure_start = state.time
    reached = [False] * n_fingers
    touch = [float("nan")] * n_fingers
    lift_start = lift_end = hold_start = hold_end = float("nan")
    z_lift = float("nan")
    quiet = 0
    since_touch = [settle_steps] * n_fingers
    speed_close, seed, tau_f = grasp.grip_speed, grasp.seed_depth, grasp.tau_f
    half_node_mass = 0.5 * setup.body.node_mass
    n_steps = 0
    # Per-finger values as Python lists and one compiled pass over the nodes per step
    # (body_summary): the driver's own cost stays small beside a compiled step.
    while True:
        out = state.contact
        hits = out.contacts
        active = hits.active.tolist()
        depths = hits.depths.tolist()
        summary = body_summary(state.state)
        centroid = summary[:3]
        for j in range(n_fingers):
            if active[j] and touch[j] != touch[j]:  # first touch (nan != nan)
                touch[j] = state.time
        if phase == "closure":
            for j in range(n_fingers):
                reached[j] = reached[j] or depths[j] >= seed
            if all(reached):
                phase, lift_start, z_lift = "lift", state.time, float(centroid[2])
        w = 0.0
        if phase != "closure":
            w = _load_fraction(state.time - lift_start, grasp.lift_time)
            if phase == "lift" and state.time - lift_start >= grasp.lift_time:
                phase, lift_end, w = "hold", state.time, 1.0
        residual_z = float(out.residual[2])
        for append, value in zip(record, (
                state.time, phase, w, out.residual, out.support_force, out.normal_forces,
                out.tangential, out.stick.sliding, hits.depths, hits.active, state.grip,
                centroid, half_node_mass * float(summary[6])), strict=True):
            append(value)

        if max(depths) > setup.max_depth:
            status = "penetration_limit"
            break
        if phase != "closure" and z_lift - float(centroid[2]) > grasp.drop_distance:
            status = "dropped"
            break
        if phase == "hold":
            speed = math.sqrt(float(summary[3]) ** 2 + float(summary[4]) ** 2
                              + float(summary[5]) ** 2)
            # Every finger touching within the window: a light contact may flicker at the onset
            # of Eq. 13.
            since_touch = [0 if a else s + 1 for a, s in zip(active, since_touch, strict=True)]
            held = (abs(residual_z) < tau_f and speed < grasp.settle_speed
                    and max(since_touch) < settle_steps)
            quiet = quiet + 1 if held else 0
            if quiet == 1:
                hold_start = state.time
            if quiet >= settle_steps:
                status, hold_end = "stable", state.time
                break
        if n_steps >= n_max:
            break

        if phase == "closure":
            rate = [0.0 if r and a else speed_close
                    for r, a in zip(reached, active, strict=True)]
        else:
            squeezing = abs(w * residual_z) >= tau_f
            rate = [speed_close if (not a) or squeezing else 0.0 for a in active]
        state = step(setup, state.commanded(rate, w))
        n_steps += 1

    if status != "stable":
        hold_start = float("nan")
    times = PhaseTimes(
        closure_start=float(closure_start),
        closure_end=float(lift_start),
        touch=np.array(touch),
        lift_start=float(lift_start),
        lift_end=float(lift_end),
        hold_start=float(hold_start),
        hold_end=float(hold_end),
    )
    return grasp_result(setup, state, traces, status, phase, times, n_steps)


def _load_fraction(elapsed: float, lift_time: float) -> float:
    """Scalar :func:`load_fraction` (the driver calls it once per step)."""
    tau = min(max(elapsed / lift_time, 0.0), 1.0)
    return 0.5 * (1.0 - math.cos(math.pi * tau))


def grasp_result(setup, state, traces, status, phase, times, n_steps) -> DynamicGraspResult:
    """Assemble a DynamicGraspResult from the per-step traces and the last state (both drivers)."""
    arrays = {key: np.asarray(value) for key, value in traces.items()}
    arrays["tangential_forces"] = np.linalg.norm(arrays.pop("tangential"), axis=-1)
    arrays["sliding"] &= arrays["in_contact"]
    out = state.contact
    hits = out.contacts
    params, contact = setup.msd_params, setup.contact
    mu_f_n = setup.mu * out.normal_forces
    loaded = hits.active & (mu_f_n > 0.0)
    if np.any(loaded):
        margins = (mu_f_n[loaded] - np.linalg.norm(out.tangential[loaded], axis=1)) / mu_f_n[loaded]
        slip_margin = float(margins.min())
    else:
        slip_margin = float("nan")
    depths = arrays["depths"]
    delta_max = float(depths.max())
    valid = delta_max <= setup.valid_depth
    stable = status == "stable"
    delta_required = float(depth_for_force(params.mass * params.g, contact.k_n_per_mm_n, contact.n))
    logger.info(
        "dynamic grasp mu=%.2f m=%.2f kg: %s in %s after %d steps (%.3f s), R_z=%.3g N, "
        "delta_max=%.3g mm (one finger alone needs %.3g mm)",
        setup.mu, params.mass, status, phase, n_steps, state.time, arrays["residual"][-1, 2],
        1e3 * delta_max, 1e3 * delta_required,
    )
    return DynamicGraspResult(
        times=arrays["times"],
        phase=arrays["phase"],
        load_fraction=arrays["load_fraction"],
        residual=arrays["residual"],
        residual_z=arrays["residual"][:, 2],
        support_force=arrays["support_force"],
        total_penetration=np.where(arrays["in_contact"], depths, 0.0).sum(axis=1),
        normal_forces=arrays["normal_forces"],
        tangential_forces=arrays["tangential_forces"],
        depths=depths,
        sliding=arrays["sliding"],
        in_contact=arrays["in_contact"],
        grip=arrays["grip"],
        centroid=arrays["centroid"],
        kinetic_energy=arrays["kinetic_energy"],
        status=status,
        final_phase=phase,
        valid_geometry=bool(valid),
        success_unbounded=bool(stable),
        success=bool(stable and valid),
        phase_times=times,
        settled_at=times.hold_end,
        delta_required=delta_required,
        wrench=wrench_residual(hits.points, out.forces, params.mass, arrays["centroid"][-1], params.g),
        contact_points=hits.points.copy(),
        contact_forces=out.forces.copy(),
        slip_margin=slip_margin,
        delta_max=delta_max,
        positions=state.state.reshape(-1, 6)[:, :3].copy(),
        dt=float(setup.dt),
        n_steps=n_steps,
    )


def dynamic_grasp(
    mesh: trimesh.Trimesh,
    mu: float,
    msd_params: MsdParams | None = None,
    contact: ContactParams | None = None,
    grasp: GraspParams | None = None,
    directions=None,
    *,
    points=None,
    normals=None,
    body=None,
    step: Step = grasp_step,
) -> DynamicGraspResult:
    """Prepare and run a dynamic grasp (Fig. 3 per step, Fig. 11 in order) on an MSD body.

    Parameters
    ----------
    mesh, mu, msd_params, contact, grasp, directions, points, normals, body
        As :func:`core.dynamics.prepare_grasp` (default: the 45/45/-90 contacts of §5.2, Table 3
        contact law, default body and loop constants).
    step : callable
        As :func:`run_grasp_phases`.

    Returns
    -------
    result : DynamicGraspResult

    References
    ----------
    Fig. 3, Fig. 11, Eq. 11-19, §5.1, §5.5.
    """
    setup, state = prepare_grasp(mesh, mu, msd_params, contact, grasp, directions,
                                 points=points, normals=normals, body=body)
    return run_grasp_phases(setup, state, step)
